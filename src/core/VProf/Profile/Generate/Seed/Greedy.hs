-- | The greedy pass: one forward pass in time that takes, at every step, the largest
-- acceleration (within the jerk and acceleration ranges) after which the brake policy
-- of "VProf.Profile.Generate.Seed.Brake" still passes the oracle.
--
-- Invariant: every state of a pass passes the oracle, so the pass can always fall back
-- on braking and stays legal; started from a state that passes the oracle, it never
-- breaks a rule. Near its terminal it rides the edge of the oracle and lands on it.
module VProf.Profile.Generate.Seed.Greedy
  ( choose
  , forward
  , forwardMarked
  , passFrom
  , passStepCap
  , passCapMessage
  ) where

import Data.Bits (popCount)

import VProf.Profile.Generate.Seed.Brake
import VProf.Profile.Generate.Seed.Explain (num)
import VProf.Profile.Problem (Problem (..))
import VProf.Profile.Request (maxSamples)
import VProf.Profile.SpeedLimit (limitAt)

-- | The most steps a pass takes: the sample cap and two. A pass is never slower than the
-- profile made of it (the landing pass is the seed; the meet's profile lies under both of
-- its passes), so a pass that has not arrived by then belongs to a profile over the cap,
-- and no pass allocates beyond it.
passStepCap :: Int
passStepCap = maxSamples + 2

-- | Why a pass stopped at 'passStepCap' without arriving.
passCapMessage :: Problem -> String -> Double -> String
passCapMessage pb which s =
  "the profile needs more than " ++ show maxSamples ++ " samples at time_step " ++ show (pbDt pb)
  ++ " s, above the cap (the generator's " ++ which ++ " pass was at " ++ num s ++ " m after them);"
  ++ " split the route or raise time_step"

-- | The probe just above the brake policy sits this fraction of the way from it to the
-- highest acceleration allowed (1/32 of the range).
probeDivisor :: Double
probeDivisor = 32

-- | Halvings of the interval between the probe and the top, once the probe passes.
bisectionSteps :: Int
bisectionSteps = 5

-- | Halvings of the interval below the probe when a pass at rest finds the probe's step
-- unsafe (a creep onto the terminal; 2⁻⁴⁰ of the probe is far below any end tolerance).
creepSteps :: Int
creepSteps = 40

-- | A velocity this close to the terminal velocity is set to it exactly.
terminalSnap :: Double
terminalSnap = 1e-11

-- | One step of the forward pass: the largest safe acceleration.
choose :: SeedEnv -> St -> St
choose e = fst . chooseStep e

-- | 'choose', and whether the step is the brake policy's own because nothing above it
-- was safe (the probe failed).
chooseStep :: SeedEnv -> St -> (St, Bool)
chooseStep e st@(St v _ s) =
  let dt = dtE e
      pb = ePb e
      (lo, hi0) = accRange e st
      Term p vt = eTerm e
      capNow = if vt > 0 && s >= p then min vt (limitAt pb s) else limitAt pb s
      hi = max lo (min hi0 ((capNow - v) / dt))
      try a = let st' = snapTo (stepTo e st a) in if stepOk e st st' && safe e st' then Just st' else Nothing
      snapTo = snapToTerminal e st
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
      probe = aB + (hi - aB) / probeDivisor
      bisectFrom stP = search probe hi stP bisectionSteps
      -- at rest short of the terminal with even the probe's step too long (a coarse time
      -- step, the last millimetres): the largest safe acceleration below the probe, a creep,
      -- instead of standing still for ever
      creep = search aB probe fallback creepSteps
      unsafeProbe = if standing st then creep else fallback
  in if stA st < 0
       then maybe (fallback, True) (\stP -> (maybe (bisectFrom stP) id (try hi), False)) (try probe)
       else maybe (maybe (unsafeProbe, True) (\stP -> (bisectFrom stP, False)) (try probe)) (\stH -> (stH, False)) (try hi)

-- | A step that ends within 'terminalSnap' of the terminal velocity the pass is told to
-- hold lands on it exactly.
snapToTerminal :: SeedEnv -> St -> St -> St
snapToTerminal e (St v _ s) st'@(St v' _ s')
  | vt > 0 && abs (v' - vt) < terminalSnap && v' /= vt = St vt ((vt - v) / dt) (s + (v + vt) * dt / 2)
  | otherwise = st' `seq` s' `seq` st'
  where
    Term _ vt = eTerm e
    dt = dtE e
{-# INLINE snapToTerminal #-}

-- | The brake policy's own step from a state (what 'chooseStep' falls back on).
brakeStep :: SeedEnv -> St -> St
brakeStep e st = snapToTerminal e st (stepTo e st (brakeAcc e st))
{-# INLINE brakeStep #-}

-- | Steps of a pass with their count of brake-policy steps in a row ('chooseStep''s flag).
--
-- Every probe asks the oracle, which runs the brake policy from the probed state to its
-- target, so where that braking is long a probe costs all of it, and probing at every one
-- of the B steps of a braking costs B²/2 oracle steps (B = 6,500 at a 1 ms step: 1.7 s for
-- one pass). So where the oracle's braking would take more than 'probeAllWithin' steps
-- (its continuous-time estimate), after n brake-policy steps in a row the pass probes only
-- when n is a power of two up to 'probeInterval' and at every multiple of it after; in
-- between it takes the brake policy's step. That step is always safe (the policy from a
-- state it keeps continues the same manoeuvre), so only the gain of a probe that would
-- have passed is forgone; the last 'probeAllWithin' steps of a braking, where it lands on
-- its target riding the oracle's edge, are probed at every step as before, and so is every
-- step of a pass whose brakings are shorter (any pass at a coarse time step). A braking of
-- B steps then costs O(B²/64 + 'probeAllWithin'²).
-- The flag tells a step taken without a probe.
scheduledStep :: SeedEnv -> (St, Int) -> ((St, Int), Bool)
scheduledStep e (st, n)
  | n > 0, not due, not (standing st), longBraking = ((brakeStep e st, n + 1), True)
  | otherwise = let (st', fell) = chooseStep e st in ((st', if fell then n + 1 else 0), False)
  where
    due = if n <= probeInterval then popCount n == 1 else n `mod` probeInterval == 0
    pb = ePb e
    St v a _ = st
    am = negate (pbAMin pb)
    j1 = negate (pbJMin pb)
    j2 = pbJMax pb
    -- the braking's duration in continuous time: a positive acceleration brought down,
    -- then the velocity still above the policy's target shed by a ramp down to a peak
    -- deceleration (the full one, or less for a small drop), a hold, and a ramp back
    ap0 = max 0 a
    drop = max 0 (v + ap0 * ap0 / (2 * j1) - brakeTarget e st)
    ramps = 1 / j1 + 1 / j2
    peak = min am (sqrt (2 * drop / ramps))
    hold = if peak > 0 then max 0 (drop - peak * peak * ramps / 2) / peak else 0
    left = ap0 / j1 + peak * ramps + hold
    longBraking = left > fromIntegral probeAllWithin * dtE e

-- | The longest run of brake-policy steps between probes of a long manoeuvre.
probeInterval :: Int
probeInterval = 64

-- | A braking is probed at every step once fewer than this many of its steps are left.
probeAllWithin :: Int
probeAllWithin = 512

-- | A velocity this low near the terminal is rest: the braking ends with a step to
-- exactly zero (or, if that step is not allowed, here), instead of creeping on towards a
-- standstill it may approach for ever. It is a tenth of the checker's slack at zero.
restVelocity :: Double
restVelocity = 1e-10

-- | At rest, or so near it that no step of the pass would move it (a velocity left by
-- rounding, some 1e-12 m/s, would take years to cover a millimetre).
standing :: St -> Bool
standing (St v a _) = v <= restVelocity && abs a <= restVelocity

-- | The forward pass toward a standstill on the terminal point, from a state: the states
-- visited after it, in order, until it has come to rest within the landing tolerance
-- of the terminal. Stops after @limit@ steps.
--
-- Inside the landing tolerance the pass brakes as hard as the hard policy allows, straight
-- to a standstill: any stop from there lands, and the gentle policy would brake only while
-- its reach touches the terminal, hold the lower speed once it no longer does, and so
-- approach the terminal in a staircase of ever slower plateaus (a crawl of seconds on a
-- route of centimetres). A hard step that a limit forbids falls back on the gentle one.
--
-- With @scheduled@ the pass probes a long manoeuvre only now and then ('scheduledStep');
-- without, at every step.
forward :: Bool -> SeedEnv -> Double -> Int -> St -> [St]
forward scheduled e landTol limit = map fst . forwardMarked scheduled e landTol limit

-- | 'forward', each state marked when the schedule took its step without a probe (never
-- without @scheduled@; never either where every braking is short, so that a scheduled pass
-- with no mark is the every-step pass).
forwardMarked :: Bool -> SeedEnv -> Double -> Int -> St -> [(St, Bool)]
forwardMarked scheduled e landTol limit st0 = go 0 (st0, 0)
  where
    p = tP (eTerm e)
    eStop = e { eHard = True }
    step sk@(st, _) = if scheduled then scheduledStep e sk else ((choose e st, 0), False)
    go n sk@(st, _)
      | n >= limit = []
      | stS st >= p - landTol = finishBraking st (n :: Int)
      -- at rest and staying there: the pass cannot go on (the landing reports where it stopped)
      | otherwise = let (sk'@(st', _), skipped) = step sk
                    in if standing st && standing st' then [] else (st', skipped) : go (n + 1) sk'
    finishBraking st n
      | atRest e st || n >= limit = []
      | stV st <= restVelocity =
          let st' = St 0 (negate (stV st) / dtE e) (stS st + stV st * dtE e / 2)
          in [ (st', False) | stepOk e st st' ]
      | otherwise =
          let hard = stepTo e st (brakeAcc eStop st)
              st' = if stepOk e st hard then hard else stepTo e st (brakeAcc e st)
          in (st', False) : finishBraking st' (n + 1)

-- | The greedy pass from a state: the states after it, up to the first for which @done@
-- holds, at most @n@.
passFrom :: SeedEnv -> Int -> (St -> Bool) -> St -> [St]
passFrom e n done = go n
  where
    go k st
      | k <= 0 = []
      | otherwise = let st' = choose e st in st' : (if done st' then [] else go (k - 1) st')
