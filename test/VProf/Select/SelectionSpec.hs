-- | Selection's invariants over random inputs: the payload filter runs before any IK, the counts
-- add up and every failure has a reason, the score puts more reached targets first and the
-- ranking is sorted; the cycle time of a joint move against the bounds of its limits; a path
-- task followed sample by sample in the work cell, and one through the table stopped at the
-- table.
module VProf.Select.SelectionSpec (spec) where

import Control.Monad (forM_)
import Control.Exception (evaluate)
import Data.List (isInfixOf, isPrefixOf, sort)
import System.Timeout (timeout)
import Data.Maybe (isJust, isNothing)
import qualified Data.Vector.Unboxed as U
import System.FilePath ((</>))
import Test.Hspec
import Test.QuickCheck

import Support.Arbitrary (shared)
import Support.Gen (genQ)
import Support.DistanceOracle (oMesh)
import Support.RobotOracle (oracleClearance, oracleTool, poseGap)
import VProf.Geometry.Mesh (triangles)
import VProf.Geometry.Bvh
import VProf.Geometry.Format.Obj
import VProf.Kinematics.Collision
import VProf.Kinematics.Forward (forward)
import VProf.Kinematics.Library
import VProf.Kinematics.Model
import VProf.Kinematics.Transform
import VProf.Select.CycleTime
import VProf.Select.Selection
import VProf.Select.Task
import VProf.Select.Format.Task (readTaskFile)

library :: [(String, Robot)]
library = [(k, r) | (k, Right r) <- libraryRobots]

task0 :: Double -> [Tf] -> Task
task0 payload poses = Task
  { taskEnvironment = [], taskBase = identity, taskTool = identity, taskToolCapsule = Nothing
  , taskPayload = payload, taskClearance = 0.01, taskIgnoreBodies = [1]
  , taskTargets = [Target ("targets[" ++ show i ++ "]") p | (i, p) <- zip [0 :: Int ..] poses]
  , taskPath = False, taskPathStep = defaultPathStep }

-- | A pose within a 1.5 m box around the base, any orientation.
genPose :: Gen Tf
genPose = do
  x <- choose (-1.5, 1.5)
  y <- choose (-1.5, 1.5)
  z <- choose (-0.5, 1.5)
  r <- choose (-pi, pi)
  p <- choose (-pi, pi)
  w <- choose (-pi, pi)
  pure (fromRpy (V3 x y z) (V3 r p w))

genResult :: Int -> Gen RobotResult
genResult total = do
  key <- elements ["a", "b", "c", "d", "e", "f"]
  rejected <- frequency [(1, Just <$> pure "payload"), (5, pure Nothing)]
  n <- choose (0, total)
  let complete = isNothing rejected && n == total
  cyc <- if complete then Just <$> choose (0.1, 30) else pure Nothing
  clr <- oneof [pure Nothing, (\c -> Just (c, "link")) <$> choose (-0.05, 0.3)]
  w <- oneof [pure Nothing, Just <$> choose (0, 0.2)]
  pure RobotResult { rrKey = key, rrName = key, rrRejected = rejected, rrTargets = [], rrSegments = []
                   , rrReached = if isJust rejected then 0 else n, rrTotal = total
                   , rrMinClearance = clr, rrMinManipulability = w, rrCycleTime = cyc
                   , rrCycleNote = Nothing, rrScore = 0 }

spec :: Spec
spec = do
  dir <- runIO shared
  cellE <- runIO (readObj (dir </> "data" </> "cell" </> "cell.obj"))
  let bvh = buildBvh (either error id cellE)
      tris = oMesh [ (pt a, pt b, pt c) | (a, b, c) <- triangles (either error id cellE) ]
      pt (V3 x y z) = (x, y, z)
      matFromTf t = let rows = toRows t in [take 4 rows, take 4 (drop 4 rows), take 4 (drop 8 rows), [0, 0, 0, 1]]
  describe "the filters and the counts (random robots, payloads and targets in the cell)" $ do
    it "a robot whose rated payload is below the task's gets no IK at all; the others are not rejected for payload" $
      withMaxSuccess 60 $ forAll (elements library) $ \(k, r) -> forAll (choose (0, 25)) $ \p ->
        forAll (resize 3 (listOf1 genPose)) $ \poses ->
          let res = evaluateRobot defaultSelectOptions (task0 p poses) bvh k r
              rated = robotPayload r
          in counterexample (show (k, rated, p, rrRejected res)) $
               case rated of
                 Just c | c < p -> isJust (rrRejected res) && null (rrTargets res) && rrReached res == 0
                                   && isNothing (rrMinClearance res) && isNothing (rrCycleTime res)
                 _ -> isNothing (rrRejected res) && length (rrTargets res) == length poses
    it "reached ≤ N; a target has joints exactly when it has no failure; the cycle time only when all are reached; every reached target's joints reach it by the independent FK, within the limits, clear of the cell by brute force over every triangle" $
      withMaxSuccess 60 $ forAll (elements library) $ \(k, r) -> forAll (resize 4 (listOf1 genPose)) $ \poses ->
        let res = evaluateRobot defaultSelectOptions (task0 0 poses) bvh k r
            cm = collisionModel defaultCollisionOptions { coSceneIgnore = [1] } r
            reached = [ (U.toList q, target) | (t, target) <- zip (rrTargets res) poses, Just q <- [trJoints t] ]
        in counterexample (show (k, map trFailure (rrTargets res))) $ conjoin
             [ property (rrReached res <= rrTotal res)
             , rrTotal res === length poses
             , rrReached res === length [t | t <- rrTargets res, isJust (trJoints t)]
             , conjoin [isJust (trJoints t) =/= isJust (trFailure t) | t <- rrTargets res]
             , isJust (rrCycleTime res) === (rrReached res == rrTotal res)
             , property (and [ maybe False (>= 0.01) (trClearance t) | t <- rrTargets res, isJust (trJoints t) ])
             , conjoin [ counterexample ("joints " ++ show qs) $
                           poseGap (oracleTool r qs) (matFromTf target) < 1e-6
                           && and [ x >= lo - 1e-9 && x <= hi + 1e-9 | (j, x) <- zip (robotJoints r) qs, let Limits lo hi = jointLimits j ]
                           && oracleClearance cm tris qs >= 0.01 - 1e-9
                       | (qs, target) <- reached ]
             ]
    it "the reach filter fails a target beyond the stretched arm without IK, naming both distances" $ do
      let ur5 = either error id (lookupRobot "ur5")
          res = evaluateRobot defaultSelectOptions (task0 0 [trans 2.5 0 0.3]) bvh "ur5" ur5
      map trFailure (rrTargets res) `shouldSatisfy` \case
        -- from the shoulder, (0, 0, 0.0892) m: the target is 2.5089 m from it
        [Just f] -> "beyond reach: 2.5089 m from the shoulder" `isInfixOf` f && "reaches at most 1.1034 m" `isInfixOf` f && "(1405.5 mm too far)" `isInfixOf` f
        _ -> False
    it "the 7-axis arms fail the far end of examples/cell-task.yaml beyond the wrist's reach, without a search (they were 'not converged' after it, 166 and 177 mm short)" $ do
      -- targets[4]: (0.95, -0.25, 0.20) m pointing down, the tool 0.12 m out of the flange
      let far = (task0 1.5 [trans 0.95 (-0.25) 0.20 `compose` rotX pi]) {taskTool = trans 0 0 0.12}
      forM_ [("kuka-lbr-iiwa14", "where the last 3 joint axes meet"), ("franka-panda", "on the last joint's axis")] $ \(k, how) -> do
        let r = either error id (lookupRobot k)
            res = evaluateRobot defaultSelectOptions far bvh k r
        map trFailureKind (rrTargets res) `shouldBe` [Just FailReach]
        map trFailure (rrTargets res) `shouldSatisfy` \case
          [Just f] -> ("beyond reach: the wrist point (" ++ how) `isInfixOf` f
          _ -> False
    it "a robot whose base column stands in the table fails every target without IK, naming the body and the point; left out, it does not" $ do
      let irb = either error id (lookupRobot "abb-irb6700-200-2.60")
          poses = [trans 1.2 0.3 1.0 `compose` rotX pi, trans 1.0 (-0.5) 1.4]
          res = evaluateRobot defaultSelectOptions (task0 0 poses) {taskIgnoreBodies = []} bvh "abb-irb6700-200-2.60" irb
          res' = evaluateRobot defaultSelectOptions (task0 0 poses) bvh "abb-irb6700-200-2.60" irb
      map trFailureKind (rrTargets res) `shouldBe` [Just FailCollision, Just FailCollision]
      map trFailure (rrTargets res) `shouldSatisfy` all (maybe False (\f -> "every configuration collides: link1 keeps the point (0.0, 0.0, 0.0) m" `isInfixOf` f))
      map trFailure (rrTargets res') `shouldSatisfy` all (maybe True (not . ("every configuration" `isInfixOf`)))
    let fixedIn r = fixedCollisions (collisionModel defaultCollisionOptions r) bvh 0.01
        withFixed = [ (k, r) | (k, r) <- library, not (null (fixedIn r)) ]
    it "the library robots with a fixed collision at the origin of cell.obj: the ABB IRB 1600 and 6700, the KUKA KR 5 and KR 6" $
      sort (map fst withFixed) `shouldBe` ["abb-irb1600-6-1.2", "abb-irb6700-200-2.60", "kuka-kr5-arc", "kuka-kr6-2"]
    it "a fixed collision is sound: no joint vector of such a robot keeps the clearance" $
      withMaxSuccess 200 $ forAll (elements withFixed) $ \(k, r) ->
        let cm = collisionModel defaultCollisionOptions r
        in forAll (genQ (compile r)) $ \q ->
             counterexample (k ++ " " ++ show (U.toList q)) (not (robotClearanceAtLeast cm bvh q 0.01))
  describe "score and ranking" $ do
    it "is sorted by score, scores lie in [0, 100], and more targets reached always scores higher" $
      property $ forAll (choose (1, 300)) $ \total -> forAll (resize 12 (listOf (genResult total))) $ \rs ->
        let ranked = scoreAndRank rs
            ss = map rrScore ranked
        in conjoin
             [ property (and (zipWith (>=) ss (drop 1 ss)))
             , property (all (\s -> s >= 0 && s <= 100) ss)
             , conjoin [ counterexample (show (rrReached a, rrScore a, rrReached b, rrScore b)) (rrScore a > rrScore b)
                       | a <- ranked, b <- ranked, isNothing (rrRejected a), isNothing (rrRejected b), rrReached a > rrReached b ]
             , length ranked === length rs
             , conjoin [ rrScore r === 0 | r <- ranked, isJust (rrRejected r) ]
             ]
  describe "the cycle time of a joint move (the jerk-limited generator)" $ do
    let ur5 = either error id (lookupRobot "ur5")
        rates = jointRates ur5
        genQ = U.fromList <$> vectorOf 6 (choose (-2 * pi, 2 * pi))
    it "is at least the time at full speed and the bang-bang time at the acceleration limit, and the same both ways" $
      withMaxSuccess 100 $ forAll genQ $ \a -> forAll genQ $ \b ->
        let d = U.map abs (U.zipWith (-) b a)
            len = U.maximum (U.zipWith (/) d (jrVelocity rates))
            acc = U.minimum (U.zipWith (\ai di -> if di > 1e-12 then ai * len / di else 1 / 0) (jrAcceleration rates) d)
        in case (moveTime rates a b, moveTime rates b a) of
             (Right t, Right t') -> counterexample (show (t, t', len, acc)) $ conjoin
               [ t >= len * (1 - 1e-3) - 1e-9
               , t >= 2 * sqrt (len * (1 - 1e-3) / acc) - 1e-9
               , abs (t - t') <= profileTimeStep + 1e-9
                 -- the trapezoid with jerk ramps, L/v + v/A + A/J (v = 1, A/J = jerkTime), plus a few steps
               , t <= 1.05 * (len + 1 / acc + jerkTime) + 4 * profileTimeStep
               ]
             other -> counterexample (show other) False
    it "is 0 for no move, and a cycle is the sum of its moves" $ do
      let a = U.fromList [0, -1, 1, 0, 1, 0]; b = U.fromList [1, -1.5, 0.5, 0, 1, 0.3]; c = U.fromList [0.2, -0.4, 1.2, 0.1, 0.5, 0]
      moveTime rates a a `shouldBe` Right 0
      let Right ab = moveTime rates a b; Right bc = moveTime rates b c
      cycleTime rates [a, b, c] `shouldBe` Right (ab + bc)
  describe "path tasks (IK continuation every 5 mm)" $ do
    let ur5 = either error id (lookupRobot "ur5")
        down x y z = trans x y z `compose` rotX pi
        pathTask poses = (task0 0 poses) {taskPath = True, taskEnvironment = [MeshPlacement "cell.obj" 1 identity]}
    it "follows straight segments above the table on one branch, every sample clear" $ do
      let poses = [down 0.5 0.2 0.35, down 0.5 (-0.2) 0.35, down 0.35 (-0.2) 0.25]
          res = evaluateRobot defaultSelectOptions (pathTask poses) bvh "ur5" ur5
          cm = collisionModel defaultCollisionOptions {coSceneIgnore = [1]} ur5
      map sgFailure (rrSegments res) `shouldBe` [Nothing, Nothing]
      map sgSamples (rrSegments res) `shouldBe` [80, 37]
      rrReached res `shouldBe` 3
      -- the solutions at the targets are the continuation's: FK reproduces each target
      sequence_ [ case trJoints t of
                    Just q -> do
                      v3Norm (v3Sub (translation (forward (compile ur5) q)) (translation p)) `shouldSatisfy` (< 1e-6)
                      robotClearanceAtLeast cm bvh q 0.01 `shouldBe` True
                    Nothing -> expectationFailure (trLabel t)
                | (t, p) <- zip (rrTargets res) poses ]
    it "a segment to a target 10^8 m away fails at its first sample out of reach (its 2e10 samples were all made first: the daemon's guard answered INTERNAL after 75 s)" $ do
      let poses = [down 0.5 0.2 0.35, down 1e8 0.2 0.35]
          res = evaluateRobot defaultSelectOptions (pathTask poses) bvh "ur5" ur5
      segmentSampleCount defaultPathStep (head poses) (poses !! 1) `shouldSatisfy` (> 10 ^ (10 :: Int))
      done <- timeout (120 * 1000000) (evaluate (length (show (rrSegments res, rrTargets res))))
      done `shouldSatisfy` isJust
      case rrSegments res of
        [sg] -> do
          sgFailure sg `shouldSatisfy` maybe False ("segment 0 -> 1 at sample " `isPrefixOf`)
          -- the UR5 reaches some 0.85 m: the walk stops within the first metre
          sgSamples sg `shouldSatisfy` (< 300)
        other -> expectationFailure (show other)
      rrReached res `shouldBe` 1
    it "a coarse path step reaches what the 5 mm step reaches (at 0.2 m and 0.5 m every move was a 'change of branch')" $ do
      Right task <- readTaskFile "examples/freiburg-task.yaml"
      let robots = [ (k, either error id (lookupRobot k)) | k <- ["ur10", "franka-panda", "abb-irb140"] ]
          reached st = [ rrReached (evaluateRobot defaultSelectOptions task {taskPathStep = st} bvh k r) | (k, r) <- robots ]
          fine = reached defaultPathStep
      head fine `shouldBe` 40
      mapM_ (\st -> reached st `shouldBe` fine) [0.1, 0.2, 0.5]
      -- where a segment does stop, the distance named is along the segment (was the sample count times the step)
      let short = task {taskPathStep = 0.5}
      sequence_ [ sgFailure sg `shouldSatisfy` maybe True (not . ("about 0.5 m along" `isInfixOf`))
                | (k, r) <- robots, sg <- rrSegments (evaluateRobot defaultSelectOptions short bvh k r) ]
    it "starts a path on a branch that can follow its first segment, with or without the cell (an elbow-down UR5 self-collided 7 cm into a 10 cm move without it)" $ do
      let tooled poses env = (pathTask poses)
            { taskTool = trans 0 0 0.12, taskToolCapsule = Just (Capsule (V3 0 0 (-0.12)) (V3 0 0 (-0.02)) 0.03)
            , taskEnvironment = if env then taskEnvironment (pathTask poses) else [] }
          placed = placeRobot (tooled [] False) ur5
          cm = collisionModel defaultCollisionOptions {coTool = Just (Capsule (V3 0 0 (-0.12)) (V3 0 0 (-0.02)) 0.03), coSceneIgnore = [1]} placed
      forM_ [(0.4, -0.2, 0.23), (0.4, -0.15, 0.23), (0.4, -0.2, 0.2)] $ \(x, y, z) -> do
        let poses = [down x y z, down (x + 0.1) y z]
        forM_ [False, True] $ \env -> do
          let res = evaluateRobot defaultSelectOptions (tooled poses env) bvh "ur5" ur5
          (env, map sgFailure (rrSegments res)) `shouldBe` (env, [Nothing])
          rrReached res `shouldBe` 2
          -- checked apart from the selection: the start is clear of itself, the end reproduces its pose
          case map trJoints (rrTargets res) of
            [Just q0, Just q1] -> do
              selfCollides cm 0 q0 `shouldBe` False
              v3Norm (v3Sub (translation (forward (compile placed) q1)) (V3 (x + 0.1) y z)) `shouldSatisfy` (< 1e-6)
            other -> expectationFailure (show other)
    it "stops a segment that dives through the table top at the table, saying where" $ do
      let poses = [down 0.5 (-0.3) 0.3, down 1.2 (-0.3) (-0.2)]
          res = evaluateRobot defaultSelectOptions (pathTask poses) bvh "ur5" ur5
      map sgFailure (rrSegments res) `shouldSatisfy` \case
        [Just f] -> "segment 0 -> 1" `isInfixOf` f && "along" `isInfixOf` f
        _ -> False
      rrReached res `shouldSatisfy` (< 2)
