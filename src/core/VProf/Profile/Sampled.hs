-- | A time-sampled velocity profile.
--
-- The profile is its velocity samples v_0..v_N at t_k = k·dt. Everything else follows
-- from them, as a controller fed these setpoints would see it:
--
-- * a_k = (v_{k+1} − v_k)/dt for k < N; before sample 0 the acceleration is the start
--   acceleration and after sample N the end acceleration;
-- * j_k = (a_{k+1} − a_k)/dt, with a_N the end acceleration, plus the jerk into the
--   first acceleration (a_0 − a_start)/dt;
-- * s_0 = 0 and s_{k+1} = s_k + (v_k + v_{k+1})·dt/2.
module VProf.Profile.Sampled
  ( Profile (..)
  , mkProfile
  , sampleCount
  , duration
  , times
  , distances
  , trapezoidDistances
  , accelerations
  , jerks
  , jerkIntoFirst
  , peakVelocity
  , finalDistance
  , Columns (..)
  , columns
  , Sample (..)
  , samples
  ) where

import qualified Data.Vector.Unboxed as U

import VProf.Units

data Profile = Profile
  { prDt         :: !Double              -- ^ s
  , prVelocities :: !(U.Vector Double)   -- ^ m/s, v_0..v_N
  , prStartAcc   :: !Double              -- ^ m/s², the acceleration before sample 0
  , prEndAcc     :: !Double              -- ^ m/s², the acceleration after sample N
  } deriving (Eq, Show)

-- | A profile from its time step and velocity samples, in units.
mkProfile :: Time Double -> [Velocity Double] -> Acceleration Double -> Acceleration Double -> Profile
mkProfile dt vs a0 aE = Profile (si dt) (U.fromList (map si vs)) (si a0) (si aE)

-- | N+1.
sampleCount :: Profile -> Int
sampleCount = U.length . prVelocities

duration :: Profile -> Double
duration p = fromIntegral (max 0 (sampleCount p - 1)) * prDt p

times :: Profile -> U.Vector Double
times p = U.generate (sampleCount p) (\k -> fromIntegral k * prDt p)

-- | s_0..s_N, trapezoidal.
distances :: Profile -> U.Vector Double
distances (Profile dt v _ _) = trapezoidDistances dt v

-- | s_0..s_N of velocity samples v_0..v_N at time step dt: s_0 = 0,
-- s_{k+1} = s_k + (v_k + v_{k+1})·dt/2.
trapezoidDistances :: Double -> U.Vector Double -> U.Vector Double
trapezoidDistances dt v
  | U.null v = U.empty
  | otherwise = U.scanl' (+) 0 (U.zipWith (\a b -> (a + b) * dt / 2) v (U.tail v))

-- | a_0..a_{N-1}.
accelerations :: Profile -> U.Vector Double
accelerations (Profile dt v _ _)
  | U.length v < 2 = U.empty
  | otherwise = U.zipWith (\a b -> (b - a) / dt) v (U.tail v)

-- | j_0..j_{N-1}: j_k = (a_{k+1} − a_k)/dt with a_N the end acceleration.
jerks :: Profile -> U.Vector Double
jerks p
  | U.null acc = U.empty   -- a single sample has no step, so no acceleration to change
  | otherwise = U.zipWith (\a b -> (b - a) / prDt p) acc (U.snoc (U.tail acc) (prEndAcc p))
  where acc = accelerations p

-- | (a_0 − a_start)/dt (or (a_end − a_start)/dt for a single sample).
jerkIntoFirst :: Profile -> Double
jerkIntoFirst p = case U.uncons (accelerations p) of
  Just (a0, _) -> (a0 - prStartAcc p) / prDt p
  Nothing -> (prEndAcc p - prStartAcc p) / prDt p

peakVelocity :: Profile -> Double
peakVelocity p = if U.null (prVelocities p) then 0 else U.maximum (prVelocities p)

finalDistance :: Profile -> Double
finalDistance p = let d = distances p in if U.null d then 0 else U.last d

-- | The profile as five columns of N+1 values, one row a sample: time, distance,
-- velocity, the acceleration toward the next sample (the end acceleration at N) and the
-- jerk (0 at N). Every output format writes these rows.
data Columns = Columns
  { colTime         :: !(U.Vector Double)
  , colDistance     :: !(U.Vector Double)
  , colVelocity     :: !(U.Vector Double)
  , colAcceleration :: !(U.Vector Double)
  , colJerk         :: !(U.Vector Double)
  } deriving (Eq, Show)

columns :: Profile -> Columns
columns p
  | U.null (prVelocities p) = Columns U.empty U.empty U.empty U.empty U.empty
  | otherwise = Columns (times p) (distances p) (prVelocities p)
                        (U.snoc (accelerations p) (prEndAcc p)) (U.snoc (jerks p) 0)

-- | One sample with its units, as a controller consumes it.
data Sample = Sample
  { smTime         :: !(Time Double)
  , smDistance     :: !(Length Double)
  , smVelocity     :: !(Velocity Double)
  , smAcceleration :: !(Acceleration Double)  -- ^ toward the next sample; the end acceleration at N
  , smJerk         :: !(Jerk Double)          -- ^ 0 at N
  } deriving (Eq, Show)

samples :: Profile -> [Sample]
samples p =
  [ Sample (fromSI t) (fromSI s) (fromSI v) (fromSI a) (fromSI j)
  | k <- [0 .. U.length colTime - 1]
  , let at c = U.unsafeIndex c k
        t = at colTime; s = at colDistance; v = at colVelocity; a = at colAcceleration; j = at colJerk ]
  where Columns{..} = columns p
