{-# LANGUAGE OverloadedStrings, RecordWildCards, LambdaCase, ScopedTypeVariables, TupleSections #-}
-- | Reads a robot file (YAML, or JSON since YAML is a superset) into a validated 'Robot'.
--
-- The file states its units (@units: {length: mm|m, angle: deg|rad}@, default m and deg) and
-- the library's files use degrees because that is what data sheets and pendants show; everything is
-- converted to SI on reading. Layout: @name@, @description@, @sources@, @convention@
-- (@standard-dh@, @modified-dh@ or @urdf@), @payload@ (kg), @reach@ (length unit), @base@ and
-- @tool@ (@xyz@, @rpy@), @joints@ (actuated, in the controller's convention: @name@, @type@,
-- @limits: [min, max]@, @max_velocity@, @max_acceleration@, absent when not published) and
-- @links@ (per link the table row, what drives it and optional @capsules@). Invariant: every
-- problem is reported at once with its path in the file (@joints[2].limits@), and the result has
-- passed 'validateRobot'.
module VProf.Kinematics.Format.RobotFile
  ( readRobotFile
  , readRobotYaml
  , defaultCapsules
  ) where

import Control.Exception (IOException, try)
import VProf.Format.IOError (ioReason)
import qualified Data.Aeson as A
import qualified Data.Aeson.Key as K
import qualified Data.Aeson.KeyMap as KM
import qualified Data.ByteString as BS
import Data.Either (lefts, rights)
import Data.List (elemIndex)
import Data.Scientific (toRealFloat)
import qualified Data.Text as T
import qualified Data.Vector as V
import qualified Data.Yaml as Y

import VProf.Format.DuplicateKeys (duplicateKeyErrors)
import VProf.Kinematics.Model
import VProf.Kinematics.Transform
import VProf.Kinematics.Validate

readRobotFile :: FilePath -> IO (Either [String] Robot)
readRobotFile path = do
  r <- try (BS.readFile path)
  pure $ case r of
    Left (e :: IOException) -> Left ["cannot read " ++ path ++ ": " ++ ioReason e]
    Right bs -> readRobotYaml bs

readRobotYaml :: BS.ByteString -> Either [String] Robot
readRobotYaml bs = case Y.decodeEither' bs of
  Left e -> Left ["not valid YAML/JSON: " ++ Y.prettyPrintParseException e]
  Right _ | dups@(_ : _) <- duplicateKeyErrors bs -> Left dups
  Right v -> do
    r <- fromValue v
    case validateRobotIn (either (const siUnits) id (fileUnits v)) r of
      [] -> Right r
      es -> Left (map renderFieldError es)

-- | The units the file's values are typed in, for its errors.
fileUnits :: A.Value -> P ShowUnits
fileUnits v = do
  (l, a) <- obj "file" v >>= units
  pure (ShowUnits l (if l == 1 then "m" else "mm") a (if a == 1 then "rad" else "deg"))

type P a = Either [String] a

obj :: String -> A.Value -> P A.Object
obj _ (A.Object o) = Right o
obj p _ = Left [p ++ ": expected a mapping"]

field :: String -> A.Object -> String -> P (Maybe A.Value)
field _ o k = Right (KM.lookup (K.fromString k) o)

req :: String -> A.Object -> String -> P A.Value
req p o k = maybe (Left [p ++ "." ++ k ++ ": missing"]) Right (KM.lookup (K.fromString k) o)

num :: String -> A.Value -> P Double
num _ (A.Number n) = Right (toRealFloat n)
num p v = Left [p ++ ": expected a number, got " ++ take 40 (show v)]

str :: String -> A.Value -> P String
str _ (A.String s) = Right (T.unpack s)
str p _ = Left [p ++ ": expected a string"]

arr :: String -> A.Value -> P [A.Value]
arr _ (A.Array a) = Right (V.toList a)
arr p _ = Left [p ++ ": expected a list"]

nums :: Int -> String -> A.Value -> P [Double]
nums k p v = do
  xs <- arr p v
  ys <- collect (zipWith (\i x -> num (p ++ "[" ++ show i ++ "]") x) [0 :: Int ..] xs)
  if length ys == k then Right ys else Left [p ++ ": expected " ++ show k ++ " numbers, got " ++ show (length ys)]

-- | All errors of all parts.
collect :: [P a] -> P [a]
collect ps = case lefts ps of
  [] -> Right (rights ps)
  es -> Left (concat es)

-- | Keys a mapping may hold: any other is an error naming it (a misspelt @limit@ would
-- otherwise leave a joint unbounded without a word).
known :: String -> [String] -> A.Object -> P ()
known p keys o = case [ K.toString k | k <- KM.keys o, K.toString k `notElem` keys ] of
  [] -> Right ()
  bad -> Left [ (if p == "file" then k else p ++ "." ++ k) ++ ": not a known key (expected one of " ++ unwords keys ++ ")" | k <- bad ]

optNum :: String -> A.Object -> String -> P (Maybe Double)
optNum p o k = field p o k >>= \case
  Nothing -> Right Nothing
  Just A.Null -> Right Nothing
  Just v -> Just <$> num (p ++ "." ++ k) v

fromValue :: A.Value -> P Robot
fromValue v = do
  o <- obj "file" v
  known "file" [ "name", "description", "sources", "units", "convention", "payload", "reach", "closed_form"
               , "capsule_radius", "base", "tool", "joints", "links" ] o
  name <- req "file" o "name" >>= str "name"
  desc <- field "file" o "description" >>= maybe (Right "") (str "description")
  sources <- field "file" o "sources" >>= maybe (Right []) (\s -> arr "sources" s >>= collect . zipWith (\i x -> str ("sources[" ++ show i ++ "]") x) [0 :: Int ..])
  (lenU, angU) <- units o
  conv <- req "file" o "convention" >>= str "convention"
  if conv `notElem` ["standard-dh", "modified-dh", "urdf"]
    then Left ["convention: " ++ show conv ++ " is not one of standard-dh, modified-dh, urdf"]
    else Right ()
  payload <- optNum "file" o "payload"
  reach <- fmap (* lenU) <$> optNum "file" o "reach"
  closed <- field "file" o "closed_form" >>= \case
    Nothing -> Right Nothing
    Just (A.String "dobot") -> Right (Just DobotLinkage)
    Just x -> Left ["closed_form: " ++ take 40 (show x) ++ " is not known (dobot)"]
  radius <- optNum "file" o "capsule_radius" >>= \case
    Nothing -> Right 0.05
    Just r | r > 0 && not (isInfinite r) -> Right (r * lenU)
           | otherwise -> Left ["capsule_radius = " ++ show r ++ ": must be a finite number > 0"]
  base <- field "file" o "base" >>= maybe (Right identity) (frame "base" lenU angU)
  tool <- field "file" o "tool" >>= maybe (Right identity) (frame "tool" lenU angU)
  jv <- req "file" o "joints" >>= arr "joints"
  lv <- req "file" o "links" >>= arr "links"
  joints <- collect (zipWith (joint lenU angU) [0 ..] jv)
  let names = map jointName joints
  links <- collect (zipWith (link conv lenU angU names joints radius) [0 ..] lv)
  pure Robot
    { robotName = name, robotDescription = desc, robotSources = sources, robotJoints = joints
    , robotLinks = links, robotBase = base, robotTool = tool, robotPayload = payload
    , robotReach = reach, robotClosedForm = closed }

units :: A.Object -> P (Double, Double)
units o = field "file" o "units" >>= \case
  Nothing -> Right (1, pi / 180)
  Just u -> do
    uo <- obj "units" u
    known "units" ["length", "angle"] uo
    l <- field "units" uo "length" >>= maybe (Right "m") (str "units.length")
    a <- field "units" uo "angle" >>= maybe (Right "deg") (str "units.angle")
    lf <- case l of
      "m" -> Right 1
      "mm" -> Right 1e-3
      _ -> Left ["units.length: " ++ show l ++ " is not m or mm"]
    af <- case a of
      "deg" -> Right (pi / 180)
      "rad" -> Right 1
      _ -> Left ["units.angle: " ++ show a ++ " is not deg or rad"]
    pure (lf, af)

frame :: String -> Double -> Double -> A.Value -> P Tf
frame p lenU angU v = do
  o <- obj p v
  known p ["xyz", "rpy"] o
  xyz <- field p o "xyz" >>= maybe (Right [0, 0, 0]) (nums 3 (p ++ ".xyz"))
  rpy <- field p o "rpy" >>= maybe (Right [0, 0, 0]) (nums 3 (p ++ ".rpy"))
  let [x, y, z] = map (* lenU) xyz
      [r, pt, yw] = map (* angU) rpy
  pure (fromRpy (V3 x y z) (V3 r pt yw))

joint :: Double -> Double -> Int -> A.Value -> P Joint
joint lenU angU i v = do
  let p = "joints[" ++ show i ++ "]"
  o <- obj p v
  known p ["name", "type", "limits", "max_velocity", "max_acceleration"] o
  name <- req p o "name" >>= str (p ++ ".name")
  kind <- field p o "type" >>= \case
    Nothing -> Right Revolute
    Just t -> str (p ++ ".type") t >>= \case
      "revolute" -> Right Revolute
      "prismatic" -> Right Prismatic
      s -> Left [p ++ ".type: " ++ show s ++ " is not revolute or prismatic"]
  let u = if kind == Revolute then angU else lenU
  lims <- field p o "limits" >>= \case
    Nothing -> Right (Limits (-1 / 0) (1 / 0))
    Just l -> nums 2 (p ++ ".limits") l >>= \[a, b] -> Right (Limits (a * u) (b * u))
  vel <- fmap (* u) <$> optNum p o "max_velocity"
  acc <- fmap (* u) <$> optNum p o "max_acceleration"
  pure (Joint name kind lims vel acc)

link :: String -> Double -> Double -> [String] -> [Joint] -> Double -> Int -> A.Value -> P Link
link conv lenU angU names joints radius i v = do
  let p = "links[" ++ show i ++ "]"
  o <- obj p v
  known p ["name", "fixed", "drive", "joint", "offset", "origin", "axis", "dh", "capsules"] o
  name <- field p o "name" >>= maybe (Right ("link" ++ show (i + 1))) (str (p ++ ".name"))
  -- what drives it: drive {joint: coefficient}, joint: NAME, fixed: true, or joint i by default
  fixed <- field p o "fixed" >>= \case
    Just (A.Bool b) -> Right b
    Nothing -> Right False
    Just _ -> Left [p ++ ".fixed: expected true or false"]
  terms <- field p o "drive" >>= \case
    Just d -> do
      dobj <- obj (p ++ ".drive") d
      collect [ case elemIndex (K.toString k) names of
                  Nothing -> Left [p ++ ".drive." ++ K.toString k ++ ": no joint of that name"]
                  Just j -> (j,) <$> num (p ++ ".drive." ++ K.toString k) c
              | (k, c) <- KM.toList dobj ]
    Nothing -> field p o "joint" >>= \case
      Just j -> str (p ++ ".joint") j >>= \s -> maybe (Left [p ++ ".joint: no joint named " ++ show s]) (\k -> Right [(k, 1)]) (elemIndex s names)
      Nothing
        | fixed -> Right []
        | i < length names -> Right [(i, 1)]
        | otherwise -> Left [p ++ ": names no driving joint (drive, joint or fixed)"]
  kind <- case terms of
    [] -> Right Nothing
    ((k, _) : _) -> Right (Just (jointKind (joints !! k)))
  let u = if kind == Just Prismatic then lenU else angU
  off <- maybe 0 (* u) <$> optNum p o "offset"
  -- the other convention's keys are an error, not ignored (a dh table under urdf moved nothing)
  case [ k | k <- if conv == "urdf" then ["dh"] else ["origin", "axis"], KM.member (K.fromString k) o ] of
    [] -> Right ()
    ks -> Left [ p ++ "." ++ k ++ ": not a key of the " ++ conv ++ " convention (" ++ (if conv == "urdf" then "a urdf link gives origin and axis" else "a DH link gives dh: {theta, d, a, alpha}") ++ ")" | k <- ks ]
  geom <- case conv of
    "urdf" -> do
      org <- field p o "origin" >>= maybe (Right identity) (frame (p ++ ".origin") lenU angU)
      ax <- field p o "axis" >>= maybe (Right [0, 0, 1]) (nums 3 (p ++ ".axis"))
      let [x, y, z] = ax
      pure (if kind == Nothing then FixedTransform org else UrdfJoint org (V3 x y z))
    _ -> do
      dv <- req p o "dh"
      d <- obj (p ++ ".dh") dv
      known (p ++ ".dh") ["theta", "d", "a", "alpha"] d
      -- a DH field left out is 0 (docs/kinematics.md); a misspelt one is an error above
      let g k s = maybe 0 (* s) <$> optNum (p ++ ".dh") d k
      th <- g "theta" angU
      dd <- g "d" lenU
      a <- g "a" lenU
      al <- g "alpha" angU
      pure (if conv == "standard-dh" then DhStandard th dd a al else DhModified al a th dd)
  caps <- field p o "capsules" >>= \case
    Nothing -> Right (defaultCapsules radius geom)
    Just cv -> arr (p ++ ".capsules") cv >>= \cs -> collect
      [ do co <- obj q c
           known q ["a", "b", "radius"] co
           a <- req q co "a" >>= nums 3 (q ++ ".a")
           b <- req q co "b" >>= nums 3 (q ++ ".b")
           r <- req q co "radius" >>= num (q ++ ".radius")
           let [ax, ay, az] = map (* lenU) a; [bx, by, bz] = map (* lenU) b
           pure (Capsule (V3 ax ay az) (V3 bx by bz) (r * lenU))
      | (k, c) <- zip [0 :: Int ..] cs, let q = p ++ ".capsules[" ++ show k ++ "]" ]
  pure (Link name kind geom (Drive off terms) caps)

-- | The documented default when a file gives no capsules for a link: one capsule of the robot's
-- @capsule_radius@ along the link's constant "bone" in its own frame — for standard DH from the
-- frame's origin to the previous frame's origin, (−a, −d·sin α, −d·cos α), which does not depend
-- on θ; for modified DH along the d offset, (0, 0, −d); for a URDF joint a sphere at the origin
-- (the parent's origin moves in the child's frame); for a fixed transform back to the parent's
-- origin. A zero-length bone gives a sphere (both ends at the origin).
defaultCapsules :: Double -> Geometry -> [Capsule]
defaultCapsules r g = [Capsule (V3 0 0 0) end r]
  where
    end = case g of
      DhStandard _ d a al -> V3 (-a) (-d * sin al) (-d * cos al)
      DhModified _ _ _ d -> V3 0 0 (-d)
      UrdfJoint _ _ -> V3 0 0 0
      FixedTransform t -> translation (inverse t)
