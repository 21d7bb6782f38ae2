-- | The seed profile: one forward pass in time that is legal by construction and close to
-- time-optimal, from which the rubber band starts (issue: "start the iterations from a
-- good profile instead of zeros"; the thesis's 4.6.2 suggests the same).
--
-- At every step the pass takes the largest acceleration (within the jerk and acceleration
-- ranges) after which the robot could still brake, as hard as its limits allow, without
-- breaking any speed limit ahead and without passing the terminal point. That braking
-- manoeuvre is the /brake policy/; checking it is the /oracle/. Because the brake policy
-- from the next state is the tail of the brake policy from this one, the pass can always
-- fall back on braking, so once the start state passes the oracle the whole pass stays
-- legal. Near the terminal the pass rides the edge of the oracle and lands on the
-- terminal point.
--
-- The end state is reached through a short /tail/ computed backwards from the requested
-- end velocity and acceleration; the forward pass aims at the tail's first sample, a
-- cruise (acceleration 0) at the tail's entry velocity. When that entry velocity is not
-- zero the landing is tuned by moving the point where the pass must be down to it
-- (a few re-runs of the pass's last part only).
module VProf.Generator.Seed
  ( seed
  , SeedFailure (..)
  , brakeStopDistance
  ) where

import qualified Data.Vector.Unboxed as U
import Numeric (showFFloat)

import VProf.Profile (trapezoidDistances)
import VProf.Request (Problem (..))
import VProf.SpeedLimit

-- | Why no seed could be made: the request is infeasible (with where and why), or the
-- landing could not be tuned (a generator limitation, reported as such).
data SeedFailure
  = Infeasible String String   -- ^ offending field, explanation
  | LandingFailed String
  deriving (Eq, Show)

-- | State at sample k: velocity v_k, the acceleration a_{k-1} that led into it, position s_k.
data St = St { stV :: !Double, stA :: !Double, stS :: !Double }

-- | Where the pass must be done: at or before position tP, and at most tV from then on.
data Term = Term { tP :: !Double, tV :: !Double }

data Env = Env
  { ePb :: !Problem
  , eTerm :: !Term
  , eHard :: !Bool   -- ^ brake to standstill (through every limit) rather than to each limit
  , eKappa :: !Double  -- ^ the forward pass takes at most this share of the acceleration and
                       --   jerk ranges upward (a landing knob; the oracle keeps the full ranges)
  }

dtE :: Env -> Double
dtE = pbDt . ePb

-- | Apply acceleration a' for one step. A velocity that would dip below zero by rounding
-- is set to zero and the acceleration recomputed from it, so that v, a and s stay exact
-- to each other.
stepTo :: Env -> St -> Double -> St
stepTo e (St v _ s) a' =
  let dt = dtE e
      v1 = v + a' * dt
      v' = if v1 < 1e-12 then 0 else v1
      a'' = if v1 < 1e-12 then (v' - v) / dt else a'
  in St v' a'' (s + (v + v') * dt / 2)
{-# INLINE stepTo #-}

-- | Is the step from one state to the next within the speed limits and the terminal rule?
stepOk :: Env -> St -> St -> Bool
stepOk e st@(St v _ s) (St v' a' s') =
  v' >= 0
    && a' >= lo - 1e-12 && a' <= hi + 1e-12
    && max v v' <= minLimitOn pb s (max s s')
    && terminalOk
  where
    (lo, hi) = accRange e st
    pb = ePb e
    Term p vt = eTerm e
    terminalOk
      | vt <= 0 = s' <= p || v' == 0 && v == 0
      | otherwise = s' <= p || v' <= vt
{-# INLINE stepOk #-}

-- | The accelerations reachable in one step from a state.
accRange :: Env -> St -> (Double, Double)
accRange e (St _ a _) =
  let pb = ePb e; dt = dtE e
  in (max (pbAMin pb) (a + pbJMin pb * dt), min (pbAMax pb) (a + pbJMax pb * dt))
{-# INLINE accRange #-}

-- | How much velocity is lost while the acceleration is brought back from x (< 0) to 0
-- as fast as the jerk allows (the steps after x, not x itself).
rampDrop :: Env -> Double -> Double
rampDrop e x
  | x >= 0 = 0
  | otherwise =
      let dt = dtE e
          j = pbJMax (ePb e) * dt
          m = fromIntegral (ceiling (negate x / j) - 1 :: Int) :: Double
      in dt * (m * x + j * m * (m + 1) / 2)
{-# INLINE rampDrop #-}

-- | The brake policy: the next acceleration of the hardest braking that still ends at
-- rest without going below zero.
brakeAcc :: Env -> St -> Double
brakeAcc e st = brakeAccTo e st (brakeTarget e st)
{-# INLINE brakeAcc #-}

-- | The brake policy toward a given target velocity.
brakeAccTo :: Env -> St -> Double -> Double
brakeAccTo e st@(St v _ _) tau
  | v <= 0 || w <= 0 = hold
  | not (ok hi) = hold
  | ok lo = lo
  | otherwise = max lo (min hi (exact m0))
  where
    dt = dtE e
    j = pbJMax (ePb e) * dt
    (lo, hi) = accRange e st
    w = v - tau
    hold = max lo (min hi 0)
    ok x = w + x * dt + rampDrop e x >= 0
    -- With m negative ramp terms after x, i.e. x in (-(m+1)j, -mj], the velocity left
    -- above the target after the ramp is w + dt((m+1)x + j m(m+1)/2); its root is x_m.
    -- The m that fits its own root is near sqrt(2w/(dt j)); look around it.
    root m = negate (w / dt + j * m * (m + 1) / 2) / (m + 1)
    fits m = let x = root m in x > negate (m + 1) * j - 1e-15 && x <= negate m * j + 1e-15
    m0 = let g = fromIntegral (floor (sqrt (2 * w / (dt * j))) :: Int) :: Double
             near k | k > 3 = far 0
                    | fits (g - k) && g - k >= 0 = g - k
                    | fits (g + k) = g + k
                    | otherwise = near (k + 1)
             far m | m > 4 * g + 16 = 0   -- unreachable: some m always fits; 0 is then nudged
                   | fits m = m
                   | otherwise = far (m + 1)
         in near 0
    -- the root may sit a rounding error below the feasible set: nudge up until ok
    exact m = nudge (root m) (8 :: Int)
    nudge x 0 = x
    nudge x n = if ok x then x else nudge (x + 1e-12 * max 1 (abs x)) (n - 1)

-- | The velocity the brake policy aims at from a state: the lowest cap within its
-- reach (speed limits, and the terminal velocity once the terminal is in reach), so that
-- it arrives at a lower limit at that limit with the acceleration back at zero instead of
-- braking through it.
brakeTarget :: Env -> St -> Double
brakeTarget e st@(St _ _ s) =
  let (d, _) = brakeBound e st
  in targetFrom e (s + d) (minLimitOn (ePb e) s (s + d))

-- | The brake target given the end of the braking reach and the lowest limit up to it.
targetFrom :: Env -> Double -> Double -> Double
targetFrom e reachEnd zoneMin
  | eHard e = 0
  | reachEnd >= tP (eTerm e) = min zoneMin (max 0 (tV (eTerm e)))
  | otherwise = zoneMin
{-# INLINE targetFrom #-}

-- | Standing still for good is possible from this state: at rest, and the acceleration
-- can return to zero within one jerk step.
atRest :: Env -> St -> Bool
atRest e (St v a _) = v == 0 && a >= negate (pbJMax (ePb e) * dtE e) && a <= negate (pbJMin (ePb e) * dtE e)
{-# INLINE atRest #-}

-- | An upper bound on the distance the brake policy needs from a state, and on the
-- highest velocity it reaches on the way.
brakeBound :: Env -> St -> (Double, Double)
brakeBound e (St v a _) =
  let pb = ePb e; dt = dtE e
      ap = max 0 a
      jm = abs (pbJMin pb); am = abs (pbAMin pb)
      vPeak = v + ap * ap / (2 * jm) + ap * dt
      -- ramping down to a_min and back up to zero take at most these times, at no more
      -- than vPeak; holding a_min from at most vPeak covers at most vPeak²/(2|a_min|)
      tRamps = ap / jm + am / jm + am / pbJMax pb + 6 * dt
  in (vPeak * tRamps + vPeak * vPeak / (2 * am), vPeak)
{-# INLINE brakeBound #-}

-- | The continuous-time distance to bring (v, a >= 0) down to velocity l with the
-- acceleration back at zero: first a down to 0, then an S-curve to a_min (or a
-- triangle short of it) and back.
brakeNeed :: Problem -> Double -> Double -> Double -> Double
brakeNeed pb v a l =
  let j1 = abs (pbJMin pb); j2 = pbJMax pb; am = abs (pbAMin pb)
      t0 = a / j1
      d0 = v * t0 + a * t0 * t0 / 2 - j1 * t0 * t0 * t0 / 6
      v1 = v + a * a / (2 * j1)
      dv = v1 - l
      full = am * am / (2 * j1) + am * am / (2 * j2)
      (ap, t2) = if dv >= full then (am, (dv - full) / am) else (sqrt (2 * dv / (1 / j1 + 1 / j2)), 0)
      t1 = ap / j1; t3 = ap / j2
      d1 = v1 * t1 - j1 * t1 * t1 * t1 / 6
      v2 = v1 - j1 * t1 * t1 / 2
      d2 = v2 * t2 - ap * t2 * t2 / 2
      v3 = v2 - ap * t2
      d3 = v3 * t3 - ap * t3 * t3 / 2 + j2 * t3 * t3 * t3 / 6
  in if dv <= 0 then d0 else d0 + d1 + d2 + d3

-- | A fast sufficient test for states that cruise or accelerate: every lower limit within
-- reach (and the terminal) is further away than the continuous braking distance plus a
-- margin of four steps at the peak velocity.
quickNeed :: Env -> St -> Bool
quickNeed e st@(St v a s)
  | a < 0 || eHard e = False
  | otherwise =
      vPeak <= limitAt pb s
        && all zoneOk (zonesIn s (s + d))
        && terminalOk
  where
    pb = ePb e
    (d, vPeak) = brakeBound e st
    margin = vPeak * 4 * pbDt pb + 1e-3
    Term p vt = eTerm e
    zoneOk (z, l) = l >= vPeak || brakeNeed pb v a l + margin <= z - s
    terminalOk
      | vt <= 0 = s + d <= p || brakeNeed pb v a 0 + margin <= p - s
      | otherwise = s + d < p || vPeak <= vt || brakeNeed pb v a vt + margin <= p - s
    zonesIn lo hi =
      let starts = pbZoneStarts pb; speeds = pbZoneSpeeds pb
          i0 = zoneIndex pb lo + 1
          go i | i >= U.length starts || U.unsafeIndex starts i > hi = []
               | otherwise = (U.unsafeIndex starts i, U.unsafeIndex speeds i) : go (i + 1)
      in go i0

-- | The oracle: can the robot brake from this state without breaking anything?
-- On failure, the state at which the braking first breaks a rule.
brakeCheck :: Env -> St -> Either (St, St) ()
brakeCheck e st0
  | quickNeed e st0 = Right ()
  | otherwise = go st0 (0 :: Int)
  where
    pb = ePb e
    Term p vt = eTerm e
    maxSteps = let (d, vp) = brakeBound e st0 in ceiling (d / max 1e-9 vp / dtE e) + 64 :: Int
    go !st n
      | atRest e st = Right ()
      | otherwise =
          let s = stS st
              (d, vPeak) = brakeBound e st
              reachEnd = s + d
              zoneMin = minLimitOn pb s reachEnd
              quick = vPeak <= zoneMin && (if vt <= 0 then reachEnd <= p else reachEnd < p || vPeak <= vt)
              tau = targetFrom e reachEnd zoneMin
          in if quick then Right ()
             else if n > maxSteps then Left (st, st)
             else let st' = stepTo e st (brakeAccTo e st tau)
                  in if stepOk e st st' then go st' (n + 1) else Left (st, st')

safe :: Env -> St -> Bool
safe e st = either (const False) (const True) (brakeCheck e st)

-- | The distance the brake policy needs to stop from a state (used in messages and tests).
brakeStopDistance :: Problem -> Double -> Double -> Double
brakeStopDistance pb v a = go (St v a 0) (0 :: Int)
  where
    e = Env pb (Term (1 / 0) (1 / 0)) True 1
    go st n
      | atRest e st || n > 10000000 = stS st
      | otherwise = go (stepTo e st (brakeAcc e st)) (n + 1)

-- | One step of the forward pass: the largest safe acceleration.
choose :: Env -> St -> St
choose e st@(St v _ s) =
  let dt = dtE e
      pb = ePb e
      (lo, hiFull) = accRange e st
      hi0 = if eKappa e >= 1 then hiFull
            else max lo (min hiFull (min (eKappa e * pbAMax pb) (stA st + eKappa e * pbJMax pb * dt)))
      Term p vt = eTerm e
      capNow = if vt > 0 && s >= p then min vt (limitAt pb s) else limitAt pb s
      hi = max lo (min hi0 ((capNow - v) / dt))
      try a = let st' = snapTo (stepTo e st a) in if stepOk e st st' && safe e st' then Just st' else Nothing
      -- land exactly on a cap the pass is told to hold (the terminal velocity)
      snapTo st'@(St v' _ s')
        | vt > 0 && abs (v' - vt) < 1e-11 && v' /= vt = St vt ((vt - v) / dt) (s + (v + vt) * dt / 2)
        | otherwise = st' `seq` s' `seq` st'
      aB = brakeAcc e st
      fallback = snapTo (stepTo e st aB)
      search a b bestSt 0 = a `seq` b `seq` bestSt
      search a b bestSt n =
        let m = (a + b) / 2
        in case try m of
             Just st' -> search m b st' (n - 1 :: Int)
             Nothing -> search a m bestSt (n - 1)
  in case try hi of
       Just st' -> st'
       Nothing -> search aB hi fallback (5 :: Int)

-- | The forward pass from a state until the terminal is reached; the states visited
-- after the given one, in order. Stops after @limit@ steps.
forward :: Env -> Double -> Double -> Double -> Int -> St -> [St]
forward e aNext aim landTol limit = go 0
  where
    Term p vt = eTerm e
    dt = dtE e
    joinable st = stV st == vt && (aNext - stA st) >= pbJMin (ePb e) * dt && (aNext - stA st) <= pbJMax (ePb e) * dt
    go n st
      | n >= limit = []
      | vt <= 0 && stS st >= p - landTol = finishBraking st (n :: Int)
      | vt > 0 && stS st >= aim + landTol && joinable st = []   -- past the aim, ready for the tail
      | vt > 0 && stS st >= aim + 4 * vt * dt + 2 * landTol && stV st < vt = []  -- never got up to it
      | otherwise = let st' = choose e st in st' : go (n + 1) st'
    finishBraking st n
      | atRest e st || n >= limit = []
      | otherwise = let st' = stepTo e st (brakeAcc e st) in st' : finishBraking st' (n + 1)

-- | The tail: velocities after the junction sample, ending with v_N = end velocity, whose
-- accelerations ramp from 0 to the end acceleration as fast as the jerk allows; and the
-- junction velocity. Coming into the end state at full jerk from a cruise loses (or
-- gains) the least velocity, so when even this tail would need a negative velocity, no
-- profile can reach the end state.
tail' :: Problem -> Either SeedFailure ([Double], Double)
tail' pb
  | m == 0 = Right ([], vE)
  | vc < -1e-9 = Left (Infeasible "end_acceleration"
      ("end_velocity " ++ num vE ++ " m/s with end_acceleration " ++ num aE
       ++ " m/s² cannot be reached: ramping the acceleration up to it within max_jerk "
       ++ num (pbJMax pb) ++ " m/s³ gains " ++ num (vE - vc) ++ " m/s, more than the end velocity"))
  | otherwise = Right (drop 1 vs, max 0 vc)
  where
    dt = pbDt pb; aE = pbAEnd pb; vE = pbVEnd pb
    step = (if aE > 0 then pbJMax pb else pbJMin pb) * dt   -- signed, same sign as aE
    m = max 0 (ceiling (abs aE / abs step - 1e-9) - 1) :: Int
    alphas = [aE - fromIntegral k * step | k <- [m, m - 1 .. 1]]
    vc = vE - dt * sum alphas
    vs = scanl (\v a -> v + a * dt) (max 0 vc) alphas

num :: Double -> String
num x = showFFloat Nothing (fromIntegral (round (x * 1e6) :: Integer) / 1e6 :: Double) ""

-- | The seed profile's velocities v_0..v_N.
seed :: Problem -> Either SeedFailure (U.Vector Double)
seed pb = do
  (tailVs, vc) <- tail' pb
  let dt = pbDt pb
      -- the acceleration right after the junction: the tail's first, or the end one
      aNext = case tailVs of
        (v1 : _) -> (v1 - vc) / dt
        [] -> pbAEnd pb
      tailLen = sum (zipWith (\a b -> (a + b) * dt / 2) (vc : tailVs) tailVs)
      aim = pbLength pb - tailLen
      landTol = pbTol pb / 2
      st0 = St (pbV0 pb) (pbA0 pb) 0
      limit = 8 * 1048576
      finish middle = Right (U.fromList (pbV0 pb : map stV middle ++ tailVs))
  -- the tail's steps, at their own positions before the end
  let tailPts = zip (vc : tailVs) tailVs
      tailPos = scanl (\acc (x, y) -> acc + (x + y) * dt / 2) (pbLength pb - tailLen) tailPts
      tailBad = [ (i, max x y, lim)
                | (i, ((x, y), (p0, p1))) <- zip [0 :: Int ..] (zip tailPts (zip tailPos (drop 1 tailPos)))
                , let lim = minLimitOn pb (max 0 p0) p1, max x y > lim ]
      lastStep = length tailPts - 1
      -- even raising the acceleration as fast as the jerk allows, the velocity ends below zero
      leastDrop = sum (takeWhile (< 0) [ pbA0 pb + fromIntegral k * pbJMax pb * dt | k <- [1 :: Int ..] ]) * dt
  if pbV0 pb + leastDrop < -1e-12
    then Left (Infeasible "start_acceleration"
           ("start_acceleration " ++ num (pbA0 pb) ++ " m/s² at start_velocity " ++ num (pbV0 pb)
            ++ " m/s drives the velocity below zero whatever the jerk: raising the acceleration at max_jerk "
            ++ num (pbJMax pb) ++ " m/s³ still loses " ++ num (negate leastDrop) ++ " m/s"))
  else if aim <= 0 && not (null tailVs)
    then Left (LandingFailed
           ("the ramp to end_acceleration " ++ num (pbAEnd pb) ++ " m/s² from a cruise needs " ++ num tailLen
            ++ " m, more than route_length " ++ num (pbLength pb) ++ " m"))
  else case tailBad of
    ((i, top, _) : _)
      | i == lastStep && pbAEnd pb < 0 && top > limitAt pb (pbLength pb) ->
          -- the step into the end touches the end's zone; coming in while still braking
          -- at end_acceleration it is faster than the end velocity: provably too fast
          Left (Infeasible "end_acceleration"
            ("end_velocity " ++ num (pbVEnd pb) ++ " m/s with end_acceleration " ++ num (pbAEnd pb)
             ++ " m/s² needs " ++ num top ++ " m/s in the last step, above the speed limit of "
             ++ num (limitAt pb (pbLength pb)) ++ " m/s at the route end"))
    ((_, top, lim) : _) ->
      Left (LandingFailed ("the ramp to end_acceleration meets the speed limit of " ++ num lim
                           ++ " m/s at " ++ num top ++ " m/s"))
    [] -> do
      -- the gentle brake policy (down to each limit, arriving with zero acceleration)
      -- gives the better profiles; when it cannot save the start state, the hardest one
      -- (braking through the limits toward standstill) may still; only when that fails
      -- too is the request infeasible
      let gentle = Env pb (Term aim vc) False 1
          hard = gentle { eHard = True }
      e0 <- case (brakeCheck gentle st0, brakeCheck hard st0) of
        (Right (), _) -> Right gentle
        (_, Right ()) -> Right hard
        (_, Left bad) -> Left (startInfeasible pb hard bad)
      if vc <= 0
        then do
          let middle = forward e0 aNext aim landTol limit st0
              sEnd = if null middle then 0 else stS (last middle)
              aRest = if null middle then pbA0 pb else stA (last middle)
              -- at rest with an acceleration the tail cannot follow in one jerk step:
              -- stand still for one more sample
              settle = let j = (aNext - aRest) / dt in if j >= pbJMin pb && j <= pbJMax pb then [] else [St 0 0 sEnd]
          if abs (sEnd - aim) <= landTol || null middle && aim <= landTol
            then finish (middle ++ settle)
            else Left (LandingFailed ("the forward pass stopped at " ++ num sEnd ++ " m, aiming at " ++ num aim ++ " m"))
        else landMoving pb e0 st0 vc aNext aim landTol limit >>= finish

-- | Landing at a moving terminal: a sample must fall within the landing tolerance of the
-- aim, at the junction velocity, with an acceleration from which the tail (or the end
-- acceleration) is one legal jerk away. First by moving the point where the pass must be
-- down to the junction velocity (cheap, and enough when the robot brakes into the end);
-- otherwise by a dent: the overshoot is taken out of the profile by lowering a window of
-- samples along a smooth bump, the first window that keeps every rule.
landMoving :: Problem -> Env -> St -> Double -> Double -> Double -> Double -> Int -> Either SeedFailure [St]
landMoving pb e0 st0 vc aNext aim landTol limit = attempt (0 :: Int) 0 first
  where
    dt = pbDt pb
    first = forward e0 aNext aim landTol limit st0
    -- the states before the terminal can matter are shared by every attempt
    rhoMax = 4 * vc * dt + 8 * pbTol pb
    prefixLen = length (takeWhile (\st -> let (d, _) = brakeBound e0 st in stS st + d < aim - rhoMax - 1e-9) first)
    prefix = take prefixLen first
    restart = if prefixLen == 0 then st0 else last prefix
    runWith rho = prefix ++ forward e0 { eTerm = Term (aim - rho) vc } aNext aim landTol (limit - prefixLen) restart
    joins st = stV st == vc && (aNext - stA st) >= pbJMin pb * dt && (aNext - stA st) <= pbJMax pb * dt
    -- the first sample from which the pass could hand over to the tail
    landing sts = case dropWhile (\st -> stS st < aim - landTol || not (joins st)) sts of
      (st : _) -> Just st
      [] -> Nothing
    cut sts = let (before, rest) = span (\st -> stS st < aim - landTol || not (joins st)) sts in before ++ take 1 rest
    -- below the junction velocity at the aim on the fastest approach: nothing can land
    aimSpeed = case dropWhile (\st -> stS st < aim - landTol) first of
      (st : _) -> Just (stV st, stS st)
      [] -> Nothing
    tooSlow = case (aimSpeed, landing first) of
      (Just (va, _), Just st) -> va < vc && stS st > aim + landTol
      _ -> False
    -- of all runs, the one whose landing sample is closest past the aim: the dent's input
    better a b = case (landing a, landing b) of
      (Just x, Just y) -> if abs (stS x - aim) <= abs (stS y - aim) then a else b
      (Just _, Nothing) -> a
      _ -> b
    attempt :: Int -> Double -> [St] -> Either SeedFailure [St]
    attempt n rho sts = attempt' n rho sts (better sts first)
    attempt' n rho sts best
      | tooSlow = Left (Infeasible "end_velocity"
          ("end_velocity " ++ num (pbVEnd pb) ++ " m/s" ++ (if pbAEnd pb /= 0 then " with end_acceleration " ++ num (pbAEnd pb) ++ " m/s²" else "")
           ++ " cannot be reached at route_length " ++ num (pbLength pb) ++ " m: the fastest legal approach is at "
           ++ maybe "?" (num . fst) aimSpeed ++ " m/s there and settles at " ++ num vc ++ " m/s only "
           ++ maybe "?" (\st -> num (stS st - aim)) (landing first) ++ " m later"))
      | n > 12 || rho > rhoMax = kappaSearch best
      | otherwise = case landing sts of
          Nothing -> kappaSearch best
          Just st
            | abs (stS st - aim) <= landTol -> Right (cut sts)
            | otherwise ->
                let rho' = rho + max (landTol / 2) (stS st - aim)
                    next = runWith rho'
                in attempt' (n + 1) rho' next (better next best)
    -- the second knob: from the last place where the pass cruised at a speed limit, take
    -- only a share kappa of the upward acceleration and jerk: the final approach slows
    -- down continuously and its samples slide back over the aim
    cruiseIdx = case [ i | (i, st) <- zip [0 :: Int ..] first, stS st < aim - rhoMax
                         , abs (stA st) < 1e-9, stV st >= limitAt pb (stS st) - 1e-9 ] of
      [] -> 0
      is -> last is + 1
    kPrefix = take cruiseIdx first
    kStart = if cruiseIdx == 0 then st0 else last kPrefix
    runKappa k = kPrefix ++ forward e0 { eKappa = k } aNext aim landTol (limit - cruiseIdx) kStart
    landIdx sts = case [ (i, st) | (i, st) <- zip [0 :: Int ..] sts, stS st >= aim - landTol, joins st ] of
      (x : _) -> Just x
      [] -> Nothing
    -- the landing moves back a few millimetres per percent of kappa, continuously but
    -- with jumps where the sample that first settles at the junction velocity changes:
    -- scan a grid, keep the closest run for the dent
    kappaSearch best0 = scan (1 :: Int) best0
    scan i best
      | i > 60 = dent pb st0 vc aNext aim landTol best
      | otherwise =
          let k = 1 - 0.01 * fromIntegral i
              sts = runKappa k
          in case landIdx sts of
               Just (_, st) | abs (stS st - aim) <= landTol -> Right (cut sts)
               _ -> scan (i + 1) (better sts best)

-- | Take the overshoot out of a pass that reached the junction velocity past the aim.
dent :: Problem -> St -> Double -> Double -> Double -> Double -> [St] -> Either SeedFailure [St]
dent pb st0 vc aNext aim landTol sts0 =
  case [ k | k <- [1 .. n], s U.! k >= aim - landTol, v U.! k == vc, joinsAt k ] of
    [] -> case [ x | (x, y) <- zip (U.toList v) (U.toList s), y >= aim - landTol ] of
      (x : _) | x < vc -> Left (Infeasible "end_velocity"
        ("end_velocity " ++ num (pbVEnd pb) ++ " m/s cannot be reached at route_length " ++ num (pbLength pb)
         ++ " m: accelerating as hard as the limits allow gets only to " ++ num x ++ " m/s there"
         ++ (if vc /= pbVEnd pb then " (" ++ num vc ++ " m/s needed before the ramp to end_acceleration)" else "")))
      _ -> Left (LandingFailed ("the forward pass never reached " ++ num aim ++ " m at the end velocity"))
    (k : _)
      | abs (s U.! k - aim) <= landTol -> Right (take k sts0)
      | otherwise ->
          let g = s U.! k - aim
              candidates = [ v' | w <- [8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256, 384, 512, 768, 1024]
                                , w + 3 < k
                                , e <- [k - 2, k - 2 - max 1 (w `div` 4) .. w + 1]
                                , Just v' <- [tryDent k g w e] ]
          in case candidates of
               (v' : _) -> Right (rebuild (U.take (k + 1) v'))
               [] -> Left (LandingFailed ("no smooth dent takes the last " ++ num g ++ " m out of the profile"))
  where
    dt = pbDt pb
    v = U.fromList (stV st0 : map stV sts0)
    aIn = U.fromList (pbA0 pb : map stA sts0)   -- aIn ! k: acceleration into sample k
    n = U.length v - 1
    s = trapezoidDistances dt v
    joinsAt k = let j = (aNext - aIn U.! k) / dt in j >= pbJMin pb && j <= pbJMax pb
    -- lower samples e-w+1..e by c·sin²: removes exactly g from every later position
    tryDent k g w e =
      let bump j = let x = sin (pi * fromIntegral j / fromIntegral (w + 1)) in x * x
          total = sum [ bump j | j <- [1 .. w] ]
          c = g / (dt * total)
          lo = e - w + 1
          v' = U.imap (\i x -> if i >= lo && i <= e then x - c * bump (i - lo + 1) else x) (U.take (k + 1) v)
      in if legalAround v' (lo - 3) (min k (e + 3)) && limitsHold v' lo k then Just v' else Nothing
    legalAround v' i0 i1 =
      let acc i | i < 0 = pbA0 pb
                | otherwise = (v' U.! (i + 1) - v' U.! i) / dt
          is = [max 0 i0 .. min (U.length v' - 2) i1]
      in all (\i -> v' U.! i >= 0) [max 0 i0 .. min (U.length v' - 1) i1]
         && all (\i -> let a = acc i in a >= pbAMin pb && a <= pbAMax pb) is
         && all (\i -> let j = (acc i - acc (i - 1)) / dt in j >= pbJMin pb && j <= pbJMax pb) is
    limitsHold v' lo k =
      let s' = trapezoidDistances dt v'
      in all (\i -> max (v' U.! i) (v' U.! (i + 1)) <= minLimitOn pb (s' U.! i) (s' U.! (i + 1))) [max 0 (lo - 1) .. k - 1]
    rebuild vs = [ St x ((x - p) / dt) 0 | (p, x) <- zip (U.toList vs) (drop 1 (U.toList vs)) ]

-- | Explain why the start state cannot be braked legally.
startInfeasible :: Problem -> Env -> (St, St) -> SeedFailure
startInfeasible pb e (St v0' _ s0', St v1 _ s)
  | s > tP (eTerm e) && tV (eTerm e) <= 0 =
      Infeasible "start_velocity"
        ("start_velocity " ++ num (pbV0 pb) ++ " m/s with start_acceleration " ++ num (pbA0 pb)
         ++ " m/s² cannot stop within route_length " ++ num (pbLength pb) ++ " m: braking at min_acceleration "
         ++ num (pbAMin pb) ++ " m/s² and min_jerk " ++ num (pbJMin pb) ++ " m/s³ needs "
         ++ num (brakeStopDistance pb (pbV0 pb) (pbA0 pb)) ++ " m")
  | otherwise =
      Infeasible "start_velocity"
        ("start_velocity " ++ num (pbV0 pb) ++ " m/s with start_acceleration " ++ num (pbA0 pb)
         ++ " m/s² cannot brake in time for the speed limit of " ++ num (minLimitOn pb s0' s)
         ++ " m/s between " ++ num s0' ++ " m and " ++ num s ++ " m: the hardest braking allowed (min_acceleration " ++ num (pbAMin pb)
         ++ " m/s², min_jerk " ++ num (pbJMin pb) ++ " m/s³) is still at " ++ num (max v0' v1) ++ " m/s there")
