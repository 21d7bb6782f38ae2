{-# LANGUAGE OverloadedStrings #-}
-- | Reads a robot-selection task file (YAML, or JSON since YAML is a superset) into a
-- 'VProf.Select.Task.Task', with its path file (RAPID @.mod@, TUM, or the CSV @vprof compress@
-- writes) read into targets. The layout is documented in docs/select.md.
--
-- Relative file names are relative to the task file's directory; a name starting with
-- @$VPROF_SHARED/@ is looked up in that directory (default: @../shared@ relative to the current
-- directory). Every problem is reported with its place: the field's path in the task file
-- (@targets[2].position@) and its value, or the path file's line.
module VProf.Select.Format.Task
  ( readTaskFile
  , readTaskFileWarned
  , parseTask
  , readPathTargets
  , resolvePath
  , taskFileInputs
  ) where

import Control.Exception (IOException, try)
import VProf.Format.IOError (ioReason)
import Control.Monad (when)
import qualified Data.Aeson as A
import qualified Data.Aeson.Key as K
import qualified Data.Aeson.KeyMap as KM
import qualified Data.ByteString as BS
import Data.Either (lefts, rights)
import Data.List (isPrefixOf)
import Data.Scientific (toRealFloat)
import qualified Data.Text as T
import qualified Data.Vector as V
import qualified Data.Yaml as Y
import System.Directory (doesDirectoryExist, doesFileExist)
import System.Environment (lookupEnv)
import System.FilePath (takeDirectory, (</>), isAbsolute)

import VProf.Compress.Format.Path (readWaypoints)
import VProf.Compress.Clean (Sample (..), fileLocator, nonUnitWarning, renderCleanWarning)
import VProf.Geometry.Vec (P3 (..), Q4 (..))
import VProf.Kinematics.Model (Capsule (..))
import VProf.Kinematics.Transform
import VProf.Format.DuplicateKeys (duplicateKeyErrors)
import VProf.Select.Task
import VProf.Validation (maxAngleDeg, maxCoordinate, renderFieldError, showNumber, tooFarRule, tooWideInRule)

type P a = Either [String] a

-- | Read, resolve the files, read the path, check the numbers; Left every problem.
readTaskFile :: FilePath -> IO (Either [String] Task)
readTaskFile = fmap (fmap fst) . readTaskFileWarned

-- | 'readTaskFile' with the warnings about what it read, for the command to say: a path file's
-- quaternions off unit length, normalised (as @vprof plan@ says of a path it is given).
readTaskFileWarned :: FilePath -> IO (Either [String] (Task, [String]))
readTaskFileWarned path = do
  r <- try (BS.readFile path)
  case r of
    Left (e :: IOException) -> pure (Left ["cannot read the task file " ++ path ++ ": " ++ ioReason e])
    Right bs -> case Y.decodeEither' bs of
      Left e -> pure (Left [path ++ ": not valid YAML/JSON: " ++ Y.prettyPrintParseException e])
      Right _ | dups@(_ : _) <- duplicateKeyErrors bs -> pure (Left (map ((path ++ ": ") ++) dups))
      Right v -> case parseTask v of
        Left es -> pure (Left (map ((path ++ ": ") ++) es))
        Right (task, pathSpec) -> do
          let dir = takeDirectory path
          -- a named file that is missing, or a directory
          let missing field given f = do
                ok <- doesFileExist f
                isDir <- doesDirectoryExist f
                pure $ if ok then Nothing
                       else Just [path ++ ": " ++ field ++ ": " ++ show given
                                  ++ (if isDir then " is a directory, not a file" else " does not exist") ++ " (looked for " ++ f ++ ")"]
          env <- mapM (\(i, m) -> do
                         f <- resolvePath dir (mpFile m)
                         maybe (Right m {mpFile = f}) Left <$> missing ("environment[" ++ show i ++ "].file") (mpFile m) f)
                      (zip [0 :: Int ..] (taskEnvironment task))
          pathTargets <- case pathSpec of
            Nothing -> pure (Right ([], []))
            Just (file, frame) -> do
              f <- resolvePath dir file
              gone <- missing "path.file" file f
              case gone of
                Just e -> pure (Left e)
                Nothing -> either (\e -> Left [e]) Right <$> readPathTargets frame f
          pure $ case (collect env, pathTargets) of
            (Right env', Right (pts, warns)) ->
              let task' = task {taskEnvironment = env', taskTargets = taskTargets task ++ pts}
              in case checkTask task' of
                   [] -> Right (task', warns)
                   es -> Left (map ((path ++ ": ") ++) (map renderFieldError es))
            (a, b) -> Left (either id (const []) a ++ either id (const []) b)

-- | The files a task file names, resolved as 'readTaskFile' resolves them, with what each is
-- ("the task's environment[0].file", "the task's path.file"), so that a command can refuse to
-- write over one; nothing for a file that cannot be read or parsed (its reader says why).
taskFileInputs :: FilePath -> IO [(String, FilePath)]
taskFileInputs path = do
  r <- try (BS.readFile path)
  case r of
    Left (_ :: IOException) -> pure []
    Right bs -> case Y.decodeEither' bs of
      Left _ -> pure []
      Right v -> mapM (\(w, f) -> (,) ("the task's " ++ w) <$> resolvePath (takeDirectory path) f) (named v)
  where
    named :: A.Value -> [(String, FilePath)]
    named (A.Object o) =
      [ ("environment[" ++ show i ++ "].file", T.unpack f)
      | Just (A.Array es) <- [KM.lookup "environment" o], (i, A.Object e) <- zip [0 :: Int ..] (V.toList es)
      , Just (A.String f) <- [KM.lookup "file" e] ]
      ++ [ ("path.file", T.unpack f) | Just (A.Object p) <- [KM.lookup "path" o], Just (A.String f) <- [KM.lookup "file" p] ]
    named _ = []

-- | A file name from the task file, made usable from the current directory.
resolvePath :: FilePath -> FilePath -> IO FilePath
resolvePath dir f
  | "$VPROF_SHARED/" `isPrefixOf` f = do
      s <- lookupEnv "VPROF_SHARED"
      pure (maybe "../shared" id s </> drop (length ("$VPROF_SHARED/" :: String)) f)
  | isAbsolute f = pure f
  | otherwise = pure (dir </> f)

-- | The task and, when it names one, its path file (name as written, frame in the world).
parseTask :: A.Value -> P (Task, Maybe (FilePath, Tf))
parseTask v = do
  o <- obj "the file" v
  onlyKeys "" ["environment", "base", "tool", "tool_capsule", "payload", "clearance", "ignore_bodies", "targets", "path"] o
  env <- optional o "environment" (Right []) (\e -> arr "environment" e >>= collect . zipWith mesh [0 :: Int ..])
  base <- optional o "base" (Right identity) (pose "base")
  tool <- optional o "tool" (Right identity) (pose "tool")
  cap <- optional o "tool_capsule" (Right Nothing) (fmap Just . capsule)
  payload <- req o "payload" >>= num "payload" "kg"
  clearance <- req o "clearance" >>= num "clearance" "m"
  ignore <- optional o "ignore_bodies" (Right []) (\e -> arr "ignore_bodies" e >>= collect . zipWith (\i x -> int ("ignore_bodies[" ++ show i ++ "]") x) [0 :: Int ..])
  targets <- optional o "targets" (Right []) (\e -> arr "targets" e >>= collect . zipWith target [0 :: Int ..])
  (pathSpec, follow, step) <- optional o "path" (Right (Nothing, False, defaultPathStep)) pathField
  case (targets, pathSpec) of
    ([], Nothing) -> Left ["targets: missing (give targets, or path: {file: ...})"]
    _ -> Right ()
  pure ( Task { taskEnvironment = env, taskBase = base, taskTool = tool, taskToolCapsule = cap
              , taskPayload = payload, taskClearance = clearance, taskIgnoreBodies = ignore
              , taskTargets = targets, taskPath = follow, taskPathStep = step }
       , pathSpec )
  where
    mesh i m = do
      let p = "environment[" ++ show i ++ "]"
      mo <- obj p m
      onlyKeys p ["file", "scale", "pose"] mo
      f <- reqP p mo "file" >>= str (p ++ ".file")
      s <- optionalP p mo "scale" (Right 1) (num (p ++ ".scale") "")
      t <- optionalP p mo "pose" (Right identity) (pose (p ++ ".pose"))
      pure (MeshPlacement f s t)
    target i t = do
      let p = "targets[" ++ show i ++ "]"
      tf <- pose p t
      pure (Target p tf)
    capsule c = do
      co <- obj "tool_capsule" c
      onlyKeys "tool_capsule" ["a", "b", "radius"] co
      a <- reqP "tool_capsule" co "a" >>= vec3 "tool_capsule.a"
      b <- reqP "tool_capsule" co "b" >>= vec3 "tool_capsule.b"
      r <- reqP "tool_capsule" co "radius" >>= num "tool_capsule.radius" "m"
      pure (Capsule a b r)
    pathField pv = do
      po <- obj "path" pv
      onlyKeys "path" ["file", "follow", "step", "frame"] po
      f <- reqP "path" po "file" >>= str "path.file"
      follow <- optionalP "path" po "follow" (Right False) (bool "path.follow")
      step <- optionalP "path" po "step" (Right defaultPathStep) (num "path.step" "m")
      if step >= minPathStep then Right () else Left ["path.step = " ++ showNumber step ++ " m: " ++ minPathStepRule]
      frame <- optionalP "path" po "frame" (Right identity) (pose "path.frame")
      pure (Just (f, frame), follow, step)

-- | Every key of a mapping (at path p; "" the file's top level) one of the known ones: a
-- misspelt key is an error, not ignored.
onlyKeys :: String -> [String] -> A.Object -> P ()
onlyKeys p known o = case [k | k <- map K.toString (KM.keys o), k `notElem` known] of
  [] -> Right ()
  ks -> Left [(if null p then k else p ++ "." ++ k) ++ ": unknown field (known: " ++ unwords known ++ ")" | k <- ks]

-- | A pose: @position: [x, y, z]@ (m) and either @quaternion: [w, x, y, z]@ (unit) or
-- @rpy_deg: [roll, pitch, yaw]@ (degrees, R = Rz(yaw)·Ry(pitch)·Rx(roll)); no orientation is
-- the identity.
pose :: String -> A.Value -> P Tf
pose p v = do
  o <- obj p v
  let known = ["position", "quaternion", "rpy_deg"]
  case [k | k <- map K.toString (KM.keys o), k `notElem` known] of
    [] -> Right ()
    ks -> Left [p ++ "." ++ k ++ ": unknown field (a pose has position, and quaternion or rpy_deg)" | k <- ks]
  pos <- optionalP p o "position" (Right (V3 0 0 0)) (vec3 (p ++ ".position"))
  let V3 px py pz = pos
  when (any ((> maxCoordinate) . abs) [px, py, pz]) $
    Left [p ++ ".position: " ++ show [px, py, pz] ++ " " ++ tooFarRule]
  case (KM.lookup "quaternion" o, KM.lookup "rpy_deg" o) of
    (Just _, Just _) -> Left [p ++ ": give quaternion or rpy_deg, not both"]
    (Just q, Nothing) -> do
      xs <- nums 4 (p ++ ".quaternion") q
      case xs of
        [w, x, y, z]
          | abs (sqrt (w * w + x * x + y * y + z * z) - 1) > 1e-6 ->
              Left [p ++ ".quaternion: " ++ show xs ++ " is not a unit quaternion (norm " ++ show (sqrt (w * w + x * x + y * y + z * z)) ++ ")"]
          | otherwise -> Right (fromQuat pos (Quat w x y z))
        _ -> Left [p ++ ".quaternion: expected 4 numbers"]
    (Nothing, Just r) -> do
      xs <- nums 3 (p ++ ".rpy_deg") r
      case xs of
        [a, b, c] | any ((> maxAngleDeg) . abs) xs ->
                      Left [p ++ ".rpy_deg: " ++ show xs ++ " " ++ tooWideInRule]
                  | otherwise -> Right (fromRpy pos (V3 (rad a) (rad b) (rad c)))
        _ -> Left [p ++ ".rpy_deg: expected 3 numbers"]
    (Nothing, Nothing) -> Right (fromQuat pos (Quat 1 0 0 0))
  where
    rad x = x * pi / 180

-- | The waypoints of a path file as targets (each placed by the frame), labelled with their line.
-- RAPID @.mod@, a headed CSV (@time,x,y,z,qw,qx,qy,qz@, as @vprof compress@ writes it), else TUM,
-- checked as @vprof plan@ checks a path ("VProf.Compress.Format.Path").
readPathTargets :: Tf -> FilePath -> IO (Either String ([Target], [String]))
readPathTargets frame f = do
  r <- try (BS.readFile f)
  pure $ case r of
    Left (e :: IOException) -> Left ("cannot read the path file " ++ f ++ ": " ++ ioReason e)
    Right bs -> do
      samples <- readWaypoints f bs
      case samples of
        [] -> Left (f ++ ": no waypoints")
        _ -> Right ( [ Target (f ++ " line " ++ show l) (frame `compose` fromQuat (V3 x y z) (normaliseQuat (Quat w a b c)))
                     | Sample l _ (P3 x y z) (Q4 w a b c) <- samples ]
                   , [ f ++ ": " ++ renderCleanWarning fileLocator w | Just w <- [nonUnitWarning samples] ] )

------------------------------------------------------------------------------ helpers

obj :: String -> A.Value -> P A.Object
obj _ (A.Object o) = Right o
obj p v = Left [p ++ ": expected a mapping, got " ++ shortValue v]

req :: A.Object -> String -> P A.Value
req o k = maybe (Left [k ++ ": missing"]) Right (KM.lookup (K.fromString k) o)

reqP :: String -> A.Object -> String -> P A.Value
reqP p o k = maybe (Left [p ++ "." ++ k ++ ": missing"]) Right (KM.lookup (K.fromString k) o)

optional :: A.Object -> String -> P a -> (A.Value -> P a) -> P a
optional o k def f = case KM.lookup (K.fromString k) o of
  Nothing -> def
  Just A.Null -> def
  Just v -> f v

optionalP :: String -> A.Object -> String -> P a -> (A.Value -> P a) -> P a
optionalP _ = optional

num :: String -> String -> A.Value -> P Double
num p unit (A.Number n)
  | isInfinite x = Left [p ++ " = " ++ show n ++ (if null unit then "" else " " ++ unit)
                         ++ ": beyond the range of a number (a double reaches about 1.8e308)"]
  | otherwise = Right x
  where x = toRealFloat n
num p unit v = Left [p ++ ": expected a number" ++ (if null unit then "" else " (" ++ unit ++ ")") ++ ", got " ++ shortValue v]

int :: String -> A.Value -> P Int
int p v@(A.Number n) = let x = toRealFloat n :: Double in
  if x == fromIntegral (round x :: Int) then Right (round x) else Left [p ++ ": expected a whole number, got " ++ shortValue v]
int p v = Left [p ++ ": expected a whole number, got " ++ shortValue v]

bool :: String -> A.Value -> P Bool
bool _ (A.Bool b) = Right b
bool p v = Left [p ++ ": expected true or false, got " ++ shortValue v]

str :: String -> A.Value -> P String
str _ (A.String s) = Right (T.unpack s)
str p v = Left [p ++ ": expected a string, got " ++ shortValue v]

arr :: String -> A.Value -> P [A.Value]
arr _ (A.Array a) = Right (V.toList a)
arr p v = Left [p ++ ": expected a list, got " ++ shortValue v]

nums :: Int -> String -> A.Value -> P [Double]
nums k p v = do
  xs <- arr p v
  ys <- collect (zipWith (\i x -> num (p ++ "[" ++ show i ++ "]") "" x) [0 :: Int ..] xs)
  if length ys == k then Right ys else Left [p ++ ": expected " ++ show k ++ " numbers, got " ++ show (length ys) ++ ": " ++ shortValue v]

vec3 :: String -> A.Value -> P V3
vec3 p v = nums 3 p v >>= \case
  [x, y, z] -> Right (V3 x y z)
  _ -> Left [p ++ ": expected 3 numbers"]

shortValue :: A.Value -> String
shortValue = \case
  A.String s -> show (T.unpack (T.take 40 s))
  A.Number n -> let x = toRealFloat n :: Double in if isInfinite x then show n else show x
  A.Bool b -> if b then "true" else "false"
  A.Null -> "null (nothing)"
  A.Array a -> "a list of " ++ show (V.length a)
  A.Object _ -> "a mapping"

collect :: [P a] -> P [a]
collect ps = case lefts ps of
  [] -> Right (rights ps)
  es -> Left (concat es)
