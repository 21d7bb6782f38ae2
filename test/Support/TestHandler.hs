{-# LANGUAGE OverloadedStrings #-}
-- | A request handler for the daemon's own tests, apart from the real one in
-- "VProf.Service". 'testHandler': ping -> pong echoing the payload (a payload @sleep:SECONDS@ makes
-- it sleep first, for drain tests); profile -> a trivial ProfileResponse echoing
-- request_id (no samples: it is NOT a generator); compress -> CompressedPath with Error
-- UNSUPPORTED; fk and ik -> a Response whose body is an Error UNSUPPORTED.
module Support.TestHandler
  ( testHandler
  , testAnswer
  , pingMsg
  , profileMsg
  , requestWith
  , simpleProfileRequest
  ) where

import Control.Concurrent (threadDelay)
import Data.ProtocolBuffers (getField, putField)
import Data.Text (Text)
import qualified Data.Text as T
import Data.Word (Word64)

import VProf.Server (Handler (..))
import VProf.Wire.Envelope
import VProf.Wire.Messages

-- | The stub as a server 'Handler', with a time limit of a second for every body.
testHandler :: Handler
testHandler = Handler testAnswer (const 1)

testAnswer :: Word64 -> Incoming -> IO ResponseMsg
testAnswer rid = \case
  InPing p -> do
    let payload = orDefault (getField (pingPayload p)) :: Text
    case T.stripPrefix "sleep:" payload of
      Just s | [(secs, "")] <- reads (T.unpack s) -> threadDelay (round ((secs :: Double) * 1e6))
      _ -> pure ()
    pure (pongResponse rid payload "stub")
  InProfile p -> pure . profileResponse rid $ ProfileResponseMsg
    { prsRequestId = putField (getField (prqRequestId p))
    , prsTimeStep = putField (Just 0.125)
    , prsVelocityStep = putField Nothing
    , prsTime = putField [], prsDistance = putField [], prsVelocity = putField []
    , prsAcceleration = putField [], prsJerk = putField []
    , prsIterations = putField (Just 1)
    , prsConverged = putField (Just True)
    , prsLegal = putField (Just True)
    , prsComputeTime = putField Nothing
    , prsViolations = putField []
    , prsError = putField Nothing
    , prsErrors = putField []
    , prsDuration = putField Nothing
    , prsAlgorithm = putField (enumField AlgorithmBand)
    }
  InCompress c -> pure . compressedResponse rid $ CompressedPathMsg
    { cpRequestId = putField (getField (crqRequestId c))
    , cpPath = putField Nothing, cpMetrics = putField Nothing, cpComputeTime = putField Nothing
    , cpError = putField (Just (mkError ErrUnsupported "compress" "the test handler does not compress"))
    , cpWarnings = putField []
    }
  other -> pure (errorResponse rid ErrUnsupported "body" ("the test handler does not serve " <> incomingKind other))

-- | An envelope with the given bodies set.
requestWith :: Word64 -> Maybe ProfileRequestMsg -> Maybe CompressRequestMsg -> Maybe PingMsg -> RequestMsg
requestWith rid p c g = RequestMsg (putField (nonDefault rid)) (putField p) (putField c) (putField g)
                                   (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing)

pingMsg :: Word64 -> Text -> RequestMsg
pingMsg rid payload = requestWith rid Nothing Nothing (Just (PingMsg (putField (nonDefault payload))))

profileMsg :: Word64 -> ProfileRequestMsg -> RequestMsg
profileMsg rid p = requestWith rid (Just p) Nothing Nothing

-- | The thesis's "simple" case (4.4.1): 10 m, 4 m/s, |a| <= 1, |j| <= 2.
simpleProfileRequest :: Word64 -> ProfileRequestMsg
simpleProfileRequest rid = ProfileRequestMsg
  { prqRequestId = putField (nonDefault rid)
  , prqRouteLength = putField (Just 10)
  , prqSpeedLimits = putField [SpeedLimitMsg (putField Nothing) (putField (Just 4))]
  , prqMinAcceleration = putField (Just (-1))
  , prqMaxAcceleration = putField (Just 1)
  , prqMinJerk = putField (Just (-2))
  , prqMaxJerk = putField (Just 2)
  , prqStartVelocity = putField Nothing
  , prqStartAcceleration = putField Nothing
  , prqEndVelocity = putField Nothing
  , prqEndAcceleration = putField Nothing
  , prqTimeStep = putField Nothing
  , prqVelocityStep = putField Nothing
  , prqMaxIterations = putField Nothing
  , prqTimeBudget = putField Nothing
  , prqEndTolerance = putField Nothing
  , prqAlgorithm = putField Nothing
  }
