-- | The speed zones of a plan never exceed the limit anywhere inside them: over random step
-- limits (the zone construction alone), and over random paths of a UR5, where the joint speed
-- bound is recomputed here from the tracked joint values.
module VProf.Plan.LimitsSpec (spec) where

import qualified Data.Vector as V
import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import VProf.Kinematics.Ik (kinematicsFor)
import VProf.Kinematics.Library (lookupRobot)
import VProf.Kinematics.Model
import VProf.Plan
import VProf.Units

-- | A grid of 1–400 steps of 0.2–2 mm with limits from 1 mm/s to 2 m/s (smooth stretches,
-- dips and spikes mixed).
genSteps :: Gen StepLimits
genSteps = do
  n <- choose (1, 400)
  hs <- vectorOf n (choose (2e-4, 2e-3))
  base <- choose (0.05, 1)
  ls <- vectorOf n (frequency [(6, pure base), (3, choose (0.001, 2)), (1, choose (0.8 * base, 1.2 * base))])
  let ss = U.fromList (scanl (+) 0 hs)
  pure (StepLimits ss (U.fromList ls) (V.fromList (replicate n ByTcp)))

zonesOK :: Double -> StepLimits -> Property
zonesOK top st =
  let ss = slS st
      n = U.length (slLimit st)
      a = U.head ss; b = U.last ss
      zs = limitZones top st a b
      covering z = [ k | k <- [0 .. n - 1], ss U.! (k + 1) > lzStart z + 1e-12, ss U.! k < lzEnd z - 1e-12 ]
  in counterexample (show zs) $
       conjoin [ counterexample ("zone " ++ show z ++ " above step " ++ show k ++ " limit " ++ show (slLimit st U.! k)) $
                   lzSpeed z <= slLimit st U.! k + 1e-12
               | z <- zs, k <- covering z ]
       .&&. conjoin [ lzSpeed z > 0 && lzSpeed z <= top | z <- zs ]
       .&&. counterexample "contiguous" (and (zipWith (\x y -> lzEnd x == lzStart y) zs (drop 1 zs))
                                        && lzStart (head zs) == a && lzEnd (last zs) == b)
       .&&. counterexample "a zone shorter than the minimum" (length zs == 1 || all (\z -> lzEnd z - lzStart z >= minZoneLength - 1e-12) zs)

spec :: Spec
spec = describe "VProf.Plan.Limits" $ do
  it "zones are contiguous, positive, at most the top speed and never above any step they cover" $
    property $ forAll genSteps $ \st -> zonesOK 0.5 st
  it "rounds down to the ladder: quantiseDown top v <= v, and within one rung (5 %) of it" $
    property $ forAll (choose (1e-4, 3)) $ \v ->
      let qv = quantiseDown 1 v in qv <= min 1 v && qv >= speedLadder * min 1 v - 1e-12
  it "on random UR5 paths the zones keep every joint within its speed limit on every step" $
    property $ forAll genPath $ \wps ->
      let Right robot = lookupRobot "ur5"
          Right rt = mkRoute (map (const (Blend (0.005 *~ meter))) wps) wps
          Right tk = trackRoute defaultTrackOptions (kinematicsFor robot) rt Nothing
          rq = planRequest robot wps
          lo = limitOptionsFor rq
          pb = pathBounds (jointPath (rtStops rt) tk)
          -- a stretch acceleration the planner could choose: 0.8 of the joints' ceiling
          st = stepLimitsAt lo rt pb (0.8 * tangentialCeiling lo pb 0 (routeLength rt)) 0 (routeLength rt)
          ss = tkS tk
          n = tkDof tk
          zs = limitZones 0.5 st 0 (routeLength rt)
          vmax = map (maybe (1 / 0) id . jointMaxVelocity) (robotJoints robot)
          q k i = tkQ tk U.! (k * n + i)
          zoneAt x = head ([ z | z <- zs, lzStart z <= x, x < lzEnd z ] ++ [last zs])
      in conjoin [ counterexample ("step " ++ show k ++ " joint " ++ show i) $
                     abs (q (k + 1) i - q k i) / (ss U.! (k + 1) - ss U.! k) * lzSpeed (zoneAt (ss U.! k)) <= vm * (1 + 1e-9)
                 | k <- [0 .. U.length ss - 2], (i, vm) <- zip [0 .. n - 1] vmax ]
        .&&. zonesOK 0.5 st
  where
    genPath = do
      k <- choose (2, 5)
      pts <- vectorOf k ((,,) <$> choose (0.3, 0.5) <*> choose (-0.2, 0.2) <*> choose (0.1, 0.4))
               `suchThat` (\ps -> and (zipWith (\(a, b, c) (x, y, z) -> (a - x) ^ (2 :: Int) + (b - y) ^ (2 :: Int) + (c - z) ^ (2 :: Int) > 1e-4) ps (drop 1 ps)))
      pure [ waypoint p (0, 1, 0, 0) | p <- pts ]
