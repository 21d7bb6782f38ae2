{-# LANGUAGE OverloadedStrings #-}
-- | Robot selection through the daemon's handler ('VProf.Service.answer' and 'serveSelect'): a
-- task built as a client would (meshes inline, one in millimetres with a scale and a pose, a base
-- pose, a tool with its capsule, a payload, targets from random joint vectors that are known to
-- be clear), encoded and decoded, answered, and checked
--
-- * against the core's selection of the same task, in process (ranking, counts, every target's
--   joints, clearance, manipulability and failure, cycle time, score);
-- * apart from the solver: every reported solution reproduces its target by the oracle's forward
--   kinematics, lies within the joint limits, and has the reported clearance by the brute-force
--   distance oracle over every triangle (at least the task's clearance);
-- * a robot rated below the payload is rejected without IK, a target beyond reach fails with the
--   REACH code;
--
-- and bad requests get INVALID_ARGUMENT with every problem, each naming its proto field.
module VProf.Service.SelectSpec (spec) where

import Control.Monad (forM, forM_, when)
import Data.List (sort)
import Data.Maybe (fromMaybe, isJust)
import Data.ProtocolBuffers (getField, putField)
import qualified Data.Text as T
import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck (Gen, choose, vectorOf)
import Test.QuickCheck.Gen (unGen)
import Test.QuickCheck.Random (mkQCGen)

import Support.DistanceOracle (Pt, oMesh)
import Support.Envelope (viaEnvelope)
import Support.RobotOracle (oracleClearance, oracleTool, poseGap)
import VProf.Geometry.Bvh (Bvh, buildBvh)
import VProf.Geometry.Mesh (ScenePart (..), composeScene, fromTriangles)
import VProf.Kinematics
import VProf.Kinematics.Collision
import VProf.Kinematics.Library (lookupRobot)
import VProf.Select.Selection
import VProf.Select.Task
import VProf.Service.Select (serveSelect)
import VProf.Wire.Envelope
import VProf.Wire.Kinematics (poseToMsg)
import VProf.Wire.Messages

------------------------------------------------------------------------------ the cell

-- | A floor plate 0.15 m under the base (metres, no pose) and a box (given in millimetres, placed
-- by its pose): 0.3 m × 0.3 m × 0.2 m, its centre 0.45 m in front of the base, 0.1 m to the side.
floorMsg :: MeshMsg
floorMsg = MeshMsg (putField [-2, -2, -0.15, 2, -2, -0.15, 2, 2, -0.15, -2, 2, -0.15]) (putField [0, 1, 2, 0, 2, 3])
                   (putField Nothing) (putField Nothing)

boxVertices :: [Double]   -- mm, centred on the origin
boxVertices = concat [ [x, y, z] | x <- [-150, 150], y <- [-150, 150], z <- [-100, 100] ]

boxTriangles :: [(Int, Int, Int)]   -- vertex i = 4·ix + 2·iy + iz
boxTriangles = [ (0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1), (2, 3, 7), (2, 7, 6)
               , (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3) ]

boxPose :: Tf
boxPose = fromQuat (V3 0.45 0.1 0.0) (Quat (cos 0.2) 0 0 (sin 0.2))

boxMsg :: MeshMsg
boxMsg = MeshMsg (putField boxVertices) (putField (concat [ map fromIntegral [a, b, c] | (a, b, c) <- boxTriangles ]))
                 (putField (Just 0.001)) (putField (Just (poseToMsg boxPose)))

-- | The same cell through the core's scene composition (what the handler must build).
cellBvh :: Bvh
cellBvh = buildBvh (composeScene [ScenePart floorMesh 1 identity, ScenePart boxMesh 0.001 boxPose])
  where
    floorMesh = fromTriangles [ (V3 (-2) (-2) (-0.15), V3 2 (-2) (-0.15), V3 2 2 (-0.15))
                              , (V3 (-2) (-2) (-0.15), V3 2 2 (-0.15), V3 (-2) 2 (-0.15)) ]
    boxMesh = fromTriangles [ (vert a, vert b, vert c) | (a, b, c) <- boxTriangles ]
    vert i = let [x, y, z] = take 3 (drop (3 * i) boxVertices) in V3 x y z

-- | The cell's triangles in the world, computed here for the oracle (mm to m, rotated about z and
-- moved by hand).
oracleTriangles :: [(Pt, Pt, Pt)]
oracleTriangles =
  [ ((-2, -2, -0.15), (2, -2, -0.15), (2, 2, -0.15)), ((-2, -2, -0.15), (2, 2, -0.15), (-2, 2, -0.15)) ]
  ++ [ (w a, w b, w c) | (a, b, c) <- boxTriangles ]
  where
    w i = let [x, y, z] = map (/ 1000) (take 3 (drop (3 * i) boxVertices))
              c = cos 0.4; s = sin 0.4
          in (0.45 + c * x - s * y, 0.1 + s * x + c * y, z)

------------------------------------------------------------------------------ the task

baseTf, toolTf :: Tf
baseTf = fromQuat (V3 0.05 (-0.1) 0) (Quat (cos (pi / 12)) 0 0 (sin (pi / 12)))
toolTf = fromQuat (V3 0 0 0.04) (Quat 1 0 0 0)

toolCapsule :: Capsule
toolCapsule = Capsule (V3 0 0 (-0.04)) (V3 0 0 0) 0.015

clearanceM, payloadKg :: Double
clearanceM = 0.01
payloadKg = 4

library :: String -> Robot
library n = either error id (lookupRobot n)

-- | The collision model of a robot placed in the task (the tool capsule included).
modelOf :: Task -> Robot -> CollisionModel
modelOf task r = collisionModel defaultCollisionOptions { coTool = taskToolCapsule task, coSceneIgnore = taskIgnoreBodies task }
                                (placeRobot task r)

genQ :: Robot -> Gen (U.Vector Double)
genQ r = U.fromList <$> mapM (\j -> let Limits lo hi = jointLimits j in choose (max lo (-pi), min hi pi)) (robotJoints r)

-- | n targets of the robot placed in the task: the tool poses of random joint vectors within the
-- limits whose clearance to the cell is at least 2 cm and which do not collide with themselves.
feasible :: Int -> Int -> Task -> Robot -> [Tf]
feasible seed n task r =
  let placed = placeRobot task r
      cm = modelOf task r
      ch = compile placed
      draws = unGen (vectorOf (200 * n) (genQ r)) (mkQCGen seed) 30
  in take n [ forward ch q | q <- draws, robotClearanceAtLeast cm cellBvh q 0.02, not (selfCollides cm 0 q) ]

-- | The pose a client sends, as the handler reads it back.
viaWire :: Tf -> Tf
viaWire t = let p = poseToMsg t in fromQuat (V3 (g poseX p) (g poseY p) (g poseZ p)) (Quat (g poseQw p) (g poseQx p) (g poseQy p) (g poseQz p))
  where g f = orDefault . getField . f

baseTask :: Task
baseTask = Task
  { taskEnvironment = [], taskBase = viaWire baseTf, taskTool = viaWire toolTf, taskToolCapsule = Just toolCapsule
  , taskPayload = payloadKg, taskClearance = clearanceM, taskIgnoreBodies = [], taskTargets = []
  , taskPath = False, taskPathStep = defaultPathStep }

-- | Two targets from each of the UR5 and the IRB 140, and one 3 m away.
targetPoses :: [Tf]
targetPoses = feasible 5 2 baseTask (library "ur5") ++ feasible 6 2 baseTask (library "abb-irb140")
              ++ [fromQuat (V3 3 0 0.5) (Quat 0 1 0 0)]

robotsAsked :: [String]
robotsAsked = ["ur5", "ABB IRB 140", "franka-panda"]

named :: String -> RobotMsg
named n = RobotMsg (putField (Just (T.pack n))) (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing)

selectReq :: Bool -> SelectRequestMsg
selectReq path = SelectRequestMsg
  { slqRequestId = putField (Just 31)
  , slqEnvironment = putField [floorMsg, boxMsg]
  , slqBase = putField (Just (poseToMsg baseTf))
  , slqTool = putField (Just (poseToMsg toolTf))
  , slqToolCapsule = putField (Just (CapsuleMsg (putField Nothing) (putField Nothing) (putField (Just (-0.04)))
                                                (putField Nothing) (putField Nothing) (putField Nothing) (putField (Just 0.015))))
  , slqPayload = putField (Just payloadKg)
  , slqClearance = putField (Just clearanceM)
  , slqTargets = putField (map poseToMsg targetPoses)
  , slqPath = putField (if path then Just True else Nothing)
  , slqPathStep = putField (if path then Just 0.02 else Nothing)
  , slqRobots = putField (map named robotsAsked)
  , slqIgnoreBodies = putField []
  }

-- | The core's selection of the task the request describes.
coreSelection :: Bool -> [RobotResult]
coreSelection path =
  let task = baseTask { taskTargets = [ Target ("targets[" ++ show i ++ "]") (viaWire p) | (i, p) <- zip [0 :: Int ..] targetPoses ]
                      , taskPath = path, taskPathStep = if path then 0.02 else defaultPathStep }
  in selectRobots defaultSelectOptions task cellBvh [ (k, library k) | k <- ["ur5", "abb-irb140", "franka-panda"] ]

------------------------------------------------------------------------------ reading responses


envelope :: SelectRequestMsg -> RequestMsg
envelope s = RequestMsg (putField (Just 77)) (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing)
                        (putField Nothing) (putField (Just s)) (putField Nothing)

txt :: Maybe T.Text -> String
txt = maybe "" T.unpack

dbl :: Maybe Double -> Double
dbl = fromMaybe 0

-- | The response's robot, field by field, against the core's.
agrees :: RobotResult -> SelectRobotResultMsg -> Expectation
agrees core msg = do
  txt (getField (srRobot msg)) `shouldBe` rrKey core
  txt (getField (srRejected msg)) `shouldBe` fromMaybe "" (rrRejected core)
  (getField (srReached msg), getField (srTotal msg)) `shouldBe` (nonDefault (fromIntegral (rrReached core)), nonDefault (fromIntegral (rrTotal core)))
  fromMaybe False (getField (srComplete msg)) `shouldBe` robotComplete core
  dbl (getField (srScore msg)) `shouldBe` rrScore core
  dbl (getField (srCycleTime msg)) `shouldBe` fromMaybe 0 (rrCycleTime core)
  txt (getField (srCycleTimeNote msg)) `shouldBe` fromMaybe "" (rrCycleNote core)
  (dbl (getField (srMinClearance msg)), txt (getField (srMinClearanceBody msg))) `shouldBe` maybe (0, "") id (rrMinClearance core)
  dbl (getField (srMinManipulability msg)) `shouldBe` fromMaybe 0 (rrMinManipulability core)
  let ts = getField (srTargets msg)
  length ts `shouldBe` length (rrTargets core)
  forM_ (zip ts (rrTargets core)) $ \(t, c) -> do
    txt (getField (stLabel t)) `shouldBe` trLabel c
    getField (stJoints t) `shouldBe` maybe [] U.toList (trJoints c)
    dbl (getField (stClearance t)) `shouldBe` fromMaybe 0 (trClearance c)
    txt (getField (stClearanceBody t)) `shouldBe` fromMaybe "" (trClearanceBody c)
    dbl (getField (stManipulability t)) `shouldBe` fromMaybe 0 (trManipulability c)
    when (isJust (trFailure c)) $ txt (getField (stFailure t)) `shouldBe` fromMaybe "" (trFailure c)
  [ (getField (ssFrom s), getField (ssTo s), txt (getField (ssFailure s))) | s <- getField (srSegments msg) ]
    `shouldBe` [ (nonDefault (fromIntegral (sgFrom s)), nonDefault (fromIntegral (sgTo s)), fromMaybe "" (sgFailure s)) | s <- rrSegments core ]

errorOf :: Maybe ErrorMsg -> (ErrorCodeEnum, String, String)
errorOf Nothing = (ErrUnspecified, "", "")
errorOf (Just e) = (getEnum (getField (errCode e)), txt (getField (errField e)), txt (getField (errMessage e)))

spec :: Spec
spec = do
  describe "selection through the daemon" $ do
    it "has feasible targets to work with (two from each arm)" $
      length targetPoses `shouldBe` 5

    it "answers a select Request in the envelope as the core selects the same task (every field)" $ do
      rsp <- viaEnvelope (envelope (selectReq False))
      responseKind rsp `shouldBe` "select"
      getField (rspRequestId rsp) `shouldBe` Just 77
      let Just sel = getField (rspSelect rsp)
          robots = getField (slrRobots sel)
          core = coreSelection False
      errorOf (getField (slrError sel)) `shouldBe` (ErrUnspecified, "", "")
      getField (slrRequestId sel) `shouldBe` Just 77
      map (txt . getField . srRobot) robots `shouldBe` map rrKey core
      map (getField . srRank) robots `shouldBe` map Just [1 .. fromIntegral (length core)]
      forM_ (zip core robots) (uncurry agrees)

    it "a path task: the segments and the targets as the core follows them" $ do
      rsp <- serveSelect (selectReq True)
      let robots = getField (slrRobots rsp)
          core = coreSelection True
      errorOf (getField (slrError rsp)) `shouldBe` (ErrUnspecified, "", "")
      map (txt . getField . srRobot) robots `shouldBe` map rrKey core
      forM_ (zip core robots) (uncurry agrees)
      -- a target whose segment is not followed is not reached, with the PATH code when solved
      forM_ robots $ \r -> forM_ (getField (srTargets r)) $ \t ->
        when (getEnum (getField (stFailureCode t)) == SelectFailurePath) $ do
          getField (stReached t) `shouldBe` Nothing
          txt (getField (stFailure t)) `shouldContain` "segment"

    it "every reported solution reproduces its target by FK, lies within the limits, and has the reported clearance by the brute-force oracle" $ do
      rsp <- serveSelect (selectReq False)
      let task = baseTask
      solved <- fmap concat $ forM (getField (slrRobots rsp)) $ \r -> do
        let robot = library (txt (getField (srRobot r)))
            placed = placeRobot task robot
            cm = modelOf task robot
        fmap concat $ forM (zip (getField (srTargets r)) targetPoses) $ \(t, target) -> case getField (stJoints t) of
          [] -> pure []
          qs -> do
            getField (stReached t) `shouldBe` Just True
            poseGap (oracleTool placed qs) (mat target) `shouldSatisfy` (< 1e-6)
            forM_ (zip (robotJoints robot) qs) $ \(j, x) -> do
              let Limits lo hi = jointLimits j
              (x >= lo - 1e-9 && x <= hi + 1e-9) `shouldBe` True
            let oc = oracleClearance cm (oMesh oracleTriangles) qs
            oc `shouldSatisfy` (>= clearanceM - 1e-9)
            abs (dbl (getField (stClearance t)) - oc) `shouldSatisfy` (< 1e-6)
            pure [()]
      -- the UR5 and the IRB 140 each reach at least their own two targets
      length solved `shouldSatisfy` (>= 4)

    it "rejects the Panda (3 kg) by the 4 kg payload without IK; the target 3 m away fails with REACH" $ do
      rsp <- serveSelect (selectReq False)
      let robots = getField (slrRobots rsp)
          byKey k = head [ r | r <- robots, txt (getField (srRobot r)) == k ]
          panda = byKey "franka-panda"
      txt (getField (srRejected panda)) `shouldContain` "payload"
      txt (getField (srRejected panda)) `shouldContain` "3.0 kg"
      getField (srTargets panda) `shouldBe` []
      getField (srRank panda) `shouldBe` Just 3
      forM_ ["ur5", "abb-irb140"] $ \k -> do
        let far = last (getField (srTargets (byKey k)))
        getEnum (getField (stFailureCode far)) `shouldBe` SelectFailureReach
        txt (getField (stFailure far)) `shouldContain` "beyond reach"
        getField (stJoints far) `shouldBe` []
        getField (srComplete (byKey k)) `shouldBe` Nothing
        getField (srDof (byKey k)) `shouldBe` Just 6

    it "a task every robot can do: complete, a cycle time, ranked by score" $ do
      let ur5Targets = take 2 targetPoses
      rsp <- serveSelect (selectReq False) { slqTargets = putField (map poseToMsg ur5Targets), slqRobots = putField [named "ur5"] }
      let [r] = getField (slrRobots rsp)
      getField (srComplete r) `shouldBe` Just True
      getField (srReached r) `shouldBe` Just 2
      dbl (getField (srCycleTime r)) `shouldSatisfy` (> 0)
      -- alone, it is the fastest and the most dexterous: s = 0.6 + 0.3 min(c, 5 cm)/5 cm + 0.1
      -- (docs/select.md), score = 100 (2 + 0.9 s)/(2 + 0.9)
      let c = dbl (getField (srMinClearance r))
          sc = 0.6 + 0.3 * min c 0.05 / 0.05 + 0.1
      c `shouldSatisfy` (>= clearanceM)
      abs (dbl (getField (srScore r)) - 100 * (2 + 0.9 * sc) / 2.9) `shouldSatisfy` (< 1e-9)
      all ((== Nothing) . getField . stFailureCode) (getField (srTargets r)) `shouldBe` True

  describe "bad requests: INVALID_ARGUMENT, every problem, each naming its field" $ do
    let good = selectReq False
        errs r = do
          rsp <- serveSelect r
          getField (slrRobots rsp) `shouldBe` []
          pure (errorOf (getField (slrError rsp)), map (errorOf . Just) (getField (slrErrors rsp)))
        fieldsOf = map (\(_, f, _) -> f)
    it "no targets, a negative clearance, NaN in a pose, a bad mesh index, an unknown robot, a negative payload: all at once" $ do
      let badBox = boxMsg { meshTriangles = putField (0 : 1 : 8 : drop 3 (getField (meshTriangles boxMsg))) }
          badBase = (poseToMsg baseTf) { poseY = putField (Just (0 / 0)) }
      ((code, first, msg), all') <- errs good
        { slqTargets = putField [], slqClearance = putField (Just (-0.01)), slqBase = putField (Just badBase)
        , slqEnvironment = putField [floorMsg, badBox], slqRobots = putField [named "ur5", named "ur55"]
        , slqPayload = putField (Just (-1)) }
      code `shouldBe` ErrInvalidArgument
      first `shouldBe` "environment[1].triangles[2]"
      sort (fieldsOf all') `shouldBe` sort ["environment[1].triangles[2]", "base.y", "payload", "clearance", "targets", "robots[1].name"]
      all (\(c, _, _) -> c == ErrInvalidArgument) all' `shouldBe` True
      msg `shouldContain` "payload = -1.0 kg"
      msg `shouldContain` "clearance = -0.01 m"
      msg `shouldContain` "\"ur55\""
      msg `shouldContain` "8"
    it "a NaN in a target, by index" $ do
      let bad = (poseToMsg (head targetPoses)) { poseQx = putField (Just (0 / 0)) }
      (_, all') <- errs good { slqTargets = putField (map poseToMsg (take 1 targetPoses) ++ [bad]) }
      fieldsOf all' `shouldBe` ["targets[1].qx"]
    it "a target quaternion that is not of unit norm, a zero capsule radius, a negative path step, body 0" $ do
      let t = (poseToMsg (head targetPoses)) { poseQw = putField (Just 3) }
      (_, all') <- errs good
        { slqTargets = putField [t]
        , slqToolCapsule = putField (Just (CapsuleMsg (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing)
                                                      (putField Nothing) (putField (Just 0.1)) (putField Nothing)))
        , slqPathStep = putField (Just (-0.005)), slqIgnoreBodies = putField [0] }
      sort (fieldsOf all') `shouldBe` sort ["targets[0]", "tool_capsule.radius", "path_step", "ignore_bodies"]
    it "an inline robot file that does not parse names robots[i].robot_file" $ do
      let broken = (named "") { robName = putField Nothing, robRobotFile = putField (Just "name: [unclosed") }
      (_, all') <- errs good { slqRobots = putField [named "ur5", broken] }
      fieldsOf all' `shouldBe` ["robots[1].robot_file"]
  where
    mat t = let rows = toRows t in [take 4 rows, take 4 (drop 4 rows), take 4 (drop 8 rows), [0, 0, 0, 1]]
