-- | The seed profile: a profile legal by construction and close to time-optimal, from
-- which the rubber band starts.
--
-- A route that ends at rest is seeded by one greedy pass ("VProf.Profile.Generate.Seed.Greedy")
-- that brakes to a standstill on the route end and creeps onto it; a route that ends in
-- motion by the two-sided meet ("VProf.Profile.Generate.Seed.Meet"). Both stand on the
-- brake policy and its oracle ("VProf.Profile.Generate.Seed.Brake"); when the start (or
-- end) state fails the oracle, the first step is searched ("VProf.Profile.Generate.Seed.LeadIn");
-- the failures are worded in "VProf.Profile.Generate.Seed.Explain". The method is
-- described in docs/profile-generator.md.
--
-- Invariant: a seed is legal for its problem (the checker's rules); an 'Unattainable'
-- failure is a claim about the request, a 'LandingFailed' one only about the generator.
module VProf.Profile.Generate.Seed
  ( seed
  , SeedFailure (..)
  , brakeStopDistance
  , mirror
  , restFrom
  ) where

import qualified Data.Vector.Unboxed as U

import VProf.Profile.Generate.Seed.Brake
import VProf.Profile.Generate.Seed.Explain
import VProf.Profile.Generate.Seed.Greedy (forward, passStepCap)
import VProf.Profile.Generate.Seed.LeadIn (leadIn, startStuck)
import VProf.Profile.Generate.Seed.Meet (meet)
import VProf.Profile.Problem (Problem (..))
import VProf.Profile.Problem.Transform (mirror)
import VProf.Profile.Request (maxSamples)

-- | Levels of lead-in: a first step, and one more within the rest.
leadInDepth :: Int
leadInDepth = 2

-- | The seed profile's velocities v_0..v_N.
seed :: Problem -> Either SeedFailure (U.Vector Double)
seed = seedWithin leadInDepth

-- | The seed with up to @depth@ levels of lead-in: when the start state is stuck, the
-- lead-in on the problem; when the end state is, the lead-in on its mirror, reversed.
seedWithin :: Int -> Problem -> Either SeedFailure (U.Vector Double)
seedWithin depth pb = case seedFrom pb of
  Left f@(Unattainable "start_velocity" _) | depth > 0, startStuck moving pb -> either (Left . maybe f id) Right (leadIn seedWithin depth pb)
  Left f@(Unattainable "end_velocity" _) | depth > 0, startStuck True (mirror pb) -> case leadIn seedWithin depth (mirror pb) of
    Right vs -> Right (U.reverse vs)
    Left (Just (LandingFailed m)) -> Left (LandingFailed ("seen from the end, backwards in time: " ++ m))
    Left _ -> Left f
  r -> r
  where moving = pbVEnd pb > 0 || pbAEnd pb /= 0

-- | The seed without a lead-in: a start acceleration that sinks the velocity is refused,
-- a moving end is met from both sides, and an end at rest is landed by one pass.
seedFrom :: Problem -> Either SeedFailure (U.Vector Double)
seedFrom pb = do
  let dt = pbDt pb
      st0 = St (pbV0 pb) (pbA0 pb) 0
  if sinksBelowZero pb
    then Left (startSinks pb)
  else if pbVEnd pb > 0 || pbAEnd pb /= 0
    then meet pb
  else do
      -- ending at rest: the pass brakes to a standstill on the route end; near rest it
      -- creeps, so it lands within the tolerance
      let term = Term (pbLength pb) 0
          landTol = pbTol pb / 2
      e0 <- either (Left . startInfeasible pb (SeedEnv pb term True)) Right (policyFor pb term st0)
      let middle = forward e0 landTol passStepCap st0
          sEnd = if null middle then 0 else stS (last middle)
          aRest = if null middle then pbA0 pb else stA (last middle)
          -- at rest with an acceleration that cannot return to zero in one jerk step:
          -- stand still for one more sample
          settle = let j = negate aRest / dt in if j >= pbJMin pb && j <= pbJMax pb then [] else [St 0 0 sEnd]
      if abs (sEnd - pbLength pb) <= landTol || null middle && pbLength pb <= landTol
        then Right (U.fromList (pbV0 pb : map stV (middle ++ settle)))
        else Left (LandingFailed ("the forward pass stopped at " ++ num sEnd ++ " m, aiming at " ++ num (pbLength pb) ++ " m"))

-- | The hardest legal braking from the start state to a standstill within the route,
-- v_0 .. 0 (just v_0 when the start is at rest): the thesis mode's way into its band,
-- which grows from rest (see "VProf.Profile.Generate.Thesis").
restFrom :: Problem -> Either SeedFailure (U.Vector Double)
restFrom pb
  | sinksBelowZero pb = Left (startSinks pb)
  | otherwise = case brakeCheck e st0 of
      Left bad -> Left (startInfeasible pb e bad)
      Right () -> Right (U.fromList (pbV0 pb : map stV (take maxSamples (braking st0))))
  where
    e = SeedEnv pb (Term (pbLength pb) 0) True
    st0 = St (pbV0 pb) (pbA0 pb) 0
    braking st
      | atRest e st = []
      | otherwise = let st' = stepTo e st (brakeAcc e st) in st' : braking st'
