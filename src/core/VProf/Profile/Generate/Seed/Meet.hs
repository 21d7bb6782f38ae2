-- | The two-sided meet: how a route that ends in motion is seeded.
--
-- A moving end state cannot be landed by creeping onto the route end, so the greedy pass
-- runs from both sides, from the start state forwards and on the mirror from the end
-- state backwards ("VProf.Profile.Generate.Seed.Join"), and the 'strategies' of
-- "VProf.Profile.Generate.Seed.Strategy" join them, in order; the first legal profile
-- is the seed. When none joins, the meet runs again with its passes planned a little
-- inside the jerk range, and with passes that probe every step. When none of them joins,
-- the exact join's proof may still show that no profile exists; otherwise the failure is
-- the generator's and says which strategies it tried.
--
-- Invariant: 'meet' returns only profiles the checker finds legal (but for a crawl, which
-- the generator cuts at the arrival), and claims
-- infeasibility only with a failed brake policy or a verified proof behind it.
module VProf.Profile.Generate.Seed.Meet
  ( meet
  , meetWith
  ) where

import Data.List (intercalate)
import qualified Data.Vector.Unboxed as U

import VProf.Profile.Generate.Exact (noProfileFits)
import VProf.Profile.Generate.Seed.Brake (fullJerkHolds, jerkPlanMargins, roundingJerk, topSpeed)
import VProf.Profile.Generate.Seed.Explain
import VProf.Profile.Generate.Seed.Join
import VProf.Profile.Generate.Seed.Strategy
import VProf.Profile.Problem (Problem (..))
import VProf.Profile.Problem.Transform (scaleJerk)

-- | A moving end state: the two-sided meet, with every strategy.
meet :: Problem -> Either SeedFailure (U.Vector Double)
meet = meetWith strategies

-- | The meet with the given strategies, tried in order, with passes that probe long
-- brakings only now and then; when no strategy joins them, the same with passes planned a
-- little inside the jerk range ('jerkPlanMargins': at a fine time step the rounding of the
-- velocities can put every join a hair beyond the jerk limit; where that rounding alone is
-- beyond the checker's slack, 'roundingJerk', these come first), and last with passes that
-- probe at every step (each only where it can matter). The joins are judged on the
-- problem's own jerk range, not the narrowed one the passes plan in: the rounding that
-- puts a full-jerk ramp beyond the range puts a join a hair beyond the narrowed range as
-- well (judged so, no plateau of a 0.1 ms request joined). When all fail, the answer is the
-- full jerk's.
meetWith :: [Strategy] -> Problem -> Either SeedFailure (U.Vector Double)
meetWith tried pb
  | fullJerk = case meetOn True pb of
      Left f@(LandingFailed _) -> maybe (Left f) Right (firstRight fallbacks)
      r -> r
  -- the rounding of the fastest velocity alone is beyond the checker's slack in jerk: the
  -- margins first, and the full jerk's meet only for its answer when none joins (a narrowed
  -- problem's failure is no claim about this one)
  | otherwise = maybe (meetOn True pb) Right (firstRight fallbacks)
  where
    fullJerk = fullJerkHolds pb
    meetOn scheduled q = meetTried tried scheduled pb q
    -- only where they can change anything: the margins where the velocities' rounding is
    -- within a hundredth of the checker's slack in jerk (a fine step), the every-step passes
    -- where a braking can outlast the schedule's 512 steps (with the first margin where the
    -- full jerk cannot do)
    margins = jerkPlanMargins pb
    fallbacks = [ meetOn True (scaleJerk (1 - m) pb) | roundingJerk pb >= 1e-11, m <- margins ]
                ++ [ meetOn False (if fullJerk then pb else scaleJerk (1 - head margins) pb) | longBrakingPossible pb ]
    firstRight rs = case [ v | Right v <- rs ] of
      v : _ -> Just v
      [] -> Nothing

-- | A braking from the fastest limit to rest (ramps and hold, continuous time) lasts more
-- than the 512 steps below which the passes probe every step anyway.
longBrakingPossible :: Problem -> Bool
longBrakingPossible pb = topSpeed pb / am + am / negate (pbJMin pb) + am / pbJMax pb > 512 * pbDt pb
  where am = negate (pbAMin pb)

-- | One meet: the passes (scheduled or not) and the strategies in order.
meetTried :: [Strategy] -> Bool -> Problem -> Problem -> Either SeedFailure (U.Vector Double)
meetTried tried scheduled judge pb = do
  c <- meetContext scheduled judge pb
  case concatMap (`strategyJoins` c) tried of
    (p : _) -> Right p
    []
      | Just why <- noProfileFits judge -> Left (Unattainable (if pbV0 pb > pbVEnd pb then "start_velocity" else "end_velocity") why)
      | mcTop c <= 0 -> Left (LandingFailed ("the forward and the backward pass do not meet" ++ triedText ++ hint))
      | otherwise -> Left (LandingFailed ("no plateau below " ++ num (mcTop c) ++ " m/s joins the forward and the backward pass" ++ triedText ++ hint))
  where
    triedText = "; tried in order: " ++ intercalate ", " (map strategyName tried)
    -- what a user can do: a finer time step gives the passes and the exact join more
    -- samples to work with
    hint = " (a limit of the generator, not a proof that no profile exists; a finer time_step, such as "
           ++ num (pbDt pb / 2) ++ " s, may give one)"
