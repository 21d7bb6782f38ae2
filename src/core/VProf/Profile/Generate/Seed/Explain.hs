-- | Why no seed could be made, in words a user can act on.
--
-- A 'SeedFailure' is either a claim that the request is infeasible, naming the field that
-- cannot be met and why, or a limit of the generator ('LandingFailed'), never worded as a
-- proof. Invariant: an 'Unattainable' text is only built from a manoeuvre no profile can
-- beat (the hardest braking the limits allow, or the acceleration raised as fast as the
-- jerk allows) that still breaks a rule; the numbers are rounded to six decimals.
module VProf.Profile.Generate.Seed.Explain
  ( SeedFailure (..)
  , num
  , startInfeasible
  , endInfeasible
  , startSinks
  , endAccFailure
  ) where

import Numeric (showFFloat)

import VProf.Profile.Generate.Seed.Brake
import VProf.Profile.Problem (Problem (..))
import VProf.Profile.Problem.Transform (mirror)
import VProf.Profile.SpeedLimit (minLimitOn)

-- | Why no seed could be made: the request is infeasible (with where and why), the
-- landing could not be tuned (a generator limitation, reported as such), or a pass
-- needs more samples than the cap (the request is refused as for any profile over it).
data SeedFailure
  = Unattainable String String   -- ^ offending field, explanation
  | LandingFailed String
  | OverCap String
  deriving (Eq, Show)

-- | A number as the messages show it: rounded to six decimals, no trailing zeros.
num :: Double -> String
num x = showFFloat Nothing (fromIntegral (round (x * 1e6) :: Integer) / 1e6 :: Double) ""

-- | Explain why the end state cannot be reached, from the failure of the backward pass
-- (positions measured from the route end).
endInfeasible :: Problem -> SeedEnv -> (St, St) -> SeedFailure
endInfeasible pb e (St v0' _ r0, St v1 _ r)
  | r > tP (eTerm e) =
      Unattainable "end_velocity"
        ("end_velocity " ++ num (pbVEnd pb) ++ " m/s" ++ withAcc ++ " cannot be reached at route_length "
         ++ num (pbLength pb) ++ " m from start_velocity " ++ num (pbV0 pb)
         ++ " m/s: even accelerating as hard as max_acceleration " ++ num (pbAMax pb) ++ " m/s² and max_jerk "
         ++ num (pbJMax pb) ++ " m/s³ allow, a profile ending so would still be at " ++ num (max v0' v1)
         ++ " m/s at the route start")
  | otherwise =
      Unattainable "end_velocity"
        ("end_velocity " ++ num (pbVEnd pb) ++ " m/s" ++ withAcc ++ " cannot be reached under the speed limit of "
         ++ num (minLimitOn (ePb e) r0 r) ++ " m/s between " ++ num (pbLength pb - r) ++ " m and "
         ++ num (pbLength pb - r0) ++ " m: accelerating into it as hard as the limits allow (max_acceleration "
         ++ num (pbAMax pb) ++ " m/s², max_jerk " ++ num (pbJMax pb) ++ " m/s³) it is still at "
         ++ num (max v0' v1) ++ " m/s there")
  where withAcc = if pbAEnd pb /= 0 then " with end_acceleration " ++ num (pbAEnd pb) ++ " m/s²" else ""

-- | Explain why the start state cannot be braked legally.
startInfeasible :: Problem -> SeedEnv -> (St, St) -> SeedFailure
startInfeasible pb e (St v0' _ s0', St v1 _ s)
  | s > tP (eTerm e) && tV (eTerm e) <= 0 =
      Unattainable "start_velocity"
        ("start_velocity " ++ num (pbV0 pb) ++ " m/s with start_acceleration " ++ num (pbA0 pb)
         ++ " m/s² cannot stop within route_length " ++ num (pbLength pb) ++ " m: braking at min_acceleration "
         ++ num (pbAMin pb) ++ " m/s² and min_jerk " ++ num (pbJMin pb) ++ " m/s³ needs "
         ++ num (brakeStopDistance pb (pbV0 pb) (pbA0 pb)) ++ " m")
  | s > tP (eTerm e) =
      Unattainable "start_velocity"
        ("start_velocity " ++ num (pbV0 pb) ++ " m/s with start_acceleration " ++ num (pbA0 pb)
         ++ " m/s² cannot come down to end_velocity " ++ num (pbVEnd pb) ++ " m/s within route_length "
         ++ num (pbLength pb) ++ " m: braking at min_acceleration " ++ num (pbAMin pb) ++ " m/s² and min_jerk "
         ++ num (pbJMin pb) ++ " m/s³ it is still at " ++ num (max v0' v1) ++ " m/s there")
  | otherwise =
      Unattainable "start_velocity"
        ("start_velocity " ++ num (pbV0 pb) ++ " m/s with start_acceleration " ++ num (pbA0 pb)
         ++ " m/s² cannot brake in time for the speed limit of " ++ num (minLimitOn pb s0' s)
         ++ " m/s between " ++ num s0' ++ " m and " ++ num s ++ " m: the hardest braking allowed (min_acceleration " ++ num (pbAMin pb)
         ++ " m/s², min_jerk " ++ num (pbJMin pb) ++ " m/s³) is still at " ++ num (max v0' v1) ++ " m/s there")

-- | The start acceleration drives the velocity below zero whatever the jerk.
startSinks :: Problem -> SeedFailure
startSinks pb =
  Unattainable "start_acceleration"
    ("start_acceleration " ++ num (pbA0 pb) ++ " m/s² at start_velocity " ++ num (pbV0 pb)
     ++ " m/s drives the velocity below zero whatever the jerk: raising the acceleration at max_jerk "
     ++ num (pbJMax pb) ++ " m/s³ still loses " ++ num (negate (leastDrop pb)) ++ " m/s")

-- | The end acceleration cannot be reached from any velocity at or above zero.
endAccFailure :: Problem -> SeedFailure
endAccFailure pb =
  Unattainable "end_acceleration"
    ("end_velocity " ++ num (pbVEnd pb) ++ " m/s with end_acceleration " ++ num (pbAEnd pb)
     ++ " m/s² cannot be reached: ramping the acceleration up to it within max_jerk "
     ++ num (pbJMax pb) ++ " m/s³ gains " ++ num (negate (leastDrop (mirror pb))) ++ " m/s, more than the end velocity")
