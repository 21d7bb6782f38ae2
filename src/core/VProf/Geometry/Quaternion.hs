{-# LANGUAGE BangPatterns #-}
-- | Unit quaternions as orientations: products, the angle between two, log and exp maps,
-- slerp the short way, and sign alignment of a sequence. Everything here is
-- sign-invariant: q and -q are the same orientation. Fast small-angle sine and arctangent
-- serve the hot loops of path compression.
module VProf.Geometry.Quaternion
  ( qdot
  , qangle
  , qlog
  , qexp
  , qmul
  , qconj
  , qneg
  , qnormalize
  , slerpShort
  , alignHemisphere
  , sinF
  , atan2F
  ) where

import VProf.Geometry.Vec

-- | sin, by its Taylor series for |x| <= 0.5 (relative error below 1e-11), else libm.
-- The compressor evaluates millions of small-angle sines per run.
sinF :: Double -> Double
sinF x
  | abs x <= 0.5 = let x2 = x * x
                   in x + x * x2 * (-0.16666666666666666 + x2 * (8.333333333333333e-3
                        + x2 * (-1.984126984126984e-4 + x2 * (2.7557319223985893e-6 - x2 * 2.505210838544172e-8))))
  | otherwise = sin x
{-# INLINE sinF #-}

-- | atan2 y x for y >= 0, x > 0, by the arctangent series when y/x <= 0.1 (error below
-- 1e-14), else libm.
atan2F :: Double -> Double -> Double
atan2F y x
  | x > 0 && y <= 0.1 * x =
      let r = y / x; r2 = r * r
      in r + r * r2 * (-0.3333333333333333 + r2 * (0.2 + r2 * (-0.14285714285714285
           + r2 * (0.1111111111111111 - r2 * 9.090909090909091e-2))))
  | otherwise = atan2 y x
{-# INLINE atan2F #-}

qdot :: Q4 -> Q4 -> Double
qdot (Q4 a b c d) (Q4 e f g h) = a * e + b * f + c * g + d * h
{-# INLINE qdot #-}

qconj :: Q4 -> Q4
qconj (Q4 w x y z) = Q4 w (negate x) (negate y) (negate z)
{-# INLINE qconj #-}

qneg :: Q4 -> Q4
qneg (Q4 w x y z) = Q4 (negate w) (negate x) (negate y) (negate z)
{-# INLINE qneg #-}

qnormalize :: Q4 -> Q4
qnormalize q@(Q4 w x y z) = let n = sqrt (qdot q q) in Q4 (w / n) (x / n) (y / n) (z / n)
{-# INLINE qnormalize #-}

qmul :: Q4 -> Q4 -> Q4
qmul (Q4 a b c d) (Q4 e f g h) =
  Q4 (a * e - b * f - c * g - d * h)
     (a * f + b * e + c * h - d * g)
     (a * g - b * h + c * e + d * f)
     (a * h + b * g - c * f + d * e)
{-# INLINE qmul #-}

-- | Rotation angle between two orientations, in [0, pi] rad: 2·acos |<q1,q2>|, computed
-- with atan2 so that it stays accurate for tiny angles.
qangle :: Q4 -> Q4 -> Double
qangle a b =
  let Q4 w x y z = qmul (qconj a) b
  in 2 * atan2F (sqrt (x * x + y * y + z * z)) (abs w)
{-# INLINE qangle #-}

-- | Rotation vector (axis·angle, rad) of a unit quaternion, taking the short way.
qlog :: Q4 -> P3
qlog (Q4 w0 x0 y0 z0) =
  let !sg = if w0 < 0 then -1 else 1
      !w = sg * w0
      !s = sqrt (x0 * x0 + y0 * y0 + z0 * z0)
      !k = if s < 1e-12 then 2 * sg else sg * 2 * atan2F s w / s
  in P3 (k * x0) (k * y0) (k * z0)
{-# INLINE qlog #-}

-- | Unit quaternion of a rotation vector.
qexp :: P3 -> Q4
qexp r@(P3 x y z) =
  let th = norm r
  in if th < 1e-12 then qnormalize (Q4 1 (0.5 * x) (0.5 * y) (0.5 * z))
     else let k = sin (th / 2) / th in Q4 (cos (th / 2)) (k * x) (k * y) (k * z)
{-# INLINE qexp #-}

-- | Spherical linear interpolation the short way (q2 is negated when <q1,q2> < 0).
slerpShort :: Q4 -> Q4 -> Double -> Q4
slerpShort q1@(Q4 a1 b1 c1 d1) q2raw t =
  let !d0 = qdot q1 q2raw
      !sg = if d0 < 0 then -1 else 1
      !d = sg * d0
      Q4 a20 b20 c20 d20 = q2raw
      !a2 = sg * a20
      !b2 = sg * b20
      !c2 = sg * c20
      !d2 = sg * d20
  in if d > 0.9999995
       then qnormalize (Q4 ((1 - t) * a1 + t * a2) ((1 - t) * b1 + t * b2)
                           ((1 - t) * c1 + t * c2) ((1 - t) * d1 + t * d2))
       else let th = acos d
                s = sin th
                k1 = sinF ((1 - t) * th) / s
                k2 = sinF (t * th) / s
            in Q4 (k1 * a1 + k2 * a2) (k1 * b1 + k2 * b2) (k1 * c1 + k2 * c2) (k1 * d1 + k2 * d2)
{-# INLINE slerpShort #-}

-- | Flip signs so that consecutive quaternions lie in the same hemisphere
-- (removes sign flips such as the one in EuRoC V1_01).
alignHemisphere :: Qs -> Qs
alignHemisphere qs
  | plength qs == 0 = qs
  | otherwise = pfromList (scanl1 step (ptoList qs))
  where step prev q = if qdot prev q < 0 then qneg q else q
