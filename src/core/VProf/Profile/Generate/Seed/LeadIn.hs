-- | The lead-in: the first step searched, when the brake policy cannot save the start.
--
-- Braking is not always the safest way on: a step that touches a short low zone must
-- keep below its limit, and a faster first step may leave that zone behind before the
-- next one, where braking from the start would still be in it. So when the start state
-- (or, on the mirrored problem, the end state) fails the oracle, a grid of first steps
-- is tried, fastest first, each followed by a seed of the rest of the route, before the
-- request is called infeasible.
--
-- Invariant: a lead-in returns only profiles the checker finds legal, and never turns
-- the rest's claim about a shortened problem into a claim about this one (it is
-- reported as the generator's failure).
module VProf.Profile.Generate.Seed.LeadIn
  ( leadIn
  , leadInMayHelp
  , startTerm
  , endFailure
  , leadInSteps
  , leadInReachSteps
  ) where

import qualified Data.Vector.Unboxed as U

import VProf.Profile.Generate.Seed.Brake
import VProf.Profile.Generate.Seed.Explain
import VProf.Profile.Legality (legalVelocities)
import VProf.Profile.Problem (Problem (..))
import VProf.Profile.Problem.Transform (mirror, startingAfter)
import VProf.Profile.Request (maxSamples)
import VProf.Profile.SpeedLimit (minLimitOn)

-- | The first steps tried: the acceleration range from the start in this many equal
-- parts (this many plus one accelerations, the highest first).
leadInSteps :: Int
leadInSteps = 32

-- | The terminal the start's oracle works with: the two-sided meet's, or the landing's.
startTerm :: Bool -> Problem -> Term
startTerm meeting pb
  | meeting = Term (pbLength pb + pbTol pb) (pbVEnd pb)
  | otherwise = Term (pbLength pb) 0

-- | How far beyond a rule the hardest braking from the start may go and a lead-in still
-- be tried: this many steps of the widest change of velocity in one step,
-- (a_max − a_min)·dt. Two first steps of the lead-in and the grid's phase at the broken
-- rule change the velocities of the braking after them by a few such steps at most.
leadInReachSteps :: Double
leadInReachSteps = 8

-- | A lead-in may save the start: the start state fails the oracle (the hardest braking
-- from it breaks a rule, with the terminal of the two-sided meet's passes, or of the
-- landing at rest), but by less than 'leadInReachSteps' can make up. A speed limit broken
-- by more than that velocity, or a terminal passed more than that velocity faster than its
-- own until further than that velocity times the braking's duration ('brakeTimeBound')
-- past it, stays broken after any first steps: at a fine time step the lead-in's 33 × 33
-- seeds of the rest, each with its own oracle over a braking of a million steps, would
-- only find that out (a route at 0.1 ms whose end velocity cannot be reached under an
-- earlier limit by 1.9 m/s took 51 s to be called infeasible).
leadInMayHelp :: Bool -> Problem -> Bool
leadInMayHelp meeting pb = case policyFor pb term st0 of
  Right _ -> False
  Left (St v _ s, st'@(St v' _ s')) -> not (limitOut || terminalOut)
    where
      limitOut = max v v' - minLimitOn pb s (max s s') > dv
      -- past the terminal still too fast: where the braking, carried on, first comes down
      -- to within dv of the terminal's velocity, less what dv lost over the whole braking
      -- can take back, is still past it
      terminalOut = s' > p && v' - vt > dv && downTo st' 0 - dv * brakeTimeBound e st0 > p
  where
    free = seedEnv pb (Term (1 / 0) (1 / 0)) True
    downTo st n
      | stV st <= vt + dv || atRest free st || n >= maxSamples = stS st
      | otherwise = downTo (stepTo free st (brakeAcc free st)) (n + 1 :: Int)
    term = startTerm meeting pb
    Term p vt0 = term
    vt = max 0 vt0
    st0 = St (pbV0 pb) (pbA0 pb) 0
    e = seedEnv pb term True
    dv = leadInReachSteps * (pbAMax pb - pbAMin pb) * pbDt pb

-- | The first step from the start state (a grid over its acceleration range, fastest
-- first) that keeps every rule and after which the rest can be seeded (by @seedRest@,
-- one level of lead-in less), on the problem that starts there. When no first step gives
-- a profile but some get past the start's oracle, the start may not be what stands in
-- the way: the failure is then the end state's, if it has one of its own
-- ('endFailure'), or else the generator's where the rest failed for want of a join (not
-- a claim), or else the start's claim stands ('Nothing').
leadIn :: (Int -> Problem -> Either SeedFailure (U.Vector Double)) -> Int -> Problem -> Either (Maybe SeedFailure) (U.Vector Double)
leadIn seedRest depth pb = case [ r | Right r <- tries ] of
  (vs : _) -> Right vs
  [] -> Left (case [ g | Left (Just g) <- tries ] of
                [] -> Nothing
                gs | Just f <- endFailure pb -> Just f
                   | (g : _) <- [ g | g@(_, LandingFailed _) <- gs ] -> Just (unclaimed g)
                   | otherwise -> Nothing)
  where
    tries =
      [ case seedRest (depth - 1) (startingAfter s1 v1 a pb) of
          Right vs | legalVelocities pb (U.cons (pbV0 pb) vs) -> Right (U.cons (pbV0 pb) vs)
                   | otherwise -> Left Nothing
          -- the first step did not get the start out of trouble
          Left (Unattainable f _) | f `elem` ["start_velocity", "start_acceleration"] -> Left Nothing
          Left g -> Left (Just (s1, g))
      | i <- [0 .. leadInSteps]
      , let a = hi - (hi - lo) * fromIntegral i / fromIntegral leadInSteps
            st1@(St v1 _ s1) = stepTo e st0 a
      , stepOk e st0 st1, s1 < pbLength pb ]
    e = seedEnv pb (Term (pbLength pb + pbTol pb) (1 / 0)) True
    st0 = St (pbV0 pb) (pbA0 pb) 0
    (lo, hi) = accRange e st0
    -- the rest's own claim is about the shortened problem after one chosen first step,
    -- not a proof for this one: reported as the generator's failure
    unclaimed (s1, g) = LandingFailed ("braking from the start breaks a rule, and after a legal first step (to "
                                       ++ num s1 ++ " m) the rest fails: " ++ case g of
                                         Unattainable _ m -> m
                                         LandingFailed m -> m
                                         OverCap m -> m)

-- | The end state's own infeasibility, when it ends in motion: its acceleration cannot
-- be reached, or the end pass (on the mirror) cannot be saved by its brake policy.
endFailure :: Problem -> Maybe SeedFailure
endFailure pb
  | pbVEnd pb <= 0 && pbAEnd pb == 0 = Nothing
  | sinksBelowZero rv = Just (endAccFailure pb)
  | otherwise = either (Just . endInfeasible pb (seedEnv rv bTerm True)) (const Nothing) (policyFor rv bTerm rt0)
  where
    rv = mirror pb
    rt0 = St (pbVEnd pb) (pbA0 rv) 0
    bTerm = Term (pbLength pb + pbTol pb) (pbV0 pb)
