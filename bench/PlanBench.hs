-- | The plan's stages on compare-plan's long smooth path (100 waypoints on a 0.45 m arc with a
-- wave in z, UR5, v3000, z10, 10 m/s², 200 m/s³, dt 4 ms, as @bench/compare-plan@ plans it):
-- the whole 'planPath', and apart its tracking in joint space ('trackRoute'), its path bounds
-- and step limits, and one profile of the generator at the rule's acceleration. Issue 15's goal
-- is 'planPath' within 50 ms for such a path.
module PlanBench (planBenchmarks) where

import Control.Exception (evaluate)
import Criterion.Main
import qualified Data.Vector.Unboxed as U

import VProf.Kinematics.Ik (Kinematics (..), kinematicsFor)
import VProf.Kinematics.Jacobian (jacobian, singularValues)
import VProf.Kinematics.Model (Chain (..))
import VProf.Kinematics.Library (lookupRobot)
import VProf.Plan
import VProf.Units

-- | compare-plan's arc-100, the tool pointing down.
arc100 :: [Waypoint]
arc100 = [ waypoint (0.45 * cos a, 0.45 * sin a, 0.25 + 0.05 * sin (3 * a)) (0, 1, 0, 0)
         | i <- [0 .. 99 :: Int], let a = -0.8 + 1.6 * fromIntegral i / 99 ]

planBenchmarks :: IO [Benchmark]
planBenchmarks = do
  robot <- either (fail . ("plan bench: " ++)) pure (lookupRobot "ur5")
  let rq = (planRequest robot arc100)
             { prSpeed = 3 *~ mps, prAcceleration = 10 *~ mps2, prJerk = 200 *~ mps3 }
      rt = either (error . show) id (mkRoute (map (const (prZone rq)) arc100) arc100)
      tracked = either (error . describeStop) id (trackRoute (prTrack rq) (kinematicsFor robot) rt Nothing)
      jp = jointPath (rtStops rt) tracked
      lo = limitOptionsFor rq
      ch = kinChain (kinematicsFor robot)
      q0 = U.slice 0 (tkDof tracked) (tkQ tracked)
  plan <- either (fail . ("plan bench: the arc did not plan: " ++) . describePlanFailure) pure (planPath rq)
  _ <- evaluate (U.sum (trQ (planTrajectory plan)))
  pure
    [ bgroup "plan-arc-100"
        [ bench "planPath" (nf (either (const 0) (U.sum . trQ . planTrajectory) . planPath) rq)
        , bench "track" (nf (\r -> either (const 0) (U.sum . tkS) (trackRoute (prTrack r) (kinematicsFor robot) rt Nothing)) rq)
        , bench "jacobian+svd-x100" (nf (\q -> sum [ minimum (singularValues (chainDof ch) (snd (jacobian ch (U.map (+ 1e-3 * fromIntegral k) q)))) | k <- [1 .. 100 :: Int] ]) q0)
        , bench "path-bounds+step-limits" (nf (\j -> let pb = pathBounds j in U.sum (slLimit (stepLimitsAt lo rt pb 0 0 (routeLength rt)))) jp)
        ]
    ]
