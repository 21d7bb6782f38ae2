{-# LANGUAGE OverloadedStrings #-}
-- | Requests and profiles as JSON, with the proto3 JSON field names of
-- @proto/vprof/v1/vprof.proto@ (snake_case as in the schema; the lowerCamelCase form that
-- proto3 JSON printers emit is accepted too). Absent fields take their proto3 default,
-- exactly as on the wire. Unknown keys (a case's @name@, @note@, reference figures) are
-- ignored, but for one a letter or two from a field's name ('misspelt'): its value would be
-- lost and the field's default taken, so it is refused, naming the field meant.
module VProf.Profile.Format.Json
  ( requestFromJson
  , requestFromValue
  , requestIdFromJson
  , profileToJson
  , profileJson
  , profileJsonFor
  ) where

import Data.Aeson hiding (Result)
import qualified Data.Aeson.Encoding as E
import qualified Data.Aeson.Key as K
import qualified Data.Aeson.KeyMap as KM
import Data.Aeson.Types (Parser, parseEither)
import qualified Data.ByteString.Builder as BB
import qualified Data.ByteString.Lazy as BL
import Data.Char (isAlphaNum, toUpper)
import Data.List (intercalate, stripPrefix)
import Data.Maybe (fromMaybe)
import Data.Scientific (floatingOrInteger, toRealFloat)
import Data.Word (Word64)
import qualified Data.Text as T
import qualified Data.Vector.Unboxed as U

import VProf.Format.DuplicateKeys (duplicateJsonKeyErrors)
import VProf.Format.Misspelt (misspelt)
import VProf.Format.Chunked (chunkRanges, renderChunked)
import VProf.Format.Number (doubleBuilder)
import VProf.Format.Text (dropBomLazy)
import VProf.Profile.Generate
import VProf.Profile.Legality
import VProf.Profile.Sampled
import VProf.Profile.Request
import VProf.Units

-- | A request from proto3 JSON (a UTF-8 byte-order mark before it is passed over); an error
-- names the field ("speed_limits[0]: ...") without the parser's own path notation.
requestFromJson :: BL.ByteString -> Either String Request
requestFromJson bs0 = case duplicateJsonKeyErrors (BL.toStrict bs) of
  [] -> plainError (eitherDecode bs >>= requestFromValue)
  dups -> Left (intercalate "; " dups)
  where bs = dropBomLazy bs0

requestFromValue :: Value -> Either String Request
requestFromValue = plainError . parseEither parseRequest

-- | A message as a nested field's: ".field: ..." when it names one, else ": ...".
under :: String -> String
under m = let (k, rest) = break (== ':') m
          in if not (null rest) && not (null k) && all (\c -> isAlphaNum c || c == '_' || c == '[' || c == ']' || c == '.') k
               then '.' : m else ": " ++ m

-- | An aeson error without its path prefixes: "Error in $: x" is "x", "Error in $.a[0]: x" is
-- "a[0]: x" (the request's own messages name their fields).
plainError :: Either String a -> Either String a
plainError = either (Left . plainMessage) Right

plainMessage :: String -> String
plainMessage e = case stripPrefix "Error in $" e of
  Just rest -> let (path, msg) = break (== ':') rest
                   msg' = plainMessage (dropWhile (== ' ') (drop 1 msg))
               in case dropWhile (== '.') path of
                    "" -> msg'
                    p -> p ++ ": " ++ msg'
  Nothing -> quotedContext e

-- | The parser's "at '...'" context (the text where it stopped, up to the end of the file)
-- cut to 20 characters, and those that are not printable ASCII escaped: a binary file's bytes
-- were written to the terminal as they were.
quotedContext :: String -> String
quotedContext e = case T.breakOn " at '" (T.pack e) of
  (pre, rest) | not (T.null rest) ->
    let ctx = T.drop 5 rest
        body = T.unpack (fromMaybe ctx (T.stripSuffix "'" ctx))
    in T.unpack pre ++ " at " ++ show (take 20 body) ++ (if null (drop 20 body) then "" else " ...")
  _ -> e

-- | The request's @request_id@ (0 when absent), which a response echoes; an id that is not
-- a uint64 is an error naming it.
requestIdFromJson :: BL.ByteString -> Either String Word64
requestIdFromJson bs = plainError (eitherDecode (dropBomLazy bs) >>= parseEither (withObject "ProfileRequest" requestId))

requestId :: Object -> Parser Word64
requestId o = fieldWith protoUInt64 o "request_id" 0

-- | Look a field up by its snake_case name or its lowerCamelCase form.
field :: FromJSON a => Object -> String -> a -> Parser a
field = fieldWith parseJSON

-- | A double as proto3 JSON writes it: a number, or a string holding a number,
-- @"NaN"@, @"Infinity"@ or @"-Infinity"@. Non-finite values are valid JSON here; the
-- request's validation rejects them by field name.
protoDouble :: Value -> Parser Double
protoDouble = \case
  Number n -> pure (toRealFloat n)
  String t -> case T.unpack (T.strip t) of
    "NaN" -> pure (0 / 0)
    "Infinity" -> pure (1 / 0)
    "-Infinity" -> pure (-1 / 0)
    str -> case reads (leadingZero str) of
      [(x, "")] -> pure x
      _ -> fail ("expected a number, \"NaN\", \"Infinity\" or \"-Infinity\", got the string " ++ show t)
  v -> fail ("expected a number, got " ++ describeValue v)
  where
    -- Haskell's reads wants a digit before the point (".5", "-.5" are valid JSON strings)
    leadingZero = \case
      '-' : '.' : r -> "-0." ++ r
      '.' : r -> "0." ++ r
      '+' : r -> r
      r -> r

-- | A uint32 field: an integer from 0 to 2^32 - 1 (a larger one would wrap on the wire).
protoUInt32 :: Value -> Parser Int
protoUInt32 = fmap fromIntegral . protoUnsigned "uint32" 4294967295

-- | A uint64 field (proto3 JSON writes it as a string): an integer from 0 to 2^64 - 1.
protoUInt64 :: Value -> Parser Word64
protoUInt64 = fmap fromIntegral . protoUnsigned "uint64" 18446744073709551615

-- | An integer from 0 to the type's largest value, else the range in the message.
protoUnsigned :: String -> Integer -> Value -> Parser Integer
protoUnsigned ty top v = do
  k <- protoInteger v
  if k < 0 || k > top
    then fail (show k ++ " is outside the range of a " ++ ty ++ ", 0 to " ++ show top)
    else pure k

-- | An integer as proto3 JSON writes it: a whole number, or a string holding one.
protoInteger :: Value -> Parser Integer
protoInteger = \case
  String t -> case reads (T.unpack (T.strip t)) of
    [(n, "")] -> pure n
    _ -> fail ("expected an integer, got the string " ++ show t)
  Number n | abs n >= 1e30 -> fail (show n ++ " is far outside the range of an integer field")
           | Right k <- (floatingOrInteger n :: Either Double Integer) -> pure k
  x -> fail ("expected an integer, got " ++ describeValue x)

-- | A JSON value as an error message shows it: a number, a string quoted, true, false, null,
-- "an object", "an array".
describeValue :: Value -> String
describeValue = \case
  Number n -> show (toRealFloat n :: Double)
  Object _ -> "an object"
  Array _ -> "an array"
  Bool b -> if b then "true" else "false"
  String t -> show t
  Null -> "null"

dbl :: Object -> String -> Parser Double
dbl o name = fieldWith protoDouble o name 0

fieldWith :: (Value -> Parser a) -> Object -> String -> a -> Parser a
fieldWith parse o name def = case KM.lookup (K.fromString name) o of
  Just _ | camel name /= name, KM.member (K.fromString (camel name)) o ->
    fail (name ++ " and " ++ camel name ++ ": the same field twice (in its two spellings); which value was meant?")
  Just v -> named v
  Nothing -> case KM.lookup (K.fromString (camel name)) o of
    Just v -> named v
    Nothing -> pure def
  where
    named Null = pure def
    named v = parse v `orFail` name
    orFail p n = either (\e -> fail (n ++ ": " ++ plainMessage e)) pure (parseEither (const p) ())
    camel = camelCase

-- | The fields of a request and of a speed limit, in the schema's spelling.
requestFields, zoneFields :: [String]
requestFields =
  [ "request_id", "route_length", "speed_limits", "min_acceleration", "max_acceleration", "min_jerk", "max_jerk"
  , "start_velocity", "start_acceleration", "end_velocity", "end_acceleration", "time_step", "velocity_step"
  , "max_iterations", "time_budget", "end_tolerance", "algorithm" ]
zoneFields = ["start_distance", "velocity"]

-- | Refuse a key a letter or two from a field's name (in either spelling, snake_case or
-- lowerCamelCase), naming it and the field.
noMisspelt :: [String] -> Object -> Parser ()
noMisspelt fields o =
  case [ (k, f) | k <- map K.toString (KM.keys o), k `notElem` spellings, Just f <- [misspelt fields k] ] of
    [] -> pure ()
    bad -> fail (intercalate "; " [ k ++ ": unknown field; did you mean " ++ f ++ "?" | (k, f) <- bad ])
  where spellings = fields ++ map camelCase fields

-- | A field's lowerCamelCase spelling, as proto3 JSON printers write it.
camelCase :: String -> String
camelCase s = case break (== '_') s of
  (a, '_' : c : rest) -> a ++ camelCase (toUpper c : rest)
  (a, _) -> a

parseRequest :: Value -> Parser Request
parseRequest = withObject "ProfileRequest" $ \o -> do
  noMisspelt requestFields o
  _ <- requestId o  -- checked here; 'requestIdFromJson' reads it for the response
  len <- dbl o "route_length"
  zonesV <- field o "speed_limits" []
  -- each zone's errors name it by its place in the list
  zones <- mapM (\(i, z) -> either (\e -> fail ("speed_limits[" ++ show i ++ "]" ++ under (plainMessage e))) pure (parseEither parseZone z))
                (zip [0 :: Int ..] zonesV)
  aMin <- dbl o "min_acceleration"
  aMax <- dbl o "max_acceleration"
  jMin <- dbl o "min_jerk"
  jMax <- dbl o "max_jerk"
  v0 <- dbl o "start_velocity"
  a0 <- dbl o "start_acceleration"
  vE <- dbl o "end_velocity"
  aE <- dbl o "end_acceleration"
  dt <- dbl o "time_step"
  dv <- dbl o "velocity_step"
  it <- fieldWith protoUInt32 o "max_iterations" 0
  budget <- dbl o "time_budget"
  tol <- dbl o "end_tolerance"
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
    , rqSeedSearch = True
    }

parseZone :: Value -> Parser SpeedZone
parseZone = withObject "SpeedLimit" $ \o -> do
  noMisspelt zoneFields o
  st <- dbl o "start_distance"
  v <- dbl o "velocity"
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
  v -> fail ("algorithm: expected a string or number, got " ++ describeValue v)

-- | The result as JSON, with the response's field names.
profileToJson :: Result -> Value
profileToJson r = object $
  summaryPairs r
  ++ [ k .= U.toList xs | Just p <- [resProfile r], (k, xs) <- sampleColumns p ]

-- | Every field of the result's JSON but the sample columns.
summaryPairs :: Result -> [(Key, Value)]
summaryPairs r =
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
  ] ++ [ "duration" .= duration p | Just p <- [resProfile r] ]
    ++ case resOutcome r of
         Generated -> []
         Failed f -> [ "error" .= object [ "field" .= failureField f, "message" .= renderFailure f ] ]

-- | The sample columns of a profile, by their JSON names.
sampleColumns :: Profile -> [(Key, U.Vector Double)]
sampleColumns p =
  [ ("time", colTime c), ("distance", colDistance c), ("velocity", colVelocity c)
  , ("acceleration", colAcceleration c), ("jerk", colJerk c) ]
  where c = columns p

-- | 'profileToJson' as the bytes the CLI writes, fast at the sample cap's scale: the sample
-- columns are written with the exact number format of the CSV ("VProf.Format.Number", which
-- reads back to the same double) straight into the builder, never as aeson 'Value's (a
-- million of them per column, and aeson's own double printing takes some 20 µs a number).
-- A non-finite number, which a profile never holds, would be @null@.
profileJson :: Result -> BL.ByteString
profileJson = profileJsonFor 0

-- | 'profileJson' answering the request with this @request_id@ (written, as proto3 JSON
-- writes a uint64, as a string; left out when 0).
profileJsonFor :: Word64 -> Result -> BL.ByteString
profileJsonFor rid r = E.encodingToLazyByteString $
  E.pairs ((if rid == 0 then mempty else "request_id" .= show rid)
           <> mconcat [ k .= v | (k, v) <- summaryPairs r ]
           <> mconcat [ E.pair k (doubles xs) | Just p <- [resProfile r], (k, xs) <- sampleColumns p ])
  where
    -- a column straight into the builder: '[', the numbers with commas, ']'; rendered
    -- 32768 numbers a piece on every core ("VProf.Format.Chunked")
    doubles xs = E.unsafeToEncoding $
      BB.char7 '[' <> BB.lazyByteString (renderChunked [ piece i m xs | (i, m) <- chunkRanges 32768 (U.length xs) ])
      <> BB.char7 ']'
    piece i m xs = U.ifoldr (\k x rest -> (if i + k == 0 then mempty else BB.char7 ',') <> number x <> rest)
                            mempty (U.slice i m xs)
    number x
      | isNaN x || isInfinite x = BB.string7 "null"
      | otherwise = doubleBuilder x
