-- | Problems made from problems, for the generator's passes: the same problem backwards
-- in time ('mirror'), its speed limits capped over a stretch ('capOn'), its ranges
-- narrowed ('scaleRanges', 'scaleJerk'), and what is left of it after a first step ('startingAfter').
--
-- Invariant: each keeps the zones sorted with the first at 0 and the acceleration and
-- jerk ranges around 0. A profile legal for 'capOn' or 'scaleRanges' of a problem is
-- legal for the problem; one legal for its 'mirror', reversed, too; one for
-- 'startingAfter' only behind a first step the caller has checked.
-- The transforms read the speed limits ("VProf.Profile.SpeedLimit"), which are defined
-- on the record, so they live in a module of their own above both.
module VProf.Profile.Problem.Transform
  ( mirror
  , capOn
  , scaleRanges
  , scaleJerk
  , startingAfter
  ) where

import Data.List (group, sort)
import qualified Data.Vector.Unboxed as U

import VProf.Profile.Problem (Problem (..))
import VProf.Profile.SpeedLimit (limitAt)

-- | The same problem backwards in time. Reversing the samples of a profile keeps its
-- velocities and jerks, negates its accelerations (so the acceleration range flips),
-- swaps the start and end states (accelerations negated) and mirrors positions about
-- the route's middle; the speed rule, the route end and the trapezoid distances are
-- symmetric. A profile legal for the mirror, reversed, is legal for the problem.
mirror :: Problem -> Problem
mirror pb = pb
  { pbZoneStarts = U.fromList (0 : [ len - z | z <- reverse (drop 1 (U.toList (pbZoneStarts pb))) ])
  , pbZoneSpeeds = U.reverse (pbZoneSpeeds pb)
  , pbAMin = negate (pbAMax pb), pbAMax = negate (pbAMin pb)
  , pbV0 = pbVEnd pb, pbA0 = negate (pbAEnd pb)
  , pbVEnd = pbV0 pb, pbAEnd = negate (pbA0 pb)
  }
  where len = pbLength pb

-- | Every speed limit on [a, b) capped at v (past the route end too when b is beyond it).
capOn :: Double -> Double -> Double -> Problem -> Problem
capOn a b v pb = pb { pbZoneStarts = U.fromList (map fst pieces), pbZoneSpeeds = U.fromList (map snd pieces) }
  where
    len = pbLength pb
    starts = map head (group (sort (U.toList (pbZoneStarts pb) ++ [ x | x <- [a, b], x > 0, x < len ])))
    pieces = [ (x, if x >= a && x < b then min v (limitAt pb x) else limitAt pb x) | x <- starts ]

-- | The acceleration and jerk ranges scaled by a factor phi in (0, 1]: a profile within
-- the narrower ranges is within the problem's.
scaleRanges :: Double -> Problem -> Problem
scaleRanges phi q = q { pbAMin = phi * pbAMin q, pbAMax = phi * pbAMax q, pbJMin = phi * pbJMin q, pbJMax = phi * pbJMax q }

-- | The jerk range alone scaled by a factor phi in (0, 1].
scaleJerk :: Double -> Problem -> Problem
scaleJerk phi q = q { pbJMin = phi * pbJMin q, pbJMax = phi * pbJMax q }

-- | The problem that starts after a first step: from position s1 at velocity v1 with
-- acceleration a, the route shortened by s1 and its zones shifted back by it.
startingAfter :: Double -> Double -> Double -> Problem -> Problem
startingAfter s1 v1 a pb =
  let later = [ (z - s1, l) | (z, l) <- zip starts speeds, z > s1 ]
  in pb { pbLength = pbLength pb - s1
        , pbZoneStarts = U.fromList (0 : map fst later), pbZoneSpeeds = U.fromList (limitAt pb s1 : map snd later)
        , pbV0 = v1, pbA0 = a }
  where
    starts = U.toList (pbZoneStarts pb)
    speeds = U.toList (pbZoneSpeeds pb)
