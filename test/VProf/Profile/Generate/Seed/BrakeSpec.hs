-- | The oracle's fast test and the jerk margins. 'quickNeed' accepts a state without running
-- the brake policy, from continuous-time braking distances and a margin; it must never
-- accept a state whose braking, run step by step ('brakeSimulate'), breaks a rule, from a
-- rising acceleration as from a falling one. The margins a landing is planned again with
-- grow and stay inside the jerk range, and a pass planned with one keeps the problem's rules
-- with the margin to spare.
module VProf.Profile.Generate.Seed.BrakeSpec (spec) where

import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import Support.Wide (logUniform)
import VProf.Profile.Generate.Seed.Brake
import VProf.Profile.Problem (Algorithm (..), Problem (..))

-- | A problem of one to five zones (0.2 to 30 m/s) with wide ranges, at a 0.1 to 100 ms step,
-- and a state on it: anywhere, at up to 1.2 times its zone's limit, with an acceleration
-- across the whole range (falling ones half the time).
genCase :: Gen (Problem, St, Term)
genCase = do
  nz <- choose (1, 5 :: Int)
  speeds <- vectorOf nz (logUniform 0.2 30)
  len <- logUniform 1 2000
  cuts <- vectorOf (nz - 1) (choose (0.02, 0.98))
  aMin <- logUniform 0.1 5
  aMax <- logUniform 0.1 5
  jMin <- logUniform 0.05 20
  jMax <- logUniform 0.05 20
  dt <- logUniform 1e-4 0.1
  let starts = 0 : map (* len) (foldr insertSorted [] cuts)
      pb = Problem
        { pbLength = len, pbZoneStarts = U.fromList starts, pbZoneSpeeds = U.fromList speeds
        , pbAMin = negate aMin, pbAMax = aMax, pbJMin = negate jMin, pbJMax = jMax
        , pbV0 = 0, pbA0 = 0, pbVEnd = 0, pbAEnd = 0, pbDt = dt, pbDv = 1e-9
        , pbMaxIter = 100, pbBudget = 10, pbTol = 1e-2, pbAlgorithm = Band, pbSeedSearch = False }
  s <- choose (0, len)
  let zoneLimit = last (speeds !! 0 : [ v | (z, v) <- zip starts speeds, z <= s ])
  v <- choose (0, 1.2 * zoneLimit)
  a <- oneof [choose (negate aMin, 0), choose (0, aMax)]
  vt <- oneof [pure 0, choose (0, maximum speeds)]
  pure (pb, St v a s, Term len vt)
  where
    insertSorted x xs = let (l, r) = span (< x) xs in l ++ x : r

spec :: Spec
spec = describe "the oracle's fast test and the jerk margins" $ do
  it "quickNeed accepts only states whose braking, run step by step, keeps every rule (rising and falling accelerations)" $
    withMaxSuccess 3000 $ forAllBlind genCase $ \(pb, st, term) ->
      let e = seedEnv pb term False
          accepted = quickNeed e st
      in classify (stA st < 0) "falling" $ classify accepted "accepted" $
           counterexample (show (pb, stV st, stA st, stS st, tP term, tV term)) $
             not accepted || either (const False) (const True) (brakeSimulate e st)

  it "quickNeed accepts some falling states far from every lower limit (the test is not vacuous)" $
    let pb = Problem
          { pbLength = 100, pbZoneStarts = U.fromList [0, 80], pbZoneSpeeds = U.fromList [10, 3]
          , pbAMin = -1.5, pbAMax = 1, pbJMin = -1, pbJMax = 0.3
          , pbV0 = 0, pbA0 = 0, pbVEnd = 0, pbAEnd = 0, pbDt = 1e-3, pbDv = 1e-9
          , pbMaxIter = 100, pbBudget = 10, pbTol = 1e-2, pbAlgorithm = Band, pbSeedSearch = False }
        e = seedEnv pb (Term 100 0) False
    in do
      quickNeed e (St 5 (-0.5) 10) `shouldBe` True
      -- 5 m/s with the deceleration at 1.2 m/s² and a weak 0.3 m/s³ to end it: the ramp back
      -- alone sheds 2.4 m/s; 3 m/s left at 80 m needs some 18 m, not 1
      quickNeed e (St 5 (-1.2) 79) `shouldBe` False

  it "the margins grow, start at 1e-8 or the velocity's rounding in jerk, and stay within a quarter of the range" $
    forAllBlind genCase $ \(pb, _, _) ->
      let ms = jerkPlanMargins pb
      in counterexample (show ms) $
           not (null ms) && head ms == jerkPlanMargin pb && jerkPlanMargin pb >= 1e-8
             && and (zipWith (<) ms (drop 1 ms)) && all (<= 0.25) ms
