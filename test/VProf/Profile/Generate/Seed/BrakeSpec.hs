-- | The oracle's bounds, its fast test and the jerk margins. 'brakeBound' bounds the
-- distance and the peak velocity of the hardest stop, run step by step. 'quickNeed' accepts a state without running
-- the brake policy, from continuous-time braking distances and a margin; it must never
-- accept a state whose braking, run step by step ('brakeSimulate'), breaks a rule beyond
-- rounding, from a rising acceleration as from a falling one, on long routes and on short ones. The margins a landing is planned again with
-- grow and stay inside the jerk range, and a pass planned with one keeps the problem's rules
-- with the margin to spare.
module VProf.Profile.Generate.Seed.BrakeSpec (spec) where

import qualified Data.Vector.Unboxed as U
import GHC.Float (castDoubleToWord64)
import Test.Hspec
import Test.QuickCheck

import Support.Routes (Ranges (..), genRestRoute, restRoute)
import Support.Wide (logUniform)
import VProf.Profile.Generate.Seed.Brake
import VProf.Profile.Problem (Problem (..))

-- | A problem of one to five zones (0.2 to 30 m/s) with wide ranges, at a 0.1 to 100 ms step,
-- and a state on it: anywhere, at up to 1.2 times its zone's limit, with an acceleration
-- across the whole range (falling ones half the time), and a terminal at the route end to be
-- passed at rest or at up to the fastest limit.
genCase :: Gen (Problem, St, Term)
genCase = genCaseOn (genRestRoute 5 (0.2, 30) (1, 2000) (0.1, 5) (0.05, 20) (const (logUniform 1e-4 0.1)) 1e-2)

-- | The same on short routes, 10 µm to 1 m, where the fast test's margin shrinks with the
-- route (a millimetre on a route of a metre or more, a thousandth of a shorter one): speeds
-- of 1 mm/s to 1 m/s, steps of 1 µs to 10 ms, strong and weak jerks, an end tolerance of a
-- thousandth of the route.
genShortCase :: Gen (Problem, St, Term)
genShortCase = genCaseOn $ do
  pb <- genRestRoute 3 (1e-3, 1) (1e-5, 1) (0.01, 50) (0.1, 1e4) (const (logUniform 1e-6 1e-2)) 1e-2
  pure pb { pbTol = 1e-3 * pbLength pb }

genCaseOn :: Gen Problem -> Gen (Problem, St, Term)
genCaseOn genPb = do
  pb <- genPb
  let len = pbLength pb
      zones = zip (U.toList (pbZoneStarts pb)) (U.toList (pbZoneSpeeds pb))
  s <- choose (0, len)
  let zoneLimit = last [ v | (z, v) <- zones, z <= s ]
  v <- choose (0, 1.2 * zoneLimit)
  a <- oneof [choose (pbAMin pb, 0), choose (0, pbAMax pb)]
  vt <- oneof [pure 0, choose (0, U.maximum (pbZoneSpeeds pb))]
  pure (pb, St v a s, Term len vt)

-- | The step at which the braking stopped broke a rule only by rounding: its top velocity is
-- above the lowest limit on it (or, past the terminal, above the terminal velocity) by at most
-- 1e-12 of it, and nothing else is wrong with it. The brake policy arrives at a limit with the
-- velocity a few bits above it now and then (3.3249195721787665 at a limit of
-- 3.3249195721787186 m/s): the step-by-step oracle refuses that, the checker's slack is 1e-9.
roundingOnly :: Problem -> Term -> (St, St) -> Bool
roundingOnly pb (Term p vt) (St v _ s, St v' a' s') =
  v' >= 0 && a' >= pbAMin pb - 1e-12 && a' <= pbAMax pb + 1e-12
    && top <= lim + 1e-12 * max 1 lim
    && (s' <= p || v' <= vt + 1e-12 * max 1 vt || v' == 0 && v == 0)
  where
    top = max v v'
    zones = zip (U.toList (pbZoneStarts pb)) (U.toList (pbZoneSpeeds pb))
    lim = minimum [ l | (i, (z, l)) <- zip [0 :: Int ..] zones
                      , let next = if i + 1 < length zones then fst (zones !! (i + 1)) else 1 / 0
                      , z <= max s s', next > min s s' ]

-- | The hardest stop from a state, run step by step by the hard brake policy: its distance,
-- its highest velocity, its duration, and whether it came to rest within the steps allowed.
hardStop :: Problem -> St -> (Double, Double, Double, Bool)
hardStop pb st0 = go st0 (stV st0) (0 :: Int)
  where
    e = seedEnv pb (Term (1 / 0) (1 / 0)) True
    go st vTop n
      | atRest e st = (stS st - stS st0, vTop, fromIntegral n * pbDt pb, True)
      | n > 4000000 = (stS st - stS st0, vTop, fromIntegral n * pbDt pb, False)
      | otherwise = let st' = stepTo e st (brakeAcc e st) in go st' (max vTop (stV st')) (n + 1)

-- | 'brakeBound' with every term written out at every step (as in
-- docs/profile-generator.md): the reference for its constants computed once a braking and
-- its terms of a⁺ or a_f dropped where they are zero.
boundWrittenOut :: Problem -> St -> (Double, Double)
boundWrittenOut pb (St v a _) =
  let dt = pbDt pb
      ap = max 0 a
      af = max 0 (negate a)
      jm = abs (pbJMin pb); jp = pbJMax pb; am = abs (pbAMin pb)
      vPeak = v + ap * ap / (2 * jm) + ap * dt
      extra = 6 * dt
      full = vPeak * (ap / jm + am / jm + am / jp + extra) + vPeak * vPeak / (2 * am)
      c = 1 / jm + 1 / jp
      triangle
        | 2 * vPeak + af * af / jm <= am * am * c = vPeak * (ap / jm + af / jp + sqrt (2 * vPeak * c) + extra)
        | otherwise = 1 / 0
  in (min full triangle, vPeak)

-- | Every state 'quickNeed' accepts keeps every rule when its braking is run step by step
-- (beyond rounding), over the cases drawn.
quickNeedSound :: Gen (Problem, St, Term) -> Property
quickNeedSound gen =
  withMaxSuccess 3000 $ forAllBlind gen $ \(pb, st, term) ->
    let e = seedEnv pb term False
        accepted = quickNeed e st
    in classify (stA st < 0) "falling" $ classify accepted "accepted" $
         counterexample (show (pb, stV st, stA st, stS st, tP term, tV term)) $
           not accepted || either (roundingOnly pb term) (const True) (brakeSimulate e st)

spec :: Spec
spec = describe "the oracle's bounds, its fast test and the jerk margins" $ do
  it "brakeBound bounds the distance and the top velocity of the hardest stop, run step by step (strong jerk and weak, rising and falling accelerations); short of a_min the stop lasts at most the continuous triangle of jerk ramps and six steps" $
    withMaxSuccess 2000 $ forAllBlind genCase $ \(pb, st, _) ->
      let (d, vPeak) = brakeBound (seedEnv pb (Term (1 / 0) (1 / 0)) True) st
          (dist, vTop, dur, stopped) = hardStop pb st
          jm = negate (pbJMin pb); jp = pbJMax pb; am = negate (pbAMin pb)
          aUp = max 0 (stA st); aDown = negate (min 0 (stA st))
          c = 1 / jm + 1 / jp
          -- the velocity when a positive acceleration is down, against what a_min needs
          v1 = stV st + aUp * aUp / (2 * jm)
          short = 2 * v1 + aDown * aDown / jm <= am * am * c
          triangle = aUp / jm + aDown / jp + sqrt (2 * v1 * c) + 6 * pbDt pb
      in classify short "short of a_min (the triangle)" $ classify (stA st < 0) "falling" $
           counterexample (show (pb, stV st, stA st, (d, vPeak), (dist, vTop, dur, stopped), triangle)) $
             stopped ==> dist <= d * (1 + 1e-12) && vTop <= vPeak + 1e-12 * max 1 vPeak
                         && (not short || dur <= triangle * (1 + 1e-12))

  it "brakeBound is its formula written out, to the bit (the oracle computes its constants once a braking and leaves out the zero terms): rising, falling and zero accelerations, at rest too" $
    withMaxSuccess 5000 $ forAllBlind genCase $ \(pb, St v a s, _) -> forAll (elements [a, 0, -0.0, negate a]) $ \a' -> forAll (elements [v, 0, -0.0]) $ \v' ->
      let st = St v' a' s
          bits (x, y) = (castDoubleToWord64 x, castDoubleToWord64 y)
          got = brakeBound (seedEnv pb (Term (1 / 0) (1 / 0)) True) st
          want = boundWrittenOut pb st
      in counterexample (show (pb, v', a', got, want)) (bits got == bits want)

  it "quickNeed accepts only states whose braking, run step by step, keeps every rule (rising and falling accelerations)" $
    quickNeedSound genCase

  it "quickNeed accepts only states whose braking, run step by step, keeps every rule, on routes of 10 µm to 1 m (the margin shrinks with the route)" $
    quickNeedSound genShortCase

  it "quickNeed accepts a slow state half a millimetre before the end of a 2 mm route (a margin of a whole millimetre refused every state of the last millimetre, and each probe ran the braking step by step)" $
    let pb = restRoute 2e-3 [0.5] [] (Ranges 1 1 100 100) 1e-5 1e-6
        e = seedEnv pb (Term 2e-3 0) False
    in do
      quickNeed e (St 1e-3 0 1.5e-3) `shouldBe` True
      -- 10 cm/s needs some 5 mm to stop at 1 m/s²: not in 0.5 mm
      quickNeed e (St 0.1 0 1.5e-3) `shouldBe` False

  it "quickNeed accepts some falling states far from every lower limit (the test is not vacuous)" $
    let pb = restRoute 100 [10, 3] [0.8] (Ranges 1.5 1 1 0.3) 1e-3 1e-2
        e = seedEnv pb (Term 100 0) False
    in do
      quickNeed e (St 5 (-0.5) 10) `shouldBe` True
      -- 5 m/s with the deceleration at 1.2 m/s² and a weak 0.3 m/s³ to end it: the ramp back
      -- alone sheds 2.4 m/s; 3 m/s left at 80 m needs some 18 m, not 1
      quickNeed e (St 5 (-1.2) 79) `shouldBe` False

  it "the margins grow, start at 1e-8 or the velocity's rounding in jerk (a hundred times it where the full jerk cannot hold), and stay within a quarter of the range" $
    forAllBlind genCase $ \(pb, _, _) ->
      let ms = jerkPlanMargins pb
          m = jerkPlanMargin pb
          first | fullJerkHolds pb || 100 * m > 0.25 = m
                | otherwise = 100 * m
      in counterexample (show (ms, m, fullJerkHolds pb)) $
           not (null ms) && head ms == first && m >= 1e-8
             && and (zipWith (<) ms (drop 1 ms)) && all (<= 0.25) ms
