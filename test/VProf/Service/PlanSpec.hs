{-# LANGUAGE OverloadedStrings #-}
-- | Path planning through the daemon's handler ('VProf.Service.answer' and 'servePlan'): the
-- waypoints of @examples/plan-square.csv@ for a UR5 placed by a base pose, with a tool offset,
-- sent as a client would, encoded and decoded, answered, and checked
--
-- * by the independent plan checker ("Support.PlanChecker") on the samples that came over the
--   wire: joints within their limits, joint speeds and accelerations within theirs, the TCP
--   (by the textbook forward kinematics) within the zone of the waypoint polyline, every
--   stretch's profile legal;
-- * against the core's 'planPath' of the same input, in process: the same duration, the same
--   samples (t, s, v, a, j, q, qd, bit for bit), the same zones and stops;
--
-- plans that stop (out of reach, a joint limit, a collision with the environment) carry the
-- status, the distance and the pose where they stop, as the core says; a budget that runs out is
-- NOT_CONVERGED; bad requests get INVALID_ARGUMENT with every problem, each naming its proto
-- field; and the messages survive the wire encoding both ways.
module VProf.Service.PlanSpec (spec) where

import Control.Monad (forM_)
import qualified Data.ByteString.Char8 as BC
import Data.List (isInfixOf, sort)
import Data.Maybe (fromMaybe)
import Data.ProtocolBuffers (getField, putField)
import qualified Data.Text as T
import qualified Data.Vector.Unboxed as U
import Test.Hspec

import Support.Envelope (viaEnvelope)
import Support.PlanChecker (checkTrajectory)
import VProf.Geometry.Bvh (buildBvh)
import VProf.Geometry.Mesh (ScenePart (..), composeScene, fromTriangles)
import VProf.Kinematics
import VProf.Kinematics.Collision (collisionModel, defaultCollisionOptions)
import VProf.Kinematics.Library (lookupRobot)
import VProf.Plan
import VProf.Service.Plan (planTimeLimit, servePlan)
import VProf.Units
import VProf.Wire.Envelope
import VProf.Wire.Kinematics (poseToMsg)
import VProf.Wire.Messages
import VProf.Wire.Validate (MsgType (..), validateWire)

------------------------------------------------------------------------------ the task

library :: String -> Robot
library n = either error id (lookupRobot n)

-- | examples/plan-square.csv: time,x,y,z,qw,qx,qy,qz (m), a closed loop of four moves.
loadSquare :: IO [[Double]]
loadSquare = do
  src <- BC.readFile "examples/plan-square.csv"
  pure [ map (read . BC.unpack) (BC.split ',' l) | l <- drop 1 (BC.lines src), not (BC.null l) ]

-- | The base: 5 cm forward, 10 cm to the right, turned 15° about z; the TCP 4 cm beyond the flange.
baseTf, toolTf :: Tf
baseTf = fromQuat (V3 0.05 (-0.1) 0) (Quat (cos (pi / 24)) 0 0 (sin (pi / 24)))
toolTf = fromQuat (V3 0 0 0.04) (Quat 1 0 0 0)

posesMsg :: [[Double]] -> PosesMsg
posesMsg rows = PosesMsg (putField (col 0)) (putField (col 1)) (putField (col 2)) (putField (col 3))
                         (putField (col 4)) (putField (col 5)) (putField (col 6)) (putField (col 7))
  where col i = map (!! i) rows

named :: String -> RobotMsg
named n = RobotMsg (putField (Just (T.pack n))) (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing)

-- | A request with every option at its default (zone: fine).
planReq :: String -> [[Double]] -> PlanRequestMsg
planReq robot rows = PlanRequestMsg
  { plqRequestId = putField (Just 5), plqWaypoints = putField (Just (posesMsg rows))
  , plqRobot = putField (Just (named robot)), plqBase = putField Nothing, plqTool = putField Nothing
  , plqEnvironment = putField [], plqClearance = putField Nothing, plqIgnoreBodies = putField []
  , plqSpeed = putField Nothing, plqAcceleration = putField Nothing, plqJerk = putField Nothing
  , plqZone = putField Nothing, plqTimeStep = putField Nothing, plqStart = putField [], plqTimeBudget = putField Nothing }

-- | The square for the placed UR5, z10 and v500 sent explicitly.
squareReq :: [[Double]] -> PlanRequestMsg
squareReq rows = (planReq "ur5" rows)
  { plqBase = putField (Just (poseToMsg baseTf)), plqTool = putField (Just (poseToMsg toolTf))
  , plqZone = putField (Just 0.01), plqSpeed = putField (Just 0.5) }

-- | The pose a client sends, as the handler reads it back.
viaWire :: Tf -> Tf
viaWire t = let p = poseToMsg t in fromQuat (V3 (g poseX p) (g poseY p) (g poseZ p)) (Quat (g poseQw p) (g poseQx p) (g poseQy p) (g poseQz p))
  where g f = orDefault . getField . f

placedUr5 :: Robot
placedUr5 = let r = library "ur5" in r { robotBase = viaWire baseTf `compose` robotBase r, robotTool = robotTool r `compose` viaWire toolTf }

waypointsOf :: [[Double]] -> [Waypoint]
waypointsOf rows = [ waypoint (x, y, z) (w, a, b, c) | [_, x, y, z, w, a, b, c] <- rows ]

-- | The core's plan of what 'squareReq' asks.
coreSquare :: [[Double]] -> Either PlanFailure Plan
coreSquare rows = planPath (planRequest placedUr5 (waypointsOf rows)) { prZone = Blend (0.01 *~ meter) }

envelope :: PlanRequestMsg -> RequestMsg
envelope p = RequestMsg (putField (Just 61)) (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing)
                        (putField Nothing) (putField Nothing) (putField (Just p))

------------------------------------------------------------------------------ reading responses

txt :: Maybe T.Text -> String
txt = maybe "" T.unpack

dbl :: Maybe Double -> Double
dbl = fromMaybe 0

errorOf :: Maybe ErrorMsg -> (ErrorCodeEnum, String, String)
errorOf Nothing = (ErrUnspecified, "", "")
errorOf (Just e) = (getEnum (getField (errCode e)), txt (getField (errField e)), txt (getField (errMessage e)))

statusOf :: PlanResponseMsg -> PlanStatusEnum
statusOf = getEnum . getField . plrStatus

-- | The samples that came over the wire as the core's trajectory record.
wireTrajectory :: PlanResponseMsg -> Trajectory
wireTrajectory r =
  Trajectory (U.fromList (getField (plrTime r))) (U.fromList (getField (plrDistance r))) (U.fromList (getField (plrVelocity r)))
             (U.fromList (getField (plrAcceleration r))) (U.fromList (getField (plrJerk r))) (U.fromList (getField (plrQ r)))
             (U.fromList (getField (plrQd r))) (fromIntegral (fromMaybe 0 (getField (plrDof r))))

positions :: [[Double]] -> [(Double, Double, Double)]
positions rows = [ (x, y, z) | (_ : x : y : z : _) <- rows ]

spec :: Spec
spec = do
  rows <- runIO loadSquare
  describe "planning through the daemon" $ do
    it "examples/plan-square.csv has its five waypoints" $ length rows `shouldBe` 5

    it "answers a plan Request in the envelope: the square for a placed UR5 passes the independent checker on the samples sent" $ do
      rsp <- viaEnvelope (envelope (squareReq rows))
      responseKind rsp `shouldBe` "plan"
      getField (rspRequestId rsp) `shouldBe` Just 61
      let Just p = getField (rspPlan rsp)
          tr = wireTrajectory p
          n = trDof tr
          m = U.length (trTime tr)
      errorOf (getField (plrError p)) `shouldBe` (ErrUnspecified, "", "")
      statusOf p `shouldBe` PlanStatusOk
      getField (plrRequestId p) `shouldBe` Just 61
      n `shouldBe` 6
      m `shouldSatisfy` (> 100)
      map U.length [trS tr, trV tr, trA tr, trJ tr] `shouldBe` replicate 4 m
      (U.length (trQ tr), U.length (trQd tr)) `shouldBe` (m * n, m * n)
      dbl (getField (plrTimeStep p)) `shouldBe` defaultTimeStep
      dbl (getField (plrDuration p)) `shouldBe` U.last (trTime tr)
      dbl (getField (plrDuration p)) `shouldSatisfy` (> dbl (getField (plrRouteLength p)) / 0.5)
      case coreSquare rows of
        Left f -> expectationFailure (describePlanFailure f)
        Right core ->
          -- the wire's samples in the core's plan: the checker sees only what was sent
          checkTrajectory placedUr5 (positions rows) 0.01 defaultAcceleration defaultJerk defaultTimeStep
                          core { planTrajectory = tr } `shouldBe` []

    it "agrees with the core's planPath for the same input: duration, sample count, every sample, the zones and the stops" $ do
      p <- servePlan (squareReq rows)
      case coreSquare rows of
        Left f -> expectationFailure (describePlanFailure f)
        Right core -> do
          let ct = planTrajectory core
              wt = wireTrajectory p
          dbl (getField (plrDuration p)) `shouldBe` planDuration core
          U.length (trTime wt) `shouldBe` trajectoryCount ct
          forM_ [ (trTime, "t"), (trS, "s"), (trV, "v"), (trA, "a"), (trJ, "j"), (trQ, "q"), (trQd, "qd") ] $ \(f, name) ->
            (name :: String, f wt) `shouldBe` (name, f ct)
          dbl (getField (plrRouteLength p)) `shouldBe` routeLength (planRoute core)
          getField (plrStops p) `shouldBe` rtStops (planRoute core)
          [ (dbl (getField (pzStartDistance z)), dbl (getField (pzEndDistance z)), dbl (getField (pzVelocity z)), txt (getField (pzBinding z)))
            | z <- getField (plrZones p) ]
            `shouldBe` [ (lzStart z, lzEnd z, lzSpeed z, describeBinding placedUr5 (lzBinding z)) | z <- planZoneList core ]
          -- a closed square with z10: no stops between the ends; the zones cover the route
          getField (plrStops p) `shouldBe` []
          let zs = getField (plrZones p)
          dbl (getField (pzStartDistance (head zs))) `shouldBe` 0
          dbl (getField (pzEndDistance (last zs))) `shouldSatisfy` (\e -> abs (e - dbl (getField (plrRouteLength p))) < 1e-9)

    it "fine stops at every waypoint: three stops, the speed 0 there" $ do
      p <- servePlan (squareReq rows) { plqZone = putField Nothing }
      statusOf p `shouldBe` PlanStatusOk
      let stops = getField (plrStops p)
          wt = wireTrajectory p
      length stops `shouldBe` 3
      forM_ stops $ \s -> do
        let (gap, v) = minimum [ (abs (x - s), abs v') | (x, v') <- zip (U.toList (trS wt)) (U.toList (trV wt)) ]
        gap `shouldSatisfy` (< 1e-9)
        v `shouldSatisfy` (< 1e-9)

  describe "plans that stop, as the core says where and why" $ do
    it "out of reach: the distance, the pose there on the route, INFEASIBLE naming waypoints" $ do
      let wps = [[0, 0.4, 0, 0.3, 0, 1, 0, 0], [1, 1.2, 0, 0.3, 0, 1, 0, 0]]
      p <- servePlan (planReq "ur5" wps)
      statusOf p `shouldBe` PlanStatusOutOfReach
      let (code, field, msg) = errorOf (getField (plrError p))
      (code, field) `shouldBe` (ErrInfeasible, "waypoints")
      msg `shouldContain` "out of reach"
      case planPath (planRequest (library "ur5") (waypointsOf wps)) of
        Left (Stopped (PlanStop _ s _)) -> do
          dbl (getField (plrStopDistance p)) `shouldBe` s
          let Just pose = getField (plrStopPose p)
          abs (dbl (getField (poseX pose)) - (0.4 + s)) `shouldSatisfy` (< 1e-9)
        _ -> expectationFailure "the core did not stop"
      getField (plrTime p) `shouldBe` []
      getField (plrDof p) `shouldBe` Just 6
      dbl (getField (plrRouteLength p)) `shouldSatisfy` (\l -> abs (l - 0.8) < 1e-9)

    it "a joint limit: an IRB 140 passing behind its base from a start configuration runs J1 into 180°" $ do
      let wps = [[0, -0.4, 0.3, 0.3, 0, 1, 0, 0], [1, -0.4, -0.3, 0.3, 0, 1, 0, 0]]
      p <- servePlan (planReq "abb-irb140" wps) { plqStart = putField (map (* (pi / 180)) [143, 20, 30, 0, 30, 0]) }
      statusOf p `shouldBe` PlanStatusJointLimit
      txt (getField (plrStopJoint p)) `shouldBe` "J1"
      abs (abs (dbl (getField (plrStopValue p))) - pi) `shouldSatisfy` (< 1e-9)
      abs (dbl (getField (plrStopDistance p)) - 0.3) `shouldSatisfy` (<= 0.0015)

    it "a plate across the route: COLLISION naming the environment, the body and its clearance, where the core stops" $ do
      -- a 2 mm thin vertical plate at x = 0.45 m across the square's first move, in the world
      let plate = MeshMsg (putField [0.45, -0.5, 0, 0.45, 0.5, 0, 0.45, 0.5, 0.8, 0.45, -0.5, 0.8])
                          (putField [0, 1, 2, 0, 2, 3]) (putField Nothing) (putField Nothing)
          req = (squareReq rows) { plqEnvironment = putField [plate], plqClearance = putField (Just 0.005) }
      p <- servePlan req
      statusOf p `shouldBe` PlanStatusCollision
      let (code, field, _) = errorOf (getField (plrError p))
      (code, field) `shouldBe` (ErrInfeasible, "environment")
      txt (getField (plrStopBody p)) `shouldSatisfy` (not . null)
      dbl (getField (plrStopValue p)) `shouldSatisfy` (< 0.005)
      -- the TCP reaches the plate 50 mm along the first move; the robot's capsules before that
      dbl (getField (plrStopDistance p)) `shouldSatisfy` (< 0.05)
      let env = Environment (collisionModel defaultCollisionOptions placedUr5)
                            (buildBvh (composeScene [ScenePart plateMesh 1 identity])) 0.005
          plateMesh = fromTriangles [ (V3 0.45 (-0.5) 0, V3 0.45 0.5 0, V3 0.45 0.5 0.8), (V3 0.45 (-0.5) 0, V3 0.45 0.5 0.8, V3 0.45 (-0.5) 0.8) ]
      case planPath (planRequest placedUr5 (waypointsOf rows)) { prZone = Blend (0.01 *~ meter), prTrack = defaultTrackOptions { toEnvironment = Just env } } of
        Left (Stopped st@(PlanStop (Collision b c need) s _)) -> do
          (txt (getField (plrStopBody p)), dbl (getField (plrStopValue p)), dbl (getField (plrStopDistance p))) `shouldBe` (b, c, s)
          need `shouldBe` 0.005
          describeStop st `shouldSatisfy` isInfixOf "mm from the environment (at least 5.00 mm asked)"
        Left f -> expectationFailure ("the core stopped otherwise: " ++ describePlanFailure f)
        Right _ -> expectationFailure "the core planned through the plate"

    it "without time_budget (or with 0) a plan gets the contract's default budget, 60 s, as vprof plan does" $ do
      defaultPlanBudget `shouldBe` 60
      planTimeLimit (squareReq rows) `shouldBe` 60 + 30
      planTimeLimit (squareReq rows) { plqTimeBudget = putField (Just 0) } `shouldBe` 60 + 30
      planTimeLimit (squareReq rows) { plqTimeBudget = putField (Just 5) } `shouldBe` 5 + 30

    it "a time budget that runs out: NOT_CONVERGED naming time_budget" $ do
      p <- servePlan (squareReq rows) { plqTimeBudget = putField (Just 1e-9) }
      statusOf p `shouldBe` PlanStatusBudget
      let (code, field, msg) = errorOf (getField (plrError p))
      (code, field) `shouldBe` (ErrNotConverged, "time_budget")
      msg `shouldContain` "time_budget = 0.000000001 s"
      getField (plrTime p) `shouldBe` []

  describe "bad requests: INVALID_ARGUMENT, every problem, each naming its field" $ do
    let errs r = do
          p <- servePlan r
          statusOf p `shouldBe` PlanStatusInvalidArgument
          getField (plrTime p) `shouldBe` []
          pure (errorOf (getField (plrError p)), map (errorOf . Just) (getField (plrErrors p)))
        fieldsOf = map (\(_, f, _) -> f)
    it "a NaN speed, an unknown robot and a single waypoint: all at once" $ do
      ((code, first, msg), all') <- errs (planReq "ur55" (take 1 rows)) { plqSpeed = putField (Just (0 / 0)) }
      code `shouldBe` ErrInvalidArgument
      first `shouldBe` "waypoints"
      sort (fieldsOf all') `shouldBe` sort ["waypoints", "robot.name", "speed"]
      all (\(c, _, _) -> c == ErrInvalidArgument) all' `shouldBe` True
      msg `shouldContain` "speed = NaN m/s"
      msg `shouldContain` "\"ur55\""
      msg `shouldContain` "at least 2 waypoints"
    it "a start configuration of the wrong length, with the robot's joint count" $ do
      ((_, first, msg), all') <- errs (squareReq rows) { plqStart = putField [0, -1.4, -2.0, -1.3, 1.57] }
      first `shouldBe` "start"
      fieldsOf all' `shouldBe` ["start"]
      msg `shouldContain` "5 values"
      msg `shouldContain` "6 joints"
    it "no waypoints; no robot" $ do
      (_, all') <- errs (planReq "ur5" rows) { plqWaypoints = putField Nothing, plqRobot = putField Nothing }
      fieldsOf all' `shouldBe` ["waypoints", "robot"]
    it "waypoint arrays of different lengths, by array" $ do
      let short = (posesMsg rows) { posQw = putField [0, 0, 0, 0] }
      (_, all') <- errs (planReq "ur5" rows) { plqWaypoints = putField (Just short) }
      fieldsOf all' `shouldBe` ["waypoints.qw"]
    it "a NaN coordinate and a quaternion far from unit norm, by waypoint; two waypoints at one position" $ do
      let bad = [ if i == 1 then [1, 0.5, 0 / 0, 0.3, 0, 1, 0, 0] else r | (i, r) <- zip [0 :: Int ..] rows ]
      (_, all1) <- errs (planReq "ur5" bad)
      fieldsOf all1 `shouldBe` ["waypoints[1].y"]
      let tilted = [ if i == 2 then take 4 r ++ [0, 3, 0, 0] else r | (i, r) <- zip [0 :: Int ..] rows ]
          repeated' = take 2 rows ++ [rows !! 1] ++ drop 2 rows
      (_, all2) <- errs (planReq "ur5" tilted)
      fieldsOf all2 `shouldBe` ["waypoints[2].orientation"]
      ((_, _, msg3), all3) <- errs (planReq "ur5" repeated')
      fieldsOf all3 `shouldBe` ["waypoints[2].position"]
      msg3 `shouldContain` "0.1 mm apart"
    it "a negative zone, a time step above 1 s, a negative acceleration, an infinite jerk, a negative budget, a bad base quaternion, body 0, a negative clearance" $ do
      let badBase = (poseToMsg baseTf) { poseQw = putField (Just 2) }
      ((_, _, msg), all') <- errs (squareReq rows)
        { plqZone = putField (Just (-0.01)), plqTimeStep = putField (Just 2), plqAcceleration = putField (Just (-1))
        , plqJerk = putField (Just (1 / 0)), plqTimeBudget = putField (Just (-1)), plqBase = putField (Just badBase)
        , plqIgnoreBodies = putField [0], plqClearance = putField (Just (-0.001)) }
      -- (and ignore_bodies as a whole: there is no environment to leave bodies out of)
      sort (fieldsOf all') `shouldBe` sort ["zone", "time_step", "acceleration", "jerk", "time_budget", "base", "ignore_bodies[0]", "clearance", "ignore_bodies"]
      msg `shouldContain` "zone = -0.01 m"
      msg `shouldContain` "time_step = 2.0 s: must be at most 1"
    it "a body the robot does not have is refused naming ignore_bodies[0] (99 was ignored)" $ do
      ((code, field, msg), _) <- errs (squareReq rows) { plqIgnoreBodies = putField [99] }
      (code, field) `shouldBe` (ErrInvalidArgument, "ignore_bodies[0]")
      msg `shouldContain` "1 to 6"
    it "a clearance or ignore_bodies without an environment is refused naming it (each went unused)" $ do
      ((code, field, msg), all') <- errs (squareReq rows) { plqClearance = putField (Just 0.01) }
      (code, field) `shouldBe` (ErrInvalidArgument, "clearance")
      msg `shouldContain` "without an environment"
      fieldsOf all' `shouldBe` ["clearance"]
      ((_, field2, _), _) <- errs (squareReq rows) { plqIgnoreBodies = putField [1] }
      field2 `shouldBe` "ignore_bodies"
    it "a zone between 0 and 0.1 mm is refused naming zone (a 0.1 µm zone planned for 12 s)" $ do
      ((code, field, msg), _) <- errs (squareReq rows) { plqZone = putField (Just 1e-7) }
      (code, field) `shouldBe` (ErrInvalidArgument, "zone")
      msg `shouldContain` "at least 0.1 mm"

  describe "the wire encoding" $ do
    it "a PlanRequest and a PlanResponse decode to what was encoded, and pass the strict wire check" $ do
      let req = (squareReq rows) { plqStart = putField [0, -1.4, -2.0, -1.3, 1.57, 0], plqIgnoreBodies = putField [1, 2]
                                 , plqTimeBudget = putField (Just 5), plqJerk = putField (Just (-0.0)) }
      decodeBare (encodeBare req) `shouldBe` Right req
      validateWire TPlanRequest (encodeBare req) `shouldBe` Right ()
      rsp <- servePlan (squareReq rows)
      decodeBare (encodeBare rsp) `shouldBe` Right rsp
      validateWire TPlanResponse (encodeBare rsp) `shouldBe` Right ()
      bad <- servePlan (planReq "ur55" rows)
      decodeBare (encodeBare bad) `shouldBe` Right bad
    it "a response whose stop pose is cut off fails the strict wire check" $ do
      p <- servePlan (planReq "ur5" [[0, 0.4, 0, 0.3, 0, 1, 0, 0], [1, 1.2, 0, 0.3, 0, 1, 0, 0]])
      let bytes = encodeBare p { plrComputeTime = putField Nothing, plrError = putField Nothing }
      validateWire TPlanResponse (BC.take (BC.length bytes - 1) bytes) `shouldSatisfy` either (const True) (const False)
