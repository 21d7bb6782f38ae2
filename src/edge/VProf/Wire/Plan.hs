{-# LANGUAGE OverloadedStrings #-}
-- | Path planning on the wire: a 'PlanRequestMsg' to the core's 'PlanRequest' (the robot placed
-- by its base and tool, the waypoints, the limits, the environment as a collision model and a
-- hierarchy), with every validation problem at once, each naming the proto field and the value in
-- its unit (@speed = -1.0 m/s@, @waypoints[2].qx = NaN@, @waypoints = 1: a route needs at
-- least 2 waypoints@, @start = 5 values: the robot UR5 has 6 joints@, @robot.name = "ur55"@); and
-- the core's plan, or the reason and the distance where it stops, back to a 'PlanResponseMsg'.
--
-- A waypoint is named @waypoints[i]@ (entry i of every array of the 'PosesMsg'), one of its
-- numbers @waypoints[i].x@ … @waypoints[i].qz@, as the core names them. Fields left at 0 take the
-- defaults of @vprof plan@, but for the zone: 0 is @fine@ (the command line's default is z10).
module VProf.Wire.Plan
  ( PlanQuery (..)
  , planFromMsg
  , planToMsg
  , planFailureToMsg
  , planErrors
  , planBudgetMsg
  , planInternal
  , defaultPlanBudget
  , planBudgetOf
  , stopStatus
  , wireName
  ) where

import Data.ProtocolBuffers (getField, putField)
import qualified Data.Text as T
import qualified Data.Vector.Unboxed as U
import Data.Word (Word64)

import VProf.Geometry.Bvh (buildBvh)
import VProf.Geometry.Mesh (composeScene)
import VProf.Kinematics
import VProf.Kinematics.Collision (CollisionOptions (..), collisionModel, defaultCollisionOptions, unknownBody)
import VProf.Plan
import VProf.Units
import VProf.Validation
import VProf.Wire.Kinematics (jointsFromMsg, meshFromMsg, mkError, poseFromMsg, poseToMsg, robotFromMsg, withoutEnvironment)
import VProf.Wire.Messages

-- | A validated plan request: the core's request (its robot placed by base and tool), the route it
-- makes (for the distance and the pose where a plan stops), and the time budget (s).
data PlanQuery = PlanQuery
  { pqRequest :: PlanRequest
  , pqRoute :: Route
  , pqBudget :: Double
  }

-- | The request's time budget: the default for 0, at most an hour; an invalid one is the default
-- (and an error of 'planFromMsg').
planBudgetOf :: PlanRequestMsg -> Double
planBudgetOf m
  | b == 0 || not (finite b) || b < 0 = defaultPlanBudget
  | otherwise = min 3600 b
  where b = orDefault (getField (plqTimeBudget m)) :: Double

-- | A non-negative finite number; 0 takes the default.
orDefaultPositive :: String -> String -> Double -> Double -> Either [FieldError] Double
orDefaultPositive field unit def v
  | not (finite v) || v < 0 =
      Left [fieldError field v unit ("must be a finite number >= 0 (0 means the default " ++ showNumber def ++ ")")]
  | v == 0 = Right def
  | otherwise = Right v

lefts' :: Either [e] a -> [e]
lefts' = either id (const [])

-- | The core's field names in the contract's terms: the time step is @time_step@, the zone in m.
wireName :: String -> Maybe UserField
wireName = \case
  "dt" -> Just (UserField "time_step" "s" 1)
  "zone" -> Just (UserField "zone" "m" 0.001)
  _ -> Nothing

-- | The waypoints: every array of the same length (time may be empty), every number finite, then
-- the core's route rules (at least 2, a quaternion of norm about 1, consecutive ones apart).
waypointsFromMsg :: Zone -> Maybe PosesMsg -> Either [FieldError] ([Waypoint], Route)
waypointsFromMsg _ Nothing = Left [literalError "waypoints" "" "is missing: the path, at least 2 waypoints (x y z in m, qw qx qy qz)"]
waypointsFromMsg zone (Just p)
  | not (null lengthErrs) = Left lengthErrs
  | not (null numberErrs) = Left (take 10 numberErrs)
  | otherwise = case mkRoute (replicate n zone) wps of
      Left es -> Left es
      Right rt -> Right (wps, rt)
  where
    arrays = [ ("x", getField (posX p), "m"), ("y", getField (posY p), "m"), ("z", getField (posZ p), "m")
             , ("qw", getField (posQw p), ""), ("qx", getField (posQx p), ""), ("qy", getField (posQy p), "")
             , ("qz", getField (posQz p), "") ]
    times = getField (posTime p)
    n = length (getField (posX p))
    lengthErrs =
      [ literalError ("waypoints." ++ k) (show (length vs) ++ " values")
          ("must hold one value per waypoint: x holds " ++ show n)
      | (k, vs, _) <- drop 1 arrays, length vs /= n ]
      ++ [ literalError "waypoints.time" (show (length times) ++ " values")
             ("must be empty or hold one value per waypoint: x holds " ++ show n)
         | not (null times), length times /= n ]
    numberErrs =
      [ fieldError ("waypoints[" ++ show i ++ "]." ++ k) v u "must be a finite number"
      | (k, vs, u) <- arrays ++ [ ("time", times, "s") | not (null times) ]
      , (i, v) <- zip [0 :: Int ..] vs, not (finite v) ]
    wps = [ waypoint (x, y, z) (w, a, b, c)
          | (x, y, z, w, a, b, c) <- zip7 (getField (posX p)) (getField (posY p)) (getField (posZ p))
                                          (getField (posQw p)) (getField (posQx p)) (getField (posQy p)) (getField (posQz p)) ]
    zip7 (a : as) (b : bs) (c : cs) (d : ds) (e : es) (f : fs) (g : gs) = (a, b, c, d, e, f, g) : zip7 as bs cs ds es fs gs
    zip7 _ _ _ _ _ _ _ = []

planFromMsg :: PlanRequestMsg -> Either [FieldError] PlanQuery
planFromMsg m =
  let zoneM = orDefault (getField (plqZone m)) :: Double
      zone
        | not (finite zoneM) || zoneM < 0 = Left [fieldError "zone" zoneM "m" "must be a finite number >= 0 (0 means fine: stop at every waypoint)"]
        | zoneM == 0 = Right Fine
        | otherwise = Right (Blend (zoneM *~ meter))
      waypoints = waypointsFromMsg (either (const Fine) id zone) (getField (plqWaypoints m))
      robot = robotFromMsg (getField (plqRobot m))
      base = maybe (Right identity) (poseFromMsg "base") (getField (plqBase m))
      tool = maybe (Right identity) (poseFromMsg "tool") (getField (plqTool m))
      envs = [ meshFromMsg ("environment[" ++ show i ++ "]") e | (i, e) <- zip [0 :: Int ..] (getField (plqEnvironment m)) ]
      clearanceM = orDefault (getField (plqClearance m))
      clearance = if finite clearanceM && clearanceM >= 0 then Right clearanceM
                  else Left [fieldError "clearance" clearanceM "m" "must be a finite number >= 0"]
      ignores = [ if b == 0 then Left [literalError ("ignore_bodies[" ++ show i ++ "]") "0" "bodies count from 1 (the first link)"]
                  else case robot of
                    Right (r, _) | Just e <- unknownBody r False (fromIntegral b) -> Left [literalError ("ignore_bodies[" ++ show i ++ "]") (show b) e]
                    _ -> Right (fromIntegral b :: Int)
                | (i, b) <- zip [0 :: Int ..] (getField (plqIgnoreBodies m)) ]
      speed = orDefaultPositive "speed" "m/s" 0.5 (orDefault (getField (plqSpeed m)))
      acc = orDefaultPositive "acceleration" "m/s²" defaultAcceleration (orDefault (getField (plqAcceleration m)))
      jerk = orDefaultPositive "jerk" "m/s³" defaultJerk (orDefault (getField (plqJerk m)))
      dt = orDefaultPositive "time_step" "s" defaultTimeStep (orDefault (getField (plqTimeStep m))) >>= \x ->
        if x <= 1 then Right x else Left [fieldError "time_step" x "s" "must be at most 1"]
      budget = let b = orDefault (getField (plqTimeBudget m)) in
        if not (finite b) || b < 0 || b > 3600
          then Left [fieldError "time_budget" b "s" "must be a finite number >= 0 and at most 3600 (0 means the default 10)"]
          else Right (planBudgetOf m)
      startList = getField (plqStart m)
      start = case robot of
        Right (r, _) | not (null startList) -> Just <$> jointsFromMsg "start" r startList
        _ -> Right Nothing
      errs = lefts' waypoints ++ lefts' robot ++ lefts' base ++ lefts' tool ++ concatMap lefts' envs
          ++ lefts' clearance ++ concatMap lefts' ignores ++ lefts' speed ++ lefts' acc ++ lefts' jerk
          ++ lefts' zone ++ lefts' dt ++ lefts' start ++ lefts' budget
          ++ withoutEnvironment (not (null envs)) clearanceM (getField (plqIgnoreBodies m))
  in case errs of
       _ : _ -> Left errs
       [] -> do
         (wps, route) <- waypoints
         (r0, _) <- robot
         b <- base
         t <- tool
         z <- zone
         parts <- sequence envs
         c <- clearance
         is <- sequence ignores
         v <- speed; a <- acc; j <- jerk; h <- dt; s <- start; bud <- budget
         let r = r0 { robotBase = b `compose` robotBase r0, robotTool = robotTool r0 `compose` t }
             env | null parts = Nothing
                 | otherwise = Just (Environment (collisionModel defaultCollisionOptions { coSceneIgnore = is } r)
                                                 (buildBvh (composeScene parts)) c)
             rq = (planRequest r wps)
               { prZone = z, prStart = s, prSpeed = v *~ mps, prAcceleration = a *~ mps2, prJerk = j *~ mps3
               , prTimeStep = h *~ second, prTrack = defaultTrackOptions { toEnvironment = env } }
         pure (PlanQuery rq route bud)

------------------------------------------------------------------------------ responses

txt :: String -> Maybe T.Text
txt = nonDefault . T.pack

-- | A response with the given status and nothing else but the request id and the compute time.
bare :: Word64 -> Double -> PlanStatusEnum -> PlanResponseMsg
bare rid secs st = PlanResponseMsg
  { plrRequestId = putField (nonDefault rid), plrStatus = putField (enumField st), plrDof = putField Nothing
  , plrTimeStep = putField Nothing, plrTime = putField [], plrDistance = putField [], plrVelocity = putField []
  , plrAcceleration = putField [], plrJerk = putField [], plrQ = putField [], plrQd = putField []
  , plrDuration = putField Nothing, plrRouteLength = putField Nothing, plrStops = putField [], plrZones = putField []
  , plrStopDistance = putField Nothing, plrStopPose = putField Nothing, plrStopJoint = putField Nothing
  , plrStopBody = putField Nothing, plrStopValue = putField Nothing, plrComputeTime = putField (nonDefault secs)
  , plrError = putField Nothing, plrErrors = putField [] }

-- | The robot's joints and the route's length and stops, set on every answer to a valid request.
withRoute :: PlanQuery -> PlanResponseMsg -> PlanResponseMsg
withRoute q msg = msg
  { plrDof = putField (nonDefault (fromIntegral (dof (prRobot (pqRequest q)))))
  , plrRouteLength = putField (nonDefault (rtLength (pqRoute q)))
  , plrStops = putField (rtStops (pqRoute q)) }

-- | A legal plan.
planToMsg :: Word64 -> Double -> PlanQuery -> Plan -> PlanResponseMsg
planToMsg rid secs q p = (withRoute q (bare rid secs PlanStatusOk))
  { plrDof = putField (nonDefault (fromIntegral (trDof tr)))
  , plrTimeStep = putField (nonDefault (si (prTimeStep (pqRequest q))))
  , plrTime = putField (U.toList (trTime tr))
  , plrDistance = putField (U.toList (trS tr))
  , plrVelocity = putField (U.toList (trV tr))
  , plrAcceleration = putField (U.toList (trA tr))
  , plrJerk = putField (U.toList (trJ tr))
  , plrQ = putField (U.toList (trQ tr))
  , plrQd = putField (U.toList (trQd tr))
  , plrDuration = putField (nonDefault (planDuration p))
  , plrZones = putField [ PlanZoneMsg (putField (nonDefault (lzStart z))) (putField (nonDefault (lzSpeed z)))
                                      (putField (nonDefault (lzEnd z))) (putField (txt (describeBinding r (lzBinding z))))
                        | z <- planZoneList p ]
  }
  where
    tr = planTrajectory p
    r = prRobot (pqRequest q)

-- | The status of a stop.
stopStatus :: StopReason -> PlanStatusEnum
stopStatus = \case
  OutOfReach _ -> PlanStatusOutOfReach
  JointLimit {} -> PlanStatusJointLimit
  Singularity _ -> PlanStatusSingularity
  Jump {} -> PlanStatusJump
  Collision {} -> PlanStatusCollision
  NoSolution _ -> PlanStatusNoSolution

-- | A plan that stops (INFEASIBLE: where, why, and the route's pose there) or has no legal profile
-- for a stretch; the core's validation errors, should it find any the wire's did not, as
-- INVALID_ARGUMENT in the contract's terms.
planFailureToMsg :: Word64 -> Double -> PlanQuery -> PlanFailure -> PlanResponseMsg
planFailureToMsg rid secs q f = case f of
  InvalidPlan es -> planErrors rid secs (inUserTerms wireName es)
  Stopped st@(PlanStop reason s _) ->
    let (joint, body, value) = case reason of
          JointLimit j _ l -> (j, "", l)
          Jump j _ x -> (j, "", x)
          Singularity sv -> ("", "", sv)
          Collision b c _ -> ("", b, c)
          _ -> ("", "", 0)
        field = case reason of
          Collision {} -> "environment"
          _ -> "waypoints"
    in (at s (stopStatus reason))
         { plrStopJoint = putField (txt joint), plrStopBody = putField (txt body)
         , plrStopValue = putField (nonDefault value)
         , plrError = putField (Just (mkError ErrInfeasible field ("the plan stops: " ++ describeStop st))) }
  ProfileFailed _ (a, _) _ ->
    (at a PlanStatusNoProfile) { plrError = putField (Just (mkError ErrInfeasible "" (describePlanFailure f))) }
  where
    at s st = (withRoute q (bare rid secs st))
      { plrStopDistance = putField (nonDefault s)
      , plrStopPose = putField (Just (poseToMsg (routeTfAt (pqRoute q) s))) }

-- | INVALID_ARGUMENT naming the first field (the message joins every problem), and every problem
-- apart.
planErrors :: Word64 -> Double -> [FieldError] -> PlanResponseMsg
planErrors rid secs errs = (bare rid secs PlanStatusInvalidArgument)
  { plrError = putField (Just (mkError ErrInvalidArgument firstField (renderFieldErrors errs)))
  , plrErrors = putField [ mkError ErrInvalidArgument (feField e) (renderFieldError e) | e <- errs ] }
  where
    firstField = case errs of
      e : _ -> feField e
      [] -> ""

-- | The time budget ran out: NOT_CONVERGED naming time_budget.
planBudgetMsg :: Word64 -> Double -> PlanQuery -> PlanResponseMsg
planBudgetMsg rid secs q = (withRoute q (bare rid secs PlanStatusBudget))
  { plrError = putField (Just (mkError ErrNotConverged "time_budget"
      ("the plan was not done within time_budget = " ++ showNumber (pqBudget q) ++ " s"))) }

-- | A bug: INTERNAL with what went wrong.
planInternal :: Word64 -> Double -> String -> PlanResponseMsg
planInternal rid secs msg = (bare rid secs PlanStatusInternal)
  { plrError = putField (Just (mkError ErrInternal "" ("internal error: " ++ msg))) }
