-- | Routes for the seed's specs, drawn as the specs need them: zones at given speeds whose
-- starts cut the route at given fractions, ranges given as magnitudes, from rest to rest;
-- and what the checker finds wrong with a seed's velocities.
module Support.Routes
  ( Ranges (..)
  , restRoute
  , genRestRoute
  , violations
  ) where

import Data.List (sort)
import qualified Data.Vector.Unboxed as U
import Test.QuickCheck

import Support.Wide (logUniform)
import VProf.Profile.Legality (Rule (..), Violation (..), check)
import VProf.Profile.Problem (Algorithm (..), Problem (..))
import VProf.Profile.Sampled (Profile (..))

-- | The magnitudes of a_min, a_max, j_min and j_max.
data Ranges = Ranges !Double !Double !Double !Double

-- | A route of the given length from rest to rest: the first zone at 0, the others from the
-- given fractions of the length (in any order), at the given time step and end tolerance.
restRoute :: Double -> [Double] -> [Double] -> Ranges -> Double -> Double -> Problem
restRoute len speeds cuts (Ranges aMin aMax jMin jMax) dt tol = Problem
  { pbLength = len, pbZoneStarts = U.fromList (0 : map (* len) (sort cuts)), pbZoneSpeeds = U.fromList speeds
  , pbAMin = negate aMin, pbAMax = aMax, pbJMin = negate jMin, pbJMax = jMax
  , pbV0 = 0, pbA0 = 0, pbVEnd = 0, pbAEnd = 0, pbDt = dt, pbDv = 1e-9
  , pbMaxIter = 100, pbBudget = 10, pbTol = tol, pbAlgorithm = Band, pbSeedSearch = False }

-- | 'restRoute' drawn log-uniformly: up to the given number of zones, speeds, lengths,
-- acceleration and jerk magnitudes in the given ranges, cuts between 5 and 95 % of the
-- length, and a time step drawn for the route so far.
genRestRoute :: Int -> (Double, Double) -> (Double, Double) -> (Double, Double) -> (Double, Double)
             -> (Problem -> Gen Double) -> Double -> Gen Problem
genRestRoute maxZones (v0, v1) (l0, l1) (a0, a1) (j0, j1) genDt tol = do
  nz <- choose (1, maxZones)
  speeds <- vectorOf nz (logUniform v0 v1)
  len <- logUniform l0 l1
  cuts <- vectorOf (nz - 1) (choose (0.05, 0.95))
  ranges <- Ranges <$> logUniform a0 a1 <*> logUniform a0 a1 <*> logUniform j0 j1 <*> logUniform j0 j1
  let pb = restRoute len speeds cuts ranges 1 tol
  dt <- genDt pb
  pure pb { pbDt = dt }

-- | The checker's violations of velocities v_0..v_N for the problem, other than a crawl
-- (the generator cuts a profile at its arrival).
violations :: Problem -> U.Vector Double -> [Violation]
violations pb v = [ x | x@(Violation r _ _ _) <- check pb (Profile (pbDt pb) v (pbA0 pb) (pbAEnd pb)), r /= Crawl ]
