{-# LANGUAGE OverloadedStrings #-}
-- | What the daemon does with one decoded request envelope. Never throws: every failure,
-- including a bug, becomes an 'ErrorMsg' in the response.
module VProf.Service
  ( handleRequest
  , serveProfile
  , version
  , unsupportedCompress
  ) where

import Control.Exception (SomeException, evaluate, try)
import Data.ProtocolBuffers (getField, putField)
import qualified Data.Text as T

import VProf.Profile.Generate
import VProf.Profile.Request (Algorithm (..))
import VProf.Wire.Profile
import VProf.Wire.Messages

version :: String
version = "0.1.0"

-- | Generate a profile for one request; the request's own time budget applies.
serveProfile :: ProfileRequestMsg -> IO ProfileResponseMsg
serveProfile m = do
  let rid = orDefault (getField (prqRequestId m))
  r <- try (generate (requestFromMsg m) >>= \res -> evaluate (resultToMsg rid res))
  pure $ case r of
    Right msg -> msg
    Left (e :: SomeException) -> (resultToMsg rid emptyResult)
      { prsError = putField (Just (errorMsg ErrInternal "" ("internal error: " ++ show e))) }
  where
    emptyResult = Result (Failed (NotConverged "internal error")) Nothing [] 0 False Band 0 0 0

handleRequest :: (CompressRequestMsg -> IO CompressedPathMsg) -> RequestMsg -> IO ResponseMsg
handleRequest compress m = do
  let rid = getField (reqRequestId m)
      base = ResponseMsg (putField rid) (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing)
      bodies = length (filter id [ has (reqProfile m), has (reqCompress m), has (reqPing m) ])
      has f = maybe False (const True) (getField f)
      err code fld msg = base { rspError = putField (Just (errorMsg code fld msg)) }
  r <- try $ case (getField (reqProfile m), getField (reqCompress m), getField (reqPing m)) of
    _ | bodies /= 1 ->
          pure (err ErrInvalidArgument "body" ("a Request must carry exactly one body (profile, compress or ping); it has " ++ show bodies))
    (Just p, _, _) -> do
      resp <- serveProfile p { prqRequestId = putField (nonDefault (orDefault rid)) }
      pure base { rspProfile = putField (Just resp) }
    (_, Just c, _) -> do
      resp <- compress c
      pure base { rspCompressed = putField (Just resp) }
    (_, _, Just pg) ->
      pure base { rspPong = putField (Just (PongMsg (putField (getField (pingPayload pg))) (putField (nonDefault (T.pack version))))) }
    _ -> pure (err ErrInvalidArgument "body" "empty request")
  pure $ case r of
    Right resp -> resp
    Left (e :: SomeException) -> err ErrInternal "" ("internal error: " ++ show e)

-- | Until a compression service is plugged in: answer UNSUPPORTED.
unsupportedCompress :: CompressRequestMsg -> IO CompressedPathMsg
unsupportedCompress m = pure CompressedPathMsg
  { cpRequestId = putField (getField (crqRequestId m))
  , cpPath = putField Nothing
  , cpMetrics = putField Nothing
  , cpComputeTime = putField Nothing
  , cpError = putField (Just (errorMsg ErrUnsupported "" "path compression is not served by this build"))
  }
