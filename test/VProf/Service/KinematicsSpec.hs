{-# LANGUAGE OverloadedStrings #-}
-- | FK and IK through the daemon's handler ('VProf.Service.answer'): requests built as a client
-- would, encoded and decoded, answered, the responses checked against the core (FK) and by
-- forward kinematics (every IK solution reproduces its target); bad requests get
-- INVALID_ARGUMENT naming the proto field; inline robot files and the shared URDFs work.
module VProf.Service.KinematicsSpec (spec) where

import Control.Monad (forM_, unless)
import Data.Maybe (fromMaybe)
import Data.ProtocolBuffers (getField, putField)
import qualified Data.Text as T
import qualified Data.Text.IO as TIO
import qualified Data.Vector.Unboxed as U
import System.FilePath ((</>))
import Test.Hspec
import Test.QuickCheck hiding (classify)
import Test.QuickCheck.Monadic (assert, monadicIO, monitor, run)

import Support.Envelope (viaEnvelope)
import Support.Gen (genQ)
import Support.Reference (sharedDir)
import VProf.Kinematics
import VProf.Kinematics.Format.Urdf (UrdfOptions (..), defaultUrdfOptions, readUrdfFile)
import VProf.Kinematics.Library (lookupRobot)
import VProf.Service.Kinematics (serveFk, serveIk)
import VProf.Wire.Envelope
import VProf.Wire.Kinematics (poseToMsg)
import VProf.Wire.Messages

------------------------------------------------------------------------------ building requests

named :: String -> RobotMsg
named n = noRobot { robName = putField (Just (T.pack n)) }

noRobot :: RobotMsg
noRobot = RobotMsg (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing)

fkReq :: RobotMsg -> [Double] -> FkRequestMsg
fkReq r q = FkRequestMsg (putField (Just 11)) (putField (Just r)) (putField q) (putField (Just True))

-- | All solutions for the closed forms (cheap); the numerical solver's nearest one otherwise.
ikReq :: RobotMsg -> Tf -> IkRequestMsg
ikReq r t = let allOf = maybe False (`elem` ["ur5", "abb-irb140", "dobot-magician-lite"]) (getField (robName r)) in IkRequestMsg
  { ikqRequestId = putField (Just 12), ikqRobot = putField (Just r), ikqTarget = putField (Just (poseToMsg t))
  , ikqSeed = putField [], ikqAllSolutions = putField (Just allOf), ikqPositionTolerance = putField Nothing
  , ikqRotationTolerance = putField Nothing, ikqTimeBudget = putField Nothing, ikqEnvironment = putField []
  , ikqClearance = putField Nothing, ikqIgnoreBodies = putField [] }


envelope :: Maybe FkRequestMsg -> Maybe IkRequestMsg -> RequestMsg
envelope f k = RequestMsg (putField (Just 99)) (putField Nothing) (putField Nothing) (putField Nothing) (putField f) (putField k) (putField Nothing)
                        (putField Nothing)

------------------------------------------------------------------------------ reading responses

errorOf :: Maybe ErrorMsg -> (ErrorCodeEnum, T.Text, T.Text)
errorOf Nothing = (ErrUnspecified, "", "")
errorOf (Just e) = (getEnum (getField (errCode e)), orDefault (getField (errField e)), orDefault (getField (errMessage e)))

poseTf :: PoseMsg -> Tf
poseTf p = fromQuat (V3 x y z) (Quat w a b c)
  where
    [x, y, z, w, a, b, c] = map orDefault [ getField (poseX p), getField (poseY p), getField (poseZ p)
                                          , getField (poseQw p), getField (poseQx p), getField (poseQy p)
                                          , getField (poseQz p) ] :: [Double]

tfDiff :: Tf -> Tf -> Double
tfDiff a b = maximum (zipWith (\x y -> abs (x - y)) (toRows a) (toRows b))

library :: String -> Robot
library n = either error id (lookupRobot n)

-- | Every solution of the response: within the limits, and its FK (computed here) reproduces the
-- target to the tolerance; the residual it reports is the true one.
checkSolutions :: Robot -> Tf -> IkResponseMsg -> Property
checkSolutions r target rsp = let (ok, why) = solutionsOk r target rsp in counterexample why ok

expectSolutions :: Robot -> Tf -> IkResponseMsg -> Expectation
expectSolutions r target rsp = let (ok, why) = solutionsOk r target rsp in unless ok (expectationFailure why)

solutionsOk :: Robot -> Tf -> IkResponseMsg -> (Bool, String)
solutionsOk r target rsp =
  let ch = compile r
      sols = getField (ikrSolutions rsp)
      ok s = let q = U.fromList (getField (iksJoints s))
                 (ep, er) = residual (forward ch q) target
                 within = and [ x >= limMin (jointLimits j) - 1e-9 && x <= limMax (jointLimits j) + 1e-9
                              | (j, x) <- zip (robotJoints r) (U.toList q) ]
             in U.length q == dof r && ep <= 1e-6 && er <= 1e-6 && within
                && abs (ep - orDefault (getField (iksPositionError s))) <= 1e-12
  in (not (null sols) && all ok sols, show (errorOf (getField (ikrError rsp)), map (getField . iksJoints) sols))

spec :: Spec
spec = do
  describe "FK through the daemon" $ do
    forM_ ["ur5", "franka-panda", "dobot-magician-lite", "kuka-lbr-iiwa14", "stanford"] $ \name ->
      it (name ++ ": tool pose, link frames, Jacobian and manipulability agree with the core for random q within limits") $ do
        let r = library name
            ch = compile r
        property $ forAll (genQ ch) $ \q -> monadicIO $ do
          rsp <- run (serveFk (fkReq (named name) (U.toList q)))
          let Just tool = getField (fksTool rsp)
              (_, jac) = jacobian ch q
              n = dof r
              frames = map poseTf (getField (fksLinkFrames rsp))
          monitor (counterexample (show rsp))
          assert (getField (fksError rsp) == Nothing)
          assert (tfDiff (poseTf tool) (forward ch q) < 1e-12)
          assert (length frames == length (linkFrames ch q))
          assert (and (zipWith (\a b -> tfDiff a b < 1e-12) frames (linkFrames ch q)))
          assert (getField (fksJacobian rsp) == concat (jacobianRows n jac))
          assert (fromMaybe 0 (getField (fksManipulability rsp)) == manipulability n jac)
          assert (getField (fksDof rsp) == Just (fromIntegral n))
          assert (getField (fksRequestId rsp) == Just 11)
    it "answers an FK Request in the envelope with an fk Response echoing the request_id" $ do
      rsp <- viaEnvelope (envelope (Just (fkReq (named "UR5") [0, -1, 1, 0, 1, 0])) Nothing)
      responseKind rsp `shouldBe` "fk"
      getField (rspRequestId rsp) `shouldBe` Just 99
      let Just fk = getField (rspFk rsp)
      getField (fksRequestId fk) `shouldBe` Just 99
      fmap poseTf (getField (fksTool fk)) `shouldSatisfy`
        maybe False (\t -> tfDiff t (forward (compile (library "ur5")) (U.fromList [0, -1, 1, 0, 1, 0])) < 1e-12)

  describe "IK through the daemon: every solution reproduces its target by FK" $ do
    forM_ ["ur5", "abb-irb140", "dobot-magician-lite", "franka-panda", "kuka-lbr-iiwa14"] $ \name ->
      it name $ do
        let r = library name
            ch = compile r
        property $ withMaxSuccess 40 $ forAll (genQ ch) $ \q -> monadicIO $ do
          let target = forward ch q
          rsp <- run (serveIk (ikReq (named name) target))
          monitor (counterexample (show (U.toList q)))
          assert (getField (ikrRequestId rsp) == Just 12)
          pure (checkSolutions r target rsp)
    it "returns the nearest solution only when all_solutions is false, and names the solver" $ do
      let r = library "ur5"
          ch = compile r
          q = U.fromList [0.3, -1.2, 1.1, -0.5, 1.2, 0.4]
          req = (ikReq (named "ur5") (forward ch q)) { ikqAllSolutions = putField Nothing, ikqSeed = putField (U.toList q) }
      rsp <- serveIk req
      length (getField (ikrSolutions rsp)) `shouldBe` 1
      getField (ikrSolver rsp) `shouldBe` Just "closed-form six-axis"
      let [s] = getField (ikrSolutions rsp)
      maximum (zipWith (\a b -> abs (a - b)) (getField (iksJoints s)) (U.toList q)) `shouldSatisfy` (< 1e-6)
      rspAll <- serveIk req { ikqAllSolutions = putField (Just True) }
      length (getField (ikrSolutions rspAll)) `shouldSatisfy` (> 1)
    it "answers an IK Request in the envelope with an ik Response" $ do
      let ch = compile (library "franka-panda")
          target = forward ch (U.fromList [0.1, -0.3, 0.2, -2.0, 0.1, 1.8, 0.5])
      rsp <- viaEnvelope (envelope Nothing (Just (ikReq (named "franka-panda") target)))
      responseKind rsp `shouldBe` "ik"
      let Just ik = getField (rspIk rsp)
      getField (ikrSolver ik) `shouldBe` Just "numerical"
      expectSolutions (library "franka-panda") target ik
    it "reports a target beyond reach as INFEASIBLE naming the target and the distance" $ do
      rsp <- serveIk (ikReq (named "ur5") (fromQuat (V3 3 0 0.5) (Quat 1 0 0 0)))
      let (code, field, msg) = errorOf (getField (ikrError rsp))
      (code, field) `shouldBe` (ErrInfeasible, "target")
      T.unpack msg `shouldContain` "beyond reach"
      getField (ikrSolutions rsp) `shouldBe` []
    it "reports a joint-limit failure with each miss in its joint's unit (a prismatic joint in mm, a revolute one in rad and degrees)" $ do
      -- the Stanford arm's prismatic J3 cannot retract this close to its base
      rsp <- serveIk (ikReq (named "stanford") (fromQuat (V3 0.2 0.1 0.3) (Quat 0 1 0 0)))
      let (code, field, msg) = errorOf (getField (ikrError rsp))
      (code, field) `shouldBe` (ErrInfeasible, "target")
      T.unpack msg `shouldContain` "every solution breaks a joint limit: J3 below its minimum by "
      T.unpack msg `shouldContain` " mm"
      T.unpack msg `shouldContain` "J5 above its maximum by "
      T.unpack msg `shouldContain` "°)"
      getField (ikrSolutions rsp) `shouldBe` []

  describe "bad requests: INVALID_ARGUMENT naming the field" $ do
    let fkErr req = errorOf . getField . fksError <$> serveFk req
        ikErr req = errorOf . getField . ikrError <$> serveIk req
        target = fromQuat (V3 0.4 0.1 0.3) (Quat 0 1 0 0)
        goodPose = poseToMsg target
    it "an unknown robot name" $ do
      (code, field, msg) <- fkErr (fkReq (named "ur55") [0, 0, 0, 0, 0, 0])
      (code, field) `shouldBe` (ErrInvalidArgument, "robot.name")
      T.unpack msg `shouldContain` "ur55"
    it "a missing robot, an empty one, and two models at once" $ do
      (c1, f1, _) <- fkErr (fkReq noRobot [0]) { fkqRobot = putField Nothing }
      (c2, f2, _) <- fkErr (fkReq noRobot [0])
      (c3, f3, m3) <- fkErr (fkReq (named "ur5") { robUrdf = putField (Just "<robot/>") } [0])
      [(c1, f1), (c2, f2), (c3, f3)] `shouldBe` replicate 3 (ErrInvalidArgument, "robot")
      T.unpack m3 `shouldContain` "name, urdf"
    it "a wrong joint count, with the robot's count" $ do
      (code, field, msg) <- fkErr (fkReq (named "ur5") [0, 0, 0])
      (code, field) `shouldBe` (ErrInvalidArgument, "joints")
      T.unpack msg `shouldContain` "3 values"
      T.unpack msg `shouldContain` "6 joints"
    it "a NaN joint value, by index and unit" $ do
      (code, field, msg) <- fkErr (fkReq (named "ur5") [0, 0, 0 / 0, 0, 0, 0])
      (code, field) `shouldBe` (ErrInvalidArgument, "joints[2]")
      T.unpack msg `shouldContain` "NaN rad"
    it "a NaN target coordinate" $ do
      (code, field, _) <- ikErr (ikReq (named "ur5") target) { ikqTarget = putField (Just goodPose { poseY = putField (Just (0 / 0)) }) }
      (code, field) `shouldBe` (ErrInvalidArgument, "target.y")
    it "a quaternion that is not of unit norm, with its norm" $ do
      (code, field, msg) <- ikErr (ikReq (named "ur5") target) { ikqTarget = putField (Just goodPose { poseQw = putField (Just 0.5) }) }
      (code, field) `shouldBe` (ErrInvalidArgument, "target")
      T.unpack msg `shouldContain` "norm 1.118"
    it "a missing target, a seed of the wrong length, a negative tolerance, a NaN budget" $ do
      (c1, f1, _) <- ikErr (ikReq (named "ur5") target) { ikqTarget = putField Nothing }
      (c2, f2, _) <- ikErr (ikReq (named "ur5") target) { ikqSeed = putField [0, 0] }
      (c3, f3, m3) <- ikErr (ikReq (named "ur5") target) { ikqPositionTolerance = putField (Just (-1e-3)) }
      (c4, f4, _) <- ikErr (ikReq (named "ur5") target) { ikqTimeBudget = putField (Just (0 / 0)) }
      [(c1, f1), (c2, f2), (c3, f3), (c4, f4)] `shouldBe`
        [(ErrInvalidArgument, "target"), (ErrInvalidArgument, "seed"), (ErrInvalidArgument, "position_tolerance"), (ErrInvalidArgument, "time_budget")]
      T.unpack m3 `shouldContain` "-0.001 m"
    it "a malformed inline robot file and URDF" $ do
      (c1, f1, _) <- fkErr (fkReq noRobot { robRobotFile = putField (Just "name: [unclosed") } [0])
      (c2, f2, m2) <- fkErr (fkReq noRobot { robUrdf = putField (Just "<robot name=\"x\"><joint name=\"j\" type=\"hinge\"/></robot>") } [0])
      [(c1, f1), (c2, f2)] `shouldBe` [(ErrInvalidArgument, "robot.robot_file"), (ErrInvalidArgument, "robot.urdf")]
      T.unpack m2 `shouldContain` "j"
    it "bad environment meshes: vertex count, triangle index, NaN vertex, negative clearance" $ do
      let mesh vs ts = MeshMsg (putField vs) (putField ts) (putField Nothing) (putField Nothing)
          withEnv ms c = (ikReq (named "ur5") target) { ikqEnvironment = putField ms, ikqClearance = putField c }
      (_, f1, _) <- ikErr (withEnv [mesh [0, 0, 0, 1, 0] [0, 1, 2]] Nothing)
      (_, f2, m2) <- ikErr (withEnv [mesh [0, 0, 0, 1, 0, 0, 0, 1, 0] [0, 1, 7]] Nothing)
      (_, f3, _) <- ikErr (withEnv [mesh [0, 0, 0, 1, 0 / 0, 0, 0, 1, 0] [0, 1, 2]] Nothing)
      (_, f4, _) <- ikErr (withEnv [mesh [0, 0, 0, 1, 0, 0, 0, 1, 0] [0, 1, 2]] (Just (-0.01)))
      [f1, f2, f3, f4] `shouldBe` ["environment[0].vertices", "environment[0].triangles[2]", "environment[0].vertices[4]", "clearance"]
      T.unpack m2 `shouldContain` "3 vertices"
    it "a scale or vertex beyond 1e9 m, a target beyond 1e9 m and a body the robot does not have (1e308 scale made every solution 'collide'; body 99 was ignored)" $ do
      let mesh vs sc = MeshMsg (putField vs) (putField [0, 1, 2]) (putField (Just sc)) (putField Nothing)
          withEnv ms = (ikReq (named "ur5") target) { ikqEnvironment = putField ms }
      (c1, f1, _) <- ikErr (withEnv [mesh [2, 2, -0.5, 3, 2, -0.5, 2, 3, -0.5] 1e308])
      (c2, f2, _) <- ikErr (withEnv [mesh [2, 2, -0.5, 3e12, 2, -0.5, 2, 3, -0.5] 0])
      (c3, f3, _) <- ikErr (ikReq (named "ur5") target) { ikqTarget = putField (Just goodPose { poseZ = putField (Just 1e308) }) }
      (c4, f4, m4) <- ikErr (withEnv [mesh [2, 2, -0.5, 3, 2, -0.5, 2, 3, -0.5] 1]) { ikqIgnoreBodies = putField [99] }
      [(c1, f1), (c2, f2), (c3, f3), (c4, f4)] `shouldBe`
        [ (ErrInvalidArgument, "environment[0].scale"), (ErrInvalidArgument, "environment[0].vertices[3]")
        , (ErrInvalidArgument, "target.z"), (ErrInvalidArgument, "ignore_bodies[0]") ]
      T.unpack m4 `shouldContain` "1 to 6"
    it "FK joints outside their limits, by index, in rad and degrees (the contract asks them within; 7 was computed as 7 rad)" $ do
      (code, field, msg) <- fkErr (fkReq (named "ur5") [0, 0, 0, 0, 0, 7])
      (code, field) `shouldBe` (ErrInvalidArgument, "joints[5]")
      T.unpack msg `shouldContain` "7.0 rad"
      T.unpack msg `shouldContain` "401.07 in [-360.0, 360.0] degrees"
      -- at a limit exactly is within it
      (c0, _, _) <- fkErr (fkReq (named "ur5") [0, 0, 0, 0, 0, 2 * pi])
      c0 `shouldBe` ErrUnspecified
    it "clearance and ignore_bodies without an environment, base_link and tip_link without a URDF (each was dropped without a word)" $ do
      (c1, f1, m1) <- ikErr (ikReq (named "ur5") target) { ikqClearance = putField (Just 0.01) }
      (c2, f2, _) <- ikErr (ikReq (named "ur5") target) { ikqIgnoreBodies = putField [1] }
      (c3, f3, m3) <- fkErr (fkReq (named "ur5") { robBaseLink = putField (Just "base_link") } [0, 0, 0, 0, 0, 0])
      (c4, f4, _) <- fkErr (fkReq noRobot { robRobotFile = putField (Just "name: x"), robTipLink = putField (Just "tool0") } [0])
      [(c1, f1), (c2, f2), (c3, f3), (c4, f4)] `shouldBe`
        [ (ErrInvalidArgument, "clearance"), (ErrInvalidArgument, "ignore_bodies")
        , (ErrInvalidArgument, "robot.base_link"), (ErrInvalidArgument, "robot.tip_link") ]
      T.unpack m1 `shouldContain` "without an environment"
      T.unpack m3 `shouldContain` "URDF only"
    it "a request with no body and one with two bodies" $ do
      let both = envelope (Just (fkReq (named "ur5") [0, 0, 0, 0, 0, 0])) (Just (ikReq (named "ur5") target))
      classify both `shouldSatisfy` either (T.isInfixOf "fk, ik" . orDefault . getField . errMessage) (const False)

  describe "inline robots" $ do
    yaml <- runIO (TIO.readFile "src/robots/ur10.yaml")
    it "a robot file's YAML text gives the library robot's FK" $ do
      let r = library "ur10"
          ch = compile r
      property $ forAll (genQ ch) $ \q -> monadicIO $ do
        rsp <- run (serveFk (fkReq noRobot { robRobotFile = putField (Just yaml) } (U.toList q)))
        monitor (counterexample (show (getField (fksError rsp), fmap (\t -> tfDiff (poseTf t) (forward ch q)) (getField (fksTool rsp)))))
        assert (maybe False (\t -> tfDiff (poseTf t) (forward ch q) < 1e-12) (getField (fksTool rsp)))
    it "JSON robot file text works as YAML does: a planar two-link arm stretched along x" $ do
      let json = T.concat [ "{\"name\": \"two-link\", \"units\": {\"length\": \"m\", \"angle\": \"deg\"}, "
                          , "\"convention\": \"standard-dh\", \"joints\": [{\"name\": \"j1\", \"limits\": [-180, 180]}, "
                          , "{\"name\": \"j2\", \"limits\": [-180, 180]}], \"links\": ["
                          , "{\"dh\": {\"theta\": 0, \"d\": 0, \"a\": 0.5, \"alpha\": 0}}, "
                          , "{\"dh\": {\"theta\": 0, \"d\": 0, \"a\": 0.5, \"alpha\": 0}}]}" ]
      rsp <- serveFk (fkReq noRobot { robRobotFile = putField (Just json) } [0, pi / 2])
      errorOf (getField (fksError rsp)) `shouldBe` (ErrUnspecified, "", "")
      let Just t = getField (fksTool rsp)
          V3 x y z = translation (poseTf t)
      maximum (map abs [x - 0.5, y - 0.5, z]) `shouldSatisfy` (< 1e-12)
    dir <- runIO sharedDir
    forM_ [("ur5_robot.urdf", "tool0"), ("panda.urdf", "panda_link8"), ("kuka_iiwa_model.urdf", "lbr_iiwa_link_7")] $ \(file, tip) ->
      describe file $ do
       text <- runIO (TIO.readFile (dir </> "data" </> "urdf" </> file))
       er <- runIO (readUrdfFile defaultUrdfOptions { urdfTip = Just tip } (dir </> "data" </> "urdf" </> file))
       it ("the URDF text (tip " ++ tip ++ "): FK as the file reader's robot, IK solutions reproduce the target") $ do
        let r = either (error . unlines) id er
            ch = compile r
            robot = noRobot { robUrdf = putField (Just text), robTipLink = putField (Just (T.pack tip)) }
        property $ withMaxSuccess 20 $ forAll (genQ ch) $ \q -> monadicIO $ do
          fk <- run (serveFk (fkReq robot (U.toList q)))
          let Just t = getField (fksTool fk)
          assert (tfDiff (poseTf t) (forward ch q) < 1e-12)
          ik <- run (serveIk (ikReq robot (forward ch q)))
          pure (checkSolutions r (forward ch q) ik)

  describe "collision-aware IK through the daemon" $ do
    let r = library "ur5"
        ch = compile r
        q0 = U.fromList [0.2, -1.3, 1.4, -1.6, -1.5, 0.3]
        target = forward ch q0
        V3 tx ty tz = translation target
        -- a square plate (two triangles) of side 2a at height h, centred under the base
        plate a h = MeshMsg (putField [-a, -a, h, a, -a, h, a, a, h, -a, a, h]) (putField [0, 1, 2, 0, 2, 3]) (putField Nothing) (putField Nothing)
        withEnv ms c = (ikReq (named "ur5") target) { ikqEnvironment = putField ms, ikqClearance = putField (Just c) }
    it "a floor under the base: solutions clear of it by the clearance, each with its clearance" $ do
      rsp <- serveIk (withEnv [plate 2 (-0.05)] 0.02) { ikqIgnoreBodies = putField [1] }
      let sols = getField (ikrSolutions rsp)
      errorOf (getField (ikrError rsp)) `shouldBe` (ErrUnspecified, "", "")
      sols `shouldSatisfy` (not . null)
      forM_ sols $ \s -> fromMaybe 0 (getField (iksClearance s)) `shouldSatisfy` (>= 0.02)
      expectSolutions r target rsp
    it "a plate through the target: INFEASIBLE naming the environment" $ do
      -- a plate in the plane z = tz through the tool point: every solution's tool touches it
      let m = MeshMsg (putField [tx - 0.2, ty - 0.2, tz, tx + 0.2, ty - 0.2, tz, tx + 0.2, ty + 0.2, tz, tx - 0.2, ty + 0.2, tz])
                      (putField [0, 1, 2, 0, 2, 3]) (putField Nothing) (putField Nothing)
      rsp <- serveIk (withEnv [m] 0.01)
      let (code, field, msg) = errorOf (getField (ikrError rsp))
      (code, field) `shouldBe` (ErrInfeasible, "environment")
      T.unpack msg `shouldContain` "collide"
    it "a mesh in millimetres with a scale and a pose: placed as asked" $ do
      -- the same floor, in mm, 1 m lower, lifted 1 m by its pose: as clear as the floor in m
      let mm = MeshMsg (putField (map (* 1000) [-2, -2, -1.05, 2, -2, -1.05, 2, 2, -1.05, -2, 2, -1.05]))
                       (putField [0, 1, 2, 0, 2, 3]) (putField (Just 0.001)) (putField (Just (poseToMsg (fromQuat (V3 0 0 1) (Quat 1 0 0 0)))))
      a <- serveIk (withEnv [plate 2 (-0.05)] 0.02) { ikqIgnoreBodies = putField [1] }
      b <- serveIk (withEnv [mm] 0.02) { ikqIgnoreBodies = putField [1] }
      let cl = map (fromMaybe 0 . getField . iksClearance) . getField . ikrSolutions
      length (cl b) `shouldBe` length (cl a)
      maximum (zipWith (\x y -> abs (x - y)) (cl a) (cl b)) `shouldSatisfy` (< 1e-9)
