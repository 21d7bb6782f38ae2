-- | What a user asks of the velocity-profile generator, in physical units, and its
-- validation.
--
-- 'Request' is what arrives (from Protobuf, JSON or Haskell code); every optional knob is
-- a 'Maybe'. 'validate' checks it all at once and returns either every problem, each
-- naming the field and the value, or a 'Problem' ("VProf.Profile.Problem", re-exported
-- here): the same request in SI doubles with the defaults filled in, which is what the
-- generator and the checker work on.
module VProf.Profile.Request
  ( -- * The request
    Request (..)
  , SpeedZone (..)
  , Algorithm (..)
  , defaultRequest
    -- * Validated problem
  , Problem (..)
  , FieldError (..)
  , validate
  , renderFieldError
    -- * Defaults and caps
  , defaultTimeStep
  , defaultTimeBudget
  , defaultEndTolerance
  , defaultMaxIterations
  , maxSamples
  , speedResolution
  , leastStepLimit
  , leastStepTime
  , leastSamples
  , dynamicLeastSamples
  , problemLeastSamples
  , autoVelocityStep
  , largestVelocityStep
  , thesisVelocityStep
  , isPowerOfTwo
  ) where

import Data.List (sortOn)
import Numeric (showGFloat)
import qualified Data.Vector.Unboxed as U

import VProf.Profile.LeastTime (Limits (..), leastTime, reachesWithin)
import VProf.Profile.Problem (Algorithm (..), Problem (..), checkerSlack)
import VProf.Units
import VProf.Validation

-- | One zone of the speed-limit function: the limit holds from 'zoneStart' to the next
-- zone's start (the last zone to the route end).
data SpeedZone = SpeedZone
  { zoneStart :: !(Length Double)
  , zoneSpeed :: !(Velocity Double)
  } deriving (Eq, Show)

data Request = Request
  { rqRouteLength       :: !(Length Double)
  , rqZones             :: ![SpeedZone]
  , rqMinAcceleration   :: !(Acceleration Double)
  , rqMaxAcceleration   :: !(Acceleration Double)
  , rqMinJerk           :: !(Jerk Double)
  , rqMaxJerk           :: !(Jerk Double)
  , rqStartVelocity     :: !(Velocity Double)
  , rqStartAcceleration :: !(Acceleration Double)
  , rqEndVelocity       :: !(Velocity Double)
  , rqEndAcceleration   :: !(Acceleration Double)
  , rqTimeStep          :: !(Maybe (Time Double))      -- ^ default 'defaultTimeStep'
  , rqVelocityStep      :: !(Maybe (Velocity Double))  -- ^ default 'autoVelocityStep'
  , rqMaxIterations     :: !(Maybe Int)                -- ^ default 'defaultMaxIterations'
  , rqTimeBudget        :: !(Maybe (Time Double))      -- ^ default 'defaultTimeBudget'
  , rqEndTolerance      :: !(Maybe (Length Double))    -- ^ default 'defaultEndTolerance'
  , rqAlgorithm         :: !Algorithm
  , rqSeedSearch        :: !Bool   -- ^ the default generator tries the seed's variants and thesis
                                   --   mode for a shorter profile (default True; a caller that
                                   --   searches over many requests itself, as the planner does,
                                   --   may turn it off: the greedy seed alone, as before)
  } deriving (Eq, Show)

-- | A request with everything at its default: a 10 m route at 1 m/s, ±1 m/s², ±1 m/s³,
-- from rest to rest. Handy to build requests with record update.
defaultRequest :: Request
defaultRequest = Request
  { rqRouteLength = 10 *~ meter
  , rqZones = [SpeedZone (0 *~ meter) (1 *~ mps)]
  , rqMinAcceleration = (-1) *~ mps2
  , rqMaxAcceleration = 1 *~ mps2
  , rqMinJerk = (-1) *~ mps3
  , rqMaxJerk = 1 *~ mps3
  , rqStartVelocity = 0 *~ mps
  , rqStartAcceleration = 0 *~ mps2
  , rqEndVelocity = 0 *~ mps
  , rqEndAcceleration = 0 *~ mps2
  , rqTimeStep = Nothing
  , rqVelocityStep = Nothing
  , rqMaxIterations = Nothing
  , rqTimeBudget = Nothing
  , rqEndTolerance = Nothing
  , rqAlgorithm = Band
  , rqSeedSearch = True
  }

defaultTimeStep :: Double
defaultTimeStep = 0.125

defaultTimeBudget :: Double
defaultTimeBudget = 1.0

-- | The shortest route taken (m): 1 nm, well below any robot's resolution, and with a tenth of it
-- a tolerance that is still a positive double.
minRouteLength :: Double
minRouteLength = 1e-9

-- | 1 cm; a route shorter than 10 cm gets a tenth of its length.
defaultEndTolerance :: Double
defaultEndTolerance = 0.01

-- | The default iteration cap: passes of the rubber band. Thesis mode grows its profile
-- from rest a sample at a time, some ten passes a sample, but each of its passes visits
-- only the samples that can still change, so its cap is higher.
defaultMaxIterations :: Algorithm -> Int
defaultMaxIterations = \case
  Band -> 100000
  Thesis -> 4000000

-- | The largest profile the generator will make: 2²⁰ samples (36 hours at the default
-- 0.125 s step). A request whose route cannot be driven in that many samples, even with
-- every zone at its speed limit, is refused by 'validate'; a profile that still comes out
-- longer (accelerating and braking take time too) is refused after generation.
maxSamples :: Int
maxSamples = 1048576

-- | The samples a profile of a route needs at the very least (route length, time step, the
-- zones' starts and limits in order): every zone driven at its own speed limit (no legal
-- profile is faster anywhere), so the time is at least the sum of the zones' lengths over
-- their limits.
leastSamples :: Double -> Double -> [(Double, Double)] -> Double
leastSamples len dt zones =
  let ends = drop 1 (map fst zones) ++ [len]
  in sum [ max 0 (min len e - max 0 st) / v | ((st, v), e) <- zip zones ends ] / dt

-- | The change of speed (m/s) that one time step at a jerk or acceleration limit must
-- exceed: the checker's resolution at zero ('checkerSlack': its slack for a limit below 1
-- is 1e-9 in the limit's unit, "VProf.Profile.Legality"). A weaker limit moves a profile by less than the
-- checker can tell from standing still, and the generator, whose thresholds for rest and
-- rounding lie at 1e-10 m/s and below, cannot plan it (it stood still, or spent its budget).
speedResolution :: Double
speedResolution = checkerSlack

-- | The least magnitude an acceleration (order 1) or a jerk (order 2) limit must exceed at
-- time step dt: a step at it, from zero, changes the speed by x·dt^order, which must be above
-- 'speedResolution'.
leastStepLimit :: Int -> Double -> Double
leastStepLimit order dt = speedResolution / dt ^ order

-- | The least time step at which a limit of magnitude x (order 1 or 2) exceeds
-- 'speedResolution' in one step ('leastStepLimit' solved for dt).
leastStepTime :: Int -> Double -> Double
leastStepTime order x = (speedResolution / abs x) ** (1 / fromIntegral order)

-- | The samples a profile needs at the very least under its jerk and acceleration limits
-- ("VProf.Profile.LeastTime": the fastest run-up from the start state and to the end
-- state, the speed at most the highest limit), less four: on its grid a profile can be
-- about half a step ahead of the continuous run-up at either end.
dynamicLeastSamples :: Limits -> Double -> Double -> Double
dynamicLeastSamples lm len dt = max 0 (leastTime lm len / dt - gridLead)

-- | The steps a profile on its grid can be ahead of the continuous run-ups
-- ('dynamicLeastSamples'); a duration this many steps above a sample count is what one
-- evaluation of the bound ('reachesWithin') must reach for the count to stand.
gridLead :: Double
gridLead = 4

-- | The fewest samples a validated problem's profile needs: the larger of 'leastSamples'
-- (every zone at its limit) and 'dynamicLeastSamples' (the jerk and acceleration limits),
-- the latter searched for only where one evaluation of it does not already put it below
-- the former (every request asks this once), both over the 'drivenLength'.
problemLeastSamples :: Problem -> Double
problemLeastSamples pb
  | reachesWithin lm len ((bySpeed + gridLead) * dt) = bySpeed
  | otherwise = max bySpeed (dynamicLeastSamples lm len dt)
  where
    bySpeed = leastSamples len dt (zip (U.toList (pbZoneStarts pb)) (U.toList (pbZoneSpeeds pb)))
    lm = problemLimits pb
    len = drivenLength (pbLength pb) (pbTol pb)
    dt = pbDt pb

-- | The least distance a legal profile covers: the route less its end tolerance (the
-- checker's rule is |s_N − L| <= end_tolerance). A profile may stop that much short, and
-- where the last zone is slow that is many samples: a 9 m route whose last 3.1 m are at
-- 0.95 mm/s, at 0.05 s, was answered in 107,936 samples, stopping 5.0 mm short (1 cm
-- allowed), 91 fewer than its zones at their limits over the whole route need. A tolerance
-- that is no tolerance (not positive, or not below the length: validation refuses it)
-- leaves the length.
drivenLength :: Double -> Double -> Double
drivenLength len tol
  | tol > 0 && tol < len = len - tol
  | otherwise = len

-- | The limits of a validated problem, for "VProf.Profile.LeastTime".
problemLimits :: Problem -> Limits
problemLimits pb = Limits
  { lmV0 = pbV0 pb, lmA0 = pbA0 pb, lmVEnd = pbVEnd pb, lmAEnd = pbAEnd pb
  , lmAMin = pbAMin pb, lmAMax = pbAMax pb, lmJMax = pbJMax pb
  , lmVTop = U.maximum (pbZoneSpeeds pb) }

-- | The automatic velocity step: the largest power of two that is at most a quarter of
-- the smallest of |j|·dt² and |a|·dt, so that one step of velocity changes acceleration
-- by at most a quarter of what the jerk allows in one time step. The rubber band can then
-- move a single sample without breaking the jerk limit wherever the profile is smooth.
autoVelocityStep :: Double -> Double -> Double -> Double -> Double -> Double
autoVelocityStep dt aMin aMax jMin jMax =
  let bound = minimum [abs jMin * dt * dt, jMax * dt * dt, abs aMin * dt, aMax * dt] / 4
  in 2 ^^ (floor (logBase 2 bound) :: Int)

-- | Thesis mode's velocity step when none is given: the largest power of two that works
-- (its band grows from rest one step a pass, and its pace sets how gently it brakes).
thesisVelocityStep :: Double -> Double -> Double -> Double -> Double -> Double
thesisVelocityStep dt aMin aMax jMin jMax = 2 ^^ (floor (logBase 2 (largestVelocityStep dt aMin aMax jMin jMax)) :: Int)

-- | The largest velocity step with which a single sample can rise on a flat stretch:
-- raising it alone changes one jerk by 2·dv/dt² and one acceleration by dv/dt.
largestVelocityStep :: Double -> Double -> Double -> Double -> Double -> Double
largestVelocityStep dt aMin aMax jMin jMax =
  minimum [abs jMin * dt * dt / 2, jMax * dt * dt / 2, abs aMin * dt, aMax * dt]

isPowerOfTwo :: Double -> Bool
isPowerOfTwo x = x > 0 && not (isInfinite x) && let (m, _) = decodeFloat x in abs m == 2 ^ (52 :: Int)

-- | Check everything; return every problem at once.
validate :: Request -> Either [FieldError] Problem
validate rq =
  validated [errors] problem
  where
    len = si (rqRouteLength rq)
    zones = [(si (zoneStart z), si (zoneSpeed z)) | z <- rqZones rq]
    aMin = si (rqMinAcceleration rq); aMax = si (rqMaxAcceleration rq)
    jMin = si (rqMinJerk rq); jMax = si (rqMaxJerk rq)
    v0 = si (rqStartVelocity rq); a0 = si (rqStartAcceleration rq)
    vE = si (rqEndVelocity rq); aE = si (rqEndAcceleration rq)
    dt = maybe defaultTimeStep si (rqTimeStep rq)
    budget = maybe defaultTimeBudget si (rqTimeBudget rq)
    -- a route no longer than its tolerance would be "reached" by standing still: the
    -- default is a tenth of a route shorter than ten times it, and a given one must be shorter
    lenOk = finite len && len >= minRouteLength   -- else route_length's own error says it
    tol = maybe (if lenOk then min defaultEndTolerance (len / 10) else defaultEndTolerance) si (rqEndTolerance rq)
    -- the size bounds count the distance a legal profile must cover at least
    driven = drivenLength len tol
    maxIt = maybe (defaultMaxIterations (rqAlgorithm rq)) id (rqMaxIterations rq)
    dvGiven = fmap si (rqVelocityStep rq)
    -- the thesis mode grows its profile from rest one step per pass, so it takes the
    -- coarsest step that still works
    dvAuto = case rqAlgorithm rq of
      Band -> autoVelocityStep dt aMin aMax jMin jMax
      Thesis -> thesisVelocityStep dt aMin aMax jMin jMax
    dv = maybe dvAuto id dvGiven

    num = showNumber
    err f x unit m = [fieldError f x unit m]
    check c f x unit m = ensure c (fieldError f x unit m)
    checkFinite = ensureFinite

    limitAt s = case [v | (st, v) <- zones, st <= s] of
      [] -> Nothing
      vs -> Just (last vs)
    firstSpeed = case zones of ((_, v) : _) -> Just v; [] -> Nothing
    lastSpeed = limitAt len

    errors = concat
      [ checkFinite "route_length" len "m" $ check (len >= minRouteLength) "route_length" len "m"
          ("must be at least " ++ num minRouteLength ++ " m (1 nm)")
      , zoneErrors
      , checkFinite "min_acceleration" aMin "m/s²" $ check (aMin < 0) "min_acceleration" aMin "m/s²" "must be < 0"
      , checkFinite "max_acceleration" aMax "m/s²" $ check (aMax > 0) "max_acceleration" aMax "m/s²" "must be > 0"
      , checkFinite "min_jerk" jMin "m/s³" $ check (jMin < 0) "min_jerk" jMin "m/s³" "must be < 0"
      , checkFinite "max_jerk" jMax "m/s³" $ check (jMax > 0) "max_jerk" jMax "m/s³" "must be > 0"
      , checkFinite "start_velocity" v0 "m/s" $ concat
          [ check (v0 >= 0) "start_velocity" v0 "m/s" "must be >= 0"
          , case firstSpeed of
              Just v | v0 > v, finite v -> err "start_velocity" v0 "m/s" ("is above the limit of the first zone, " ++ num v ++ " m/s")
              _ -> [] ]
      , checkFinite "end_velocity" vE "m/s" $ concat
          [ check (vE >= 0) "end_velocity" vE "m/s" "must be >= 0"
          , case lastSpeed of
              Just v | vE > v, finite v -> err "end_velocity" vE "m/s" ("is above the limit of the zone at the route end, " ++ num v ++ " m/s")
              _ -> [] ]
      , checkFinite "start_acceleration" a0 "m/s²" $
          check (not (finite aMin && finite aMax) || (a0 >= aMin && a0 <= aMax)) "start_acceleration" a0 "m/s²"
            ("must lie within [min_acceleration, max_acceleration] = [" ++ num aMin ++ ", " ++ num aMax ++ "] m/s²")
      , checkFinite "end_acceleration" aE "m/s²" $
          check (not (finite aMin && finite aMax) || (aE >= aMin && aE <= aMax)) "end_acceleration" aE "m/s²"
            ("must lie within [min_acceleration, max_acceleration] = [" ++ num aMin ++ ", " ++ num aMax ++ "] m/s²")
      , checkFinite "time_step" dt "s" $ check (dt >= minTimeStep && dt <= maxTimeStep) "time_step" dt "s" timeStepRule
      , case dvGiven of
          Nothing -> []
          Just d -> checkFinite "velocity_step" d "m/s" $ concat
            [ check (d > 0) "velocity_step" d "m/s" "must be > 0"
            , if d > 0 && finite jMin && finite jMax && finite aMin && finite aMax && finite dt && dt > 0
                 && d > largestVelocityStep dt aMin aMax jMin jMax
                then err "velocity_step" d "m/s"
                       ("is too coarse: one sample raised by one step must fit inside the jerk and acceleration ranges at time_step "
                        ++ num dt ++ " s, i.e. the step must be at most min(|j|·dt²/2, |a|·dt) = "
                        ++ num (largestVelocityStep dt aMin aMax jMin jMax)
                        ++ " m/s (suggested: " ++ num dvAuto ++ " m/s, or 0 for automatic)")
                else [] ]
      , check (maxIt > 0) "max_iterations" (fromIntegral maxIt :: Double) "" "must be > 0"
      , checkFinite "time_budget" budget "s" $ check (budget > 0 && budget <= 3600) "time_budget" budget "s"
          "must be > 0 and at most 3600 (an hour; a larger one would hold a worker of the daemon for as long)"
      , checkFinite "end_tolerance" tol "m" $ concat
          [ check (tol > 0) "end_tolerance" tol "m" "must be > 0"
          , check (not lenOk || tol < len) "end_tolerance" tol "m"
              ("must be smaller than route_length, " ++ num len ++ " m: a profile that stands still would reach the end within it")
          ]
      , resolutionErrors
      , if null resolutionErrors then sizeErrors else []
      ]

    -- One step at each jerk and acceleration limit must change the speed by more than
    -- 'speedResolution': from zero acceleration a step at the jerk j gives the acceleration
    -- j·dt and the speed j·dt², a step at the acceleration a the speed a·dt.
    resolutionErrors
      | finite dt && dt >= minTimeStep && dt <= maxTimeStep = concat
          [ weak "min_jerk" jMin "m/s³" "time_step²" 2
          , weak "max_jerk" jMax "m/s³" "time_step²" 2
          , weak "min_acceleration" aMin "m/s²" "time_step" 1
          , weak "max_acceleration" aMax "m/s²" "time_step" 1 ]
      | otherwise = []
    weak f x unit by order
      | finite x && x /= 0 && abs x <= leastStepLimit order dt =
          let least = leastStepLimit order dt
              scale = dt ^ order
              dtLeast = leastStepTime order x
          in err f x unit
               ("is too weak for time_step " ++ num dt ++ " s: one step at it changes the speed by "
                ++ sig (abs x * scale) ++ " m/s (|" ++ f ++ "|·" ++ by ++ "), not more than the checker's resolution of "
                ++ show speedResolution ++ " m/s; at this time_step its magnitude must be above " ++ sig least ++ " " ++ unit
                ++ (if dtLeast < maxTimeStep then ", or keep it with a time_step above " ++ sig dtLeast ++ " s" else ""))
      | otherwise = []
    sig x = showGFloat (Just 2) x ""

    zoneErrors
      | null zones = [literalError "speed_limits" "[]" "must hold at least one zone"]
      | otherwise = concat
          [ concat [ checkFinite (fld i "start_distance") st "m" $ concat
                       [ check (st >= 0) (fld i "start_distance") st "m" "must be >= 0"
                       , check (not (finite len) || st < len) (fld i "start_distance") st "m"
                           ("lies at or beyond the route end, route_length = " ++ num len ++ " m") ]
                   | (i, (st, _)) <- izones ]
          , concat [ checkFinite (fld i "velocity") v "m/s" $ check (v > 0) (fld i "velocity") v "m/s" "must be > 0"
                   | (i, (_, v)) <- izones ]
          , case zones of
              ((st, _) : _) | finite st && st /= 0 -> err (fld (0 :: Int) "start_distance") st "m" "the first zone must start at 0"
              _ -> []
          , concat [ err (fld i "start_distance") st "m"
                       ("must be greater than the previous zone's start, " ++ num prev ++ " m (zones must be sorted and must not overlap)")
                   | ((_, (prev, _)), (i, (st, _))) <- zip izones (drop 1 izones), finite st, finite prev, st <= prev ]
          ]
    izones = zip [0 :: Int ..] zones
    fld i f = "speed_limits[" ++ show i ++ "]." ++ f

    -- The samples the profile needs at the very least: every zone driven at its own speed
    -- limit (no legal profile is faster anywhere), so the time is at least the sum of the
    -- zones' lengths over their limits, up to the route end less its tolerance.
    sizeErrors
      | all finite [len, dt] && len > 0 && dt >= minTimeStep && dt <= maxTimeStep && not (null zones)
      , all (\(st, v) -> finite st && finite v && v > 0) zones =
          let lower = leastSamples driven dt sorted
              -- one zone of several that alone needs more than the cap is named: its speed is the
              -- cause (so is a speed so low that no route could be driven at it, even the only
              -- zone's); not on a route beyond any robot's (1e9 m), whose length is the cause
              ends = drop 1 (map fst sorted) ++ [driven]
              alone = [ (i, v, n) | len <= maxCoordinate, (i, ((st, v), e)) <- zip [0 :: Int ..] (zip sorted ends)
                                  , let n = max 0 (min driven e - max 0 st) / v / dt
                                  , n > fromIntegral maxSamples, length zones > 1 || n > 1e15 ]
          in case alone of
               (i, v, n) : _ -> err (fld i "velocity") v "m/s"
                 ("is too slow: its zone alone needs " ++ (if n < 1e15 then show (ceiling n :: Integer) else showNumber n)
                  ++ " samples at time_step " ++ num dt ++ " s, above the cap of " ++ show maxSamples
                  ++ " samples; raise it, split the route or raise time_step")
               [] | lower > fromIntegral maxSamples -> err "route_length" len "m"
                       ("needs at least " ++ (if lower < 1e15 then show (ceiling lower :: Integer) else if isInfinite lower then "1.8e308" else showNumber lower) ++ " samples at time_step " ++ num dt
                        ++ " s (each zone at its speed limit), above the cap of " ++ show maxSamples
                        ++ " samples; split the route or raise time_step")
                  | otherwise -> dynamicErrors
      | otherwise = []

    -- The same cap under the jerk and acceleration limits (the fastest run-up from the
    -- start state and to the end state): where they make the route too long, the limit
    -- that does is named, the first of max_jerk, max_acceleration and min_acceleration
    -- whose removal (with those before it) brings the bound under the cap.
    dynamicErrors
      | lenOk, all finite [v0, a0, vE, aE, aMin, aMax, jMax] && aMin < 0 && aMax > 0 && jMax > 0
      , a0 >= aMin && a0 <= aMax && aE >= aMin && aE <= aMax && v0 >= 0 && vE >= 0
      , not (reachesWithin lm driven ((fromIntegral maxSamples + gridLead) * dt))   -- one evaluation, where 'need' takes some thirty
      , need > fromIntegral maxSamples =
          let inf = 1 / 0
              under l = dynamicLeastSamples l driven dt <= fromIntegral maxSamples
              (f, x, unit)
                | under lm { lmJMax = inf } = ("max_jerk", jMax, "m/s³")
                | under lm { lmJMax = inf, lmAMax = inf } = ("max_acceleration", aMax, "m/s²")
                | otherwise = ("min_acceleration", aMin, "m/s²")
          in err f x unit
               ("makes the route too long: with it the profile needs at least "
                ++ (if need < 1e15 then show (ceiling need :: Integer) else showNumber need) ++ " samples at time_step " ++ num dt
                ++ " s (" ++ showGFloat (Just 1) (need * dt) "" ++ " s for route_length " ++ num len ++ " m, the fastest run-up from the start state and to the end state),"
                ++ " above the cap of " ++ show maxSamples ++ " samples; raise its magnitude or time_step, or split the route")
      | otherwise = []
      where
        lm = problemLimits problem
        need = dynamicLeastSamples lm driven dt

    sorted = sortOn fst zones
    problem = Problem
      { pbLength = len
      , pbZoneStarts = U.fromList (map fst sorted)
      , pbZoneSpeeds = U.fromList (map snd sorted)
      , pbAMin = aMin, pbAMax = aMax, pbJMin = jMin, pbJMax = jMax
      , pbV0 = v0, pbA0 = a0, pbVEnd = vE, pbAEnd = aE
      , pbDt = dt, pbDv = dv, pbMaxIter = maxIt, pbBudget = budget, pbTol = tol
      , pbAlgorithm = rqAlgorithm rq, pbSeedSearch = rqSeedSearch rq
      }
