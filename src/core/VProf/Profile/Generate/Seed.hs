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
-- A route that ends at rest is landed by that pass alone: near rest it creeps onto the
-- route end. A route that ends in motion (a moving end state) cannot be landed by
-- creeping; it is met from both sides ('meet'): the same pass runs on the problem
-- mirrored in time, from the end state backwards, and the two passes are joined on a
-- cruise whose length absorbs the distance exactly.
module VProf.Profile.Generate.Seed
  ( seed
  , SeedFailure (..)
  , brakeStopDistance
  , mirror
  , restFrom
  ) where

import Data.List (group, sortBy)
import Data.Ord (comparing)
import qualified Data.Vector.Unboxed as U
import Numeric (showFFloat)

import VProf.Profile.Generate.Exact (exactJoin, noProfileFits)
import VProf.Profile.Legality (legalVelocities)
import VProf.Profile.Problem (Problem (..))
import VProf.Profile.Problem.Transform (capOn, mirror, scaleRanges, startingAfter)
import VProf.Profile.Request (maxSamples)
import VProf.Profile.SpeedLimit

-- | Why no seed could be made: the request is infeasible (with where and why), or the
-- landing could not be tuned (a generator limitation, reported as such).
data SeedFailure
  = Infeasible String String   -- ^ offending field, explanation
  | LandingFailed String
  deriving (Eq, Show)

-- | State at sample k: velocity v_k, the acceleration a_{k-1} that led into it, position s_k.
data St = St { stV :: !Double, stA :: !Double, stS :: !Double }

-- | Two capped passes of the meet (the states after the start and after the end), their
-- cruise velocities and the distance left between them.
data Capped = Capped [St] [St] !Double !Double !Double

-- | Where the pass must be done: at or before position tP, and at most tV from then on.
data Term = Term { tP :: !Double, tV :: !Double }

data Env = Env
  { ePb :: !Problem
  , eTerm :: !Term
  , eHard :: !Bool   -- ^ brake to standstill (through every limit) rather than to each limit
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
    e = Env pb (Term (1 / 0) (1 / 0)) True
    go st n
      | atRest e st || n > 10000000 = stS st
      | otherwise = go (stepTo e st (brakeAcc e st)) (n + 1)

-- | One step of the forward pass: the largest safe acceleration.
choose :: Env -> St -> St
choose e st@(St v _ s) =
  let dt = dtE e
      pb = ePb e
      (lo, hi0) = accRange e st
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
      -- on the edge of the oracle the answer is usually the brake policy itself: one
      -- probe just above it settles that before the bisection (a higher acceleration is
      -- never safer, so while braking the probe goes first and the top is tried only
      -- when the probe passes)
      probe = aB + (hi - aB) / 32
      bisectFrom stP = search probe hi stP (5 :: Int)
  in if stA st < 0
       then maybe fallback (\stP -> maybe (bisectFrom stP) id (try hi)) (try probe)
       else maybe (maybe fallback bisectFrom (try probe)) id (try hi)

-- | The forward pass toward a standstill on the terminal point, from a state: the states
-- visited after it, in order, until it has come to rest within the landing tolerance
-- of the terminal. Stops after @limit@ steps.
forward :: Env -> Double -> Int -> St -> [St]
forward e landTol limit = go 0
  where
    p = tP (eTerm e)
    go n st
      | n >= limit = []
      | stS st >= p - landTol = finishBraking st (n :: Int)
      | otherwise = let st' = choose e st in st' : go (n + 1) st'
    finishBraking st n
      | atRest e st || n >= limit = []
      | otherwise = let st' = stepTo e st (brakeAcc e st) in st' : finishBraking st' (n + 1)

num :: Double -> String
num x = showFFloat Nothing (fromIntegral (round (x * 1e6) :: Integer) / 1e6 :: Double) ""

-- | The seed profile's velocities v_0..v_N.
--
-- The passes start from a state the brake policy can save. Braking is not always the
-- safest way on, though: a step that touches a short low zone must keep below its limit,
-- and a faster first step may leave that zone behind before the next one, where
-- braking from the start would still be in it. So when the start (or, on the mirrored
-- problem, the end) state fails the oracle, the first steps are searched ('leadIn')
-- before the request is called infeasible.
seed :: Problem -> Either SeedFailure (U.Vector Double)
seed = seedWithin 2

seedWithin :: Int -> Problem -> Either SeedFailure (U.Vector Double)
seedWithin depth pb = case seedFrom pb of
  Left f@(Infeasible "start_velocity" _) | depth > 0, startStuck moving pb -> either (Left . maybe f id) Right (leadIn depth pb)
  Left f@(Infeasible "end_velocity" _) | depth > 0, startStuck True (mirror pb) -> case leadIn depth (mirror pb) of
    Right vs -> Right (U.reverse vs)
    Left (Just (LandingFailed m)) -> Left (LandingFailed ("seen from the end, backwards in time: " ++ m))
    Left _ -> Left f
  r -> r
  where moving = pbVEnd pb > 0 || pbAEnd pb /= 0

-- | The start state fails the oracle: the hardest braking from it breaks a rule (with
-- the terminal of the two-sided meet's passes, or of the landing at rest).
startStuck :: Bool -> Problem -> Bool
startStuck meeting pb = either (const True) (const False) (policyFor pb term (St (pbV0 pb) (pbA0 pb) 0))
  where term | meeting = Term (pbLength pb + pbTol pb) (pbVEnd pb)
             | otherwise = Term (pbLength pb) 0

-- | The first step from the start state (a grid over its acceleration range, fastest
-- first) that keeps every rule and after which the rest can be seeded, on the problem
-- that starts there (the route shortened by the step, its zones shifted). When no first
-- step gives a profile but some get past the start's oracle, the start may not be what
-- stands in the way: the failure is then the end state's, if it has one of its own
-- ('endFailure'), or else the generator's where the rest failed for want of a join (not
-- a claim), or else the start's claim stands.
leadIn :: Int -> Problem -> Either (Maybe SeedFailure) (U.Vector Double)
leadIn depth pb = case [ r | Right r <- tries ] of
  (vs : _) -> Right vs
  [] -> Left (case [ g | Left (Just g) <- tries ] of
                [] -> Nothing
                gs | Just f <- endFailure pb -> Just f
                   | (g : _) <- [ g | g@(_, LandingFailed _) <- gs ] -> Just (unclaimed g)
                   | otherwise -> Nothing)
  where
    tries =
      [ case seedWithin (depth - 1) (startingAfter s1 v1 a pb) of
          Right vs | legalVelocities pb (U.cons (pbV0 pb) vs) -> Right (U.cons (pbV0 pb) vs)
                   | otherwise -> Left Nothing
          -- the first step did not get the start out of trouble
          Left (Infeasible f _) | f `elem` ["start_velocity", "start_acceleration"] -> Left Nothing
          Left g -> Left (Just (s1, g))
      | i <- [0 .. 32 :: Int]
      , let a = hi - (hi - lo) * fromIntegral i / 32
            st1@(St v1 _ s1) = stepTo e st0 a
      , stepOk e st0 st1, s1 < pbLength pb ]
    e = Env pb (Term (pbLength pb + pbTol pb) (1 / 0)) True
    st0 = St (pbV0 pb) (pbA0 pb) 0
    (lo, hi) = accRange e st0
    -- the rest's own claim is about the shortened problem after one chosen first step,
    -- not a proof for this one: reported as the generator's failure
    unclaimed (s1, g) = LandingFailed ("braking from the start breaks a rule, and after a legal first step (to "
                                       ++ num s1 ++ " m) the rest fails: " ++ case g of
                                         Infeasible _ m -> m
                                         LandingFailed m -> m)

-- | The end state's own infeasibility, when it ends in motion: its acceleration cannot
-- be reached, or the end pass (on the mirror) cannot be saved by its brake policy.
endFailure :: Problem -> Maybe SeedFailure
endFailure pb
  | pbVEnd pb <= 0 && pbAEnd pb == 0 = Nothing
  | sinksBelowZero rv = Just (endAccFailure pb)
  | otherwise = either (Just . endInfeasible pb (Env rv bTerm True)) (const Nothing) (policyFor rv bTerm rt0)
  where
    rv = mirror pb
    rt0 = St (pbVEnd pb) (pbA0 rv) 0
    bTerm = Term (pbLength pb + pbTol pb) (pbV0 pb)

endAccFailure :: Problem -> SeedFailure
endAccFailure pb =
  Infeasible "end_acceleration"
    ("end_velocity " ++ num (pbVEnd pb) ++ " m/s with end_acceleration " ++ num (pbAEnd pb)
     ++ " m/s² cannot be reached: ramping the acceleration up to it within max_jerk "
     ++ num (pbJMax pb) ++ " m/s³ gains " ++ num (negate (leastDrop (mirror pb))) ++ " m/s, more than the end velocity")

seedFrom :: Problem -> Either SeedFailure (U.Vector Double)
seedFrom pb = do
  let dt = pbDt pb
      st0 = St (pbV0 pb) (pbA0 pb) 0
  if sinksBelowZero pb
    then Left (startSinks pb)
  else if pbVEnd pb > 0 || pbAEnd pb /= 0
    then meet pb
  else do
      -- ending at rest: the pass brakes to a standstill on the route end; near rest it
      -- creeps, so it lands within the tolerance
      let term = Term (pbLength pb) 0
          landTol = pbTol pb / 2
      e0 <- either (Left . startInfeasible pb (Env pb term True)) Right (policyFor pb term st0)
      let middle = forward e0 landTol (8 * 1048576) st0
          sEnd = if null middle then 0 else stS (last middle)
          aRest = if null middle then pbA0 pb else stA (last middle)
          -- at rest with an acceleration that cannot return to zero in one jerk step:
          -- stand still for one more sample
          settle = let j = negate aRest / dt in if j >= pbJMin pb && j <= pbJMax pb then [] else [St 0 0 sEnd]
      if abs (sEnd - pbLength pb) <= landTol || null middle && pbLength pb <= landTol
        then Right (U.fromList (pbV0 pb : map stV (middle ++ settle)))
        else Left (LandingFailed ("the forward pass stopped at " ++ num sEnd ++ " m, aiming at " ++ num (pbLength pb) ++ " m"))

startSinks :: Problem -> SeedFailure
startSinks pb =
  Infeasible "start_acceleration"
    ("start_acceleration " ++ num (pbA0 pb) ++ " m/s² at start_velocity " ++ num (pbV0 pb)
     ++ " m/s drives the velocity below zero whatever the jerk: raising the acceleration at max_jerk "
     ++ num (pbJMax pb) ++ " m/s³ still loses " ++ num (negate (leastDrop pb)) ++ " m/s")

-- | The hardest legal braking from the start state to a standstill within the route,
-- v_0 .. 0 (just v_0 when the start is at rest): the thesis mode's way into its band,
-- which grows from rest (see "VProf.Profile.Generate.Thesis").
restFrom :: Problem -> Either SeedFailure (U.Vector Double)
restFrom pb
  | sinksBelowZero pb = Left (startSinks pb)
  | otherwise = case brakeCheck e st0 of
      Left bad -> Left (startInfeasible pb e bad)
      Right () -> Right (U.fromList (pbV0 pb : map stV (take maxSamples (braking st0))))
  where
    e = Env pb (Term (pbLength pb) 0) True
    st0 = St (pbV0 pb) (pbA0 pb) 0
    braking st
      | atRest e st = []
      | otherwise = let st' = stepTo e st (brakeAcc e st) in st' : braking st'

-- | Even raising the acceleration as fast as the jerk allows, the velocity from the start
-- state ends below zero.
sinksBelowZero :: Problem -> Bool
sinksBelowZero q = pbV0 q + leastDrop q < -1e-12

-- | The least velocity change from the start acceleration: raising it as fast as the jerk
-- allows while it is negative.
leastDrop :: Problem -> Double
leastDrop pb = sum (takeWhile (< 0) [ pbA0 pb + fromIntegral k * pbJMax pb * pbDt pb | k <- [1 :: Int ..] ]) * pbDt pb

-- | The gentle brake policy (down to each limit, arriving with zero acceleration) gives
-- the better profiles; when it cannot save the start state, the hardest one (braking
-- through the limits toward standstill) may still; when that fails too, the state at
-- which the hardest braking breaks a rule.
policyFor :: Problem -> Term -> St -> Either (St, St) Env
policyFor q term st0 =
  let gentle = Env q term False
      hard = gentle { eHard = True }
  in case (brakeCheck gentle st0, brakeCheck hard st0) of
       (Right (), _) -> Right gentle
       (_, Right ()) -> Right hard
       (_, Left bad) -> Left bad

-- | The greedy pass from a state: the states after it, up to the first for which @done@
-- holds, at most @n@.
passFrom :: Env -> Int -> (St -> Bool) -> St -> [St]
passFrom e n done = go n
  where
    go k st
      | k <= 0 = []
      | otherwise = let st' = choose e st in st' : (if done st' then [] else go (k - 1) st')

-- | Linear interpolation of ys over ascending xs, clamped at both ends.
interpolate :: U.Vector Double -> U.Vector Double -> Double -> Double
interpolate xs ys x
  | n == 0 = 0
  | x <= U.head xs = U.head ys
  | x >= U.last xs = U.last ys
  | otherwise =
      let i = go 0 (n - 1)
          x0 = xs U.! i; x1 = xs U.! (i + 1)
          w = if x1 > x0 then (x - x0) / (x1 - x0) else 0
      in ys U.! i + w * (ys U.! (i + 1) - ys U.! i)
  where
    n = U.length xs
    -- invariant: xs[lo] <= x < xs[hi]
    go lo hi
      | hi - lo <= 1 = lo
      | otherwise = let mid = (lo + hi) `div` 2 in if xs U.! mid <= x then go mid hi else go lo mid

-- | The distance the brake policy needs to bring a state down to velocity v with the
-- acceleration back at zero (infinite when it does not get there).
brakeDistanceTo :: Problem -> St -> Double -> Double
brakeDistanceTo q st0 v = go st0 (0 :: Int)
  where
    e = Env q (Term (1 / 0) (1 / 0)) False
    go st n
      | stV st <= v && stA st >= 0 = stS st - stS st0
      | n > 4000000 = 1 / 0
      | otherwise = go (stepTo e st (brakeAccTo e st v)) (n + 1)

-- | A moving end state: the two-sided meet.
--
-- The forward pass from the start state and the same pass on the 'mirror' (from the
-- end state, backwards in time) are each legal by construction and near time-optimal
-- for their own end: the first is the highest velocity reachable from the start, the
-- second the highest from which the end state can still be reached. The profile follows
-- the lower of the two. They are joined on a /plateau/: both passes are run again with
-- every limit capped at a level V just below the highest point of the lower envelope,
-- over the stretch where that envelope is above V, so that each ends in a cruise at
-- exactly V with zero acceleration. Between the forward pass's first cruise sample and
-- the backward pass's, the profile cruises at V for as many steps as the distance
-- needs, and a smooth sin² dent in that cruise takes out the fraction of a step left
-- over: the route end is met exactly whatever the sampling. Stretches where both passes
-- already cruise at the same speed limit are tried first (V is that limit and nothing
-- is clipped), then the levels below the top, from the highest down (a lower V gives a
-- longer plateau and a gentler dent). The first profile the checker finds legal is the
-- seed. On a short route there may be no plateau at all; then the join is solved
-- exactly, as a linear program over the number of steps ("VProf.Profile.Generate.Exact"),
-- which also proves, where it can, that no profile exists. When neither gives an
-- answer, the request is answered NOT_CONVERGED with the reason.
meet :: Problem -> Either SeedFailure (U.Vector Double)
meet pb = do
  let rv = mirror pb
      rt0 = St (pbVEnd pb) (pbA0 rv) 0
  if sinksBelowZero rv then Left (endAccFailure pb) else Right ()
  fEnv <- either (Left . startInfeasible pb (Env pb fTerm True)) Right (policyFor pb fTerm st0)
  bEnv <- either (Left . endInfeasible pb (Env rv bTerm True)) Right (policyFor rv bTerm rt0)
  let fAll = st0 : passFrom fEnv limit (\st -> stS st >= len) st0
      bAll = rt0 : passFrom bEnv limit (\st -> stS st >= len) rt0
      fS = U.fromList (map stS fAll)
      fV = U.fromList (map stV fAll)
      bX = U.fromList (reverse (map ((len -) . stS) bAll))
      bW = U.fromList (reverse (map stV bAll))
      -- the lower envelope at the forward pass's samples up to the route end
      h = U.generate (U.length (U.takeWhile (<= len) fS)) (\k -> min (fV U.! k) (interpolate bX bW (fS U.! k)))
      kStar = U.maxIndex h
      top = h U.! kStar
      levels = [ top * (1 - d) | d <- [0.001, 0.003, 0.01, 0.02, 0.04, 0.07, 0.12, 0.2, 0.3, 0.45, 0.6, 0.75, 0.9] ]
      -- stretches where both passes cruise at the same speed limit: the lower envelope
      -- is already flat there, the plateau costs nothing but the dent (long stretches
      -- first, of 16 samples or more, the last of them first)
      atCap k = abs (h U.! k - limitAt pb (fS U.! k)) <= 1e-9 * max 1 (h U.! k)
      -- (the last first: the backward pass then has the least to do again, and the
      -- forward one resumes from nearly all of its uncapped run)
      runs = sortBy (comparing (\(a, b) -> (b - a < 16, negate b)))
               [ (head ks, last ks) | ks <- groupRuns [ k | k <- [0 .. U.length h - 1], atCap k ], length ks >= 4 ]
      flat = [ (v, fS U.! a, fS U.! b) | (a, b) <- take 4 runs, let v = h U.! a ]
      peak = [ (v, alpha, beta) | v <- levels, v > 0, Just (alpha, beta) <- [around v] ]
      around v =
        let n = U.length h
            kl = last (-1 : [ k | k <- [0 .. kStar - 1], h U.! k <= v ])
            kr = head ([ k | k <- [kStar + 1 .. n - 1], h U.! k <= v ] ++ [n])
            margin = 2 * v * dt + tol
            alpha = if kl < 0 then brakeDistanceTo pb st0 v + margin else fS U.! kl
            beta = if kr >= n then len - brakeDistanceTo rv rt0 v - margin else fS U.! kr
        in if alpha < beta then Just (alpha, beta) else Nothing
      capped' = capped fEnv bEnv (drop 1 fAll) (drop 1 bAll) rv rt0
      attempts = [ p | (v, alpha, beta) <- flat ++ peak, Just c <- [capped' v alpha beta], Just p <- [plateau v c] ]
      -- Fallbacks, tried only when no plateau above joins (short routes, where the
      -- envelopes meet in a sharp peak and every plateau is too short for its dent).
      -- Tuned: between two levels the distance the cruise must cover changes
      -- continuously with the level (the passes land on it smoothly), while each cruise
      -- step covers v·dt: so for a fixed number of cruise steps the overshoot changes
      -- sign between levels where that number fits the one and not the other, and a
      -- bisection on the level finds where no dent is needed at all.
      -- Each pair of levels is tried over the stretch where the envelope is above the
      -- lower one and over the widest stretch the ends can brake to it for (there the
      -- passes do not rise above the level first only to come back down to it).
      -- The start and end velocities are levels too: a profile that only speeds up (or
      -- only slows down) on a short route has its plateau at one of them.
      tuned = [ p | (v1, v2) <- zip tunedLevels (drop 1 tunedLevels), v2 > 0, stretch <- [around, wide]
                  , Just (alpha, beta) <- [stretch v2], Just p <- [tune capped' v1 v2 alpha beta] ]
      ends = [ x | x <- [pbVEnd pb, pbV0 pb], x > 0, x < top ]
      -- a finer grid than the plateau levels: the overshoot left over (modulo a cruise
      -- step) moves slowly with the level, so the brackets must be narrow enough to see
      -- it change sign between them, and cover enough to see it change at all
      tunedLevels = map head (group (sortBy (flip compare) ([ top * (1 - 0.7 * fromIntegral i / 32) | i <- [0 .. 32 :: Int] ] ++ ends)))
      atEnds = [ p | v <- ends, Just (alpha, beta) <- [wide v], Just c <- [capped' v alpha beta], Just p <- [plateau v c] ]
      -- a state that needs no braking to be at v caps from where it is
      wide v =
        let margin = 2 * v * dt + tol
            reach q st = let d = brakeDistanceTo q st v in if d > 0 then d + margin else 0
            alpha = reach pb st0
            beta = len - reach rv rt0
        in if alpha < beta then Just (alpha, beta) else Nothing
      -- Valley: a level low enough that both ends can brake to it with room to spare,
      -- over the whole stretch between (below every limit there), so the plateau is long
      -- and its dent gentle; slow, but the rubber band raises it afterwards.
      -- Softened: the plateau at v, with both passes run within a fraction of the
      -- acceleration and jerk ranges (still legal for the problem): their ramps then take
      -- longer, continuously with the fraction, so that the overshoot left over moves
      -- through zero (where a plateau too short for its dent needs none). The passes
      -- start afresh (the uncapped ones were made with the full ranges).
      softened = [ p | v <- ends ++ [ top * (1 - d) | d <- [0.02, 0.1, 0.3] ], Just (alpha, beta) <- [wide v]
                     , Just p <- [soften v alpha beta] ]
      soften v alpha beta =
        let at phi = let q = scaleRanges phi pb; rq = scaleRanges phi rv
                     in cappedOn q fEnv bEnv [] [] rq rt0 v alpha beta
            r = leftOver v
            grid = [ (phi, c) | i <- [0 .. 15 :: Int], let phi = 1 - 0.04 * fromIntegral i, Just c <- [at phi] ]
            -- a sign change between neighbours with a small step is a root; a step of
            -- nearly a cruise step's distance is a wrap (a pass took a step more)
            roots = [ p | ((p1, c1), (p2, c2)) <- zip grid (drop 1 grid), r c1 * r c2 <= 0
                        , abs (r c1 - r c2) < v * dt / 2, Just p <- [bisectJoin at (const v) p1 p2 (signum (r c1)) 48] ]
        in case roots of
             (p : _) -> Just p
             [] -> Nothing
      valley = [ p | f <- [0.5, 0.25, 0.1, 0.03], Just (v, alpha, beta) <- [lowPlateau (top * f) (3 :: Int)]
                   , Just c <- [capped' v alpha beta], Just p <- [plateau v c] ]
      lowPlateau v n
        | v <= 0 || n <= 0 = Nothing
        | otherwise = do
            (alpha, beta) <- wide v
            let lim = minLimitOn pb (max 0 alpha) (min len beta)
            if lim >= v then Just (v, alpha, beta) else lowPlateau (lim * (1 - 1e-6)) (n - 1)
  case attempts ++ tuned ++ atEnds ++ softened ++ valley ++ maybe [] pure (exactJoin pb) of
    (p : _) -> Right p
    []
      | Just why <- noProfileFits pb -> Left (Infeasible (if pbV0 pb > pbVEnd pb then "start_velocity" else "end_velocity") why)
      | top <= 0 -> Left (LandingFailed ("the forward and the backward pass do not meet" ++ hint))
      | otherwise -> Left (LandingFailed ("no plateau below " ++ num top ++ " m/s joins the forward and the backward pass" ++ hint))
  where
    len = pbLength pb
    tol = pbTol pb
    dt = pbDt pb
    limit = 8 * 1048576
    -- what a user can do: before the exact join, 13 requests in 10 000 random ones ended
    -- here, and half the time step gave 3 of them a legal profile; with the exact join
    -- none of those 10 000 does (a request it cannot bound, or with more steps than its
    -- programs take, still may)
    hint = " (a limit of the generator, not a proof that no profile exists; a finer time_step, such as "
           ++ num (dt / 2) ++ " s, may give one)"
    st0 = St (pbV0 pb) (pbA0 pb) 0
    -- the start pass must be able to come down to the end velocity by the route end;
    -- the end pass (backwards) to the start velocity by the route start
    fTerm = Term (len + tol) (pbVEnd pb)
    bTerm = Term (len + tol) (pbV0 pb)
    cruising v st = abs (stV st - v) <= 1e-9 * max 1 v && abs (stA st) <= 1e-9
    -- the two passes capped at v over [alpha, beta], each up to its first cruise sample at
    -- v, and the distance the cruise between them must cover
    capped = cappedOn pb
    cappedOn base fEnv bEnv fFree bFree rv rt0 v alpha beta = do
      -- the forward pass capped at v from alpha on, until it cruises at v
      let pF = capOn alpha (len + 1) v base
          pB = capOn (len - beta) (len + 1) v rv
      fE <- either (const Nothing) Just (policyFor pF fTerm st0)
      bE <- either (const Nothing) Just (policyFor pB bTerm rt0)
      let fRun = resume fEnv fE fFree alpha st0 (\st -> stS st > beta || stS st >= alpha && cruising v st)
          bRun = resume bEnv bE bFree (len - beta) rt0 (\st -> stS st > len - alpha || stS st >= len - beta && cruising v st)
      fi <- lastMaybe fRun
      bm <- lastMaybe bRun
      guardM (cruising v fi && cruising v bm)
      pure (Capped fRun bRun (stV fi) (stV bm) (len - stS bm - stS fi))
    -- k steps at the plateau level, from the forward pass's cruise sample to the
    -- backward pass's, cover this much more than the gap
    overBy v (Capped _ _ vi vm gap) k = dt * (vi + vm) / 2 + dt * v * fromIntegral (k - 1) - gap
    kUpOf v (Capped _ _ vi vm gap) = 1 + max 0 (ceiling ((gap / dt - (vi + vm) / 2) / v - 1e-12)) :: Int
    plateau v c =
      let kUp = kUpOf v c
          -- one step more than the gap (a dent takes the rest out) or one fewer (a bump
          -- adds it, where the limits leave room above the plateau): the smaller first
          ks = sortBy (comparing (abs . overBy v c)) (kUp : [ kUp - 1 | kUp > 1 ])
      in joinAt v c ks
    joinAt v c@(Capped fRun bRun _ _ _) ks =
      let over = overBy v c
          profileWith dent k =
            let d = if dent && k > 1 then over k / (dt * fromIntegral k / 2) else 0
                bump j = let x = sin (pi * fromIntegral j / fromIntegral k) in x * x
                cruise = [ v - d * bump j | j <- [1 .. k - 1] ]
            in U.fromList ([pbV0 pb] ++ map stV fRun ++ cruise ++ reverse (pbVEnd pb : map stV bRun))
          -- the dent first (the route end met exactly); a cruise without it when the
          -- overshoot is within half the end tolerance
          tries = [ profileWith True k | k <- ks, k > 1 || abs (over k) <= tol / 2 ]
                  ++ [ profileWith False k | k <- ks, k > 1, abs (over k) <= tol / 2 ]
      in case filter (legalVelocities pb) tries of
           (vs : _) -> Just vs
           [] -> Nothing
    -- the tuned plateau between levels v1 > v2 over the same stretch: for each cruise
    -- length whose overshoot changes sign between them, bisect the level down to an
    -- overshoot of a hundredth of the tolerance
    tune capped' v1 v2 alpha beta = do
      c1 <- capped' v1 alpha beta
      c2 <- capped' v2 alpha beta
      let r1 = leftOver v1 c1; r2 = leftOver v2 c2
      guardM (r1 * r2 <= 0 && abs (r1 - r2) < v2 * dt / 2)
      bisectJoin (\x -> capped' x alpha beta) id v1 v2 (signum r1) 48
    -- the cruise length nearest to the gap at level v, and the overshoot it leaves: that
    -- changes sign where one of them fits exactly, or where it wraps round (by a step's
    -- distance) when one of the passes takes a step more; a bisection tells them apart
    nearestK v c = let k0 = kUpOf v c in minimumOn (abs . overBy v c) [ k | k <- [k0 - 1, k0], k >= 1 ]
    leftOver v c = overBy v c (nearestK v c)
    -- bisect a parameter x from a, where the overshoot of the passes made at x (with the
    -- plateau at level x) has sign sa, towards b, where it has the other, down to an
    -- overshoot of a hundredth of the tolerance; then join there
    bisectJoin at level a b sa n
      | n <= (0 :: Int) = Nothing
      | otherwise = do
          let mid = (a + b) / 2
              v = level mid
          cm <- at mid
          let o = leftOver v cm
          if abs o <= tol / 100 then joinAt v cm [nearestK v cm]
            else if signum o == sa then bisectJoin at level mid b sa (n - 1) else bisectJoin at level a mid sa (n - 1)
    guardM b = if b then Just () else Nothing
    -- a capped pass follows the uncapped one for as long as the cap lies beyond the
    -- reach of every brake test it makes (twice the braking reach, plus a metre): it
    -- resumes from there rather than from the start
    resume e0 e1 free cut start stop =
      let shared = if eHard e0 /= eHard e1 then []
                   else takeWhile (\st -> let (d, _) = brakeBound e0 st in stS st + 2 * d + 1 < cut) free
          from = if null shared then start else last shared
      in shared ++ passFrom e1 limit stop from
    lastMaybe xs = if null xs then Nothing else Just (last xs)
    minimumOn f = head . sortBy (comparing f)
    groupRuns [] = []
    groupRuns (k : ks) = let (run, rest) = go k ks in (k : run) : groupRuns rest
      where go p (x : xs) | x == p + 1 = let (r, t) = go x xs in (x : r, t)
            go _ xs = ([], xs)

-- | Explain why the end state cannot be reached, from the failure of the backward pass
-- (positions measured from the route end).
endInfeasible :: Problem -> Env -> (St, St) -> SeedFailure
endInfeasible pb e (St v0' _ r0, St v1 _ r)
  | r > tP (eTerm e) =
      Infeasible "end_velocity"
        ("end_velocity " ++ num (pbVEnd pb) ++ " m/s" ++ withAcc ++ " cannot be reached at route_length "
         ++ num (pbLength pb) ++ " m from start_velocity " ++ num (pbV0 pb)
         ++ " m/s: even accelerating as hard as max_acceleration " ++ num (pbAMax pb) ++ " m/s² and max_jerk "
         ++ num (pbJMax pb) ++ " m/s³ allow, a profile ending so would still be at " ++ num (max v0' v1)
         ++ " m/s at the route start")
  | otherwise =
      Infeasible "end_velocity"
        ("end_velocity " ++ num (pbVEnd pb) ++ " m/s" ++ withAcc ++ " cannot be reached under the speed limit of "
         ++ num (minLimitOn (ePb e) r0 r) ++ " m/s between " ++ num (pbLength pb - r) ++ " m and "
         ++ num (pbLength pb - r0) ++ " m: accelerating into it as hard as the limits allow (max_acceleration "
         ++ num (pbAMax pb) ++ " m/s², max_jerk " ++ num (pbJMax pb) ++ " m/s³) it is still at "
         ++ num (max v0' v1) ++ " m/s there")
  where withAcc = if pbAEnd pb /= 0 then " with end_acceleration " ++ num (pbAEnd pb) ++ " m/s²" else ""

-- | Explain why the start state cannot be braked legally.
startInfeasible :: Problem -> Env -> (St, St) -> SeedFailure
startInfeasible pb e (St v0' _ s0', St v1 _ s)
  | s > tP (eTerm e) && tV (eTerm e) <= 0 =
      Infeasible "start_velocity"
        ("start_velocity " ++ num (pbV0 pb) ++ " m/s with start_acceleration " ++ num (pbA0 pb)
         ++ " m/s² cannot stop within route_length " ++ num (pbLength pb) ++ " m: braking at min_acceleration "
         ++ num (pbAMin pb) ++ " m/s² and min_jerk " ++ num (pbJMin pb) ++ " m/s³ needs "
         ++ num (brakeStopDistance pb (pbV0 pb) (pbA0 pb)) ++ " m")
  | s > tP (eTerm e) =
      Infeasible "start_velocity"
        ("start_velocity " ++ num (pbV0 pb) ++ " m/s with start_acceleration " ++ num (pbA0 pb)
         ++ " m/s² cannot come down to end_velocity " ++ num (pbVEnd pb) ++ " m/s within route_length "
         ++ num (pbLength pb) ++ " m: braking at min_acceleration " ++ num (pbAMin pb) ++ " m/s² and min_jerk "
         ++ num (pbJMin pb) ++ " m/s³ it is still at " ++ num (max v0' v1) ++ " m/s there")
  | otherwise =
      Infeasible "start_velocity"
        ("start_velocity " ++ num (pbV0 pb) ++ " m/s with start_acceleration " ++ num (pbA0 pb)
         ++ " m/s² cannot brake in time for the speed limit of " ++ num (minLimitOn pb s0' s)
         ++ " m/s between " ++ num s0' ++ " m and " ++ num s ++ " m: the hardest braking allowed (min_acceleration " ++ num (pbAMin pb)
         ++ " m/s², min_jerk " ++ num (pbJMin pb) ++ " m/s³) is still at " ++ num (max v0' v1) ++ " m/s there")
