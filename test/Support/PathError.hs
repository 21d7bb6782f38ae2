-- | The compression tests' measure of a path against a recording, independent of vprof's
-- own measures ("VProf.Compress.Metrics"): the path interpolated at every sample's time.
-- The orientation error is the rotation angle between the recorded and the path's
-- quaternion, 2·acos |⟨q, q̂⟩|, computed here (not by the library's angle function).
module Support.PathError
  ( worstPositionError
  , positionErrorsOf
  , orientationErrorsOf
  , withinBudget
  ) where

import qualified Data.Vector.Unboxed as U
import Test.QuickCheck (Property, (.&&.), counterexample)

import VProf.Compress.Objective (PathA (..), Prepared (..), totalCost)
import VProf.Compress.Types
import VProf.Geometry.Polyline (polylineAt)
import VProf.Geometry.Vec

-- | The largest time-synchronous position error (m) of a path's track against a
-- recording's: the distance from each sample to the path's position at the sample's time.
worstPositionError :: Track -> Track -> Double
worstPositionError path rec = maximum (positionErrorsOf path rec)

-- | Every sample's time-synchronous position error (m), in the recording's order.
positionErrorsOf :: Track -> Track -> [Double]
positionErrorsOf path rec =
  [ distance (fst (polylineAt (tTime path) (tPos path) (tRot path) t)) x
  | (t, x) <- zip (U.toList (tTime rec)) (ptoList (tPos rec)) ]

-- | Every sample's time-synchronous orientation error (rad), in the recording's order: the
-- angle of the rotation from the path's orientation at the sample's time to the recorded one
-- (q and −q alike).
orientationErrorsOf :: Track -> Track -> [Double]
orientationErrorsOf path rec =
  [ 2 * acos (min 1 (abs (qa * qb + xa * xb + ya * yb + za * zb) / (len4 a * len4 b)))
  | (t, b@(Q4 qb xb yb zb)) <- zip (U.toList (tTime rec)) (ptoList (tRot rec))
  , let a@(Q4 qa xa ya za) = snd (polylineAt (tTime path) (tPos path) (tRot path) t) ]
  where len4 (Q4 w x y z) = sqrt (w * w + x * x + y * y + z * z)

-- | What the knot fit's budgeted last steps promise of a path @pa@ made from @pa0@: its
-- position sum of squares (measured here) and its position-and-velocity objective within
-- (1 + b) times @pa0@'s, and pinned ends where they are pinned.
withinBudget :: Prepared -> Weights -> Double -> PathA -> PathA -> Property
withinBudget pr w b pa0@(PathA _ p0 _) pa@(PathA _ p _) =
  counterexample (show ("position sum of squares", ssq pa0, ssq pa)) (ssq pa <= (1 + b) * ssq pa0 * (1 + 1e-9))
  .&&. counterexample (show ("position and velocity", pv pa0, pv pa)) (pv pa <= (1 + b) * pv pa0 * (1 + 1e-9))
  .&&. counterexample "a pinned end moved"
         (rcEnds pr == EndsFree || (pindex p 0 == pindex p0 0 && pindex p (kk - 1) == pindex p0 (kk - 1)))
  where
    rec = Track (rcT pr) (rcP pr) (rcQ pr)
    ssq (PathA t x q) = sum (map (^ (2 :: Int)) (positionErrorsOf (Track t x q) rec))
    pv = totalCost pr w { wOrientation = 0 }
    kk = plength p0
