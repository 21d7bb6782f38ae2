-- | Collision benchmarks on the work cell of ../shared/data/cell (13,392 triangles) and the UR5
-- placed at its origin: OBJ parsing, the BVH build, the robot's clearance (nearest triangle over
-- six capsules) and its early-exit test at 0.05 m, the self-collision check, and collision-aware
-- IK (512 closed-form solutions, 8 distinct geometries).
module CollisionBench (collisionBenchmarks) where

import qualified Data.ByteString as BS
import qualified Data.Vector.Unboxed as U
import Criterion (Benchmark, bench, bgroup, env, nf, whnf)

import VProf.Geometry.Bvh
import VProf.Geometry.Format.Obj
import VProf.Kinematics.Collision
import VProf.Kinematics.Ik (kinematicsFor)
import VProf.Kinematics.Library
import VProf.Kinematics.Transform
import VProf.Select.Ik

cellPath :: FilePath
cellPath = "../shared/data/cell/cell.obj"

-- | Pseudo-random joint vectors in [−3, 3] rad (about half of them hit the table or the wall).
joints :: [U.Vector Double]
joints = [U.fromList [3 * sin (fromIntegral (k * j)) | j <- [1 .. 6 :: Int]] | k <- [1 .. 1000 :: Int]]

collisionBenchmarks :: [Benchmark]
collisionBenchmarks =
  [ env (BS.readFile cellPath) $ \bs ->
      env (pure (either (error . show) id (parseObj bs))) $ \mesh ->
        let bvh = buildBvh mesh
            ur5 = either error id (lookupRobot "ur5")
            cm = collisionModel defaultCollisionOptions ur5
            cm' = collisionModel defaultCollisionOptions {coSceneIgnore = [1]} ur5
            kin = kinematicsFor ur5
            opts = defaultSelectIkOptions {siClearance = 0.01}
        in bgroup "collision"
             [ bench "parse cell.obj" (whnf parseObj bs)
             , bench "build BVH of cell.obj" (whnf (bvhNodeCount . buildBvh) mesh)
             , bench "UR5 clearance x1000" (nf (map (fmap clrDistance . robotClearance cm bvh)) joints)
             , bench "UR5 clearanceAtLeast 0.05 x1000" (nf (map (\q -> robotClearanceAtLeast cm bvh q 0.05)) joints)
             , bench "UR5 self-collision x1000" (nf (map (selfCollides cm 0)) joints)
             , bench "UR5 collision-free IK above the table" $
                 nf (either (const 0) length . solveCollisionFree opts kin cm' bvh (trans 0.5 0.2 0.3 `compose` rotX pi)) Nothing
             ]
  ]
