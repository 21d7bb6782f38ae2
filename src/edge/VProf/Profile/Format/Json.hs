{-# LANGUAGE OverloadedStrings #-}
-- | Requests and profiles as JSON, with the proto3 JSON field names of
-- @proto/vprof/v1/vprof.proto@ (snake_case as in the schema; the lowerCamelCase form that
-- proto3 JSON printers emit is accepted too). Absent fields take their proto3 default,
-- exactly as on the wire. Unknown keys (a case's @name@, @note@, reference figures) are
-- ignored.
module VProf.Profile.Format.Json
  ( requestFromJson
  , requestFromValue
  , profileToJson
  ) where

import Data.Aeson hiding (Result)
import qualified Data.Aeson.Key as K
import qualified Data.Aeson.KeyMap as KM
import Data.Aeson.Types (Parser, parseEither)
import qualified Data.ByteString.Lazy as BL
import Data.Char (toUpper)
import qualified Data.Text as T
import qualified Data.Vector.Unboxed as U

import VProf.Profile.Generate
import VProf.Profile.Legality
import VProf.Profile.Sampled
import VProf.Profile.Request
import VProf.Units

requestFromJson :: BL.ByteString -> Either String Request
requestFromJson bs = eitherDecode bs >>= requestFromValue

requestFromValue :: Value -> Either String Request
requestFromValue = parseEither parseRequest

-- | Look a field up by its snake_case name or its lowerCamelCase form.
field :: FromJSON a => Object -> String -> a -> Parser a
field o name def = case KM.lookup (K.fromString name) o of
  Just v -> named v
  Nothing -> case KM.lookup (K.fromString (camel name)) o of
    Just v -> named v
    Nothing -> pure def
  where
    named Null = pure def
    named v = parseJSON v `orFail` name
    orFail p n = either (\e -> fail (n ++ ": " ++ e)) pure (parseEither (const p) ())
    camel s = case break (== '_') s of
      (a, '_' : c : rest) -> a ++ camel (toUpper c : rest)
      (a, _) -> a

parseRequest :: Value -> Parser Request
parseRequest = withObject "ProfileRequest" $ \o -> do
  len <- field o "route_length" 0
  zonesV <- field o "speed_limits" []
  zones <- mapM parseZone zonesV
  aMin <- field o "min_acceleration" 0
  aMax <- field o "max_acceleration" 0
  jMin <- field o "min_jerk" 0
  jMax <- field o "max_jerk" 0
  v0 <- field o "start_velocity" 0
  a0 <- field o "start_acceleration" 0
  vE <- field o "end_velocity" 0
  aE <- field o "end_acceleration" 0
  dt <- field o "time_step" 0
  dv <- field o "velocity_step" 0
  it <- field o "max_iterations" (0 :: Int)
  budget <- field o "time_budget" 0
  tol <- field o "end_tolerance" 0
  alg <- field o "algorithm" (String "ALGORITHM_DEFAULT") >>= parseAlgorithm
  let opt x = if x == 0 then Nothing else Just x
  pure Request
    { rqRouteLength = len *~ meter
    , rqZones = zones
    , rqMinAcceleration = aMin *~ mps2, rqMaxAcceleration = aMax *~ mps2
    , rqMinJerk = jMin *~ mps3, rqMaxJerk = jMax *~ mps3
    , rqStartVelocity = v0 *~ mps, rqStartAcceleration = a0 *~ mps2
    , rqEndVelocity = vE *~ mps, rqEndAcceleration = aE *~ mps2
    , rqTimeStep = fmap (*~ second) (opt dt)
    , rqVelocityStep = fmap (*~ mps) (opt dv)
    , rqMaxIterations = if it == 0 then Nothing else Just it
    , rqTimeBudget = fmap (*~ second) (opt budget)
    , rqEndTolerance = fmap (*~ meter) (opt tol)
    , rqAlgorithm = alg
    }

parseZone :: Value -> Parser SpeedZone
parseZone = withObject "SpeedLimit" $ \o -> do
  st <- field o "start_distance" 0
  v <- field o "velocity" 0
  pure (SpeedZone (st *~ meter) (v *~ mps))

parseAlgorithm :: Value -> Parser Algorithm
parseAlgorithm = \case
  String s -> case T.toUpper s of
    "ALGORITHM_DEFAULT" -> pure Band
    "ALGORITHM_BAND" -> pure Band
    "BAND" -> pure Band
    "ALGORITHM_THESIS" -> pure Thesis
    "THESIS" -> pure Thesis
    other -> fail ("algorithm: unknown value " ++ show other ++ " (ALGORITHM_DEFAULT, ALGORITHM_BAND or ALGORITHM_THESIS)")
  Number n
    | n == 0 || n == 1 -> pure Band
    | n == 2 -> pure Thesis
    | otherwise -> fail ("algorithm: unknown value " ++ show n)
  v -> fail ("algorithm: expected a string or number, got " ++ show v)

-- | The result as JSON, with the response's field names.
profileToJson :: Result -> Value
profileToJson r = object $
  [ "time_step" .= resTimeStep r
  , "velocity_step" .= resVelStep r
  , "iterations" .= resIterations r
  , "converged" .= resConverged r
  , "legal" .= resultLegal r
  , "compute_time" .= resSeconds r
  , "algorithm" .= (case resAlgorithm r of Band -> "ALGORITHM_BAND" :: String; Thesis -> "ALGORITHM_THESIS")
  , "violations" .= [ object [ "rule" .= ruleName (vRule v), "sample" .= vSample v, "value" .= vValue v
                             , "limit" .= vLimit v, "message" .= renderViolation v ]
                    | v <- resViolations r ]
  ] ++ case resProfile r of
         Nothing -> []
         Just p ->
           [ "duration" .= duration p
           , "time" .= U.toList (colTime c)
           , "distance" .= U.toList (colDistance c)
           , "velocity" .= U.toList (colVelocity c)
           , "acceleration" .= U.toList (colAcceleration c)
           , "jerk" .= U.toList (colJerk c)
           ]
           where c = columns p
    ++ case resOutcome r of
         Generated -> []
         Failed f -> [ "error" .= object [ "field" .= failureField f, "message" .= renderFailure f ] ]
