-- | The field table of @proto/vprof/v1/vprof.proto@ as the wire walkers need it: for each
-- message and field number, how its value is encoded ('Kind'). Fields not listed are unknown
-- to this server (skipped, as protoc does).
module VProf.Wire.Schema
  ( MsgType (..)
  , Kind (..)
  , fields
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
    | n `elem` [1, 3, 4, 10] -> Just KVarint
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
