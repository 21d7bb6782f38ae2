-- | The two-sided meet: how a route that ends in motion is seeded.
--
-- A moving end state cannot be landed by creeping onto the route end, so the greedy pass
-- runs from both sides, from the start state forwards and on the mirror from the end
-- state backwards ("VProf.Profile.Generate.Seed.Join"), and the 'strategies' of
-- "VProf.Profile.Generate.Seed.Strategy" join them, in order; the first legal profile
-- is the seed. When none joins, the exact join's proof may still show that no profile
-- exists; otherwise the failure is the generator's and says which strategies it tried.
--
-- Invariant: 'meet' returns only profiles the checker finds legal, and claims
-- infeasibility only with a failed brake policy or a verified proof behind it.
module VProf.Profile.Generate.Seed.Meet
  ( meet
  , meetWith
  ) where

import Data.List (intercalate)
import qualified Data.Vector.Unboxed as U

import VProf.Profile.Generate.Exact (noProfileFits)
import VProf.Profile.Generate.Seed.Explain
import VProf.Profile.Generate.Seed.Join
import VProf.Profile.Generate.Seed.Strategy
import VProf.Profile.Problem (Problem (..))

-- | A moving end state: the two-sided meet, with every strategy.
meet :: Problem -> Either SeedFailure (U.Vector Double)
meet = meetWith strategies

-- | The meet with the given strategies, tried in order.
meetWith :: [Strategy] -> Problem -> Either SeedFailure (U.Vector Double)
meetWith tried pb = do
  c <- meetContext pb
  case concatMap (`strategyJoins` c) tried of
    (p : _) -> Right p
    []
      | Just why <- noProfileFits pb -> Left (Unattainable (if pbV0 pb > pbVEnd pb then "start_velocity" else "end_velocity") why)
      | mcTop c <= 0 -> Left (LandingFailed ("the forward and the backward pass do not meet" ++ triedText ++ hint))
      | otherwise -> Left (LandingFailed ("no plateau below " ++ num (mcTop c) ++ " m/s joins the forward and the backward pass" ++ triedText ++ hint))
  where
    triedText = "; tried in order: " ++ intercalate ", " (map strategyName tried)
    -- what a user can do: a finer time step gives the passes and the exact join more
    -- samples to work with
    hint = " (a limit of the generator, not a proof that no profile exists; a finer time_step, such as "
           ++ num (pbDt pb / 2) ++ " s, may give one)"
