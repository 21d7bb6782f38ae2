{-# LANGUAGE OverloadedStrings #-}
-- | The domain view of the daemon envelope (@Request@ / @Response@ of
-- @proto/vprof/v1/vprof.proto@). On the wire @oneof body@ is a set of optional fields of
-- which at most one may be present; 'classify' turns a decoded 'RequestMsg' into exactly
-- one 'Incoming' body or an 'ErrorMsg' naming the field @body@.
module VProf.Wire.Envelope
  ( Incoming (..)
  , incomingKind
  , classify
  , requestIdOf
    -- * Building responses
  , mkError
  , emptyResponse
  , errorResponse
  , pongResponse
  , profileResponse
  , compressedResponse
  , fkResponse
  , ikResponse
  , selectResponse
  , planResponse
  , responseKind
  , errorCodeName
  ) where

import qualified Data.Text as T
import Data.Text (Text)
import Data.ProtocolBuffers (getField, putField)
import Data.Word (Word64)

import VProf.Wire.Messages

data Incoming
  = InProfile ProfileRequestMsg
  | InCompress CompressRequestMsg
  | InPing PingMsg
  | InFk FkRequestMsg
  | InIk IkRequestMsg
  | InSelect SelectRequestMsg
  | InPlan PlanRequestMsg
  deriving (Eq, Show)

-- | "profile", "compress", "ping", "fk", "ik", "select" or "plan" (as logged).
incomingKind :: Incoming -> Text
incomingKind = \case
  InProfile _ -> "profile"
  InCompress _ -> "compress"
  InPing _ -> "ping"
  InFk _ -> "fk"
  InIk _ -> "ik"
  InSelect _ -> "select"
  InPlan _ -> "plan"

requestIdOf :: RequestMsg -> Word64
requestIdOf = orDefault . getField . reqRequestId

-- | Exactly one body, or an INVALID_ARGUMENT error naming @body@.
classify :: RequestMsg -> Either ErrorMsg Incoming
classify r = case bodies of
  [b] -> Right b
  [] -> Left (mkError ErrInvalidArgument "body"
               "Request.body is empty: set exactly one of profile, compress, ping, fk, ik, select, plan")
  bs -> Left (mkError ErrInvalidArgument "body"
               ("Request.body has " <> T.pack (show (length bs)) <> " bodies ("
                <> T.intercalate ", " (map incomingKind bs)
                <> "): set exactly one of profile, compress, ping, fk, ik, select, plan"))
  where
    bodies = maybe [] (pure . InProfile) (getField (reqProfile r))
          ++ maybe [] (pure . InCompress) (getField (reqCompress r))
          ++ maybe [] (pure . InPing) (getField (reqPing r))
          ++ maybe [] (pure . InFk) (getField (reqFk r))
          ++ maybe [] (pure . InIk) (getField (reqIk r))
          ++ maybe [] (pure . InSelect) (getField (reqSelect r))
          ++ maybe [] (pure . InPlan) (getField (reqPlan r))

mkError :: ErrorCodeEnum -> Text -> Text -> ErrorMsg
mkError code field msg = ErrorMsg
  { errCode = putField (enumField code)
  , errField = putField (nonDefault field)
  , errMessage = putField (nonDefault msg)
  }

-- | A Response with the request_id and no body.
emptyResponse :: Word64 -> ResponseMsg
emptyResponse rid = ResponseMsg
  { rspRequestId = putField (nonDefault rid)
  , rspProfile = putField Nothing
  , rspCompressed = putField Nothing
  , rspPong = putField Nothing
  , rspError = putField Nothing
  , rspFk = putField Nothing
  , rspIk = putField Nothing
  , rspSelect = putField Nothing
  , rspPlan = putField Nothing
  }

-- | A Response whose body is an Error.
errorResponse :: Word64 -> ErrorCodeEnum -> Text -> Text -> ResponseMsg
errorResponse rid code field msg =
  (emptyResponse rid) { rspError = putField (Just (mkError code field msg)) }

pongResponse :: Word64 -> Text -> Text -> ResponseMsg
pongResponse rid payload version =
  (emptyResponse rid) { rspPong = putField (Just (PongMsg (putField (nonDefault payload))
                                                          (putField (nonDefault version)))) }

profileResponse :: Word64 -> ProfileResponseMsg -> ResponseMsg
profileResponse rid p = (emptyResponse rid) { rspProfile = putField (Just p) }

compressedResponse :: Word64 -> CompressedPathMsg -> ResponseMsg
compressedResponse rid p = (emptyResponse rid) { rspCompressed = putField (Just p) }

fkResponse :: Word64 -> FkResponseMsg -> ResponseMsg
fkResponse rid p = (emptyResponse rid) { rspFk = putField (Just p) }

ikResponse :: Word64 -> IkResponseMsg -> ResponseMsg
ikResponse rid p = (emptyResponse rid) { rspIk = putField (Just p) }

selectResponse :: Word64 -> SelectResponseMsg -> ResponseMsg
selectResponse rid p = (emptyResponse rid) { rspSelect = putField (Just p) }

planResponse :: Word64 -> PlanResponseMsg -> ResponseMsg
planResponse rid p = (emptyResponse rid) { rspPlan = putField (Just p) }

-- | The body a response carries: "profile", "compressed", "pong", "error", "fk", "ik", "select",
-- "plan" or "empty".
responseKind :: ResponseMsg -> Text
responseKind r
  | Just _ <- getField (rspProfile r) = "profile"
  | Just _ <- getField (rspCompressed r) = "compressed"
  | Just _ <- getField (rspPong r) = "pong"
  | Just _ <- getField (rspError r) = "error"
  | Just _ <- getField (rspFk r) = "fk"
  | Just _ <- getField (rspIk r) = "ik"
  | Just _ <- getField (rspSelect r) = "select"
  | Just _ <- getField (rspPlan r) = "plan"
  | otherwise = "empty"

-- | The lower-case name of an error code as logged (@invalid_argument@, ...).
errorCodeName :: ErrorCodeEnum -> Text
errorCodeName = \case
  ErrUnspecified -> "unspecified"
  ErrInvalidArgument -> "invalid_argument"
  ErrInfeasible -> "infeasible"
  ErrNotConverged -> "not_converged"
  ErrMalformed -> "malformed"
  ErrFrameTooLarge -> "frame_too_large"
  ErrUnsupported -> "unsupported"
  ErrInternal -> "internal"
