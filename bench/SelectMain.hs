{-# OPTIONS_GHC -fno-full-laziness #-}
{-# LANGUAGE OverloadedStrings #-}
-- | The driver of @bench/compare-select@ (benchmark @vprof-select-compare@):
--
-- * @--thesis N SEED OUT.json [robot …]@: the thesis experiment in cell.obj — per robot (default
--   the UR5, the IRB 140 and the Panda) N targets, each the tool pose of a random joint vector
--   within the limits (from SEED) whose clearance is at least 1 cm and that does not collide with
--   itself; each target solved on its own by selection's collision-aware IK (a one-target task,
--   no seed), timed; every solution checked by forward kinematics, the joint limits and a brute
--   force over every triangle (no BVH); OUT gets the figures and the targets (for the peers);
-- * @--check IN.json OUT.json@: the same checks of given joint vectors (a peer's solutions);
-- * @--task N SEED ROBOT OUT.yaml@: a task file in the cell with N such targets of ROBOT.
--
-- The cell is found as $VPROF_SHARED/data/cell/cell.obj or ../shared/data/cell/cell.obj.
module Main (main) where

import Control.Exception (evaluate)
import Control.Monad (forM)
import qualified Data.Aeson as A
import qualified Data.Aeson.Types as A (parseMaybe)
import Data.Aeson ((.:), (.=))
import qualified Data.ByteString.Lazy as BL
import Data.List (sort)
import qualified Data.Vector.Unboxed as U
import GHC.Clock (getMonotonicTimeNSec)
import System.Directory (makeAbsolute)
import System.Environment (getArgs, lookupEnv)
import System.Exit (exitFailure)
import System.FilePath ((</>))
import System.IO (hPutStrLn, stderr)
import Text.Printf (printf)

import VProf.Geometry.Bvh (Bvh, buildBvh)
import VProf.Geometry.Distance (segmentTriangle, Closest (..))
import VProf.Geometry.Format.Obj (readObj)
import VProf.Geometry.Mesh (Mesh, triangles)
import VProf.Kinematics
import VProf.Kinematics.Collision
import VProf.Kinematics.Ik.Numeric (SplitMix (..), nextDouble)
import VProf.Kinematics.Library
import VProf.Select.CycleTime (cycleTime, jointRates)
import VProf.Select.Ik
import VProf.Select.Selection
import VProf.Select.Task

main :: IO ()
main = do
  args <- getArgs
  cellPath <- (\d -> maybe "../shared" id d </> "data" </> "cell" </> "cell.obj") <$> lookupEnv "VPROF_SHARED"
  mesh <- readObj cellPath >>= either (\e -> hPutStrLn stderr e >> exitFailure) pure
  let bvh = buildBvh mesh
  case args of
    ("--thesis" : n : seed : out : robots) ->
      thesis cellPath mesh bvh (read n) (read seed) out (if null robots then ["ur5", "abb-irb140", "franka-panda"] else robots)
    ["--check", inp, out] -> checkMode mesh inp out
    ["--pieces", key] -> pieces cellPath bvh key
    ["--task", n, seed, key, out] -> do
      let robot = libRobot key
          ts = feasible (read seed) (read n) robot bvh
      absCell <- makeAbsolute cellPath
      writeFile out (taskYaml absCell (map snd ts))
    _ -> hPutStrLn stderr "usage: vprof-select-compare --thesis N SEED OUT.json [robot ...] | --check IN.json OUT.json | --task N SEED ROBOT OUT.yaml" >> exitFailure

libRobot :: String -> Robot
libRobot k = either error id (lookupRobot k)

-- | Random joint vectors within the limits (clamped to ±2π), kept when clear by 1 cm and free of
-- self-collision: (q, its tool pose).
feasible :: Int -> Int -> Robot -> Bvh -> [(U.Vector Double, Tf)]
feasible seed n robot bvh = take n [(q, forward ch q) | q <- draws (SplitMix (fromIntegral seed)), ok q]
  where
    cm = collisionModel defaultCollisionOptions robot
    ch = compile robot
    ok q = robotClearanceAtLeast cm bvh q 0.01 && not (selfCollides cm 0 q)
    lims = [(max lo (-2 * pi), min hi (2 * pi)) | j <- robotJoints robot, let Limits lo hi = jointLimits j]
    draws g = let (q, g') = drawQ g lims [] in U.fromList q : draws g'
    drawQ g [] acc = (reverse acc, g)
    drawQ g ((lo, hi) : rest) acc = let (u, g') = nextDouble g in drawQ g' rest (lo + u * (hi - lo) : acc)

-- | Everything a target result reports (its fields are lazy): joints, clearance, manipulability.
forceAll :: RobotResult -> Double
forceAll r = fromIntegral (rrReached r)
  + sum [ maybe 0 U.sum (trJoints tr) + maybe 0 id (trClearance tr) + maybe 0 id (trManipulability tr)
          + maybe 0 (fromIntegral . length) (trFailure tr) + maybe 0 (fromIntegral . length) (trClearanceBody tr)
        | tr <- rrTargets r ]

oneTask :: FilePath -> Tf -> Task
oneTask cell p = Task
  { taskEnvironment = [MeshPlacement cell 1 identity], taskBase = identity, taskTool = identity
  , taskToolCapsule = Nothing, taskPayload = 0, taskClearance = 0.01, taskIgnoreBodies = []
  , taskTargets = [Target "target" p], taskPath = False, taskPathStep = defaultPathStep }

-- | Brute force over every triangle with the exact segment–triangle distance (no BVH).
bruteClearance :: CollisionModel -> [(V3, V3, V3)] -> U.Vector Double -> Double
bruteClearance cm tris q =
  minimum (1 / 0 : [ sqrt (clSquared (segmentTriangle a b x y z)) - r
                   | w <- robotCapsules cm q, let Capsule a b r = wcCapsule w, (x, y, z) <- tris ])

data Check = Check {ckPos :: Double, ckRot :: Double, ckLimits :: Bool, ckClearance :: Double, ckSelf :: Bool}

check :: Robot -> CollisionModel -> [(V3, V3, V3)] -> Tf -> U.Vector Double -> Check
check robot cm tris target q =
  let ch = compile robot
      (pe, re) = residual (forward ch q) target
  in Check pe re (withinLimits 1e-9 ch q) (bruteClearance cm tris q) (selfCollides cm 0 q)

violates :: Check -> Bool
violates c = ckPos c > 1e-6 || ckRot c > 1e-6 || not (ckLimits c) || ckClearance c < 0.01 - 1e-9 || ckSelf c

thesis :: FilePath -> Mesh -> Bvh -> Int -> Int -> FilePath -> [String] -> IO ()
thesis cell mesh bvh n seed out keys = do
  let tris = triangles mesh
  rows <- forM keys $ \key -> do
    let robot = libRobot key
        cm = collisionModel defaultCollisionOptions robot
        ts = feasible seed n robot bvh
    _ <- evaluate (sum [U.sum q | (q, _) <- ts])
    -- a warm-up target
    _ <- evaluate (rrReached (evaluateRobot defaultSelectOptions (oneTask cell (snd (head ts))) bvh key robot))
    -- all targets in one task, each solved on its own (no seed): the mean per target
    let batch = (oneTask cell identity) {taskTargets = [Target ("targets[" ++ show i ++ "]") p | (i, (_, p)) <- zip [0 :: Int ..] ts]}
    t0 <- getMonotonicTimeNSec
    let all' = evaluateRobot defaultSelectOptions {soSeeded = False} batch bvh key robot
    _ <- evaluate (forceAll all')
    t1 <- getMonotonicTimeNSec
    -- the cycle time through the targets (the jerk-limited generator), timed apart
    c0 <- getMonotonicTimeNSec
    cyc <- evaluate (either (const 0) id (cycleTime (jointRates robot) [q | tr <- rrTargets all', Just q <- [trJoints tr]]))
    c1 <- getMonotonicTimeNSec
    let cycleMs = fromIntegral (c1 - c0) / 1e6 :: Double
        -- (the batch's own cycle time is lazy and not forced above: the batch time is the IK's)
        batchMean = fromIntegral (t1 - t0) / 1e6 / fromIntegral (length ts) :: Double
        moveMean = cycleMs / fromIntegral (max 1 (length ts - 1))
    printf "%-14s cycle time through the %d targets %.1f s, the generator %.3f ms a move\n" key (length ts) cyc moveMean
    -- each target as a one-target task (its own setup: chain, solver, capsules): the spread
    singles <- forM ts $ \(_, p) -> do
      s0 <- getMonotonicTimeNSec
      let res = evaluateRobot defaultSelectOptions (oneTask cell p) bvh key robot
      _ <- evaluate (forceAll res)
      s1 <- getMonotonicTimeNSec
      pure (fromIntegral (s1 - s0) / 1e6 :: Double)
    let results = zip (rrTargets all') singles
    let solved = [(q, p) | ((tr, _), (_, p)) <- zip results ts, Just q <- [trJoints tr]]
        checks = [check robot cm tris p q | (q, p) <- solved]
        nviol = length (filter violates checks)
        times = map snd results
        sorted = sort times
        mean = batchMean
        median = sorted !! (length sorted `div` 2)
        minClr = minimum (1 / 0 : map ckClearance checks)
    printf "%-14s solved %d/%d  violations %d  min clearance (brute force) %.2f mm  mean %.3f ms (all in one task)  one-target tasks: median %.3f ms  max %.3f ms\n"
      key (length solved) (length ts) nviol (1000 * minClr) mean median (last sorted)
    pure $ A.object
      [ "robot" .= key, "targets" .= length ts, "solved" .= length solved, "violations" .= nviol
      , "clearance_or_limit_violations" .= length [c | c <- checks, ckClearance c < 0.01 - 1e-9 || not (ckLimits c)]
      , "pose_errors" .= length [c | c <- checks, ckPos c > 1e-6 || ckRot c > 1e-6]
      , "self_collisions" .= length (filter ckSelf checks)
      , "min_clearance_m" .= minClr, "mean_ms" .= mean, "move_ms" .= moveMean, "median_ms" .= median, "max_ms" .= last sorted
      , "failures" .= [f | (tr, _) <- results, Just f <- [trFailure tr]]
      , "model" .= modelJson robot cm
      , "cases" .= [ A.object ["q" .= U.toList q, "pose" .= toRows p] | (q, p) <- ts ] ]
  BL.writeFile out (A.encode (A.object ["robots" .= rows]))

-- | Where a target's time goes (mean µs over 50 targets, each piece repeated 20 times).
pieces :: FilePath -> Bvh -> String -> IO ()
pieces cell bvh key = do
  let robot = libRobot key
      kin = kinematicsFor robot
      cm = collisionModel defaultCollisionOptions robot
      ts = feasible 7 50 robot bvh
      sopts = defaultSelectIkOptions
  _ <- evaluate (sum [U.sum q | (q, _) <- ts])
  let timeIt name f = do
        t0 <- getMonotonicTimeNSec
        mapM_ (\(q, p) -> mapM_ (\k -> evaluate (f k q p)) [1 .. 20 :: Int]) ts
        t1 <- getMonotonicTimeNSec
        printf "%-40s %10.1f us\n" (name :: String) (fromIntegral (t1 - t0) / 1e3 / fromIntegral (20 * length ts) :: Double)
  timeIt "solveIk (all solutions)" (\k _ p -> either (const 0) length (solveIk defaultIkOptions {ikAllSolutions = True, ikTolPosition = 1e-6 + fromIntegral k * 1e-12} kin p Nothing))
  timeIt "robotClearance (exact, BVH)" (\k q _ -> maybe 0 (round . (* 1e6) . clrDistance) (robotClearance cm bvh (U.map (+ fromIntegral k * 1e-12) q)))
  timeIt "robotClearanceAtLeast 1 cm" (\k q _ -> if robotClearanceAtLeast cm bvh (U.map (+ fromIntegral k * 1e-12) q) 0.01 then 1 else 0 :: Int)
  timeIt "selfClearance" (\k q _ -> maybe 0 (round . (* 1e6) . scDistance) (selfClearance cm (U.map (+ fromIntegral k * 1e-12) q)))
  timeIt "solveCollisionFree" (\k _ p -> either (const 0) length (solveCollisionFree sopts {siClearance = 0.01 + fromIntegral k * 1e-12} kin cm bvh p Nothing))
  timeIt "evaluateRobot (one target)" (\k _ p -> rrReached (evaluateRobot defaultSelectOptions (oneTask cell p) {taskClearance = 0.01 + fromIntegral k * 1e-12} bvh key robot))

-- | The DH table, limits, base, tool and collision parts, for a peer to build the same robot.
modelJson :: Robot -> CollisionModel -> A.Value
modelJson robot cm = A.object
  [ "links" .= [ case (linkGeometry l, linkDrive l) of
                   (DhStandard th d a al, Drive off ts) -> A.object ["convention" .= ("standard" :: String), "theta" .= th, "d" .= d, "a" .= a, "alpha" .= al, "offset" .= off, "terms" .= ts, "moving" .= (linkJointKind l /= Nothing)]
                   (DhModified al a th d, Drive off ts) -> A.object ["convention" .= ("modified" :: String), "theta" .= th, "d" .= d, "a" .= a, "alpha" .= al, "offset" .= off, "terms" .= ts, "moving" .= (linkJointKind l /= Nothing)]
                   _ -> A.object ["convention" .= ("other" :: String)]
               | l <- robotLinks robot ]
  , "lower" .= [limMin (jointLimits j) | j <- robotJoints robot]
  , "upper" .= [limMax (jointLimits j) | j <- robotJoints robot]
  , "base" .= toRows (robotBase robot), "tool" .= toRows (robotTool robot)
  , "parts" .= [ case p of
                   Attached b (Capsule a e r) -> A.object ["body" .= b, "a" .= v a, "b" .= v e, "r" .= r]
                   Bone b r -> A.object ["bone" .= b, "r" .= r]
               | p <- foldr (:) [] (cmParts cm) ] ]
  where
    v (V3 x y z) = [x, y, z]

-- | IN: {"robots": [{"robot": key, "cases": [{"pose": [12 numbers], "q": [...] or null}]}]}.
checkMode :: Mesh -> FilePath -> FilePath -> IO ()
checkMode mesh inp out = do
  v <- A.decode <$> BL.readFile inp
  let tris = triangles mesh
      robots = maybe [] id (v >>= A.parseMaybe (A.withObject "in" (.: "robots"))) :: [A.Object]
  rows <- forM robots $ \ro -> do
    let key = maybe "" id (A.parseMaybe (.: "robot") ro) :: String
        cases = maybe [] id (A.parseMaybe (.: "cases") ro) :: [A.Object]
        robot = libRobot key
        cm = collisionModel defaultCollisionOptions robot
        one c = case (A.parseMaybe (.: "q") c, A.parseMaybe (.: "pose") c >>= fromRows) of
          (Just (Just qs), Just p) ->
            let k = check robot cm tris p (U.fromList qs)
            in A.object [ "solved" .= True, "violation" .= violates k, "clearance_m" .= ckClearance k
                        , "position_error" .= ckPos k, "rotation_error" .= ckRot k, "within_limits" .= ckLimits k
                        , "self_collision" .= ckSelf k ]
          _ -> A.object ["solved" .= False]
    pure (A.object ["robot" .= key, "checks" .= map one cases])
  BL.writeFile out (A.encode (A.object ["robots" .= rows]))

taskYaml :: FilePath -> [Tf] -> String
taskYaml cell ps = unlines $
  [ "# " ++ show (length ps) ++ " feasible targets in the cell (written by vprof-select-compare --task)"
  , "environment:"
  , "  - {file: " ++ show cell ++ "}"
  , "payload: 0"
  , "clearance: 0.01"
  , "targets:" ]
  ++ [ "  - {position: [" ++ showList' [x, y, z] ++ "], quaternion: [" ++ showList' [w, a, b, c] ++ "]}"
     | p <- ps, let V3 x y z = translation p; Quat w a b c = normaliseQuat (toQuat p) ]
  where
    showList' = foldr1 (\s r -> s ++ ", " ++ r) . map (\d -> printf "%.12f" d)
