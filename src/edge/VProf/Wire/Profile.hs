{-# LANGUAGE TypeFamilies #-}
{-# LANGUAGE OverloadedStrings #-}
-- | The message handler (thesis 4.6.1): Protobuf records of "VProf.Wire.Messages" to the
-- @dimensional@ domain of "VProf.Profile.Request" and results back. proto3 defaults become
-- 'Nothing' ("0 means default"); nothing is validated here, "VProf.Profile.Request" does that.
module VProf.Wire.Profile
  ( requestFromMsg
  , requestToMsg
  , resultToMsg
  , failureToErrors
  , errorMsg
  ) where

import Data.ProtocolBuffers (getField, putField)
import qualified Data.Text as T
import qualified Data.Vector.Unboxed as U
import Data.Word (Word64)

import VProf.Profile.Generate
import VProf.Profile.Legality
import VProf.Profile.Sampled
import VProf.Profile.Request
import VProf.Units
import VProf.Wire.Messages

dbl :: Maybe Double -> Double
dbl = orDefault

requestFromMsg :: ProfileRequestMsg -> Request
requestFromMsg m = Request
  { rqRouteLength = dbl (getField (prqRouteLength m)) *~ meter
  , rqZones = [ SpeedZone (dbl (getField (slStartDistance z)) *~ meter) (dbl (getField (slVelocity z)) *~ mps)
              | z <- getField (prqSpeedLimits m) ]
  , rqMinAcceleration = dbl (getField (prqMinAcceleration m)) *~ mps2
  , rqMaxAcceleration = dbl (getField (prqMaxAcceleration m)) *~ mps2
  , rqMinJerk = dbl (getField (prqMinJerk m)) *~ mps3
  , rqMaxJerk = dbl (getField (prqMaxJerk m)) *~ mps3
  , rqStartVelocity = dbl (getField (prqStartVelocity m)) *~ mps
  , rqStartAcceleration = dbl (getField (prqStartAcceleration m)) *~ mps2
  , rqEndVelocity = dbl (getField (prqEndVelocity m)) *~ mps
  , rqEndAcceleration = dbl (getField (prqEndAcceleration m)) *~ mps2
  , rqTimeStep = (*~ second) <$> positive (prqTimeStep m)
  , rqVelocityStep = (*~ mps) <$> positive (prqVelocityStep m)
  , rqMaxIterations = case getField (prqMaxIterations m) of
      Just n | n > 0 -> Just (fromIntegral n)
      _ -> Nothing
  , rqTimeBudget = (*~ second) <$> positive (prqTimeBudget m)
  , rqEndTolerance = (*~ meter) <$> positive (prqEndTolerance m)
  , rqAlgorithm = case getEnum (getField (prqAlgorithm m)) of
      AlgorithmThesis -> Thesis
      _ -> Band
  , rqSeedSearch = True
  }
  where
    -- 0 (absent) means the default; any other value, even a bad one, goes to validation
    positive f = case getField f of
      Just x | x /= 0 -> Just x
      _ -> Nothing

requestToMsg :: Word64 -> Request -> ProfileRequestMsg
requestToMsg rid r = ProfileRequestMsg
  { prqRequestId = putField (nonDefault rid)
  , prqRouteLength = d (si (rqRouteLength r))
  , prqSpeedLimits = putField [ SpeedLimitMsg (d (si (zoneStart z))) (d (si (zoneSpeed z))) | z <- rqZones r ]
  , prqMinAcceleration = d (si (rqMinAcceleration r))
  , prqMaxAcceleration = d (si (rqMaxAcceleration r))
  , prqMinJerk = d (si (rqMinJerk r))
  , prqMaxJerk = d (si (rqMaxJerk r))
  , prqStartVelocity = d (si (rqStartVelocity r))
  , prqStartAcceleration = d (si (rqStartAcceleration r))
  , prqEndVelocity = d (si (rqEndVelocity r))
  , prqEndAcceleration = d (si (rqEndAcceleration r))
  , prqTimeStep = d (maybe 0 si (rqTimeStep r))
  , prqVelocityStep = d (maybe 0 si (rqVelocityStep r))
  , prqMaxIterations = putField (nonDefault (maybe 0 fromIntegral (rqMaxIterations r)))
  , prqTimeBudget = d (maybe 0 si (rqTimeBudget r))
  , prqEndTolerance = d (maybe 0 si (rqEndTolerance r))
  , prqAlgorithm = putField (enumField (case rqAlgorithm r of Band -> AlgorithmDefault; Thesis -> AlgorithmThesis))
  }
  where d x = putField (nonDefault x)

errorMsg :: ErrorCodeEnum -> String -> String -> ErrorMsg
errorMsg code fld msg = ErrorMsg
  { errCode = putField (enumField code)
  , errField = putField (nonDefault (T.pack fld))
  , errMessage = putField (nonDefault (T.pack msg))
  }

-- | The main error and the list of all errors for a failure.
failureToErrors :: Failure -> (ErrorMsg, [ErrorMsg])
failureToErrors = \case
  InvalidRequest es ->
    let all' = [ errorMsg ErrInvalidArgument (feField e) (renderFieldError e) | e <- es ]
    in (case all' of (e : _) -> e; [] -> errorMsg ErrInvalidArgument "" "invalid request", all')
  f@(InfeasibleRequest fld _) -> (errorMsg ErrInfeasible fld (renderFailure f), [])
  f@(NotConverged _) -> (errorMsg ErrNotConverged "" (renderFailure f), [])

resultToMsg :: Word64 -> Result -> ProfileResponseMsg
resultToMsg rid r = ProfileResponseMsg
  { prsRequestId = putField (nonDefault rid)
  , prsTimeStep = d (resTimeStep r)
  , prsVelocityStep = d (resVelStep r)
  , prsTime = putField (arr colTime)
  , prsDistance = putField (arr colDistance)
  , prsVelocity = putField (arr colVelocity)
  , prsAcceleration = putField (arr colAcceleration)
  , prsJerk = putField (arr colJerk)
  , prsIterations = putField (nonDefault (fromIntegral (resIterations r)))
  , prsConverged = putField (nonDefault (resConverged r))
  , prsLegal = putField (nonDefault legal)
  , prsComputeTime = d (resSeconds r)
  , prsViolations = putField (map violationMsg (resViolations r))
  , prsError = putField (fmap fst failure)
  , prsErrors = putField (maybe [] snd failure)
  , prsDuration = d (maybe 0 duration (resProfile r))
  , prsAlgorithm = putField (enumField (case resAlgorithm r of Band -> AlgorithmBand; Thesis -> AlgorithmThesis))
  }
  where
    d x = putField (nonDefault x)
    arr f = maybe [] (U.toList . f . columns) (resProfile r)
    legal = resultLegal r
    failure = case resOutcome r of
      Generated -> Nothing
      Failed f -> Just (failureToErrors f)

violationMsg :: Violation -> ViolationMsg
violationMsg v = ViolationMsg
  { vioRule = putField (nonDefault (T.pack (ruleName (vRule v))))
  , vioSample = putField (nonDefault (fromIntegral (vSample v)))
  , vioValue = putField (nonDefault (vValue v))
  , vioLimit = putField (nonDefault (vLimit v))
  , vioMessage = putField (nonDefault (T.pack (renderViolation v)))
  }
