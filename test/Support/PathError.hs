-- | The compression tests' measure of a path against a recording, independent of vprof's
-- own measures ("VProf.Compress.Metrics") and of its interpolation ("VProf.Geometry.Polyline"):
-- the path's pose at every sample's time, computed here ('pathPoseAt'). The orientation error is
-- the rotation angle between the recorded and the path's quaternion, 2·acos |⟨q, q̂⟩|, computed
-- here (not by the library's angle function).
module Support.PathError
  ( worstPositionError
  , pathPoseAt
  , pathPosesAt
  , positionErrorsOf
  , orientationErrorsOf
  , withinBudget
  , quatProduct
  ) where

import qualified Data.Vector.Unboxed as U
import Test.QuickCheck (Property, (.&&.), counterexample)

import VProf.Compress.Objective (PathA (..), Prepared (..), totalCost)
import VProf.Compress.Types
import VProf.Geometry.Vec (P3 (..), Q4 (..), pindex, plength, ptoList)

-- | The largest time-synchronous position error (m) of a path's track against a
-- recording's: the distance from each sample to the path's position at the sample's time.
worstPositionError :: Track -> Track -> Double
worstPositionError path rec = maximum (positionErrorsOf path rec)

-- | Every sample's time-synchronous position error (m), in the recording's order.
positionErrorsOf :: Track -> Track -> [Double]
positionErrorsOf path rec =
  [ dist p x | ((p, _), x) <- zip (pathPosesAt path (U.toList (tTime rec))) (ptoList (tPos rec)) ]
  where dist (P3 a b c) (P3 x y z) = sqrt ((a - x) ^ (2 :: Int) + (b - y) ^ (2 :: Int) + (c - z) ^ (2 :: Int))

-- | Every sample's time-synchronous orientation error (rad), in the recording's order: the
-- angle of the rotation from the path's orientation at the sample's time to the recorded one
-- (q and −q alike).
orientationErrorsOf :: Track -> Track -> [Double]
orientationErrorsOf path rec =
  [ 2 * acos (min 1 (abs (qa * qb + xa * xb + ya * yb + za * zb) / (len4 a * len4 b)))
  | ((_, a@(Q4 qa xa ya za)), b@(Q4 qb xb yb zb)) <- zip (pathPosesAt path (U.toList (tTime rec))) (ptoList (tRot rec)) ]
  where len4 (Q4 w x y z) = sqrt (w * w + x * x + y * y + z * z)

-- | The path's pose at a time, clamped to its span: the position linear in time between the
-- two knots around it, and the orientation turned from the first knot's by the same share
-- of the shortest rotation to the second's (the axis and angle of q₀⁻¹·q₁, raised to that
-- power: the same curve as slerp, computed another way).
pathPoseAt :: Track -> Double -> (P3, Q4)
pathPoseAt path t = head (pathPosesAt path [t])

-- | 'pathPoseAt' at each of increasing times, by one walk along the knots (an error for times
-- that decrease: a recording's times increase).
pathPosesAt :: Track -> [Double] -> [(P3, Q4)]
pathPosesAt path times0
  | k == 0 = error "Support.PathError: a path without knots"
  | k == 1 = map (const (pindex (tPos path) 0, pindex (tRot path) 0)) times0
  | otherwise = go segments times0 (-1 / 0)
  where
    k = U.length (tTime path)
    segments = [ (U.unsafeIndex (tTime path) j, U.unsafeIndex (tTime path) (j + 1), j) | j <- [0 .. k - 2] ]
    go _ [] _ = []
    go segs (t : ts) before
      | t < before = error ("Support.PathError: the times decrease at " ++ show t)
      | otherwise =
          -- the segment [t0, t1) holding t, the last one for t at or past its end
          let segs'@((t0, t1, j) : _) = dropWhile (\(_, t1', j') -> t >= t1' && j' < k - 2) segs
              a = max 0 (min 1 ((t - t0) / (t1 - t0)))
          in (lerp a (pindex (tPos path) j) (pindex (tPos path) (j + 1)), turn a (pindex (tRot path) j) (pindex (tRot path) (j + 1)))
             : go segs' ts t
    lerp a (P3 x0 y0 z0) (P3 x1 y1 z1) = P3 (x0 + a * (x1 - x0)) (y0 + a * (y1 - y0)) (z0 + a * (z1 - z0))
    turn a q0 q1 =
      let u0 = unit q0
          Q4 rw rx ry rz = mul (conj u0) (unit q1)
          -- the shorter way round: q and −q are one rotation
          (w, x, y, z) = if rw < 0 then (negate rw, negate rx, negate ry, negate rz) else (rw, rx, ry, rz)
          sn = sqrt (x * x + y * y + z * z)
          half = atan2 sn w
      in if sn == 0 then u0
         else let c = cos (a * half); s = sin (a * half) / sn
              in mul u0 (Q4 c (s * x) (s * y) (s * z))
    unit q@(Q4 w x y z) = let n = sqrt (w * w + x * x + y * y + z * z) in if n == 0 then q else Q4 (w / n) (x / n) (y / n) (z / n)
    conj (Q4 w x y z) = Q4 w (negate x) (negate y) (negate z)
    mul = quatProduct

-- | The Hamilton product of two quaternions (w, x, y, z), written here rather than taken from
-- the library: the composition of the rotations, the right one first.
quatProduct :: Q4 -> Q4 -> Q4
quatProduct (Q4 a1 b1 c1 d1) (Q4 a2 b2 c2 d2) =
  Q4 (a1 * a2 - b1 * b2 - c1 * c2 - d1 * d2) (a1 * b2 + b1 * a2 + c1 * d2 - d1 * c2)
     (a1 * c2 - b1 * d2 + c1 * a2 + d1 * b2) (a1 * d2 + b1 * c2 - c1 * b2 + d1 * a2)

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
