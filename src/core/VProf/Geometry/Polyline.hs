{-# LANGUAGE BangPatterns #-}
-- | Timed polylines of poses: waypoints at times, linear in position and slerp in
-- orientation between them (both linear in time), looked up by time (binary search, or
-- a precomputed segment table for many look-ups); and the distance of a point to a
-- segment. Orientations are sign-invariant: q and -q are the same.
module VProf.Geometry.Polyline
  ( segmentIndex
  , segmentIndices
  , polylineAt
  , interpolateAt
  , pointSegmentDistance
  , SegTable
  , mkSegTable
  , tableAt
  , tableInterp
  ) where

import qualified Data.Vector.Unboxed as U

import VProf.Geometry.Quaternion
import VProf.Geometry.Vec

-- | Segment of a time in a sorted array of waypoint times: the j in [0, K-2] with
-- T_j <= t < T_{j+1} (clamped at both ends).
segmentIndex :: U.Vector Double -> Double -> Int
segmentIndex ts t = go 0 (U.length ts - 1)
  where
    go lo hi
      | hi - lo <= 1 = lo
      | otherwise = let m = (lo + hi) `div` 2
                    in if U.unsafeIndex ts m <= t then go m hi else go lo m

-- | 'segmentIndex' for every time of a sorted array, by one merge sweep.
segmentIndices :: U.Vector Double -> U.Vector Double -> U.Vector Int
segmentIndices wts sts = U.unfoldrExactN (U.length sts) step (0, 0)
  where
    k = U.length wts
    step (i, j) =
      let t = U.unsafeIndex sts i
          j' = advance j t
      in (j', (i + 1, j'))
    advance j t
      | j + 2 < k && U.unsafeIndex wts (j + 1) <= t = advance (j + 1) t
      | otherwise = j

-- | Pose of a path (times, positions, orientations) at time t, given its segment j.
interpolateAt :: U.Vector Double -> V3s -> Qs -> Int -> Double -> (P3, Q4)
interpolateAt ts ps qs j t =
  let t0 = U.unsafeIndex ts j
      t1 = U.unsafeIndex ts (j + 1)
      a = max 0 (min 1 ((t - t0) / (t1 - t0)))
      p0 = pindex ps j
      p1 = pindex ps (j + 1)
      !p = p0 ^+^ a *^ (p1 ^-^ p0)
      !q = slerpShort (pindex qs j) (pindex qs (j + 1)) a
  in (p, q)
{-# INLINE interpolateAt #-}

-- | Pose of a path at time t (clamped to its time span; a path of one knot is that pose).
polylineAt :: U.Vector Double -> V3s -> Qs -> Double -> (P3, Q4)
polylineAt ts ps qs t
  | U.length ts < 2 = (pindex ps 0, pindex qs 0)
  | otherwise = interpolateAt ts ps qs (segmentIndex ts t) t
{-# INLINE polylineAt #-}

-- | A path with its per-segment slerp constants computed once (sign-aligned end
-- quaternion, angle, 1/sin angle), for passes that polylineAt at every sample.
data SegTable = SegTable !(U.Vector Double) !V3s !Qs !Qs !(U.Vector Double) !(U.Vector Double) !(U.Vector Double)

mkSegTable :: U.Vector Double -> V3s -> Qs -> SegTable
mkSegTable ts ps qs = SegTable ts ps qs q1s ths invs invdt
  where
    k = U.length ts
    m = max 0 (k - 1)
    q1s = pgenerate m (\j -> let a = pindex qs j; b = pindex qs (j + 1) in if qdot a b < 0 then qneg b else b)
    ths = U.generate m (\j -> let d = qdot (pindex qs j) (pindex q1s j)
                              in if d > 0.9999995 then 0 else acos (min 1 d))
    invs = U.map (\th -> if th == 0 then 0 else 1 / sin th) ths
    invdt = U.generate m (\j -> 1 / (U.unsafeIndex ts (j + 1) - U.unsafeIndex ts j))

-- | Pose at time t in segment j of a table.
tableAt :: SegTable -> Int -> Double -> (P3, Q4)
tableAt (SegTable ts ps q0s q1s ths invs invdt) j t =
  let t0 = U.unsafeIndex ts j
      s = max 0 (min 1 ((t - t0) * U.unsafeIndex invdt j))
      p0 = pindex ps j
      p = p0 ^+^ s *^ (pindex ps (j + 1) ^-^ p0)
      th = U.unsafeIndex ths j
      Q4 a1 b1 c1 d1 = pindex q0s j
      Q4 a2 b2 c2 d2 = pindex q1s j
      is = U.unsafeIndex invs j
      (k1, k2) = if th == 0 then (1 - s, s) else (sinF ((1 - s) * th) * is, sinF (s * th) * is)
      q = Q4 (k1 * a1 + k2 * a2) (k1 * b1 + k2 * b2) (k1 * c1 + k2 * c2) (k1 * d1 + k2 * d2)
      !q' = if th == 0 then qnormalize q else q
      !p' = p
  in (p', q')
{-# INLINE tableAt #-}

tableInterp :: SegTable -> Double -> (P3, Q4)
tableInterp tb@(SegTable ts _ _ _ _ _ _) t = tableAt tb (segmentIndex ts t) t
{-# INLINE tableInterp #-}

-- | Euclidean distance of a point to a segment.
pointSegmentDistance :: P3 -> P3 -> P3 -> Double
pointSegmentDistance a b p =
  let d = b ^-^ a
      l2 = quadrance d
      s = if l2 <= 0 then 0 else max 0 (min 1 (dot (p ^-^ a) d / l2))
  in norm (p ^-^ (a ^+^ s *^ d))
{-# INLINE pointSegmentDistance #-}
