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
  , passFrom
  , passStepCap
  , passCapMessage
  ) where

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
        | vt > 0 && abs (v' - vt) < terminalSnap && v' /= vt = St vt ((vt - v) / dt) (s + (v + vt) * dt / 2)
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
      probe = aB + (hi - aB) / probeDivisor
      bisectFrom stP = search probe hi stP bisectionSteps
      -- at rest short of the terminal with even the probe's step too long (a coarse time
      -- step, the last millimetres): the largest safe acceleration below the probe, a creep,
      -- instead of standing still for ever
      creep = search aB probe fallback creepSteps
      unsafeProbe = if standing st then creep else fallback
  in if stA st < 0
       then maybe fallback (\stP -> maybe (bisectFrom stP) id (try hi)) (try probe)
       else maybe (maybe unsafeProbe bisectFrom (try probe)) id (try hi)

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
forward :: SeedEnv -> Double -> Int -> St -> [St]
forward e landTol limit = go 0
  where
    p = tP (eTerm e)
    eStop = e { eHard = True }
    go n st
      | n >= limit = []
      | stS st >= p - landTol = finishBraking st (n :: Int)
      -- at rest and staying there: the pass cannot go on (the landing reports where it stopped)
      | otherwise = let st' = choose e st
                    in if standing st && standing st' then [] else st' : go (n + 1) st'
    finishBraking st n
      | atRest e st || n >= limit = []
      | stV st <= restVelocity =
          let st' = St 0 (negate (stV st) / dtE e) (stS st + stV st * dtE e / 2)
          in [ st' | stepOk e st st' ]
      | otherwise =
          let hard = stepTo e st (brakeAcc eStop st)
              st' = if stepOk e st hard then hard else stepTo e st (brakeAcc e st)
          in st' : finishBraking st' (n + 1)

-- | The greedy pass from a state: the states after it, up to the first for which @done@
-- holds, at most @n@.
passFrom :: SeedEnv -> Int -> (St -> Bool) -> St -> [St]
passFrom e n done = go n
  where
    go k st
      | k <= 0 = []
      | otherwise = let st' = choose e st in st' : (if done st' then [] else go (k - 1) st')
