{-# LANGUAGE OverloadedStrings #-}
-- | Robot selection on the wire: a 'SelectRequestMsg' to the core's 'Task', its cell (the inline
-- meshes composed into one bounding-volume hierarchy) and the robots to check, with every
-- validation problem at once, each naming the proto field and the value in its unit
-- (@payload = -1.0 kg: must be >= 0@, @targets[2].qw = NaN@, @robots[1].name = "ur55": ...@,
-- @environment[0].triangles[5] = 9: is not a vertex index ...@); and the core's ranked
-- 'RobotResult's back to a 'SelectResponseMsg'.
--
-- The meshes, base and targets are in the world (the cell's) frame; the task's tool is the tool
-- frame in the flange frame. No robots means the whole library.
module VProf.Wire.Select
  ( SelectQuery (..)
  , selectFromMsg
  , selectToMsg
  , selectErrors
  , failureCode
  ) where

import Data.Char (isAlphaNum, toLower)
import Data.List (isPrefixOf)
import Data.ProtocolBuffers (getField, putField)
import qualified Data.Text as T
import qualified Data.Vector.Unboxed as U
import Data.Word (Word64)

import VProf.Geometry.Bvh (Bvh, buildBvh)
import VProf.Geometry.Mesh (composeScene)
import VProf.Kinematics
import VProf.Kinematics.Library (libraryRobots)
import VProf.Select.Selection
import VProf.Select.Task
import VProf.Validation (FieldValue (..), ensureFinite, renderFieldErrors)
import VProf.Wire.Kinematics (meshFromMsg, mkError, poseFromMsg, robotFromMsg)
import VProf.Wire.Messages

-- | A validated selection request: the task (its environment list is empty: the cell is the
-- hierarchy), the cell, and the robots by key (a library key, or an inline robot's name).
data SelectQuery = SelectQuery
  { sqTask :: Task
  , sqCell :: Bvh
  , sqRobots :: [(String, Robot)]
  }

norm :: String -> String
norm = map toLower . filter isAlphaNum

-- | The library key of a name as the client spelt it ("UR5", "franka panda"), else the name.
libraryKey :: String -> String
libraryKey n = case [ k | (k, Right r) <- libraryRobots, norm k == norm n || norm (robotName r) == norm n ] of
  k : _ -> k
  [] -> n

-- | A robot's errors name @robots[i]@, @robots[i].name@ ... instead of @robot@, @robot.name@.
renameRobot :: Int -> FieldError -> FieldError
renameRobot i e
  | "robot" `isPrefixOf` feField e = e { feField = "robots[" ++ show i ++ "]" ++ drop 5 (feField e) }
  | otherwise = e

lefts' :: Either [e] a -> [e]
lefts' = either id (const [])

selectFromMsg :: SelectRequestMsg -> Either [FieldError] SelectQuery
selectFromMsg m =
  let envs = zipWith (\i e -> meshFromMsg ("environment[" ++ show i ++ "]") e) [0 :: Int ..] (getField (slqEnvironment m))
      base = maybe (Right identity) (poseFromMsg "base") (getField (slqBase m))
      tool = maybe (Right identity) (poseFromMsg "tool") (getField (slqTool m))
      capsule = case getField (slqToolCapsule m) of
        Nothing -> Right Nothing
        Just c ->
          let [ax, ay, az, bx, by, bz, r] = map orDefault
                [ getField (cslMsgAx c), getField (cslMsgAy c), getField (cslMsgAz c), getField (cslMsgBx c)
                , getField (cslMsgBy c), getField (cslMsgBz c), getField (cslMsgRadius c) ] :: [Double]
              bad = concat [ ensureFinite ("tool_capsule." ++ k) v "m" []
                           | (k, v) <- zip ["ax", "ay", "az", "bx", "by", "bz"] [ax, ay, az, bx, by, bz] ]
          in if null bad then Right (Just (Capsule (V3 ax ay az) (V3 bx by bz) r)) else Left bad
      targetMsgs = getField (slqTargets m)
      targets = [ Target label <$> poseFromMsg label p
                | (i, p) <- zip [0 :: Int ..] targetMsgs, let label = "targets[" ++ show i ++ "]" ]
      robotMsgs = getField (slqRobots m)
      robots
        | null robotMsgs = [ Right (k, r) | (k, Right r) <- libraryRobots ]
        | otherwise =
            [ either (Left . map (renameRobot i)) (\(r, _) -> Right (key r, r)) (robotFromMsg (Just rm))
            | (i, rm) <- zip [0 :: Int ..] robotMsgs
            , let name = T.unpack (orDefault (getField (robName rm)))
                  key r = if null (filter isAlphaNum name) then robotName r else libraryKey name ]
      pathStep = let s = orDefault (getField (slqPathStep m)) :: Double in
        if s == 0 then Right defaultPathStep
        else if s > 0 && s < 1 / 0 then Right s
        else Left [FieldError "path_step" (Number s) "m" "must be a finite number > 0 (0 means 0.005)"]
      task = Task
        { taskEnvironment = []
        , taskBase = either (const identity) id base
        , taskTool = either (const identity) id tool
        , taskToolCapsule = either (const Nothing) id capsule
        , taskPayload = orDefault (getField (slqPayload m))
        , taskClearance = orDefault (getField (slqClearance m))
        , taskIgnoreBodies = map fromIntegral (getField (slqIgnoreBodies m))
        , taskTargets = [ t | Right t <- targets ]
        , taskPath = orDefault (getField (slqPath m))
        , taskPathStep = either (const defaultPathStep) id pathStep
        }
      -- checkTask names payload, clearance, tool_capsule.radius, ignore_bodies and an empty
      -- target list; a target whose pose is bad is named by its own error instead
      taskErrs = [ e | e <- checkTask task, not (feField e == "targets" && not (null targetMsgs)) ]
      errs = concatMap lefts' envs ++ lefts' base ++ lefts' tool ++ lefts' capsule ++ lefts' pathStep
          ++ taskErrs ++ concatMap lefts' targets ++ concatMap lefts' robots
  in case errs of
       _ : _ -> Left errs
       [] -> Right SelectQuery
         { sqTask = task
         , sqCell = buildBvh (composeScene [ p | Right p <- envs ])
         , sqRobots = [ kr | Right kr <- robots ] }

-- | The code of a target's failure.
failureCode :: FailureKind -> SelectFailureEnum
failureCode = \case
  FailReach -> SelectFailureReach
  FailJointLimits -> SelectFailureJointLimits
  FailOrientation -> SelectFailureOrientation
  FailCollision -> SelectFailureCollision
  FailSingular -> SelectFailureSingular
  FailBudget -> SelectFailureBudget
  FailOther -> SelectFailureOther

txt :: String -> Maybe T.Text
txt = nonDefault . T.pack

-- | The ranked results (best first, as 'scoreAndRank' returns them).
selectToMsg :: Word64 -> Double -> SelectQuery -> [RobotResult] -> SelectResponseMsg
selectToMsg rid secs q ranked = SelectResponseMsg
  { slrRequestId = putField (nonDefault rid)
  , slrRobots = putField (zipWith robotMsg [1 ..] ranked)
  , slrComputeTime = putField (nonDefault secs)
  , slrError = putField Nothing
  , slrErrors = putField []
  }
  where
    dofOf key = case [ r | (k, r) <- sqRobots q, k == key ] of
      r : _ -> length (robotJoints r)
      [] -> 0
    robotMsg rank r = SelectRobotResultMsg
      { srRobot = putField (txt (rrKey r))
      , srName = putField (txt (rrName r))
      , srRank = putField (nonDefault rank)
      , srRejected = putField (txt =<< rrRejected r)
      , srTargets = putField (zipWith (targetMsg r) [0 :: Int ..] (rrTargets r))
      , srSegments = putField [ SelectSegmentMsg (putField (nonDefault (fromIntegral (sgFrom s))))
                                                 (putField (nonDefault (fromIntegral (sgTo s))))
                                                 (putField (nonDefault (fromIntegral (sgSamples s))))
                                                 (putField (txt =<< sgFailure s))
                              | s <- rrSegments r ]
      , srReached = putField (nonDefault (fromIntegral (rrReached r)))
      , srTotal = putField (nonDefault (fromIntegral (rrTotal r)))
      , srComplete = putField (nonDefault (robotComplete r))
      , srMinClearance = putField (nonDefault . fst =<< rrMinClearance r)
      , srMinClearanceBody = putField (txt . snd =<< rrMinClearance r)
      , srMinManipulability = putField (nonDefault =<< rrMinManipulability r)
      , srCycleTime = putField (nonDefault =<< rrCycleTime r)
      , srCycleTimeNote = putField (txt =<< rrCycleNote r)
      , srScore = putField (nonDefault (rrScore r))
      , srDof = putField (nonDefault (fromIntegral (dofOf (rrKey r))))
      }
    targetMsg r i t =
      let segFailure = [ f | s <- rrSegments r, sgTo s == i, Just f <- [sgFailure s] ]
          (failure, code) = case (trFailure t, trFailureKind t, segFailure) of
            (Just f, k, _) -> (Just f, maybe SelectFailureOther failureCode k)
            (Nothing, _, f : _) -> (Just f, SelectFailurePath)
            _ -> (Nothing, SelectFailureNone)
      in SelectTargetMsg
        { stLabel = putField (txt (trLabel t))
        , stReached = putField (nonDefault (maybe False (const True) (trJoints t) && null segFailure))
        , stJoints = putField (maybe [] U.toList (trJoints t))
        , stBranch = putField (txt =<< trBranch t)
        , stClearance = putField (nonDefault =<< trClearance t)
        , stClearanceBody = putField (txt =<< trClearanceBody t)
        , stManipulability = putField (nonDefault =<< trManipulability t)
        , stFailure = putField (txt =<< failure)
        , stFailureCode = putField (enumField code)
        }

-- | A response carrying only errors: INVALID_ARGUMENT naming the first field (the message joins
-- every problem), and every problem apart.
selectErrors :: Word64 -> Double -> [FieldError] -> SelectResponseMsg
selectErrors rid secs errs = SelectResponseMsg
  { slrRequestId = putField (nonDefault rid)
  , slrRobots = putField []
  , slrComputeTime = putField (nonDefault secs)
  , slrError = putField (Just (mkError ErrInvalidArgument firstField (joined errs)))
  , slrErrors = putField [ mkError ErrInvalidArgument (feField e) (renderFieldError e) | e <- errs ]
  }
  where
    firstField = case errs of
      e : _ -> feField e
      [] -> ""
    joined = renderFieldErrors

