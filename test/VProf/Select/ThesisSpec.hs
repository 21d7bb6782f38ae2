-- | The thesis experiment at CI size (bench/SelectBench.hs runs it at 200): targets in the real
-- work cell (../shared/data/cell/cell.obj), each the tool pose of a random joint vector within the
-- limits whose clearance is at least 1 cm and which does not collide with itself, so each is
-- known to be feasible; for the UR5, the ABB IRB 140 and the Franka Panda, selection must reach
-- every one, and every returned solution is checked apart from the solver: the oracle's forward
-- kinematics reproduces the target, the joints lie within the limits, and the brute-force oracle
-- over every triangle finds the clearance at least the task's.
module VProf.Select.ThesisSpec (spec, feasibleTargets) where

import Control.Monad (forM_, when)
import qualified Data.Vector.Unboxed as U
import System.FilePath ((</>))
import Test.Hspec
import Test.QuickCheck (Gen, choose, vectorOf)
import Test.QuickCheck.Gen (unGen)
import Test.QuickCheck.Random (mkQCGen)

import Support.Arbitrary (shared)
import Support.DistanceOracle (Pt, oMesh)
import Support.RobotOracle
import VProf.Geometry.Bvh
import VProf.Geometry.Format.Obj
import VProf.Geometry.Mesh (Mesh, triangles)
import VProf.Kinematics.Collision
import VProf.Kinematics.Forward (forward)
import VProf.Kinematics.Library
import VProf.Kinematics.Model
import VProf.Kinematics.Transform
import VProf.Select.Selection
import VProf.Select.Task

-- | n feasible targets for the robot (with the joint vectors they came from): random joint
-- vectors within the limits, kept when the clearance is at least d and no part hits another.
feasibleTargets :: Int -> Int -> Double -> Robot -> Bvh -> [(U.Vector Double, Tf)]
feasibleTargets seed n d robot bvh =
  let cm = collisionModel defaultCollisionOptions robot
      ch = compile robot
      draws = unGen (vectorOf (40 * n) (genQ robot)) (mkQCGen seed) 30
      ok q = robotClearanceAtLeast cm bvh q d && not (selfCollides cm 0 q)
  in take n [(q, forward ch q) | q <- draws, ok q]

genQ :: Robot -> Gen (U.Vector Double)
genQ r = U.fromList <$> mapM (\j -> let Limits lo hi = jointLimits j in choose (max lo (-2 * pi), min hi (2 * pi))) (robotJoints r)

cellTask :: FilePath -> [Tf] -> Task
cellTask cell poses = Task
  { taskEnvironment = [MeshPlacement cell 1 identity], taskBase = identity, taskTool = identity
  , taskToolCapsule = Nothing, taskPayload = 0, taskClearance = 0.01, taskIgnoreBodies = []
  , taskTargets = [Target ("targets[" ++ show i ++ "]") p | (i, p) <- zip [0 :: Int ..] poses]
  , taskPath = False, taskPathStep = defaultPathStep }

pt :: V3 -> Pt
pt (V3 x y z) = (x, y, z)

spec :: Spec
spec = do
  dir <- runIO shared
  let cellPath = dir </> "data" </> "cell" </> "cell.obj"
  cell <- runIO (readObj cellPath)
  let mesh = either error id cell :: Mesh
      bvh = buildBvh mesh
      tris = oMesh [(pt a, pt b, pt c) | (a, b, c) <- triangles mesh]
      size = 20
  describe "the thesis experiment in cell.obj (20 feasible targets a robot)" $
    forM_ ["ur5", "abb-irb140", "franka-panda"] $ \name -> do
      let robot = either error id (lookupRobot name)
          targets = feasibleTargets 14 size 0.01 robot bvh
          task = cellTask cellPath (map snd targets)
          result = evaluateRobot defaultSelectOptions task bvh name robot
          cm = collisionModel defaultCollisionOptions robot
      it (name ++ ": every target reached, every solution checked by the oracles (FK, limits, clearance over every triangle)") $ do
        length targets `shouldBe` size
        forM_ (rrTargets result) $ \t -> when (trFailure t /= Nothing) $
          expectationFailure (trLabel t ++ ": " ++ show (trFailure t))
        rrReached result `shouldBe` size
        forM_ (zip (rrTargets result) targets) $ \(t, (_, target)) -> case trJoints t of
          Nothing -> expectationFailure (trLabel t ++ " has no solution")
          Just q -> do
            let qs = U.toList q
            poseGap (oracleTool robot qs) (matFromTf target) `shouldSatisfy` (< 1e-6)
            forM_ (zip (robotJoints robot) qs) $ \(j, x) -> do
              let Limits lo hi = jointLimits j
              (x >= lo - 1e-9 && x <= hi + 1e-9) `shouldBe` True
            let oc = oracleClearance cm tris qs
            oc `shouldSatisfy` (>= 0.01 - 1e-9)
            -- the reported clearance is the oracle's
            fmap (\c -> abs (c - oc)) (trClearance t) `shouldSatisfy` maybe False (< 1e-6)
            selfCollides cm 0 q `shouldBe` False
  where
    matFromTf t = let rows = toRows t in take 4 ([take 4 rows, take 4 (drop 4 rows), take 4 (drop 8 rows)] ++ [[0, 0, 0, 1]])
