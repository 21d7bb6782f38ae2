{-# LANGUAGE DataKinds #-}
-- | Domain types of path compression.
--
-- A 'Recording' is what a hand-held 6-DOF sensor delivers: samples of (time, position,
-- orientation). A 'Path' is what the robot runs: waypoints with the same three fields;
-- between consecutive waypoints the robot moves linearly in position and by slerp in
-- orientation, both linear in time (see "VProf.Geometry.Polyline").
--
-- Internally both are structure-of-arrays of unboxed vectors in SI units (s, m, unit
-- quaternion); the public constructors take and give 'Pose's with @dimensional@ units.
-- A quaternion and its negation are the same orientation everywhere in this package.
module VProf.Compress.Types
  ( Pose (..)
  , Track (..)
  , Recording (..)
  , Path (..)
  , trackLength
  , trackPoses
  , poseAt
  , mkTrack
  , mkRecording
  , mkPath
  , recordingFromArrays
  , pathFromArrays
  , Weights (..)
  , defaultWeights
  , thesisWeights
  , Ends (..)
  ) where

import qualified Data.Vector.Unboxed as U
import Linear (Quaternion (..), V3 (..))
import VProf.Geometry.Vec
import Numeric.Units.Dimensional.Prelude (Length, Time, (*~), (/~), metre, second)
import Prelude
import VProf.Validation (maxTime, showNumber, tooLateRule)

-- | One sample of a recording or one waypoint of a path.
data Pose = Pose
  { poseTime        :: !(Time Double)
  , posePosition    :: !(V3 (Length Double))
  , poseOrientation :: !(Quaternion Double)  -- ^ unit quaternion; q and -q are the same
  } deriving (Show, Eq)

-- | Parallel arrays, SI units: time (s), position (m), orientation (unit quaternion).
data Track = Track
  { tTime :: !(U.Vector Double)
  , tPos  :: !V3s
  , tRot  :: !Qs
  } deriving (Show, Eq)

newtype Recording = Recording { recTrack :: Track } deriving (Show, Eq)
newtype Path = Path { pathTrack :: Track } deriving (Show, Eq)

trackLength :: Track -> Int
trackLength = U.length . tTime

poseAt :: Track -> Int -> Pose
poseAt tr i = Pose (tTime tr U.! i *~ second) (fmap (*~ metre) (toV3 (pindex (tPos tr) i))) (toQuat (pindex (tRot tr) i))

trackPoses :: Track -> [Pose]
trackPoses tr = map (poseAt tr) [0 .. trackLength tr - 1]

-- | Validate and build a track: at least two poses, finite numbers, strictly increasing
-- times, quaternions of non-negligible norm (they are normalised). Errors name the index
-- (0-based) and the value.
mkTrack :: String -> [Pose] -> Either String Track
mkTrack what ps = recordingFromArraysT what ts xs qs
  where
    ts = U.fromList [poseTime p /~ second | p <- ps]
    xs = pfromList [fromV3 (fmap (/~ metre) (posePosition p)) | p <- ps]
    qs = pfromList (map (fromQuat . poseOrientation) ps)

mkRecording :: [Pose] -> Either String Recording
mkRecording = fmap Recording . mkTrack "sample"

mkPath :: [Pose] -> Either String Path
mkPath = fmap Path . mkTrack "waypoint"

recordingFromArrays :: U.Vector Double -> V3s -> Qs
                    -> Either String Recording
recordingFromArrays t p q = Recording <$> recordingFromArraysT "sample" t p q

pathFromArrays :: U.Vector Double -> V3s -> Qs
               -> Either String Path
pathFromArrays t p q = Path <$> recordingFromArraysT "waypoint" t p q

recordingFromArraysT :: String -> U.Vector Double -> V3s -> Qs
                     -> Either String Track
recordingFromArraysT what ts xs qs
  | U.length ts /= plength xs || U.length ts /= plength qs =
      Left ("time, position and orientation arrays differ in length: "
            ++ show (U.length ts) ++ ", " ++ show (plength xs) ++ ", " ++ show (plength qs))
  | U.length ts < 2 = Left ("need at least 2 " ++ what ++ "s, got " ++ show (U.length ts))
  | otherwise = do
      mapM_ checkT [0 .. U.length ts - 1]
      mapM_ checkP [0 .. U.length ts - 1]
      qs' <- traverse checkQ [0 .. U.length ts - 1]
      pure (Track ts xs (pfromList qs'))
  where
    bad x = isNaN x || isInfinite x
    checkT i
      | bad t = Left (what ++ " " ++ show i ++ ": time is not a finite number: " ++ show t)
      -- (so every span between times is finite too: -1e308 to 1.7e308 s is not, and a fit's
      -- times became NaN)
      | abs t > maxTime = Left (what ++ " " ++ show i ++ ": time " ++ showNumber t ++ " s " ++ tooLateRule)
      | i > 0 && t <= ts U.! (i - 1) =
          Left (what ++ " " ++ show i ++ ": time " ++ show t ++ " s is not after the previous time "
                ++ show (ts U.! (i - 1)) ++ " s (times must be strictly increasing)")
      | otherwise = Right ()
      where t = ts U.! i
    checkP i = case pindex xs i of
      P3 x y z | any bad [x, y, z] ->
        Left (what ++ " " ++ show i ++ ": position is not finite: " ++ show (x, y, z))
      _ -> Right ()
    checkQ i =
      let Q4 w a b c = pindex qs i
          n = sqrt (w * w + a * a + b * b + c * c)
      in if any bad [w, a, b, c] || n < 0.5 || n > 2
           then Left (what ++ " " ++ show i ++ ": orientation quaternion (w,x,y,z) = "
                      ++ show (w, a, b, c) ++ " is not a unit quaternion (norm " ++ show n ++ ")")
           else Right (Q4 (w / n) (a / n) (b / n) (c / n))

-- | Weights of the objective, in SI: position (1/m^2), orientation (1/rad^2),
-- velocity (s^2/m^2). Only ratios matter.
data Weights = Weights
  { wPosition    :: !Double
  , wOrientation :: !Double
  , wVelocity    :: !Double
  } deriving (Show, Eq)

-- | The thesis's @vekt = [p o v]@ in its units (mm, degrees, m/s) turned into SI weights:
-- with @thesisWeights 1 1 1@ one millimetre, one degree and one m/s count the same.
thesisWeights :: Double -> Double -> Double -> Weights
thesisWeights p o v = Weights p (o * 1e-6 * (180 / pi) ^ (2 :: Int)) (v * 1e-6)

-- | The thesis's default @vekt = [1 1 1]@.
defaultWeights :: Weights
defaultWeights = thesisWeights 1 1 1

-- | What the first and last waypoint are: pinned to the first and last sample's pose (the
-- thesis; a program that starts and ends where the recording did), or fitted by least
-- squares like every other waypoint (lower error; the path then starts near, not at, the
-- first sample). Their times are the first and last sample's either way.
data Ends = EndsPinned | EndsFree deriving (Show, Eq)
