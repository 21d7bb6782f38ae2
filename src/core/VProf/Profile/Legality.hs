-- | The legality checker: does a sampled profile obey every limit of a problem?
--
-- It is independent of the generators: it shares no code with them beyond the
-- 'Problem' and 'Profile' types (it even does its own zone look-up), and it returns
-- every violation, not the first. A profile is legal when 'check' returns [].
--
-- Rules (profile as defined in "VProf.Profile.Sampled"):
--
-- * @negative_velocity@: v_k >= 0;
-- * @speed@: for every step, max(v_k, v_{k+1}) <= the lowest speed limit anywhere on
--   [s_k, s_{k+1}] (for a single-sample profile, v_0 <= the limit at 0);
-- * @acceleration@: a_min <= a_k <= a_max;
-- * @jerk@: j_min <= j <= j_max, including the jerk into the first acceleration (from the
--   start acceleration) and out of the last (into the end acceleration);
-- * @start_velocity@ / @end_velocity@: v_0 and v_N equal the requested values;
-- * @route_end@: |s_N − L| <= end tolerance (value: s_N − L; limit: the tolerance);
-- * @overshoot@: no s_k beyond L + end tolerance;
-- * @crawl@: the profile ends at the first sample at which it could end: no sample k < N
--   has arrived (|s_k − L| <= end tolerance, v_k = the end velocity) with the jerk from
--   a_{k−1} (the start acceleration for k = 0) into the end acceleration within range.
--   A profile that arrives and then goes on creeping or standing is reported here;
-- * @non_finite@: every velocity (and the time step) is a finite number: a NaN would
--   pass every comparison above.
--
-- Comparisons allow a rounding slack of 1e-9 relative to the limit (at least 1e-9
-- absolute): profiles travel as decimal text and doubles, and a limit met to nine
-- digits is met.
module VProf.Profile.Legality
  ( Rule (..)
  , Violation (..)
  , ruleName
  , check
  , isLegal
  , legalVelocities
  , legalButCrawl
  , renderViolation
  , slack
  ) where

import qualified Data.Vector.Unboxed as U
import Numeric (showEFloat, showFFloat)

import VProf.Profile.Sampled
import VProf.Profile.Problem (checkerSlack)
import VProf.Profile.Request (Problem (..))

data Rule
  = NegativeVelocity | Speed | AccelerationRule | JerkRule
  | StartVelocity | EndVelocity | RouteEnd | Overshoot | Crawl | EmptyProfile | NonFinite
  deriving (Eq, Ord, Show, Enum, Bounded)

ruleName :: Rule -> String
ruleName = \case
  NegativeVelocity -> "negative_velocity"
  Speed -> "speed"
  AccelerationRule -> "acceleration"
  JerkRule -> "jerk"
  StartVelocity -> "start_velocity"
  EndVelocity -> "end_velocity"
  RouteEnd -> "route_end"
  Overshoot -> "overshoot"
  Crawl -> "crawl"
  EmptyProfile -> "empty"
  NonFinite -> "non_finite"

data Violation = Violation
  { vRule   :: !Rule
  , vSample :: !Int     -- ^ the sample, or the first sample of the offending step
  , vValue  :: !Double  -- ^ SI
  , vLimit  :: !Double  -- ^ SI
  } deriving (Eq, Show)

renderViolation :: Violation -> String
renderViolation (Violation NonFinite k _ _) =
  "non_finite at sample " ++ show k ++ ": the velocity (or the time step) is not a finite number"
renderViolation (Violation RouteEnd k off tol) =
  "route_end at sample " ++ show k ++ ": the profile ends " ++ metres (abs off) ++ " m "
  ++ (if off < 0 then "short of" else "past") ++ " the route end, more than the end tolerance "
  ++ metres tol ++ " m"
  where
    -- six decimals, or three significant digits below a millimetre (a route of 1 µm has a
    -- tolerance of 0.1 µm: "0.000000 m" said nothing)
    metres x | x /= 0 && x < 1e-3 = showEFloat (Just 2) x ""
             | otherwise = showFFloat (Just 6) x ""
renderViolation (Violation r k v l) =
  ruleName r ++ " at sample " ++ show k ++ ": " ++ num v ++ " " ++ unit ++ relation ++ num l ++ " " ++ unit
    ++ excess
  where
    num x = showFFloat (Just 6) x ""
    -- a value past the limit by less than the six decimals show (rounding at a fine time
    -- step: a jerk 8e-8 over) would read "0.500000 beyond the limit 0.500000": say by how much
    excess
      | num v == num l && v /= l = " (by " ++ showEFloat (Just 1) (abs (v - l)) "" ++ " " ++ unit ++ ")"
      | otherwise = ""
    unit = case r of
      AccelerationRule -> "m/s²"
      JerkRule -> "m/s³"
      Overshoot -> "m"
      Crawl -> "s"
      _ -> "m/s"
    relation = case r of
      StartVelocity -> " instead of "
      EndVelocity -> " instead of "
      Crawl -> " into the profile, which goes on until "
      NegativeVelocity -> " below "
      _ -> " beyond the limit "

-- | The rounding slack allowed around a limit.
slack :: Double -> Double
slack l = checkerSlack * max 1 (abs l)

isLegal :: Problem -> Profile -> Bool
isLegal pb = null . check pb

-- | The verdict on velocities v_0..v_N at the problem's time step, between its start and
-- end accelerations.
legalVelocities :: Problem -> U.Vector Double -> Bool
legalVelocities pb vs = isLegal pb (Profile (pbDt pb) vs (pbA0 pb) (pbAEnd pb))

-- | Legal but for a crawl: velocities that arrive (within the tolerance of the route end,
-- at the end velocity) before their last sample, where the generator cuts a profile.
legalButCrawl :: Problem -> U.Vector Double -> Bool
legalButCrawl pb vs = all ((== Crawl) . vRule) (check pb (Profile (pbDt pb) vs (pbA0 pb) (pbAEnd pb)))

check :: Problem -> Profile -> [Violation]
check pb p
  | U.null v = [Violation EmptyProfile 0 0 0]
  | not (finite dt) || dt <= 0 = [Violation NonFinite 0 0 0]
  | not (U.null nonFinite) = [ Violation NonFinite k 0 0 | k <- U.toList nonFinite ]
  | otherwise = concat
      [ [ Violation NegativeVelocity k (v U.! k) 0 | k <- U.toList (U.findIndices (< negate (slack 0)) v) ]
      , speedViolations
      , [ Violation AccelerationRule k a (if a > aMax then aMax else aMin)
        | k <- U.toList (U.findIndices (\a -> a > aMax + slack aMax || a < aMin - slack aMin) acc), let a = acc U.! k ]
      , [ Violation JerkRule k j (if j > jMax then jMax else jMin)
        | k <- U.toList (U.findIndices (\j -> j > jMax + slack jMax || j < jMin - slack jMin) allJerks), let j = allJerks U.! k ]
      , [ Violation StartVelocity 0 (U.head v) (pbV0 pb) | abs (U.head v - pbV0 pb) > slack (pbV0 pb) ]
      , [ Violation EndVelocity n (U.last v) (pbVEnd pb) | abs (U.last v - pbVEnd pb) > slack (pbVEnd pb) ]
      , [ Violation RouteEnd n (U.last s - len) (pbTol pb) | abs (U.last s - len) > pbTol pb + slack len ]
      , [ Violation Overshoot k (s U.! k) (len + pbTol pb) | k <- U.toList (U.findIndices (> len + pbTol pb + slack len) s) ]
      , [ Violation Crawl k (fromIntegral k * dt) (fromIntegral n * dt) | Just k <- [arrival] ]
      ]
  where
    dt = prDt p
    v = prVelocities p
    nonFinite = U.findIndices (not . finite) v
    finite x = not (isNaN x || isInfinite x)
    n = U.length v - 1
    s = distances p
    len = pbLength pb
    aMin = pbAMin pb; aMax = pbAMax pb; jMin = pbJMin pb; jMax = pbJMax pb
    acc = U.zipWith (\a b -> (b - a) / dt) v (U.tail v)
    -- jerk into a_0 is "at sample 0"; j between a_k and a_{k+1} at sample k+1; out of the
    -- last acceleration at sample N. A single sample: start → end acceleration.
    accAll = U.cons (prStartAcc p) acc `U.snoc` prEndAcc p
    allJerks = U.zipWith (\a b -> (b - a) / dt) accAll (U.tail accAll)

    -- the first sample before N at which the profile could end: arrived, and the jerk
    -- from the acceleration before it into the end acceleration within range
    arrival = U.find arrivedAt (U.enumFromN 0 n)
    arrivedAt k =
      let aBefore = if k == 0 then prStartAcc p else acc U.! (k - 1)
          j = (prEndAcc p - aBefore) / dt
      in abs (s U.! k - len) <= pbTol pb + slack len
         && abs (v U.! k - pbVEnd pb) <= slack (pbVEnd pb)
         && j <= jMax + slack jMax && j >= jMin - slack jMin

    starts = pbZoneStarts pb
    speeds = pbZoneSpeeds pb
    nz = U.length starts
    -- the zone holding at x: the last whose start is <= x (the first zone before 0)
    zoneAt x = go 0 (nz - 1)
      where go lo hi | lo >= hi = lo
                     | otherwise = let mid = (lo + hi + 1) `div` 2
                                   in if starts U.! mid <= x then go mid hi else go lo (mid - 1)
    -- lowest limit on the closed interval [a, b]: every zone that holds somewhere on it
    lowestOn a b = let i = zoneAt a; j = zoneAt b in U.minimum (U.slice i (j - i + 1) speeds)
    stepLimit k = let a = s U.! k; b = s U.! (k + 1) in if a <= b then lowestOn a b else lowestOn b a
    stepTop k = max (v U.! k) (v U.! (k + 1))
    speedViolations
      | n == 0 = [ Violation Speed 0 (U.head v) l | let l = lowestOn 0 0, U.head v > l + slack l ]
      | otherwise =
          [ Violation Speed k (stepTop k) (stepLimit k)
          | k <- U.toList (U.findIndices id (U.generate n (\k -> let l = stepLimit k in stepTop k > l + slack l))) ]
