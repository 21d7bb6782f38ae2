-- | The landing pass's probe schedule: on long brakings at a fine time step the pass that
-- probes now and then lands as the pass that probes at every step does, legal and at most a
-- hair longer, and the seed built on it is legal whenever the every-step pass is. The
-- landing planned a little below the jerk limit (the seed's fallback when rounding puts the
-- full-jerk landing beyond it) is as legal and at most a sample longer. At a fine time step
-- with fast zones, where the rounding of the velocities alone puts a full-jerk ramp beyond
-- the checker's slack, the seed is still legal, landed or met. With a weak jerk against a
-- strong acceleration, where the pass takes runs at the highest acceleration without asking
-- the oracle at every step, the same holds.
module VProf.Profile.Generate.Seed.GreedySpec (spec) where

import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import Support.Routes (Ranges (..), genRestRoute, restRoute, violations)
import Support.Wide (logUniform)
import VProf.Profile.Generate.Seed (seed)
import VProf.Profile.Generate.Seed.Brake (St (..), Term (..), jerkPlanMargin, policyWith)
import VProf.Profile.Generate.Seed.Greedy (forward)
import VProf.Profile.Legality (Rule (..), Violation (..))
import VProf.Profile.Problem (Algorithm (..), Problem (..))

-- | A route from rest to rest of one to four zones whose brakings span some 600 to 2,000
-- steps: the time step is the braking time from the highest limit over that many steps.
genLongBraking :: Gen Problem
genLongBraking = genRestRoute 4 (0.3, 5) (5, 200) (0.2, 3) (0.1, 5) brakingStep 1e-3

-- | A time step for a route: its braking from the highest limit over 600 to 2,000 steps.
brakingStep :: Problem -> Gen Double
brakingStep pb = do
  steps <- choose (600, 2000 :: Double)
  let vTop = U.maximum (pbZoneSpeeds pb)
      aMin = negate (pbAMin pb)
      tBrake = vTop / aMin + aMin / negate (pbJMin pb) + aMin / pbJMax pb
  pure (tBrake / steps)

-- | Weak jerk against a strong acceleration over up to eight zones: bringing a rising
-- acceleration down takes thousands of steps, and the pass takes runs at the highest
-- acceleration without asking the oracle at every step.
genWeakJerk :: Gen Problem
genWeakJerk = genRestRoute 8 (0.2, 3) (2, 60) (0.5, 3) (0.05, 0.4) brakingStep 1e-3

-- | The landing pass's velocities (v_0 first), probing on the schedule or at every step.
landingPass :: Bool -> Problem -> Maybe (U.Vector Double)
landingPass scheduled = landingPassWith scheduled 0

-- | The same, planning the ramps with this share of the jerk limit left out.
landingPassWith :: Bool -> Double -> Problem -> Maybe (U.Vector Double)
landingPassWith scheduled margin pb = case policyWith margin pb (Term (pbLength pb) 0) st0 of
  Left _ -> Nothing
  Right e -> Just (U.fromList (0 : map stV (forward scheduled e (pbTol pb / 2) 4000000 st0)))
  where st0 = St 0 0 0

-- | Route-abcd (examples/route-abcd.json: 50 m, 4 / 2 / 5 m/s from 0 / 25 / 30 m, ±1 m/s²,
-- ±0.5 m/s³) at a 1 ms step.
routeAbcd1ms :: Problem
routeAbcd1ms = Problem
  { pbLength = 50, pbZoneStarts = U.fromList [0, 25, 30], pbZoneSpeeds = U.fromList [4, 2, 5]
  , pbAMin = -1, pbAMax = 1, pbJMin = -0.5, pbJMax = 0.5
  , pbV0 = 0, pbA0 = 0, pbVEnd = 0, pbAEnd = 0, pbDt = 1e-3, pbDv = 1e-9
  , pbMaxIter = 100, pbBudget = 30, pbTol = 1e-2, pbAlgorithm = Band, pbSeedSearch = False }

-- | Fast zones at a fine step: a route from rest to rest of one to three zones at 4 to 30
-- m/s, 10 to 60 m long, at a 0.25 to 1 ms step.
genFineFast :: Gen Problem
genFineFast = genRestRoute 3 (4, 30) (10, 60) (0.5, 4) (0.5, 8) (const (logUniform 2.5e-4 1e-3)) 1e-2

-- | The first 100 m of kitti-00-first-2km (10 / 6.5 / 3 m/s from 0 / 60 / 80 m, -1.5 to
-- 1 m/s², ±1 m/s³) at a 1 ms step.
kittiFirst100m1ms :: Problem
kittiFirst100m1ms = restRoute 100 [10, 6.5, 3] [0.6, 0.8] (Ranges 1.5 1 1 1) 1e-3 1e-2

-- | A moving end at a 0.2 ms step: 21.7 m at up to 2.6 m/s from rest to 1.08 m/s, a 0.36 m/s²
-- deceleration ended by a 0.33 m/s³ jerk (a braking of some 30,000 steps from either end).
movingEnd02ms :: Problem
movingEnd02ms = Problem
  { pbLength = 21.663841454587345, pbZoneStarts = U.fromList [0], pbZoneSpeeds = U.fromList [2.6033857184411544]
  , pbAMin = -0.35884101889369846, pbAMax = 0.7159546673499497, pbJMin = -2.633391250585501, pbJMax = 0.332523413480545
  , pbV0 = 0, pbA0 = 0, pbVEnd = 1.0765896382762787, pbAEnd = 0, pbDt = 2e-4, pbDv = 1e-9
  , pbMaxIter = 100, pbBudget = 30, pbTol = 1e-2, pbAlgorithm = Band, pbSeedSearch = False }

-- | The seed of a problem (its start and end at rest or at zero acceleration) is legal.
seedIsLegal :: Problem -> Expectation
seedIsLegal pb = case seed pb of
  Right v -> violations pb v `shouldBe` []
  Left f -> expectationFailure (show f)

spec :: Spec
spec = describe "the landing pass's probe schedule (long brakings at a fine time step)" $ do
  it "kitti-00-first-2km's first 100 m at 1 ms: the seed is legal (full-jerk ramps at 8 m/s broke the jerk limit by 1.03e-9 m/s³ at 926 samples, by rounding)" $
    seedIsLegal kittiFirst100m1ms

  it "fast zones at a 0.25 to 1 ms step: the seed is legal" $
    withMaxSuccess 6 $ forAll genFineFast $ \pb ->
      case seed pb of
        Right v -> counterexample (show pb) $ counterexample (show (take 3 (violations pb v))) (null (violations pb v))
        Left f -> counterexample (show pb ++ "\n" ++ show f) False

  it "a moving end at 0.2 ms with a 6 s braking at either end: the two-sided meet's seed is legal" $
    seedIsLegal movingEnd02ms

  it "route-abcd at 1 ms: the seed is legal (the landing at the full jerk ends 8e-8 m/s³ beyond it by rounding)" $
    seedIsLegal routeAbcd1ms

  it "planned a little below the jerk limit, the landing is legal whenever the full-jerk one is, and at most a sample longer" $
    withMaxSuccess 25 $ checkCoverage $ forAll genLongBraking $ \pb ->
      case (landingPass True pb, landingPassWith True (jerkPlanMargin pb) pb) of
        (Just full, Just marg) ->
          tabulate "the full-jerk landing" [if null (violations pb full) then "legal" else "breaks a rule"] $
          cover 50 (null (violations pb full)) "the full-jerk landing legal (the legality claim checked)" $
          counterexample (show pb) $
            counterexample ("samples: full jerk " ++ show (U.length full) ++ ", with the margin " ++ show (U.length marg)) $
              U.length marg <= U.length full + 1
              .&&. (if null (violations pb full) then counterexample (show (take 3 (violations pb marg))) (null (violations pb marg)) else property True)
        _ -> property Discard

  it "lands within 1 % of the every-step pass's samples, and the seed is legal whenever the every-step pass is" $
    withMaxSuccess 25 $ checkCoverage $ forAll genLongBraking closeToEveryStep

  it "with a weak jerk (runs at the highest acceleration) too: within 1 % of the every-step pass, and legal whenever it is" $
    withMaxSuccess 25 $ checkCoverage $ forAll genWeakJerk closeToEveryStep

-- | The scheduled landing pass lands within 1 % (and two samples) of the every-step pass's
-- samples, breaks no rule but the jerk rule's rounding where the every-step pass breaks
-- none, and the seed is legal whenever the every-step pass is.
closeToEveryStep :: Problem -> Property
closeToEveryStep pb = case (landingPass False pb, landingPass True pb) of
  (Just full, Just sched) ->
    let legalFull = null (violations pb full)
        broken = [ x | x@(Violation r _ _ _) <- violations pb sched, r /= JerkRule ]
    in tabulate "the every-step pass" [if legalFull then "legal" else "breaks a rule"] $
       cover 50 legalFull "the every-step pass legal (the legality claims checked)" $
       counterexample (show pb) $
         counterexample ("samples: every step " ++ show (U.length full) ++ ", scheduled " ++ show (U.length sched)) $
           fromIntegral (U.length sched) <= 1.01 * fromIntegral (U.length full) + (2 :: Double)
           .&&. (if not legalFull then property True
                 else counterexample ("the scheduled pass breaks " ++ show (take 3 broken)) (null broken)
                      .&&. case seed pb of
                             Right v -> counterexample (show (take 3 (violations pb v))) (null (violations pb v))
                             Left f -> counterexample (show f) False)
  _ -> property Discard
