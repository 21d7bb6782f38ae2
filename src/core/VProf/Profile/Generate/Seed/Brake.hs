-- | The brake policy and its oracle, on which every pass of the seed stands.
--
-- A pass moves a state 'St' (velocity, the acceleration that led into it, position) one
-- time step at a time ('stepTo'). The /brake policy/ is the braking manoeuvre from a
-- state: the hardest braking the jerk and acceleration ranges allow that still arrives
-- at its target velocity (the next speed limit within reach, or a standstill for the
-- /hard/ policy) with the acceleration back at zero and the velocity never below zero.
-- The /oracle/ ('brakeCheck') runs it and reports whether it keeps every rule: the speed
-- limits, the ranges, and the terminal ('Term': where the pass must be done, and how
-- fast it may be there).
--
-- Invariant: the brake policy from the state after one of its own steps is the rest of
-- the same manoeuvre, so a state that passes the oracle has a successor that passes it
-- too; this is what keeps every pass legal by construction.
module VProf.Profile.Generate.Seed.Brake
  ( -- * States and steps
    St (..)
  , Term (..)
  , SeedEnv (..)
  , seedEnv
  , jerkPlanMargin
  , jerkPlanMargins
  , roundingJerk
  , fullJerkHolds
  , topSpeed
  , dtE
  , stepTo
  , stepOk
  , accRange
  , reachableAcc
    -- * The brake policy
  , brakeAcc
  , brakeAccTo
  , brakeTarget
  , atRest
  , brakeBound
    -- * The oracle
  , brakeCheck
  , brakeSimulate
  , brakeTimeBound
  , quickNeed
  , safe
  , policyFor
  , policyWith
    -- * Distances and the start state
  , brakeStopDistance
  , brakeDistanceTo
  , sinksBelowZero
  , leastDrop
    -- * Bounds
  , velocityFloor
  , roundingSlack
  ) where

import qualified Data.Vector.Unboxed as U

import VProf.Profile.Problem (Problem (..))
import VProf.Profile.Problem.Transform (scaleJerk)
import VProf.Profile.Request (maxSamples)
import VProf.Profile.SpeedLimit

-- | State at sample k: velocity v_k, the acceleration a_{k-1} that led into it, position s_k.
data St = St { stV :: !Double, stA :: !Double, stS :: !Double }

-- | Where the pass must be done: at or before position tP, and at most tV from then on.
data Term = Term { tP :: !Double, tV :: !Double }

-- | What a pass works under: the problem, its terminal, and which brake policy.
data SeedEnv = SeedEnv
  { ePb :: !Problem
  , eTerm :: !Term
  , eHard :: !Bool   -- ^ brake to standstill (through every limit) rather than to each limit
  }

-- | A pass's environment.
seedEnv :: Problem -> Term -> Bool -> SeedEnv
seedEnv = SeedEnv

-- | A velocity below this after a step is a standstill missed by rounding.
velocityFloor :: Double
velocityFloor = 1e-12

-- | The rounding allowed on the acceleration range of a step and on a nearly-zero
-- velocity change.
roundingSlack :: Double
roundingSlack = 1e-12

-- | The share of the jerk range a pass that plans with a margin leaves out of every step
-- (it runs on the problem with its jerk range narrowed by it, 'policyWith'): at least
-- 1e-8, and at least twice the jerk a rounding of the fastest velocity makes,
-- 2·ε·v_top/(dt²·|j|) (relative to the weaker jerk limit; at most a quarter). A pass plans
-- every step at a planned jerk, but its samples are doubles: each velocity is rounded to
-- its last bit, and the checker's jerk, a second difference over dt², carries that
-- rounding divided by dt². At a 1 ms step a velocity of 8 m/s is exact to 1.8e-15 m/s, a
-- jerk to 1.8e-9 m/s³, beyond the checker's slack of 1e-9 (kitti-00-first-2km's first
-- 100 m at 1 ms: a ramp at the full jerk broke it at 926 samples). A long ramp back to zero
-- acceleration also gathers rounding in its last step (route-abcd at 1 ms: 8e-8 m/s³
-- beyond a 0.5 m/s³ limit). Passes plan at the full jerk first (a margin can cost a whole
-- step at a coarse step), with it only when that landing breaks a rule.
jerkPlanMargin :: Problem -> Double
jerkPlanMargin q = min 0.25 (max 1e-8 (2 * roundingJerk q))

-- | The jerk, relative to the weaker jerk limit, that a rounding of the fastest velocity to
-- its last bit makes in the checker's second difference: ε·v_top/(dt²·|j|).
roundingJerk :: Problem -> Double
roundingJerk q = epsilon * topSpeed q / (dt * dt * jWeak)
  where
    epsilon = 2.220446049250313e-16
    dt = pbDt q
    jWeak = min (negate (pbJMin q)) (pbJMax q)

-- | Whether a ramp at the full jerk can keep the jerk rule at all: the rounding of the
-- fastest velocity alone ('roundingJerk') is within the checker's slack (1e-9). Where it
-- is not, the passes plan with the 'jerkPlanMargins' from the start.
fullJerkHolds :: Problem -> Bool
fullJerkHolds q = roundingJerk q <= 1e-9

-- | The fastest velocity a profile of the problem can have: the highest zone limit, or the
-- start or end velocity.
topSpeed :: Problem -> Double
topSpeed q = maximum (pbV0 q : pbVEnd q : U.toList (pbZoneSpeeds q))

-- | The margins a landing that breaks a rule is planned again with, in turn: 'jerkPlanMargin',
-- and a hundred and ten thousand times it (at most a quarter). The rounding a long ramp back
-- to zero acceleration gathers in its last step is not bounded by the velocity's last bit:
-- kitti-00-first-2km's first 100 m at 1 ms, planned with 1e-8 of the jerk range left out,
-- still ended 5.8e-8 m/s³ beyond it; with 1e-6, legal. Each costs a pass, only when the
-- one before it lands and breaks a rule, and even 1e-4 of the range lengthens a ramp by
-- 1e-4 of its time.
--
-- Where the full jerk cannot hold ('fullJerkHolds'), the ladder starts at the hundredfold
-- margin (or 'jerkPlanMargin' where that is beyond a quarter). There the last step of a
-- braking to rest carries the velocity's rounding gathered over the whole braking, some 5
-- to 150 times 'roundingJerk' (the velocity ends a few 1e-16 m/s below zero and is set to
-- zero, which raises the last jerk by that over dt²): the first margin broke the jerk rule
-- in its last step in 10 of the 24 such landings of bench/fuzz-requests --fine (seeds 5
-- and 6), each a whole pass of up to 640,000 samples lost, and the hundredfold in none:
-- those ten keep their answers a pass sooner, and the other fourteen changed by at most 2
-- samples.
jerkPlanMargins :: Problem -> [Double]
jerkPlanMargins q
  | fullJerkHolds q = takeWhile (<= 0.25) [ m, 100 * m, 10000 * m ]
  | otherwise = case takeWhile (<= 0.25) [ 100 * m, 10000 * m ] of
      [] -> [m]
      ms -> ms
  where m = jerkPlanMargin q

-- | The jerk step the brake policy plans its ramps with.
planJerkStep :: SeedEnv -> Double
planJerkStep e = pbJMax (ePb e) * dtE e
{-# INLINE planJerkStep #-}

-- | How far a root of the brake policy may sit outside its ramp interval and still count.
rootSlack :: Double
rootSlack = 1e-15

-- | How often, and by how much relative to its size, a brake root is nudged up onto the
-- feasible side when rounding leaves it just below.
nudgeTries :: Int
nudgeTries = 8

nudgeStep :: Double
nudgeStep = 1e-12

-- | How many ramp lengths either side of the estimate are searched for the brake root
-- before the search goes up from zero.
nearRamps :: Double
nearRamps = 3

-- | The most ramp steps 'brakeAcc''s scan tries (four times the sample cap, 'maxSamples'): a
-- longer ramp has no place in a profile.
farRamps :: Double
farRamps = 4 * fromIntegral maxSamples

-- | Time steps added to the ramp times in 'brakeBound', for the discrete ramps' rounding.
boundExtraSteps :: Double
boundExtraSteps = 6

-- | The fast oracle's margin: this many steps at the peak velocity, plus 'quickMarginM'.
quickMarginSteps :: Double
quickMarginSteps = 4

-- | A millimetre on a route of a metre or more, a thousandth of a shorter one: a whole
-- millimetre refused every state within a millimetre of a limit, which on a route of a few
-- millimetres is nearly all of it, and each refused probe ran the braking step by step
-- (an 8 mm route at a 1 µs step ending in motion spent a 10 s budget in the seed). Without
-- any margin (none of the steps either), 11 of the generator's tests failed: fixed points
-- over a limit, passes that stopped short of the route end.
quickMarginM :: Double
quickMarginM = 1e-3

-- | The least peak velocity the oracle's step bound divides by (a state at rest has none).
peakFloor :: Double
peakFloor = 1e-9

-- | Steps the oracle's braking may take beyond its bound before it is called stuck.
oracleExtraSteps :: Int
oracleExtraSteps = 64

-- | Steps 'brakeStopDistance' and 'brakeDistanceTo' may take before they give up.
stopDistanceSteps, distanceToSteps :: Int
stopDistanceSteps = 10000000
distanceToSteps = 4000000

dtE :: SeedEnv -> Double
dtE = pbDt . ePb

-- | Apply acceleration a' for one step. A velocity that would dip below zero by rounding
-- is set to zero and the acceleration recomputed from it, so that v, a and s stay exact
-- to each other.
stepTo :: SeedEnv -> St -> Double -> St
stepTo e (St v _ s) a' =
  let dt = dtE e
      v1 = v + a' * dt
      v' = if v1 < velocityFloor then 0 else v1
      a'' = if v1 < velocityFloor then (v' - v) / dt else a'
  in St v' a'' (s + (v + v') * dt * 0.5)   -- (× 0.5: the same number as / 2, without a division)
{-# INLINE stepTo #-}

-- | Is the step from one state to the next within the speed limits and the terminal rule?
stepOk :: SeedEnv -> St -> St -> Bool
stepOk e st@(St v _ s) (St v' a' s') =
  v' >= 0
    && a' >= lo - roundingSlack && a' <= hi + roundingSlack
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
accRange :: SeedEnv -> St -> (Double, Double)
accRange e (St _ a _) =
  let pb = ePb e
  in reachableAcc (dtE e) (pbAMin pb) (pbAMax pb) (pbJMin pb) (pbJMax pb) a
{-# INLINE accRange #-}

-- | The accelerations reachable in one step of dt from acceleration a, within the
-- acceleration range [aLo, aHi] and the jerk range [jLo, jHi]. The seed's passes use
-- the problem's ranges; the exact join's envelopes ("VProf.Profile.Generate.Exact") the
-- ranges widened by the checker's slack.
reachableAcc :: Double -> Double -> Double -> Double -> Double -> Double -> (Double, Double)
reachableAcc dt aLo aHi jLo jHi a = (max aLo (a + jLo * dt), min aHi (a + jHi * dt))
{-# INLINE reachableAcc #-}

-- | How much velocity is lost while the acceleration is brought back from x (< 0) to 0
-- as fast as the jerk allows (the steps after x, not x itself).
rampDrop :: SeedEnv -> Double -> Double
rampDrop e x
  | x >= 0 = 0
  | otherwise =
      let dt = dtE e
          j = planJerkStep e
          m = fromIntegral (ceiling (negate x / j) - 1 :: Int) :: Double
      in dt * (m * x + j * m * (m + 1) * 0.5)
{-# INLINE rampDrop #-}

-- | The brake policy: the next acceleration of the hardest braking that still ends at
-- rest without going below zero.
brakeAcc :: SeedEnv -> St -> Double
brakeAcc e st = brakeAccTo e st (brakeTarget e st)
{-# INLINE brakeAcc #-}

-- | The brake policy toward a given target velocity.
brakeAccTo :: SeedEnv -> St -> Double -> Double
brakeAccTo e st@(St v _ _) !tau
  | v <= 0 || w <= 0 = hold
  | not (ok hi) = hold
  | ok lo = lo
  | otherwise = max lo (min hi (exact m0))
  where
    dt = dtE e
    j = planJerkStep e
    (lo, hi) = accRange e st
    w = v - tau
    hold = max lo (min hi 0)
    ok x = w + x * dt + rampDrop e x >= 0
    -- With m negative ramp terms after x, i.e. x in (-(m+1)j, -mj], the velocity left
    -- above the target after the ramp is w + dt((m+1)x + j m(m+1)/2); its root is x_m.
    -- The m that fits its own root is near sqrt(2w/(dt j)); look around it.
    root m = negate (w / dt + j * m * (m + 1) * 0.5) / (m + 1)
    fits m = let x = root m in x > negate (m + 1) * j - rootSlack && x <= negate m * j + rootSlack
    m0 = let g = fromIntegral (floor (sqrt (2 * w / (dt * j))) :: Int) :: Double
             near k | k > nearRamps = far 0
                    | fits (g - k) && g - k >= 0 = g - k
                    | fits (g + k) = g + k
                    | otherwise = near (k + 1)
             -- unreachable: some m always fits; 0 is then nudged. The scan stops at
             -- 'farRamps' too: with a jerk so weak that the ramp needs more steps than any
             -- profile may have (g near 1e10 for 5e-20 m/s³), it would never end
             far m | m > min (4 * g + 16) farRamps = 0
                   | fits m = m
                   | otherwise = far (m + 1)
         in near 0
    -- the root may sit a rounding error below the feasible set: nudge up until ok
    exact m = nudge (root m) nudgeTries
    nudge x 0 = x
    nudge x n = if ok x then x else nudge (x + nudgeStep * max 1 (abs x)) (n - 1)

-- | The velocity the brake policy aims at from a state: the lowest cap within its
-- reach (speed limits, and the terminal velocity once the terminal is in reach), so that
-- it arrives at a lower limit at that limit with the acceleration back at zero instead of
-- braking through it.
brakeTarget :: SeedEnv -> St -> Double
brakeTarget e st@(St _ _ s) =
  let (d, _) = brakeBound e st
  in targetFrom e (s + d) (minLimitOn (ePb e) s (s + d))

-- | The brake target given the end of the braking reach and the lowest limit up to it.
targetFrom :: SeedEnv -> Double -> Double -> Double
targetFrom e reachEnd zoneMin
  | eHard e = 0
  | reachEnd >= tP (eTerm e) = min zoneMin (max 0 (tV (eTerm e)))
  | otherwise = zoneMin
{-# INLINE targetFrom #-}

-- | Standing still for good is possible from this state: at rest, and the acceleration
-- can return to zero within one jerk step.
atRest :: SeedEnv -> St -> Bool
atRest e (St v a _) = v == 0 && a >= negate (pbJMax (ePb e) * dtE e) && a <= negate (pbJMin (ePb e) * dtE e)
{-# INLINE atRest #-}

-- | An upper bound on the distance the brake policy needs from a state, and on the
-- highest velocity it reaches on the way: the time of the hardest stop, times that peak
-- velocity. The stop brings a positive acceleration down (a/|j_min|; the velocity peaks at
-- v + a²/(2|j_min|), and a step more), then sheds the peak velocity: with full ramps to
-- a_min and back (a_min/|j_min| + a_min/j_max) and a hold whose distance is at most
-- vPeak²/(2|a_min|); or, when the peak velocity is too small to need a_min (a deceleration
-- already under way counted in), in a triangle of jerk ramps: |a|/j_max to bring a falling
-- acceleration back, and sqrt(2·vPeak·(1/|j_min| + 1/j_max)) more (derivation in
-- docs/profile-generator.md). The triangle is much the shorter where the jerk is weak
-- against the acceleration range (0.53 m/s³ against 16.9 m/s²: 7 s against 76 s from
-- 5.8 m/s); the reach it gives decides which limits the brake policy aims at, and a reach
-- grown to the terminal made a pass brake for a standstill there, through the lower limit
-- before it (a 187 m route at 0.13 ms dipped to 0.16 m/s at the start of its last zone of
-- 2.1 m/s). Each time has 'boundExtraSteps' steps added for the discrete ramps' rounding.
brakeBound :: SeedEnv -> St -> (Double, Double)
brakeBound e (St v a _) = brakeBoundK (boundConsts e) v a
{-# INLINE brakeBound #-}

-- | The constants of 'brakeBound' for a pass's environment, computed once for a braking
-- run step by step ('brakeSimulate') rather than at every step: the same operations on the
-- same numbers, so the bound is the same to the bit (BrakeSpec), and the oracle's steps
-- some 15 % faster (with the halvings by multiplying: fine seed 5 #13, 5.25 -> 4.38 s). In
-- order: |j_min|, j_max, |a_min|, dt, the 'boundExtraSteps' time, a_min/|j_min|,
-- a_min/j_max, their sum and the extra time (the full ramps' time with no positive
-- acceleration), c = 1/|j_min| + 1/j_max, and a_min²·c.
data BoundK = BoundK !Double !Double !Double !Double !Double !Double !Double !Double !Double !Double

boundConsts :: SeedEnv -> BoundK
boundConsts e =
  let pb = ePb e; dt = dtE e
      jm = abs (pbJMin pb); jp = pbJMax pb; am = abs (pbAMin pb)
      extra = boundExtraSteps * dt
      c = 1 / jm + 1 / jp
  in BoundK jm jp am dt extra (am / jm) (am / jp) (am / jm + am / jp + extra) c (am * am * c)
{-# INLINE boundConsts #-}

-- | 'brakeBound' from its constants. Ramping down to a_min and back up to zero take at most
-- a_min/|j_min| + a_min/j_max (and a⁺/|j_min| first), at no more than vPeak; holding a_min
-- from at most vPeak covers at most vPeak²/(2|a_min|). Short of a_min, a ramp from the
-- falling acceleration's magnitude up to a peak and both ramps back shed vPeak; the peak
-- stays within a_min while 2·vPeak + a_f²/|j_min| <= a_min²·c. Where the acceleration is
-- not positive (every step of a braking) the terms of a⁺ are zero, and where it is positive
-- those of a_f: 0 + x = x, so these are the same numbers without their divisions.
brakeBoundK :: BoundK -> Double -> Double -> (Double, Double)
brakeBoundK (BoundK jm jp am dt extra amJm amJp full0 c am2c) v a
  | a <= 0 =
      let af = negate a
          vPeak = if v == 0 then 0 else v   -- v + 0 (GHC folds that to v, and −0 + 0 is +0)
          full = vPeak * full0 + vPeak * vPeak / (2 * am)
          triangle
            | 2 * vPeak + af * af / jm <= am2c = vPeak * (af / jp + sqrt (2 * vPeak * c) + extra)
            | otherwise = 1 / 0
      in (min full triangle, vPeak)
  | otherwise =
      let ap = a
          vPeak = v + ap * ap / (2 * jm) + ap * dt
          full = vPeak * (ap / jm + amJm + amJp + extra) + vPeak * vPeak / (2 * am)
          triangle
            | 2 * vPeak <= am2c = vPeak * (ap / jm + sqrt (2 * vPeak * c) + extra)
            | otherwise = 1 / 0
      in (min full triangle, vPeak)
{-# INLINE brakeBoundK #-}

-- | The continuous-time distance to bring (v, a >= 0) down to velocity l with the
-- acceleration back at zero: first a down to 0, then an S-curve to a_min (or a
-- triangle short of it) and back (derivation in docs/profile-generator.md).
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

-- | The continuous-time distance to bring (v, a < 0) down to velocity l with the
-- acceleration back at zero, braking as hard as the ranges allow: a further down to the
-- peak deceleration (a_min, or less for a small drop), a hold, and the ramp back. When the
-- ramp back alone sheds more than v − l, the distance until the acceleration is back at
-- zero (the velocity is below l by then), unless the velocity would sink below zero on the
-- way: Nothing (derivation in docs/profile-generator.md).
brakeNeedFalling :: Problem -> Double -> Double -> Double -> Maybe Double
brakeNeedFalling pb v a l
  | v - a0 * a0 / (2 * j2) < 0 = Nothing
  | dv <= a0 * a0 / (2 * j2) = Just (v * t0 - a0 * t0 * t0 / 2 + j2 * t0 * t0 * t0 / 6)
  | otherwise = Just (d1 + d2 + d3)
  where
    j1 = abs (pbJMin pb); j2 = pbJMax pb; am = abs (pbAMin pb)
    a0 = negate a
    dv = v - l
    t0 = a0 / j2
    -- the velocity shed by a ramp from a0 to ap, a hold at ap and the ramp back
    full = (am * am - a0 * a0) / (2 * j1) + am * am / (2 * j2)
    (ap, t2) = if dv >= full then (am, (dv - full) / am)
               else (max a0 (sqrt ((dv + a0 * a0 / (2 * j1)) / (1 / (2 * j1) + 1 / (2 * j2)))), 0)
    t1 = (ap - a0) / j1; t3 = ap / j2
    d1 = v * t1 - a0 * t1 * t1 / 2 - j1 * t1 * t1 * t1 / 6
    v1 = v - a0 * t1 - j1 * t1 * t1 / 2
    d2 = v1 * t2 - ap * t2 * t2 / 2
    v2 = v1 - ap * t2
    d3 = v2 * t3 - ap * t3 * t3 / 2 + j2 * t3 * t3 * t3 / 6

-- | A fast sufficient test: every lower limit within reach (and the terminal) is further
-- away than the continuous braking distance plus a margin of 'quickMarginSteps' steps at
-- the peak velocity. From a falling acceleration the braking continues from it
-- ('brakeNeedFalling'): a pass that ramps its deceleration back up at a weak jerk, far
-- from the edge, probes at every step, and without this each probe would run the whole
-- braking.
quickNeed :: SeedEnv -> St -> Bool
quickNeed e st@(St v a s)
  | eHard e = False
  | otherwise =
      vPeak <= limitAt pb s
        && zonesOk (zoneIndex pb s + 1)
        && terminalOk
  where
    pb = ePb e
    !(d, vPeak) = brakeBound e st
    margin = vPeak * quickMarginSteps * pbDt pb + quickMarginM * min 1 (pbLength pb)
    Term p vt = eTerm e
    need l | a >= 0 = Just (brakeNeed pb v a l)
           | otherwise = brakeNeedFalling pb v a l
    fits l room = maybe False (\x -> x + margin <= room) (need l)
    zoneOk (z, l) = l >= vPeak || fits l (z - s)
    terminalOk
      | vt <= 0 = s + d <= p || fits 0 (p - s)
      | otherwise = s + d < p || vPeak <= vt || fits vt (p - s)
    -- every zone that starts within the reach (s, s + d]
    zonesOk !i
      | i >= U.length starts || z > s + d = True
      | otherwise = zoneOk (z, U.unsafeIndex (pbZoneSpeeds pb) i) && zonesOk (i + 1)
      where starts = pbZoneStarts pb
            z = U.unsafeIndex starts i

-- | The oracle: can the robot brake from this state without breaking anything?
-- On failure, the state at which the braking first breaks a rule.
brakeCheck :: SeedEnv -> St -> Either (St, St) ()
brakeCheck e st0
  | quickNeed e st0 = Right ()
  | otherwise = brakeSimulate e st0

-- | The oracle without 'quickNeed': the brake policy run step by step (its own bound test,
-- no lower limit and no terminal within the braking's reach, ends it early).
brakeSimulate :: SeedEnv -> St -> Either (St, St) ()
brakeSimulate e st0 = go st0 (0 :: Int)
  where
    pb = ePb e
    Term p vt = eTerm e
    -- a guard against a braking that never ends, so it must exceed every braking that
    -- does ('brakeTimeBound'). (Distance over peak velocity, the earlier guard, is shorter
    -- than a long braking takes: 3.83 to 1.23 m/s at 0.291 m/s² lasts 8.9 s, the guard
    -- allowed 7.5, and a feasible request was called infeasible.)
    maxSteps =
      let (d, vp) = brakeBound e st0
          dt = dtE e
      in max (ceiling (d / max peakFloor vp / dt)) (ceiling (min 1e15 (brakeTimeBound e st0 / dt))) + oracleExtraSteps :: Int
    -- (strict throughout: the loop runs up to some 10⁵ steps a call, millions a pass, and
    -- a lazy binding here is a heap object every step)
    !k = boundConsts e
    go !st !n
      | atRest e st = Right ()
      | otherwise =
          let !s = stS st
              !(d, vPeak) = brakeBoundK k (stV st) (stA st)
              !reachEnd = s + d
              !zoneMin = minLimitOn pb s reachEnd
              quick = vPeak <= zoneMin && (if vt <= 0 then reachEnd <= p else reachEnd < p || vPeak <= vt)
          in if quick then Right ()
             else if n > maxSteps then Left (st, st)
             else let !tau = targetFrom e reachEnd zoneMin
                      !st' = stepTo e st (brakeAccTo e st tau)
                  in if stepOk e st st' then go st' (n + 1) else Left (st, st')

-- | An upper bound on how long the brake policy brakes from a state: it brakes at once, as
-- hard as the ranges allow, toward the lowest limit in its reach, and again at each lower
-- limit the reach takes in as it moves (at most the limits within the first reach, plus
-- the terminal); each such phase ramps to a_min and back, and all of them together shed at
-- most the peak velocity at |a_min|.
brakeTimeBound :: SeedEnv -> St -> Double
brakeTimeBound e st0 =
  let pb = ePb e
      (d, vp) = brakeBound e st0
      am = abs (pbAMin pb)
      phases = fromIntegral (zoneIndex pb (stS st0 + d) - zoneIndex pb (stS st0) + 2) :: Double
      tRamp = am / abs (pbJMin pb) + am / pbJMax pb + boundExtraSteps * dtE e
  in max 0 (stA st0) / abs (pbJMin pb) + phases * tRamp + vp / am

safe :: SeedEnv -> St -> Bool
safe e st = either (const False) (const True) (brakeCheck e st)

-- | The gentle brake policy (down to each limit, arriving with zero acceleration) gives
-- the better profiles; when it cannot save the start state, the hardest one (braking
-- through the limits toward standstill) may still; when that fails too, the state at
-- which the hardest braking breaks a rule.
policyFor :: Problem -> Term -> St -> Either (St, St) SeedEnv
policyFor = policyWith 0

-- | 'policyFor' for passes that plan every step with this share of the jerk range left out
-- ('jerkPlanMargin'): the pass runs on the problem with its jerk range narrowed by it, so
-- its profile is within the problem's range by the margin.
policyWith :: Double -> Problem -> Term -> St -> Either (St, St) SeedEnv
policyWith margin q0 term st0 =
  let q = if margin > 0 then scaleJerk (1 - margin) q0 else q0
      gentle = SeedEnv q term False
      hard = gentle { eHard = True }
  in case (brakeCheck gentle st0, brakeCheck hard st0) of
       (Right (), _) -> Right gentle
       (_, Right ()) -> Right hard
       (_, Left bad) -> Left bad

-- | The distance the brake policy needs to stop from a state (used in messages and tests).
brakeStopDistance :: Problem -> Double -> Double -> Double
brakeStopDistance pb v a = go (St v a 0) (0 :: Int)
  where
    e = seedEnv pb (Term (1 / 0) (1 / 0)) True
    go st n
      | atRest e st || n > stopDistanceSteps = stS st
      | otherwise = go (stepTo e st (brakeAcc e st)) (n + 1)

-- | The distance the brake policy needs to bring a state down to velocity v with the
-- acceleration back at zero (infinite when it does not get there).
brakeDistanceTo :: Problem -> St -> Double -> Double
brakeDistanceTo q st0 v = go st0 (0 :: Int)
  where
    e = seedEnv q (Term (1 / 0) (1 / 0)) False
    go st n
      | stV st <= v && stA st >= 0 = stS st - stS st0
      | n > distanceToSteps = 1 / 0
      | otherwise = go (stepTo e st (brakeAccTo e st v)) (n + 1)

-- | Even raising the acceleration as fast as the jerk allows, the velocity from the start
-- state ends below zero.
sinksBelowZero :: Problem -> Bool
sinksBelowZero q = pbV0 q + leastDrop q < negate roundingSlack

-- | The least velocity change from the start acceleration: raising it as fast as the jerk
-- allows while it is negative.
leastDrop :: Problem -> Double
leastDrop pb = sum (takeWhile (< 0) [ pbA0 pb + fromIntegral k * pbJMax pb * pbDt pb | k <- [1 :: Int ..] ]) * pbDt pb
