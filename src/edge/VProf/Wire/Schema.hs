-- | The field table of @proto/vprof/v1/vprof.proto@ as the wire walkers need it: for each
-- message and field number, how its value is encoded ('Kind') and its name (for messages
-- about bytes that are wrong). Fields not listed are unknown to this server (skipped, as
-- protoc does). Checked against the .proto file by VProf.Wire.SchemaSpec.
module VProf.Wire.Schema
  ( MsgType (..)
  , Kind (..)
  , fields
  , messageName
  , fieldName
  ) where

import Data.Word (Word64)

data MsgType
  = TRequest | TResponse | TProfileRequest | TSpeedLimit | TProfileResponse | TViolation
  | TError | TPoses | TCompressRequest | TCompressMetrics | TCompressedPath | TPing | TPong
  | TRobot | TPose | TFkRequest | TFkResponse | TMesh | TIkRequest | TIkSolution | TIkResponse
  | TCapsule | TSelectRequest | TSelectTarget | TSelectSegment | TSelectRobotResult | TSelectResponse
  | TPlanZone | TPlanRequest | TPlanResponse
  deriving (Eq, Show, Enum, Bounded)

-- | A field's encoding: a varint, a double, a string, a message, repeated doubles or
-- repeated integers (packed in proto3, unpacked from some encoders).
data Kind = KVarint | KF64 | KStr | KMsg MsgType | KPackedF64 | KPackedVarint

-- | The encoding of field number n of a message, when the schema has it.
fields :: MsgType -> Word64 -> Maybe Kind
fields t n = case t of
  TRequest -> lookup n [ (1, KVarint), (2, KMsg TProfileRequest), (3, KMsg TCompressRequest), (4, KMsg TPing)
                       , (5, KMsg TFkRequest), (6, KMsg TIkRequest), (7, KMsg TSelectRequest), (8, KMsg TPlanRequest) ]
  TResponse -> lookup n [ (1, KVarint), (2, KMsg TProfileResponse), (3, KMsg TCompressedPath), (4, KMsg TPong), (5, KMsg TError)
                        , (6, KMsg TFkResponse), (7, KMsg TIkResponse), (8, KMsg TSelectResponse), (9, KMsg TPlanResponse) ]
  TProfileRequest
    | n == 1 || n == 14 || n == 17 -> Just KVarint
    | n == 3 -> Just (KMsg TSpeedLimit)
    | n >= 2 && n <= 16 -> Just KF64
    | otherwise -> Nothing
  TSpeedLimit -> if n == 1 || n == 2 then Just KF64 else Nothing
  TProfileResponse
    | n `elem` [1, 9, 10, 11, 17] -> Just KVarint
    | n `elem` [2, 3, 12, 16] -> Just KF64
    | n >= 4 && n <= 8 -> Just KPackedF64
    | n == 13 -> Just (KMsg TViolation)
    | n == 14 || n == 15 -> Just (KMsg TError)
    | otherwise -> Nothing
  TViolation -> lookup n [(1, KStr), (2, KVarint), (3, KF64), (4, KF64), (5, KStr)]
  TError -> lookup n [(1, KVarint), (2, KStr), (3, KStr)]
  TPoses -> if n >= 1 && n <= 8 then Just KPackedF64 else Nothing
  TCompressRequest
    | n `elem` [1, 3, 4, 10, 11, 12] -> Just KVarint
    | n == 2 -> Just (KMsg TPoses)
    | n >= 5 && n <= 9 -> Just KF64
    | otherwise -> Nothing
  TCompressMetrics
    | n == 15 || n == 16 -> Just KVarint
    | n >= 1 && n <= 17 -> Just KF64
    | otherwise -> Nothing
  TCompressedPath -> lookup n [(1, KVarint), (2, KMsg TPoses), (3, KMsg TCompressMetrics), (4, KF64), (5, KMsg TError), (6, KStr)]
  TPing -> lookup n [(1, KStr)]
  TPong -> lookup n [(1, KStr), (2, KStr)]
  TRobot -> if n >= 1 && n <= 5 then Just KStr else Nothing
  TPose -> if n >= 1 && n <= 7 then Just KF64 else Nothing
  TFkRequest -> lookup n [(1, KVarint), (2, KMsg TRobot), (3, KPackedF64), (4, KVarint)]
  TFkResponse -> lookup n [ (1, KVarint), (2, KMsg TPose), (3, KMsg TPose), (4, KPackedF64), (5, KF64), (6, KF64)
                          , (7, KF64), (8, KMsg TError), (9, KVarint) ]
  TMesh -> lookup n [(1, KPackedF64), (2, KPackedVarint), (3, KF64), (4, KMsg TPose)]
  TIkRequest -> lookup n [ (1, KVarint), (2, KMsg TRobot), (3, KMsg TPose), (4, KPackedF64), (5, KVarint), (6, KF64)
                         , (7, KF64), (8, KF64), (9, KMsg TMesh), (10, KF64), (11, KPackedVarint) ]
  TIkSolution -> lookup n [(1, KPackedF64), (2, KF64), (3, KF64), (4, KStr), (5, KF64), (6, KF64), (7, KF64)]
  TIkResponse -> lookup n [(1, KVarint), (2, KMsg TIkSolution), (3, KStr), (4, KF64), (5, KMsg TError), (6, KVarint)]
  TCapsule -> if n >= 1 && n <= 7 then Just KF64 else Nothing
  TSelectRequest -> lookup n [ (1, KVarint), (2, KMsg TMesh), (3, KMsg TPose), (4, KMsg TPose), (5, KMsg TCapsule), (6, KF64)
                             , (7, KF64), (8, KMsg TPose), (9, KVarint), (10, KF64), (11, KMsg TRobot), (12, KPackedVarint) ]
  TSelectTarget -> lookup n [ (1, KStr), (2, KVarint), (3, KPackedF64), (4, KStr), (5, KF64), (6, KStr), (7, KF64)
                            , (8, KStr), (9, KVarint) ]
  TSelectSegment -> lookup n [(1, KVarint), (2, KVarint), (3, KVarint), (4, KStr)]
  TSelectRobotResult -> lookup n [ (1, KStr), (2, KStr), (3, KVarint), (4, KStr), (5, KMsg TSelectTarget)
                                 , (6, KMsg TSelectSegment), (7, KVarint), (8, KVarint), (9, KVarint), (10, KF64)
                                 , (11, KStr), (12, KF64), (13, KF64), (14, KStr), (15, KF64), (16, KVarint) ]
  TSelectResponse -> lookup n [(1, KVarint), (2, KMsg TSelectRobotResult), (3, KF64), (4, KMsg TError), (5, KMsg TError)]
  TPlanZone -> lookup n [(1, KF64), (2, KF64), (3, KF64), (4, KStr)]
  TPlanRequest -> lookup n [ (1, KVarint), (2, KMsg TPoses), (3, KMsg TRobot), (4, KMsg TPose), (5, KMsg TPose), (6, KMsg TMesh)
                           , (7, KF64), (8, KPackedVarint), (9, KF64), (10, KF64), (11, KF64), (12, KF64), (13, KF64)
                           , (14, KPackedF64), (15, KF64) ]
  TPlanResponse
    | n == 1 || n == 2 || n == 3 -> Just KVarint
    | n == 4 || n == 12 || n == 13 || n == 16 || n == 20 || n == 21 -> Just KF64
    | (n >= 5 && n <= 11) || n == 14 -> Just KPackedF64
    | n == 15 -> Just (KMsg TPlanZone)
    | n == 17 -> Just (KMsg TPose)
    | n == 18 || n == 19 -> Just KStr
    | n == 22 || n == 23 -> Just (KMsg TError)
    | otherwise -> Nothing
-- | The message's name in the schema.
messageName :: MsgType -> String
messageName = drop 1 . show

-- | The name of field number n of a message, as the schema spells it.
fieldName :: MsgType -> Word64 -> Maybe String
fieldName t n = lookup n $ case t of
  TSpeedLimit -> [(1, "start_distance"), (2, "velocity")]
  TProfileRequest ->
    [ (1, "request_id"), (2, "route_length"), (3, "speed_limits"), (4, "min_acceleration")
    , (5, "max_acceleration"), (6, "min_jerk"), (7, "max_jerk"), (8, "start_velocity")
    , (9, "start_acceleration"), (10, "end_velocity"), (11, "end_acceleration"), (12, "time_step")
    , (13, "velocity_step"), (14, "max_iterations"), (15, "time_budget"), (16, "end_tolerance")
    , (17, "algorithm") ]
  TError -> [(1, "code"), (2, "field"), (3, "message")]
  TViolation -> [(1, "rule"), (2, "sample"), (3, "value"), (4, "limit"), (5, "message")]
  TProfileResponse ->
    [ (1, "request_id"), (2, "time_step"), (3, "velocity_step"), (4, "time"), (5, "distance")
    , (6, "velocity"), (7, "acceleration"), (8, "jerk"), (9, "iterations"), (10, "converged")
    , (11, "legal"), (12, "compute_time"), (13, "violations"), (14, "error"), (15, "errors")
    , (16, "duration"), (17, "algorithm") ]
  TPoses -> [(1, "time"), (2, "x"), (3, "y"), (4, "z"), (5, "qw"), (6, "qx"), (7, "qy"), (8, "qz")]
  TCompressRequest ->
    [ (1, "request_id"), (2, "recording"), (3, "method"), (4, "points"), (5, "margin")
    , (6, "tolerance"), (7, "weight_position"), (8, "weight_orientation"), (9, "weight_velocity")
    , (10, "search_rounds"), (11, "free_ends"), (12, "least_squares_only") ]
  TCompressMetrics ->
    [ (1, "position_sse"), (2, "position_rmse"), (3, "position_mean"), (4, "position_max")
    , (5, "orientation_rmse"), (6, "orientation_mean"), (7, "orientation_max"), (8, "velocity_rmse")
    , (9, "velocity_mean"), (10, "velocity_max"), (11, "geometric_rmse"), (12, "geometric_max")
    , (13, "length_ratio"), (14, "orientation_ratio"), (15, "points"), (16, "samples")
    , (17, "reduction") ]
  TCompressedPath ->
    [ (1, "request_id"), (2, "path"), (3, "metrics"), (4, "compute_time"), (5, "error")
    , (6, "warnings") ]
  TRobot -> [(1, "name"), (2, "robot_file"), (3, "urdf"), (4, "base_link"), (5, "tip_link")]
  TPose -> [(1, "x"), (2, "y"), (3, "z"), (4, "qw"), (5, "qx"), (6, "qy"), (7, "qz")]
  TFkRequest -> [(1, "request_id"), (2, "robot"), (3, "joints"), (4, "link_frames")]
  TFkResponse ->
    [ (1, "request_id"), (2, "tool"), (3, "link_frames"), (4, "jacobian"), (5, "manipulability")
    , (6, "condition_number"), (7, "compute_time"), (8, "error"), (9, "dof") ]
  TMesh -> [(1, "vertices"), (2, "triangles"), (3, "scale"), (4, "pose")]
  TIkRequest ->
    [ (1, "request_id"), (2, "robot"), (3, "target"), (4, "seed"), (5, "all_solutions")
    , (6, "position_tolerance"), (7, "rotation_tolerance"), (8, "time_budget"), (9, "environment")
    , (10, "clearance"), (11, "ignore_bodies") ]
  TIkSolution ->
    [ (1, "joints"), (2, "position_error"), (3, "rotation_error"), (4, "branch")
    , (5, "manipulability"), (6, "clearance"), (7, "seed_distance") ]
  TIkResponse ->
    [ (1, "request_id"), (2, "solutions"), (3, "solver"), (4, "compute_time"), (5, "error")
    , (6, "dof") ]
  TCapsule -> [(1, "ax"), (2, "ay"), (3, "az"), (4, "bx"), (5, "by"), (6, "bz"), (7, "radius")]
  TSelectRequest ->
    [ (1, "request_id"), (2, "environment"), (3, "base"), (4, "tool"), (5, "tool_capsule")
    , (6, "payload"), (7, "clearance"), (8, "targets"), (9, "path"), (10, "path_step")
    , (11, "robots"), (12, "ignore_bodies") ]
  TSelectTarget ->
    [ (1, "label"), (2, "reached"), (3, "joints"), (4, "branch"), (5, "clearance")
    , (6, "clearance_body"), (7, "manipulability"), (8, "failure"), (9, "failure_code") ]
  TSelectSegment -> [(1, "from"), (2, "to"), (3, "samples"), (4, "failure")]
  TSelectRobotResult ->
    [ (1, "robot"), (2, "name"), (3, "rank"), (4, "rejected"), (5, "targets"), (6, "segments")
    , (7, "reached"), (8, "total"), (9, "complete"), (10, "min_clearance")
    , (11, "min_clearance_body"), (12, "min_manipulability"), (13, "cycle_time")
    , (14, "cycle_time_note"), (15, "score"), (16, "dof") ]
  TSelectResponse -> [(1, "request_id"), (2, "robots"), (3, "compute_time"), (4, "error"), (5, "errors")]
  TPlanZone -> [(1, "start_distance"), (2, "velocity"), (3, "end_distance"), (4, "binding")]
  TPlanRequest ->
    [ (1, "request_id"), (2, "waypoints"), (3, "robot"), (4, "base"), (5, "tool"), (6, "environment")
    , (7, "clearance"), (8, "ignore_bodies"), (9, "speed"), (10, "acceleration"), (11, "jerk")
    , (12, "zone"), (13, "time_step"), (14, "start"), (15, "time_budget") ]
  TPlanResponse ->
    [ (1, "request_id"), (2, "status"), (3, "dof"), (4, "time_step"), (5, "time"), (6, "distance")
    , (7, "velocity"), (8, "acceleration"), (9, "jerk"), (10, "q"), (11, "qd"), (12, "duration")
    , (13, "route_length"), (14, "stops"), (15, "zones"), (16, "stop_distance"), (17, "stop_pose")
    , (18, "stop_joint"), (19, "stop_body"), (20, "stop_value"), (21, "compute_time"), (22, "error")
    , (23, "errors") ]
  TPing -> [(1, "payload")]
  TPong -> [(1, "payload"), (2, "version")]
  TRequest ->
    [ (1, "request_id"), (2, "profile"), (3, "compress"), (4, "ping"), (5, "fk"), (6, "ik")
    , (7, "select"), (8, "plan") ]
  TResponse ->
    [ (1, "request_id"), (2, "profile"), (3, "compressed"), (4, "pong"), (5, "error"), (6, "fk")
    , (7, "ik"), (8, "select"), (9, "plan") ]
