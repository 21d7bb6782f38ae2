-- | Random requests for the property tests: 1–100 zones over 5 m–2 km, speeds
-- 0.1–10 m/s, acceleration and jerk magnitudes 0.5–3 with asymmetric ranges, non-zero
-- start and end states; and the problem of a request a test built to be valid.
module Support.Arbitrary
  ( RandomRequest (..)
  , genRequest
  , shared
  , propertyCount
  , problemOf
  ) where

import Data.List (nub, sort)
import System.Environment (lookupEnv)
import Test.QuickCheck

import VProf.Profile.Request
import VProf.Units

newtype RandomRequest = RandomRequest Request deriving (Show)

instance Arbitrary RandomRequest where
  arbitrary = RandomRequest <$> genRequest

-- | Round to a few decimals so that counterexamples read well.
r3 :: Double -> Double
r3 x = fromIntegral (round (x * 1000) :: Integer) / 1000

genRequest :: Gen Request
genRequest = do
  len <- r3 <$> oneof [choose (5, 50), choose (50, 500), choose (500, 2000)]
  nz <- oneof [choose (1, 5), choose (1, 100)]
  cuts <- vectorOf (nz - 1) (choose (0.001, 0.999))
  let starts = 0 : nub (sort [ r3 (c * len) | c <- cuts, r3 (c * len) > 0, r3 (c * len) < len ])
  speeds <- vectorOf (length starts) (r3 <$> frequency [(1, choose (0.1, 1)), (4, choose (0.1, 10))])
  aMin <- negate . r3 <$> choose (0.5, 3)
  aMax <- r3 <$> choose (0.5, 3)
  jMin <- negate . r3 <$> choose (0.5, 3)
  jMax <- r3 <$> choose (0.5, 3)
  let vFirst = head speeds
      vLast = last speeds
  v0 <- r3 <$> frequency [(2, pure 0), (3, choose (0, vFirst))]
  vE <- r3 <$> frequency [(2, pure 0), (3, choose (0, vLast))]
  a0 <- r3 <$> frequency [(2, pure 0), (3, choose (aMin, aMax))]
  aE <- r3 <$> frequency [(2, pure 0), (3, choose (aMin, aMax))]
  pure defaultRequest
    { rqRouteLength = len *~ meter
    , rqZones = zipWith (\s v -> SpeedZone (s *~ meter) (v *~ mps)) starts speeds
    , rqMinAcceleration = aMin *~ mps2, rqMaxAcceleration = aMax *~ mps2
    , rqMinJerk = jMin *~ mps3, rqMaxJerk = jMax *~ mps3
    , rqStartVelocity = v0 *~ mps, rqStartAcceleration = a0 *~ mps2
    , rqEndVelocity = vE *~ mps, rqEndAcceleration = aE *~ mps2
    , rqTimeBudget = Just (30 *~ second)
    }

-- | The project's shared/ folder: ../shared from the project root (CI and the main
-- checkout), or VPROF_SHARED.
shared :: IO FilePath
shared = do
  env <- lookupEnv "VPROF_SHARED"
  case env of
    Just d -> pure d
    Nothing -> pure "../shared"

-- | How many random cases a property runs: 1000, or VPROF_PROPERTY_CASES.
propertyCount :: IO Int
propertyCount = maybe 1000 read <$> lookupEnv "VPROF_PROPERTY_CASES"

-- | The validated problem of a request the test built to be valid; an invalid one fails
-- the test with its field errors.
problemOf :: Request -> Problem
problemOf rq = either (error . ("the test's request is invalid: " ++) . unlines . map renderFieldError) id (validate rq)
