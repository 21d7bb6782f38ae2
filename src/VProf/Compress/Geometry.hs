-- | Quaternion and polyline geometry used by the compressor. Everything here is
-- sign-invariant: q and -q are the same orientation.
module VProf.Compress.Geometry
  ( qdot
  , qangle
  , qlog
  , qexp
  , qmul
  , qconj
  , slerpShort
  , alignHemisphere
  , segmentIndex
  , segmentIndices
  , interpolate
  , interpolateAt
  , pointSegmentDistance
  ) where

import qualified Data.Vector.Unboxed as U
import Linear (Quaternion (..), V3 (..), dot, norm, quadrance, (*^), (^+^), (^-^), (^/))

import VProf.Compress.Vec

qdot :: Quaternion Double -> Quaternion Double -> Double
qdot (Quaternion a u) (Quaternion b v) = a * b + dot u v
{-# INLINE qdot #-}

qconj :: Quaternion Double -> Quaternion Double
qconj (Quaternion w v) = Quaternion w (negate <$> v)
{-# INLINE qconj #-}

qmul :: Quaternion Double -> Quaternion Double -> Quaternion Double
qmul (Quaternion a u) (Quaternion b v) =
  Quaternion (a * b - dot u v) (a *^ v ^+^ b *^ u ^+^ cross u v)
  where cross (V3 x1 y1 z1) (V3 x2 y2 z2) = V3 (y1 * z2 - z1 * y2) (z1 * x2 - x1 * z2) (x1 * y2 - y1 * x2)
{-# INLINE qmul #-}

-- | Rotation angle between two orientations, in [0, pi] rad: 2·acos |<q1,q2>|, computed
-- with atan2 so that it stays accurate for tiny angles.
qangle :: Quaternion Double -> Quaternion Double -> Double
qangle a b =
  let Quaternion w v = qmul (qconj a) b
  in 2 * atan2 (norm v) (abs w)
{-# INLINE qangle #-}

-- | Rotation vector (axis·angle, rad) of a unit quaternion, taking the short way.
qlog :: Quaternion Double -> V3 Double
qlog (Quaternion w0 v0) =
  let (w, v) = if w0 < 0 then (negate w0, negate <$> v0) else (w0, v0)
      s = norm v
  in if s < 1e-12 then 2 *^ v else (2 * atan2 s w / s) *^ v
{-# INLINE qlog #-}

-- | Unit quaternion of a rotation vector.
qexp :: V3 Double -> Quaternion Double
qexp r =
  let th = norm r
  in if th < 1e-12 then Quaternion 1 (0.5 *^ r)
     else Quaternion (cos (th / 2)) ((sin (th / 2) / th) *^ r)
{-# INLINE qexp #-}

-- | Spherical linear interpolation the short way (q2 is negated when <q1,q2> < 0).
slerpShort :: Quaternion Double -> Quaternion Double -> Double -> Quaternion Double
slerpShort q1@(Quaternion a1 u1) (Quaternion b0 v0) t =
  let d0 = qdot q1 (Quaternion b0 v0)
      (d, b, v) = if d0 < 0 then (negate d0, negate b0, negate <$> v0) else (d0, b0, v0)
  in if d > 0.9999995
       then let w = (1 - t) * a1 + t * b
                x = (1 - t) *^ u1 ^+^ t *^ v
                n = sqrt (w * w + quadrance x)
            in Quaternion (w / n) (x ^/ n)
       else let th = acos d
                s = sin th
                c1 = sin ((1 - t) * th) / s
                c2 = sin (t * th) / s
            in Quaternion (c1 * a1 + c2 * b) (c1 *^ u1 ^+^ c2 *^ v)
{-# INLINE slerpShort #-}

-- | Flip signs so that consecutive quaternions lie in the same hemisphere
-- (removes sign flips such as the one in EuRoC V1_01).
alignHemisphere :: Qs -> Qs
alignHemisphere qs
  | plength qs == 0 = qs
  | otherwise = pfromList (scanl1 step (ptoList qs))
  where step prev q = if qdot prev q < 0 then negate <$> q else q

-- | Segment of a time in a sorted array of waypoint times: the j in [0, K-2] with
-- T_j <= t < T_{j+1} (clamped at both ends).
segmentIndex :: U.Vector Double -> Double -> Int
segmentIndex ts t = go 0 (U.length ts - 1)
  where
    -- invariant: ts[lo] <= t (or lo == 0), t < ts[hi] (or hi == K-1)
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
interpolateAt :: U.Vector Double -> V3s -> Qs
              -> Int -> Double -> (V3 Double, Quaternion Double)
interpolateAt ts ps qs j t =
  let t0 = U.unsafeIndex ts j
      t1 = U.unsafeIndex ts (j + 1)
      a = max 0 (min 1 ((t - t0) / (t1 - t0)))
      p0 = pindex ps j
      p1 = pindex ps (j + 1)
  in (p0 ^+^ a *^ (p1 ^-^ p0), slerpShort (pindex qs j) (pindex qs (j + 1)) a)
{-# INLINE interpolateAt #-}

-- | Pose of a path at time t (clamped to its time span).
interpolate :: U.Vector Double -> V3s -> Qs
            -> Double -> (V3 Double, Quaternion Double)
interpolate ts ps qs t = interpolateAt ts ps qs (segmentIndex ts t) t
{-# INLINE interpolate #-}

-- | Euclidean distance of a point to a segment.
pointSegmentDistance :: V3 Double -> V3 Double -> V3 Double -> Double
pointSegmentDistance a b p =
  let d = b ^-^ a
      l2 = quadrance d
      s = if l2 <= 0 then 0 else max 0 (min 1 (dot (p ^-^ a) d / l2))
  in norm (p ^-^ (a ^+^ s *^ d))
{-# INLINE pointSegmentDistance #-}
