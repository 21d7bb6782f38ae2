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
import VProf.Profile.SpeedLimit (limitAt, zoneIndex)

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
-- was safe (the probe failed) or in range.
chooseStep :: SeedEnv -> St -> (St, Bool)
chooseStep e st = let (st', taken) = chooseTaken e st in (st', taken == Fell)

-- | Which step 'chooseTaken' took: the brake policy's own (nothing above it was safe or in
-- range), the one at the highest acceleration ('topStep'), or one found between them.
data Taken = Fell | Top | Between
  deriving (Eq)

-- | 'choose', and which step it took.
chooseTaken :: SeedEnv -> St -> (St, Taken)
chooseTaken e st =
  let hi = topAcc e st
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
      -- nothing above the brake policy is reachable (its ramp back at the full jerk): its
      -- step, safe by the oracle's invariant, without a probe (each would run the braking)
      noRoom = hi <= aB + roundingSlack * max 1 (abs aB)
  in if noRoom && not (standing st) then (fallback, Fell)
     else if stA st < 0
       then maybe (fallback, Fell) (\stP -> maybe (bisectFrom stP, Between) (, Top) (try hi)) (try probe)
       else maybe (maybe (unsafeProbe, Fell) (\stP -> (bisectFrom stP, Between)) (try probe)) (, Top) (try hi)

-- | The highest acceleration a step from a state may take: the top of the ranges, and no
-- more than the speed limit there (or the terminal velocity past the terminal) allows.
topAcc :: SeedEnv -> St -> Double
topAcc e st@(St v _ s) = max lo (min hi0 ((capNow - v) / dtE e))
  where
    pb = ePb e
    (lo, hi0) = accRange e st
    Term p vt = eTerm e
    capNow = if vt > 0 && s >= p then min vt (limitAt pb s) else limitAt pb s
{-# INLINE topAcc #-}

-- | The step at the highest acceleration ('topAcc'), as 'chooseStep' takes it.
topStep :: SeedEnv -> St -> St
topStep e st = snapToTerminal e st (stepTo e st (topAcc e st))
{-# INLINE topStep #-}

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

-- | The next steps of a pass (one or more), each with the schedule after it and whether
-- it was taken without a probe.
--
-- Every probe asks the oracle, which runs the brake policy from the probed state to its
-- target, so where that braking is long a probe costs all of it, and probing at every one
-- of the B steps of a braking costs B²/2 oracle steps (B = 6,500 at a 1 ms step: 1.7 s for
-- one pass). So where the oracle's braking would take more than 'probeAllWithin' steps
-- (its continuous-time estimate), after n brake-policy steps in a row the pass probes only
-- when n is a power of two up to an interval and at every multiple of it after, and takes
-- the brake policy's steps in between. The interval is 'probeInterval' (64), or a
-- 'probeShare'th (1/8) of the braking's steps left when that is more: some eight probes
-- each time what is left halves, each at most the B oracle steps of the braking, O(B·log B
-- + 'probeAllWithin'²) in all (a fixed interval of 64 costs B²/64: 14 M oracle steps for a
-- 6 s braking at a 0.2 ms step; a 64th of what is left cost a 23 m route at 0.12 ms 20 M
-- oracle steps in its brakings, an eighth 9 M, for a landing of the same 641,672 samples).
-- (Without the powers of two, a 118 m route at 0.14 ms whose brakings at 0.6 m/s² take 13 s
-- spent half the oracle steps in the meet's two passes, but its meet joined lower, and the
-- rubber band did not reach its fixed point in 100,000 passes.)
-- The last 'probeAllWithin' steps of a braking, where it lands on its target riding the
-- oracle's edge, are probed at every step, and so is every step of a pass whose brakings
-- are shorter (any pass at a coarse time step).
--
-- The brake policy's steps are always safe (the policy from a state it keeps continues the
-- same manoeuvre), but a probe that would have passed between two scheduled ones is a
-- gain forgone, and a large one where the jerk that ends a braking is weak: the pass brakes
-- on, and takes long to recover (a landing at a 12 ms step lost 16 %). So when a scheduled
-- probe passes, the pass goes back over the policy's steps since the last one and finds by
-- bisection the first at which the probe passes, and continues from there: where the
-- probes along the policy's steps fail up to some step and pass from it on, the pass is the
-- every-step pass, for some log₂ of the interval probes more. That is not always so: where
-- a zone is entered, the braking for it is over and the probes pass for a few steps, and
-- then the policy's braking for the next target reaches the edge again. So a probe that
-- passes restarts the count, and so does a new manoeuvre: a new target of the brake
-- policy, or a new zone (a landing at a 12 ms step whose probes passed for 20 steps on
-- entering a zone lost 16 % without).
--
-- Steps at the highest acceleration ('topStep') are taken in runs too, where each one's
-- oracle runs a long braking ('quickNeed' cannot settle it): a weak jerk brings a rising
-- acceleration down over thousands of steps, and every step of the ramp towards the edge
-- asks the oracle (a 23 m route at 0.12 ms spent 15 M oracle steps there). After
-- h such steps in a row, the pass takes the next 2h (at most 'topRunMost') at the highest
-- acceleration when every one keeps the step rules and the oracle passes the last, and
-- otherwise steps as before. The states inside such a run are not asked: the run from one
-- of them and the braking after it keep every rule, though the brake policy from it
-- might not; the pass's profile stays legal. Such runs are marked as skipped (a landing
-- that breaks a rule is made again by the every-step pass), and none ends within the end
-- tolerance of the terminal.
scheduledSteps :: SeedEnv -> (St, Sched) -> [((St, Sched), Bool)]
scheduledSteps e (st, Sched n0 target0 zone0 h0)
  | n > 0, not due, not (standing st), longBraking = gallop
  | h0 > 0, Just run <- topRun = run
  | otherwise = [probed st n]
  where
    -- a new target or a new zone is a new manoeuvre: its count starts again, with a probe
    target = brakeTarget e st
    zone = zoneIndex pb (stS st)
    n = if target == target0 && zone == zone0 then n0 else 0
    dueAt m = if m <= interval then popCount m == 1 else m `mod` interval == 0
    due = dueAt n
    -- the probe's step, from a state reached after m brake-policy steps; a step at the
    -- highest acceleration whose oracle ran the braking starts a run at the top (but not
    -- right after a run that failed)
    probedAs m (x', taken) =
      ((x', Sched (if taken == Fell then m + 1 else 0) target zone
                  (if taken == Top && h0 == 0 && not (quickNeed e x') then 1 else 0)), False)
    probed x m = probedAs m (chooseTaken e x)
    -- the next 2h steps at the top, when each keeps the step rules and the oracle passes
    -- the last, short of the terminal by more than the end tolerance (a landing pass brakes
    -- differently within half of it)
    topRun = go (min topRunMost (2 * h0)) st []
      where
        go :: Int -> St -> [St] -> Maybe [((St, Sched), Bool)]
        go 0 x acc
          | stS x < tP (eTerm e) - pbTol (ePb e), safe e x =
              Just [ ((y, Sched 0 target zone (h0 + i)), True) | (i, y) <- zip [1 ..] (reverse acc) ]
          | otherwise = Nothing
        go k x acc =
          let x' = topStep e x
          in if stepOk e x x' && not (standing x') then go (k - 1) x' (x' : acc) else Nothing
    -- the policy's steps up to the next scheduled probe (cut where the target or the zone
    -- changes or the pass comes to rest), and the probes from them, each made at most once
    gap = head [ k | k <- [1 ..], dueAt (n + k) ]
    run = takeUntil (\x -> standing x || brakeTarget e x /= target || zoneIndex pb (stS x) /= zone) (take gap (tail (iterate (brakeStep e) st)))
    choices = map (chooseTaken e) run
    passesAt i = snd (choices !! (i - 1)) /= Fell
    skippedTo k = [ ((x, Sched (n + i) target zone 0), True) | (i, x) <- zip [1 ..] (take k run) ]
    gallop
      | length run < gap = skippedTo (length run)
      | not (passesAt gap) = skippedTo gap ++ [probedAs (n + gap) (choices !! (gap - 1))]
      | otherwise =
          -- the first of the run at which the probe passes, by bisection (lo fails, hi passes)
          let first lo hi | hi - lo <= 1 = hi
                          | otherwise = let mid = (lo + hi) `div` 2 in if passesAt mid then first lo mid else first mid hi
              k = first 0 gap
          in skippedTo k ++ [probedAs (n + k) (choices !! (k - 1))]
    -- an eighth of the braking's steps left (a power of two, at least 'probeInterval')
    interval = let b = left / dtE e / fromIntegral probeShare
               in if b < fromIntegral (2 * probeInterval) then probeInterval
                  else 2 ^ (floor (logBase 2 b) :: Int)
    pb = ePb e
    St v a _ = st
    am = negate (pbAMin pb)
    j1 = negate (pbJMin pb)
    j2 = pbJMax pb
    -- the braking's duration in continuous time: a positive acceleration brought down,
    -- then the velocity still above the policy's target shed by a ramp down to a peak
    -- deceleration (the full one, or less for a small drop), a hold, and a ramp back
    ap0 = max 0 a
    drop = max 0 (v + ap0 * ap0 / (2 * j1) - target)
    ramps = 1 / j1 + 1 / j2
    peak = min am (sqrt (2 * drop / ramps))
    hold = if peak > 0 then max 0 (drop - peak * peak * ramps / 2) / peak else 0
    left = ap0 / j1 + peak * ramps + hold
    longBraking = left > fromIntegral probeAllWithin * dtE e

-- | The schedule's state: brake-policy steps in a row, the brake policy's target and the
-- zone then, and steps at the top whose oracle ran the braking, in a row.
data Sched = Sched !Int !Double !Int !Int

-- | The elements of a list up to and including the first for which the test holds.
takeUntil :: (a -> Bool) -> [a] -> [a]
takeUntil _ [] = []
takeUntil f (x : xs) = x : (if f x then [] else takeUntil f xs)

-- | A pass starts with no braking behind it.
startSched :: Sched
startSched = Sched 0 (-1) (-1) 0

-- | The longest run at the highest acceleration taken without asking the oracle at every
-- step ('scheduledSteps').
topRunMost :: Int
topRunMost = 256

-- | The least run of brake-policy steps between probes of a long manoeuvre.
probeInterval :: Int
probeInterval = 64

-- | A long braking's run between probes is its steps left over this (rounded down to a
-- power of two), when that is more than 'probeInterval'.
probeShare :: Int
probeShare = 8

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
-- With @scheduled@ the pass probes a long manoeuvre only now and then ('scheduledSteps');
-- without, at every step.
forward :: Bool -> SeedEnv -> Double -> Int -> St -> [St]
forward scheduled e landTol limit = map fst . forwardMarked scheduled e landTol limit

-- | 'forward', each state marked when the schedule took its step without a probe (never
-- without @scheduled@; never either where every braking is short, so that a scheduled pass
-- with no mark is the every-step pass).
forwardMarked :: Bool -> SeedEnv -> Double -> Int -> St -> [(St, Bool)]
forwardMarked scheduled e landTol limit st0 = go 0 (st0, startSched)
  where
    p = tP (eTerm e)
    eStop = e { eHard = True }
    steps sk@(st, sc) = if scheduled then scheduledSteps e sk else [((choose e st, sc), False)]
    go n sk@(st, _)
      | n >= limit = []
      | stS st >= p - landTol = finishBraking st (n :: Int)
      | otherwise = walk n st (steps sk)
    -- the steps one at a time, each checked as 'go' checks a state before it steps on
    walk n st ((sk'@(st', _), skipped) : rest)
      -- at rest and staying there: the pass cannot go on (the landing reports where it stopped)
      | standing st && standing st' = []
      | null rest || n + 1 >= limit || stS st' >= p - landTol = (st', skipped) : go (n + 1) sk'
      | otherwise = (st', skipped) : walk (n + 1) st' rest
    walk n st [] = go n (st, startSched)
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
-- holds, at most @n@; with @scheduled@ probing a long braking only now and then
-- ('scheduledSteps'), without at every step. A pass that comes to rest and stays there
-- ends ('standing'), as 'forwardMarked' does: it cannot go on, and standing still up to @n@
-- steps (the sample cap) would spend seconds a pass (a 10 µm route at a 10 ms step, where
-- the meet's passes stop short of the end, ran out of a 5 s budget in them).
passFrom :: Bool -> SeedEnv -> Int -> (St -> Bool) -> St -> [St]
passFrom scheduled e n done st0 = go n (st0, startSched)
  where
    steps sk@(st, sc) = if scheduled then map fst (scheduledSteps e sk) else [(choose e st, sc)]
    go k sk@(st, _)
      | k <= 0 = []
      | otherwise = walk k st (steps sk)
    walk k st (sk'@(st', _) : rest)
      | done st' = [st']
      | standing st && standing st' = []
      | null rest || k - 1 <= 0 = st' : go (k - 1) sk'
      | otherwise = st' : walk (k - 1) st' rest
    walk _ _ [] = []
