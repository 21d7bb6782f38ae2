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
stepOk e (St v _ s) (St v' _ s') =
  v' >= 0
    && max v v' <= minLimitOn pb s (max s s')
    && terminalOk
  where
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
brakeAcc e st@(St v _ _)
  | v <= 0 || w <= 0 = hold
  | not (ok hi) = hold
  | ok lo = lo
  | otherwise = max lo (min hi (exact m0))
  where
    dt = dtE e
    j = pbJMax (ePb e) * dt
    (lo, hi) = accRange e st
    tau = brakeTarget e st
    w = v - tau
    hold = max lo (min hi 0)
    ok x = w + x * dt + rampDrop e x >= 0
    -- With m negative ramp terms after x, i.e. x in (-(m+1)j, -mj], the velocity left
    -- above the target after the ramp is w + dt((m+1)x + j m(m+1)/2); its root is x_m.
    -- The m that fits its own root is near sqrt(2w/(dt j)); look around it.
    root m = negate (w / dt + j * m * (m + 1) / 2) / (m + 1)
    fits m = let x = root m in x > negate (m + 1) * j - 1e-15 && x <= negate m * j + 1e-15
    m0 = let g = fromIntegral (floor (sqrt (2 * w / (dt * j))) :: Int) :: Double
             cands = filter (>= 0) [g, g - 1, g + 1, g - 2, g + 2, g - 3, g + 3]
         in case filter fits cands of
              (m : _) -> m
              [] -> case filter fits [0 .. 4 * g + 16] of
                (m : _) -> m
                [] -> 0   -- unreachable: some m always fits; 0 is then nudged to feasibility
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
      Term p vt = eTerm e
      zoneMin = minLimitOn (ePb e) s (s + d)
  in if s + d >= p then min zoneMin (max 0 vt) else zoneMin

-- | Standing still for good is possible from this state: at rest, and the acceleration
-- can return to zero within one jerk step.
atRest :: Env -> St -> Bool
atRest e (St v a _) = v == 0 && a >= negate (pbJMax (ePb e) * dtE e) && a <= negate (pbJMin (ePb e) * dtE e)

-- | An upper bound on the distance the brake policy needs from a state, and on the
-- highest velocity it reaches on the way.
brakeBound :: Env -> St -> (Double, Double)
brakeBound e (St v a _) =
  let pb = ePb e; dt = dtE e
      ap = max 0 a
      jm = abs (pbJMin pb); am = abs (pbAMin pb)
      vPeak = v + ap * ap / (2 * jm) + ap * dt
      t = ap / jm + am / jm + vPeak / am + am / pbJMax pb + 6 * dt
  in (vPeak * t, vPeak)

-- | The oracle: can the robot brake from this state without breaking anything?
-- On failure, the state at which the braking first breaks a rule.
brakeCheck :: Env -> St -> Either St ()
brakeCheck e st0 = go st0 (0 :: Int)
  where
    pb = ePb e
    Term p vt = eTerm e
    maxSteps = let (d, vp) = brakeBound e st0 in ceiling (d / max 1e-9 vp / dtE e) + 64 :: Int
    go st n
      | atRest e st = Right ()
      | quick st = Right ()
      | n > maxSteps = Left st
      | otherwise =
          let st' = stepTo e st (brakeAcc e st)
          in if stepOk e st st' then go st' (n + 1) else Left st'
    quick st@(St _ _ s) =
      let (d, vPeak) = brakeBound e st
          reachEnd = s + d
      in vPeak <= minLimitOn pb s reachEnd
           && (if vt <= 0 then reachEnd <= p else reachEnd < p || vPeak <= vt)

safe :: Env -> St -> Bool
safe e st = either (const False) (const True) (brakeCheck e st)

-- | The distance the brake policy needs to stop from a state (used in messages and tests).
brakeStopDistance :: Problem -> Double -> Double -> Double
brakeStopDistance pb v a = go (St v a 0) (0 :: Int)
  where
    e = Env pb (Term (1 / 0) (1 / 0))
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
  in case try hi of
       Just st' -> st'
       Nothing -> search aB hi fallback (24 :: Int)

-- | The forward pass from a state until the terminal is reached; the states visited
-- after the given one, in order. Stops after @limit@ steps.
forward :: Env -> Double -> Int -> St -> [St]
forward e landTol limit = go 0
  where
    Term p vt = eTerm e
    go n st
      | n >= limit = []
      | vt <= 0 && stS st >= p - landTol = finishBraking st (n :: Int)
      | vt > 0 && stS st >= p + landTol && stV st == vt = []   -- past the aim, cruising
      | otherwise = let st' = choose e st in st' : go (n + 1) st'
    finishBraking st n
      | atRest e st || n >= limit = []
      | otherwise = let st' = stepTo e st (brakeAcc e st) in st' : finishBraking st' (n + 1)

-- | The tail: velocities after the junction sample, ending with v_N = end velocity, whose
-- accelerations ramp from 0 to the end acceleration; and the junction velocity.
tail' :: Problem -> Either SeedFailure ([Double], Double)
tail' pb
  | m == 0 = Right ([], vE)
  | vc < -1e-9 = Left (Infeasible "end_acceleration"
      ("end_velocity " ++ num vE ++ " m/s with end_acceleration " ++ num aE
       ++ " m/s² cannot be reached: ramping the acceleration up to it within max_jerk "
       ++ num (pbJMax pb) ++ " m/s³ needs a velocity below zero before the end"))
  | otherwise = Right (drop 1 vs, max 0 vc)
  where
    dt = pbDt pb; aE = pbAEnd pb; vE = pbVEnd pb
    jLim = if aE > 0 then pbJMax pb else abs (pbJMin pb)
    m = max 0 (ceiling (abs aE / (jLim * dt) - 1e-9) - 1) :: Int
    alphas = [aE * fromIntegral i / fromIntegral (m + 1) | i <- [1 .. m]]
    vc = vE - dt * sum alphas
    vs = scanl (\v a -> v + a * dt) (max 0 vc) alphas

num :: Double -> String
num x = showFFloat Nothing (fromIntegral (round (x * 1e6) :: Integer) / 1e6) ""

-- | The seed profile's velocities v_0..v_N.
seed :: Problem -> Either SeedFailure (U.Vector Double)
seed pb = do
  (tailVs, vc) <- tail' pb
  let dt = pbDt pb
      tailLen = sum (zipWith (\a b -> (a + b) * dt / 2) (vc : tailVs) tailVs)
      aim = pbLength pb - tailLen
      landTol = pbTol pb / 2
      st0 = St (pbV0 pb) (pbA0 pb) 0
      limit = 8 * 1048576
      finish middle = Right (U.fromList (pbV0 pb : map stV middle ++ tailVs))
  if aim <= 0 && not (null tailVs)
    then Left (Infeasible "end_acceleration"
           ("the ramp to end_acceleration " ++ num (pbAEnd pb) ++ " m/s² needs " ++ num tailLen
            ++ " m, more than route_length " ++ num (pbLength pb) ++ " m"))
    else do
      let e0 = Env pb (Term aim vc)
      case brakeCheck e0 st0 of
        Left bad -> Left (startInfeasible pb e0 bad)
        Right () -> pure ()
      if vc <= 0
        then do
          let middle = forward e0 landTol limit st0
              sEnd = if null middle then 0 else stS (last middle)
          if abs (sEnd - aim) <= landTol || null middle && aim <= landTol
            then finish middle
            else Left (LandingFailed ("the forward pass stopped at " ++ num sEnd ++ " m, aiming at " ++ num aim ++ " m"))
        else landMoving pb e0 st0 vc aim landTol limit >>= finish

-- | Landing at a moving terminal: find the point before the aim where the pass must be
-- down to the junction velocity so that a sample falls on the aim.
landMoving :: Problem -> Env -> St -> Double -> Double -> Double -> Int -> Either SeedFailure [St]
landMoving pb e0 st0 vc aim landTol limit = attempt (0 :: Int) 0 first
  where
    dt = pbDt pb
    first = forward e0 landTol limit st0
    -- the states before the terminal can matter are shared by every attempt
    rhoMax = 4 * vc * dt + 8 * pbTol pb
    prefixLen = length (takeWhile (\st -> let (d, _) = brakeBound e0 st in stS st + d < aim - rhoMax - 1e-9) first)
    prefix = take prefixLen first
    restart = if prefixLen == 0 then st0 else last prefix
    runWith rho = prefix ++ forward (Env pb (Term (aim - rho) vc)) landTol (limit - prefixLen) restart
    landing sts = case dropWhile (\st -> stS st < aim - landTol) sts of
      (st : _) -> Just st
      [] -> Nothing
    good st = abs (stS st - aim) <= landTol && stV st == vc && abs (stA st) <= min (pbJMax pb) (abs (pbJMin pb)) * dt
    cut sts = let (before, rest) = span (\st -> stS st < aim - landTol) sts in before ++ take 1 rest
    attempt n rho sts
      | n > 60 || rho > rhoMax = Left (LandingFailed ("could not land within " ++ num landTol ++ " m of " ++ num aim ++ " m"))
      | otherwise = case landing sts of
          Nothing -> Left (LandingFailed ("the forward pass never reached " ++ num aim ++ " m"))
          Just st
            | good st -> Right (cut sts)
            | otherwise ->
                let g = stS st - aim
                    shift = if stV st /= vc then max g (vc * dt / 4) else g
                    rho' = rho + max (landTol / 2) shift
                in attempt (n + 1) rho' (runWith rho')

-- | Explain why the start state cannot be braked legally.
startInfeasible :: Problem -> Env -> St -> SeedFailure
startInfeasible pb e (St v _ s)
  | s > tP (eTerm e) && tV (eTerm e) <= 0 =
      Infeasible "start_velocity"
        ("start_velocity " ++ num (pbV0 pb) ++ " m/s with start_acceleration " ++ num (pbA0 pb)
         ++ " m/s² cannot stop within route_length " ++ num (pbLength pb) ++ " m: braking at min_acceleration "
         ++ num (pbAMin pb) ++ " m/s² and min_jerk " ++ num (pbJMin pb) ++ " m/s³ needs "
         ++ num (brakeStopDistance pb (pbV0 pb) (pbA0 pb)) ++ " m")
  | otherwise =
      Infeasible "start_velocity"
        ("start_velocity " ++ num (pbV0 pb) ++ " m/s with start_acceleration " ++ num (pbA0 pb)
         ++ " m/s² cannot brake in time for the speed limit of " ++ num (minLimitOn pb s s)
         ++ " m/s at " ++ num s ++ " m: the hardest braking allowed (min_acceleration " ++ num (pbAMin pb)
         ++ " m/s², min_jerk " ++ num (pbJMin pb) ++ " m/s³) is still at " ++ num v ++ " m/s there")
