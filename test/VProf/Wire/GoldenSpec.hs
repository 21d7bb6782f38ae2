{-# LANGUAGE OverloadedStrings #-}
{-# LANGUAGE TypeFamilies #-}
{-# LANGUAGE NoMonoLocalBinds #-}
-- | Byte-level agreement with protoc's generated code. For every @test/golden/NAME.json@
-- (a value-level description, see @test/golden/make_golden.py@) the Haskell records are
-- built from the same JSON and
--
-- * encode to exactly the bytes of @NAME.bin@ (written by protoc-generated Python);
-- * @NAME.bin@ decodes to the same record (bit-exact doubles: -0.0 is not 0.0);
-- * @NAME.bin@ passes the strict wire check, and every truncation of it that cuts a
--   field is rejected by it.
--
-- Note: the records are built with 'present', which keeps -0.0 (proto3 writes it, since
-- it is not the default bit pattern); 'nonDefault' of "VProf.Wire.Messages" drops it.
module VProf.Wire.GoldenSpec (spec) where

import Control.Monad
import qualified Data.Aeson as A
import qualified Data.Aeson.Key as K
import qualified Data.Aeson.KeyMap as KM
import Data.Aeson.Types (Parser, parseEither)
import qualified Data.ByteString as B
import Data.List (isSuffixOf, sort)
import Data.ProtocolBuffers (putField)
import Data.Scientific (toBoundedInteger, toRealFloat)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Vector as V
import Data.Word (Word32, Word64)
import System.Directory (listDirectory)
import System.FilePath ((</>), dropExtension)
import Test.Hspec

import VProf.Wire.Messages
import VProf.Wire.Validate

goldenDir :: FilePath
goldenDir = "test/golden"

data Built = BRequest RequestMsg | BResponse ResponseMsg deriving (Eq, Show)

spec :: Spec
spec = do
  names <- runIO (sort . map dropExtension . filter (".json" `isSuffixOf`) <$> listDirectory goldenDir)
  it "has golden vectors (requests and responses)" $ do
    length (filter (T.isPrefixOf "req_" . T.pack) names) `shouldSatisfy` (>= 5)
    length (filter (T.isPrefixOf "rsp_" . T.pack) names) `shouldSatisfy` (>= 5)
  forM_ names $ \name -> describe name $ do
    let load = do
          json <- B.readFile (goldenDir </> name ++ ".json")
          bin <- B.readFile (goldenDir </> name ++ ".bin")
          built <- either (fail . (("bad golden JSON " ++ name ++ ": ") ++)) pure
                     (A.eitherDecodeStrict json >>= parseEither parseGolden)
          pure (built, bin)
    it "Haskell encodes the same bytes as protoc's Python" $ do
      (built, bin) <- load
      encodeBuilt built `shouldBe` bin
    it "Haskell decodes protoc's bytes to the same value (bit-exact doubles)" $ do
      (built, bin) <- load
      case built of
        BRequest r -> fmap (encodeBare :: RequestMsg -> B.ByteString) (decodeBare bin) `shouldBe` Right (encodeBare r)
        BResponse r -> fmap (encodeBare :: ResponseMsg -> B.ByteString) (decodeBare bin) `shouldBe` Right (encodeBare r)
      case built of
        BRequest r -> decodeBare bin `shouldBe` Right r
        BResponse r -> decodeBare bin `shouldBe` Right r
    it "passes the strict wire check; truncations inside a field fail it" $ do
      (built, bin) <- load
      let ty = case built of BRequest _ -> TRequest; BResponse _ -> TResponse
      validateWire ty bin `shouldBe` Right ()
      -- cutting the last byte always cuts inside the last field
      unless (B.null bin) $
        validateWire ty (B.take (B.length bin - 1) bin) `shouldSatisfy` either (const True) (const False)

encodeBuilt :: Built -> B.ByteString
encodeBuilt (BRequest r) = encodeBare r
encodeBuilt (BResponse r) = encodeBare r

----------------------------------------------------------------------------- JSON -> records

type Obj = KM.KeyMap A.Value

parseGolden :: A.Value -> Parser Built
parseGolden = A.withObject "golden" $ \o -> do
  m <- o A..: "message" :: Parser Text
  v <- o A..: "value"
  case m of
    "Request" -> BRequest <$> A.withObject "Request" request v
    "Response" -> BResponse <$> A.withObject "Response" response v
    _ -> fail ("unknown message " ++ T.unpack m)

field :: Obj -> Text -> Maybe A.Value
field o k = KM.lookup (K.fromText k) o

-- | A double from a JSON number or a string ("-0", "1e308").
toDouble :: A.Value -> Parser Double
toDouble (A.Number n) = pure (toRealFloat n)
toDouble (A.String s) = case reads (T.unpack (fixup s)) of
  [(d, "")] -> pure d
  _ -> fail ("not a double: " ++ show s)
  where fixup t = if T.isPrefixOf "." t then "0" <> t else t
toDouble v = fail ("not a double: " ++ show v)

toIntegral :: forall a. (Integral a, Bounded a) => A.Value -> Parser a
toIntegral (A.Number n) = maybe (fail ("out of range: " ++ show n)) pure (toBoundedInteger n)
toIntegral (A.String s) = case reads (T.unpack s) of
  [(i, "")] | i >= toInteger (minBound :: a) && i <= toInteger (maxBound :: a) -> pure (fromInteger i)
  _ -> fail ("not an integer: " ++ show s)
toIntegral v = fail ("not an integer: " ++ show v)

-- | proto3 presence: absent when the default bit pattern (so -0.0 is present).
present :: Double -> Maybe Double
present x = if x == 0 && not (isNegativeZero x) then Nothing else Just x

dbl :: Obj -> Text -> Parser (Maybe Double)
dbl o k = maybe (pure Nothing) (fmap present . toDouble) (field o k)

u64 :: Obj -> Text -> Parser (Maybe Word64)
u64 o k = maybe (pure Nothing) (fmap nonDefault . toIntegral) (field o k)

u32 :: Obj -> Text -> Parser (Maybe Word32)
u32 o k = maybe (pure Nothing) (fmap nonDefault . toIntegral) (field o k)

bool :: Obj -> Text -> Parser (Maybe Bool)
bool o k = maybe (pure Nothing) (fmap nonDefault . A.parseJSON) (field o k)

str :: Obj -> Text -> Parser (Maybe Text)
str o k = maybe (pure Nothing) (fmap nonDefault . A.parseJSON) (field o k)

enum :: Enum e => [Text] -> Obj -> Text -> Parser (Maybe e)
enum names o k = case field o k of
  Nothing -> pure Nothing
  Just (A.String s) | Just i <- lookup s (zip names [0 ..]) -> pure (enumField (toEnum i))
  Just v -> fail ("bad enum value for " ++ T.unpack k ++ ": " ++ show v)

dbls :: Obj -> Text -> Parser [Double]
dbls o k = maybe (pure []) (A.withArray (T.unpack k) (mapM toDouble . V.toList)) (field o k)

msg :: (Obj -> Parser a) -> Obj -> Text -> Parser (Maybe a)
msg p o k = maybe (pure Nothing) (fmap Just . A.withObject (T.unpack k) p) (field o k)

msgs :: (Obj -> Parser a) -> Obj -> Text -> Parser [a]
msgs p o k = maybe (pure []) (A.withArray (T.unpack k) (mapM (A.withObject (T.unpack k) p) . V.toList)) (field o k)

algorithmNames, errorCodeNames, compressMethodNames :: [Text]
algorithmNames = ["ALGORITHM_DEFAULT", "ALGORITHM_BAND", "ALGORITHM_THESIS"]
errorCodeNames = [ "ERROR_CODE_UNSPECIFIED", "ERROR_CODE_INVALID_ARGUMENT", "ERROR_CODE_INFEASIBLE"
                 , "ERROR_CODE_NOT_CONVERGED", "ERROR_CODE_MALFORMED", "ERROR_CODE_FRAME_TOO_LARGE"
                 , "ERROR_CODE_UNSUPPORTED", "ERROR_CODE_INTERNAL" ]
compressMethodNames = ["COMPRESS_METHOD_DEFAULT", "COMPRESS_METHOD_THESIS", "COMPRESS_METHOD_RDP", "COMPRESS_METHOD_KNOTS"]

request :: Obj -> Parser RequestMsg
request o = RequestMsg <$> (putField <$> u64 o "request_id") <*> (putField <$> msg profileRequest o "profile")
  <*> (putField <$> msg compressRequest o "compress") <*> (putField <$> msg ping o "ping")
  <*> (putField <$> msg fkRequest o "fk") <*> (putField <$> msg ikRequest o "ik")
  <*> (putField <$> msg selectRequest o "select") <*> (putField <$> msg planRequest o "plan")

response :: Obj -> Parser ResponseMsg
response o = ResponseMsg <$> (putField <$> u64 o "request_id") <*> (putField <$> msg profileResponse o "profile")
  <*> (putField <$> msg compressedPath o "compressed") <*> (putField <$> msg pong o "pong")
  <*> (putField <$> msg errorMsg o "error")
  <*> (putField <$> msg fkResponse o "fk") <*> (putField <$> msg ikResponse o "ik")
  <*> (putField <$> msg selectResponse o "select") <*> (putField <$> msg planResponse o "plan")

ping :: Obj -> Parser PingMsg
ping o = PingMsg . putField <$> str o "payload"

pong :: Obj -> Parser PongMsg
pong o = PongMsg <$> (putField <$> str o "payload") <*> (putField <$> str o "version")

errorMsg :: Obj -> Parser ErrorMsg
errorMsg o = ErrorMsg <$> (putField <$> enum errorCodeNames o "code") <*> (putField <$> str o "field")
  <*> (putField <$> str o "message")

speedLimit :: Obj -> Parser SpeedLimitMsg
speedLimit o = SpeedLimitMsg <$> (putField <$> dbl o "start_distance") <*> (putField <$> dbl o "velocity")

profileRequest :: Obj -> Parser ProfileRequestMsg
profileRequest o = ProfileRequestMsg
  <$> (putField <$> u64 o "request_id") <*> d "route_length"
  <*> (putField <$> msgs speedLimit o "speed_limits")
  <*> d "min_acceleration" <*> d "max_acceleration" <*> d "min_jerk" <*> d "max_jerk"
  <*> d "start_velocity" <*> d "start_acceleration" <*> d "end_velocity" <*> d "end_acceleration"
  <*> d "time_step" <*> d "velocity_step" <*> (putField <$> u32 o "max_iterations")
  <*> d "time_budget" <*> d "end_tolerance" <*> (putField <$> enum algorithmNames o "algorithm")
  where d k = putField <$> dbl o k

violation :: Obj -> Parser ViolationMsg
violation o = ViolationMsg <$> (putField <$> str o "rule") <*> (putField <$> u32 o "sample")
  <*> (putField <$> dbl o "value") <*> (putField <$> dbl o "limit") <*> (putField <$> str o "message")

profileResponse :: Obj -> Parser ProfileResponseMsg
profileResponse o = ProfileResponseMsg
  <$> (putField <$> u64 o "request_id") <*> d "time_step" <*> d "velocity_step"
  <*> ds "time" <*> ds "distance" <*> ds "velocity" <*> ds "acceleration" <*> ds "jerk"
  <*> (putField <$> u32 o "iterations") <*> (putField <$> bool o "converged")
  <*> (putField <$> bool o "legal") <*> d "compute_time"
  <*> (putField <$> msgs violation o "violations") <*> (putField <$> msg errorMsg o "error")
  <*> (putField <$> msgs errorMsg o "errors") <*> d "duration"
  <*> (putField <$> enum algorithmNames o "algorithm")
  where d k = putField <$> dbl o k
        ds k = putField <$> dbls o k

poses :: Obj -> Parser PosesMsg
poses o = PosesMsg <$> ds "time" <*> ds "x" <*> ds "y" <*> ds "z" <*> ds "qw" <*> ds "qx" <*> ds "qy" <*> ds "qz"
  where ds k = putField <$> dbls o k

compressRequest :: Obj -> Parser CompressRequestMsg
compressRequest o = CompressRequestMsg
  <$> (putField <$> u64 o "request_id") <*> (putField <$> msg poses o "recording")
  <*> (putField <$> enum compressMethodNames o "method") <*> (putField <$> u32 o "points")
  <*> d "margin" <*> d "tolerance" <*> d "weight_position" <*> d "weight_orientation" <*> d "weight_velocity"
  <*> (putField <$> u32 o "search_rounds") <*> (putField <$> bool o "free_ends")
  <*> (putField <$> bool o "least_squares_only")
  where d k = putField <$> dbl o k

compressMetrics :: Obj -> Parser CompressMetricsMsg
compressMetrics o = CompressMetricsMsg
  <$> d "position_sse" <*> d "position_rmse" <*> d "position_mean" <*> d "position_max"
  <*> d "orientation_rmse" <*> d "orientation_mean" <*> d "orientation_max"
  <*> d "velocity_rmse" <*> d "velocity_mean" <*> d "velocity_max"
  <*> d "geometric_rmse" <*> d "geometric_max" <*> d "length_ratio" <*> d "orientation_ratio"
  <*> (putField <$> u32 o "points") <*> (putField <$> u32 o "samples") <*> d "reduction"
  where d k = putField <$> dbl o k

compressedPath :: Obj -> Parser CompressedPathMsg
compressedPath o = CompressedPathMsg
  <$> (putField <$> u64 o "request_id") <*> (putField <$> msg poses o "path")
  <*> (putField <$> msg compressMetrics o "metrics") <*> (putField <$> dbl o "compute_time")
  <*> (putField <$> msg errorMsg o "error") <*> pure (putField [])

u32s :: Obj -> Text -> Parser [Word32]
u32s o k = maybe (pure []) (A.withArray (T.unpack k) (mapM toIntegral . V.toList)) (field o k)

robot :: Obj -> Parser RobotMsg
robot o = RobotMsg <$> s "name" <*> s "robot_file" <*> s "urdf" <*> s "base_link" <*> s "tip_link"
  where s k = putField <$> str o k

pose :: Obj -> Parser PoseMsg
pose o = PoseMsg <$> d "x" <*> d "y" <*> d "z" <*> d "qw" <*> d "qx" <*> d "qy" <*> d "qz"
  where d k = putField <$> dbl o k

fkRequest :: Obj -> Parser FkRequestMsg
fkRequest o = FkRequestMsg <$> (putField <$> u64 o "request_id") <*> (putField <$> msg robot o "robot")
  <*> (putField <$> dbls o "joints") <*> (putField <$> bool o "link_frames")

fkResponse :: Obj -> Parser FkResponseMsg
fkResponse o = FkResponseMsg <$> (putField <$> u64 o "request_id") <*> (putField <$> msg pose o "tool")
  <*> (putField <$> msgs pose o "link_frames") <*> (putField <$> dbls o "jacobian")
  <*> d "manipulability" <*> d "condition_number" <*> d "compute_time"
  <*> (putField <$> msg errorMsg o "error") <*> (putField <$> u32 o "dof")
  where d k = putField <$> dbl o k

mesh :: Obj -> Parser MeshMsg
mesh o = MeshMsg <$> (putField <$> dbls o "vertices") <*> (putField <$> u32s o "triangles")
  <*> (putField <$> dbl o "scale") <*> (putField <$> msg pose o "pose")

ikRequest :: Obj -> Parser IkRequestMsg
ikRequest o = IkRequestMsg <$> (putField <$> u64 o "request_id") <*> (putField <$> msg robot o "robot")
  <*> (putField <$> msg pose o "target") <*> (putField <$> dbls o "seed") <*> (putField <$> bool o "all_solutions")
  <*> d "position_tolerance" <*> d "rotation_tolerance" <*> d "time_budget"
  <*> (putField <$> msgs mesh o "environment") <*> d "clearance" <*> (putField <$> u32s o "ignore_bodies")
  where d k = putField <$> dbl o k

ikSolution :: Obj -> Parser IkSolutionMsg
ikSolution o = IkSolutionMsg <$> (putField <$> dbls o "joints") <*> d "position_error" <*> d "rotation_error"
  <*> (putField <$> str o "branch") <*> d "manipulability" <*> d "clearance" <*> d "seed_distance"
  where d k = putField <$> dbl o k

ikResponse :: Obj -> Parser IkResponseMsg
ikResponse o = IkResponseMsg <$> (putField <$> u64 o "request_id") <*> (putField <$> msgs ikSolution o "solutions")
  <*> (putField <$> str o "solver") <*> (putField <$> dbl o "compute_time")
  <*> (putField <$> msg errorMsg o "error") <*> (putField <$> u32 o "dof")

selectFailureNames :: [Text]
selectFailureNames = [ "SELECT_FAILURE_NONE", "SELECT_FAILURE_REACH", "SELECT_FAILURE_JOINT_LIMITS"
                     , "SELECT_FAILURE_ORIENTATION", "SELECT_FAILURE_COLLISION", "SELECT_FAILURE_SINGULAR"
                     , "SELECT_FAILURE_BUDGET", "SELECT_FAILURE_PATH", "SELECT_FAILURE_OTHER" ]

capsule :: Obj -> Parser CapsuleMsg
capsule o = CapsuleMsg <$> d "ax" <*> d "ay" <*> d "az" <*> d "bx" <*> d "by" <*> d "bz" <*> d "radius"
  where d k = putField <$> dbl o k

selectRequest :: Obj -> Parser SelectRequestMsg
selectRequest o = SelectRequestMsg <$> (putField <$> u64 o "request_id") <*> (putField <$> msgs mesh o "environment")
  <*> (putField <$> msg pose o "base") <*> (putField <$> msg pose o "tool") <*> (putField <$> msg capsule o "tool_capsule")
  <*> d "payload" <*> d "clearance" <*> (putField <$> msgs pose o "targets") <*> (putField <$> bool o "path")
  <*> d "path_step" <*> (putField <$> msgs robot o "robots") <*> (putField <$> u32s o "ignore_bodies")
  where d k = putField <$> dbl o k

selectTarget :: Obj -> Parser SelectTargetMsg
selectTarget o = SelectTargetMsg <$> s "label" <*> (putField <$> bool o "reached") <*> (putField <$> dbls o "joints")
  <*> s "branch" <*> d "clearance" <*> s "clearance_body" <*> d "manipulability" <*> s "failure"
  <*> (putField <$> enum selectFailureNames o "failure_code")
  where d k = putField <$> dbl o k
        s k = putField <$> str o k

selectSegment :: Obj -> Parser SelectSegmentMsg
selectSegment o = SelectSegmentMsg <$> (putField <$> u32 o "from") <*> (putField <$> u32 o "to")
  <*> (putField <$> u32 o "samples") <*> (putField <$> str o "failure")

selectRobotResult :: Obj -> Parser SelectRobotResultMsg
selectRobotResult o = SelectRobotResultMsg <$> s "robot" <*> s "name" <*> (putField <$> u32 o "rank") <*> s "rejected"
  <*> (putField <$> msgs selectTarget o "targets") <*> (putField <$> msgs selectSegment o "segments")
  <*> (putField <$> u32 o "reached") <*> (putField <$> u32 o "total") <*> (putField <$> bool o "complete")
  <*> d "min_clearance" <*> s "min_clearance_body" <*> d "min_manipulability" <*> d "cycle_time"
  <*> s "cycle_time_note" <*> d "score" <*> (putField <$> u32 o "dof")
  where d k = putField <$> dbl o k
        s k = putField <$> str o k

selectResponse :: Obj -> Parser SelectResponseMsg
selectResponse o = SelectResponseMsg <$> (putField <$> u64 o "request_id") <*> (putField <$> msgs selectRobotResult o "robots")
  <*> (putField <$> dbl o "compute_time") <*> (putField <$> msg errorMsg o "error") <*> (putField <$> msgs errorMsg o "errors")

planStatusNames :: [Text]
planStatusNames = [ "PLAN_STATUS_UNSPECIFIED", "PLAN_STATUS_OK", "PLAN_STATUS_INVALID_ARGUMENT", "PLAN_STATUS_OUT_OF_REACH"
                  , "PLAN_STATUS_JOINT_LIMIT", "PLAN_STATUS_SINGULARITY", "PLAN_STATUS_JUMP", "PLAN_STATUS_COLLISION"
                  , "PLAN_STATUS_NO_SOLUTION", "PLAN_STATUS_NO_PROFILE", "PLAN_STATUS_BUDGET", "PLAN_STATUS_INTERNAL" ]

planRequest :: Obj -> Parser PlanRequestMsg
planRequest o = PlanRequestMsg <$> (putField <$> u64 o "request_id") <*> (putField <$> msg poses o "waypoints")
  <*> (putField <$> msg robot o "robot") <*> (putField <$> msg pose o "base") <*> (putField <$> msg pose o "tool")
  <*> (putField <$> msgs mesh o "environment") <*> d "clearance" <*> (putField <$> u32s o "ignore_bodies")
  <*> d "speed" <*> d "acceleration" <*> d "jerk" <*> d "zone" <*> d "time_step"
  <*> (putField <$> dbls o "start") <*> d "time_budget"
  where d k = putField <$> dbl o k

planZone :: Obj -> Parser PlanZoneMsg
planZone o = PlanZoneMsg <$> d "start_distance" <*> d "velocity" <*> d "end_distance" <*> (putField <$> str o "binding")
  where d k = putField <$> dbl o k

planResponse :: Obj -> Parser PlanResponseMsg
planResponse o = PlanResponseMsg <$> (putField <$> u64 o "request_id") <*> (putField <$> enum planStatusNames o "status")
  <*> (putField <$> u32 o "dof") <*> d "time_step"
  <*> ds "time" <*> ds "distance" <*> ds "velocity" <*> ds "acceleration" <*> ds "jerk" <*> ds "q" <*> ds "qd"
  <*> d "duration" <*> d "route_length" <*> ds "stops" <*> (putField <$> msgs planZone o "zones")
  <*> d "stop_distance" <*> (putField <$> msg pose o "stop_pose") <*> (putField <$> str o "stop_joint")
  <*> (putField <$> str o "stop_body") <*> d "stop_value" <*> d "compute_time"
  <*> (putField <$> msg errorMsg o "error") <*> (putField <$> msgs errorMsg o "errors")
  where d k = putField <$> dbl o k
        ds k = putField <$> dbls o k
