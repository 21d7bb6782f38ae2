{-# LANGUAGE OverloadedStrings #-}
-- | The daemon's request handler: one classified request body (profile, compress, ping, fk, ik,
-- select or plan) to one response, and how long each kind may take. Never throws: every failure,
-- including a bug, becomes an 'ErrorMsg' in the response.
module VProf.Service
  ( service
  , answer
  , timeLimit
  ) where

import Control.Exception (SomeException, try)
import Data.ProtocolBuffers (getField, putField)
import qualified Data.Text as T
import Data.Word (Word64)

import VProf.Server (Handler (..))
import VProf.Service.Compress
import VProf.Service.Kinematics
import VProf.Service.Plan
import VProf.Service.Profile
import VProf.Service.Select
import VProf.Version (versionString)
import VProf.Wire.Envelope
import VProf.Wire.Messages

-- | The handler @vprof serve@ runs.
service :: Handler
service = Handler answer timeLimit

-- | Answer one body; the envelope's request_id is also the profile, FK, IK, select and plan
-- response's.
answer :: Word64 -> Incoming -> IO ResponseMsg
answer rid inc = do
  r <- try $ case inc of
    InProfile p -> profileResponse rid <$> serveProfile p { prqRequestId = putField (nonDefault rid) }
    InCompress c -> compressedResponse rid <$> serveCompress c
    InFk f -> fkResponse rid <$> serveFk f { fkqRequestId = putField (nonDefault rid) }
    InIk k -> ikResponse rid <$> serveIk k { ikqRequestId = putField (nonDefault rid) }
    InSelect sq -> selectResponse rid <$> serveSelect sq { slqRequestId = putField (nonDefault rid) }
    InPlan pq -> planResponse rid <$> servePlan pq { plqRequestId = putField (nonDefault rid) }
    InPing pg -> pure (emptyResponse rid)
      { rspPong = putField (Just (PongMsg (putField (getField (pingPayload pg))) (putField (nonDefault (T.pack versionString))))) }
  pure $ case r of
    Right resp -> resp
    Left (e :: SomeException) -> errorResponse rid ErrInternal "" ("internal error: " <> T.pack (show e))

-- | Seconds a body may take before the server's grace.
timeLimit :: Incoming -> Double
timeLimit = \case
  InProfile p -> profileTimeLimit p
  InCompress _ -> compressTimeLimit
  InPing _ -> 0
  InFk _ -> fkTimeLimit
  InIk k -> ikTimeLimit k
  InSelect sq -> selectTimeLimit sq
  InPlan pq -> planTimeLimit pq
