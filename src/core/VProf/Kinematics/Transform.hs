{-# LANGUAGE BangPatterns, RecordWildCards #-}
-- | Rigid transforms of 3-D space (rotation + translation, the top three rows of a homogeneous
-- 4×4 matrix) and unit quaternions.
--
-- A 'Tf' holds twelve strict, unpacked doubles so that chains of products allocate nothing in a
-- tight loop. Invariant: the rotation part is orthonormal with determinant +1 whenever it was built
-- from the constructors here ('rotX', 'fromRpy', 'fromQuat', …) and products of them; 'fromRows'
-- takes any 3×4 and leaves the check to the caller ('isRigid').
module VProf.Kinematics.Transform
  ( Tf (..)
  , V3 (..)
  , Quat (..)
  , identity
  , compose
  , inverse
  , rotX
  , rotY
  , rotZ
  , trans
  , fromRpy
  , fromRows
  , toRows
  , toRows4
  , translation
  , applyPoint
  , applyVector
  , rotationColumn
  , toQuat
  , fromQuat
  , normaliseQuat
  , rotationLog
  , rotationAngle
  , rotationBetween
  , isRigid
  , v3Norm
  , v3Sub
  , v3Add
  , v3Scale
  , v3Dot
  , v3Cross
  ) where

import Control.DeepSeq (NFData (..))
import VProf.Validation (finite)

-- | A 3-vector.
data V3 = V3 {-# UNPACK #-} !Double {-# UNPACK #-} !Double {-# UNPACK #-} !Double
  deriving (Eq, Show)

instance NFData V3 where rnf !_ = ()

-- | A quaternion w + xi + yj + zk (a rotation when of unit norm).
data Quat = Quat {qw, qx, qy, qz :: {-# UNPACK #-} !Double}
  deriving (Eq, Show)

instance NFData Quat where rnf !_ = ()

-- | Rotation r_ij (row i, column j) and translation t.
data Tf = Tf
  { r00, r01, r02, tx
  , r10, r11, r12, ty
  , r20, r21, r22, tz :: {-# UNPACK #-} !Double
  }
  deriving (Eq, Show)

instance NFData Tf where rnf !_ = ()

identity :: Tf
identity = Tf 1 0 0 0 0 1 0 0 0 0 1 0

-- | The product a·b (first a, then b in a's frame).
compose :: Tf -> Tf -> Tf
compose (Tf a00 a01 a02 ax a10 a11 a12 ay a20 a21 a22 az) (Tf b00 b01 b02 bx b10 b11 b12 by b20 b21 b22 bz) =
  Tf (a00*b00 + a01*b10 + a02*b20) (a00*b01 + a01*b11 + a02*b21) (a00*b02 + a01*b12 + a02*b22) (a00*bx + a01*by + a02*bz + ax)
     (a10*b00 + a11*b10 + a12*b20) (a10*b01 + a11*b11 + a12*b21) (a10*b02 + a11*b12 + a12*b22) (a10*bx + a11*by + a12*bz + ay)
     (a20*b00 + a21*b10 + a22*b20) (a20*b01 + a21*b11 + a22*b21) (a20*b02 + a21*b12 + a22*b22) (a20*bx + a21*by + a22*bz + az)
{-# INLINE compose #-}

-- | The inverse of a rigid transform (transpose rotation, rotate back the translation).
inverse :: Tf -> Tf
inverse (Tf a00 a01 a02 ax a10 a11 a12 ay a20 a21 a22 az) =
  Tf a00 a10 a20 (-(a00*ax + a10*ay + a20*az))
     a01 a11 a21 (-(a01*ax + a11*ay + a21*az))
     a02 a12 a22 (-(a02*ax + a12*ay + a22*az))

rotX, rotY, rotZ :: Double -> Tf
rotX a = let c = cos a; s = sin a in Tf 1 0 0 0 0 c (-s) 0 0 s c 0
rotY a = let c = cos a; s = sin a in Tf c 0 s 0 0 1 0 0 (-s) 0 c 0
rotZ a = let c = cos a; s = sin a in Tf c (-s) 0 0 s c 0 0 0 0 1 0

trans :: Double -> Double -> Double -> Tf
trans x y z = Tf 1 0 0 x 0 1 0 y 0 0 1 z

-- | URDF's origin: translation xyz, rotation Rz(yaw)·Ry(pitch)·Rx(roll).
fromRpy :: V3 -> V3 -> Tf
fromRpy (V3 x y z) (V3 roll pitch yaw) =
  trans x y z `compose` rotZ yaw `compose` rotY pitch `compose` rotX roll

-- | From three rows of four (row-major 3×4 or the top of a 4×4).
fromRows :: [Double] -> Maybe Tf
fromRows (a:b:c:d:e:f:g:h:i:j:k:l:_) = Just (Tf a b c d e f g h i j k l)
fromRows _ = Nothing

toRows :: Tf -> [Double]
toRows (Tf a b c d e f g h i j k l) = [a, b, c, d, e, f, g, h, i, j, k, l]

-- | The 16 entries of the homogeneous matrix, row-major.
toRows4 :: Tf -> [Double]
toRows4 t = toRows t ++ [0, 0, 0, 1]

translation :: Tf -> V3
translation t = V3 (tx t) (ty t) (tz t)

applyPoint :: Tf -> V3 -> V3
applyPoint t (V3 x y z) =
  V3 (r00 t*x + r01 t*y + r02 t*z + tx t) (r10 t*x + r11 t*y + r12 t*z + ty t) (r20 t*x + r21 t*y + r22 t*z + tz t)

applyVector :: Tf -> V3 -> V3
applyVector t (V3 x y z) =
  V3 (r00 t*x + r01 t*y + r02 t*z) (r10 t*x + r11 t*y + r12 t*z) (r20 t*x + r21 t*y + r22 t*z)

-- | Column 0, 1 or 2 of the rotation.
rotationColumn :: Int -> Tf -> V3
rotationColumn 0 t = V3 (r00 t) (r10 t) (r20 t)
rotationColumn 1 t = V3 (r01 t) (r11 t) (r21 t)
rotationColumn _ t = V3 (r02 t) (r12 t) (r22 t)

-- | The unit quaternion of the rotation part (Shepperd's method; w ≥ 0).
toQuat :: Tf -> Quat
toQuat Tf{..}
  | tr > 0 = let s = 2 * sqrt (tr + 1) in pos (Quat (0.25 * s) ((r21 - r12) / s) ((r02 - r20) / s) ((r10 - r01) / s))
  | r00 > r11 && r00 > r22 = let s = 2 * sqrt (1 + r00 - r11 - r22) in pos (Quat ((r21 - r12) / s) (0.25 * s) ((r01 + r10) / s) ((r02 + r20) / s))
  | r11 > r22 = let s = 2 * sqrt (1 + r11 - r00 - r22) in pos (Quat ((r02 - r20) / s) ((r01 + r10) / s) (0.25 * s) ((r12 + r21) / s))
  | otherwise = let s = 2 * sqrt (1 + r22 - r00 - r11) in pos (Quat ((r10 - r01) / s) ((r02 + r20) / s) ((r12 + r21) / s) (0.25 * s))
  where
    tr = r00 + r11 + r22
    pos q = normaliseQuat (if qw q < 0 then Quat (-qw q) (-qx q) (-qy q) (-qz q) else q)

normaliseQuat :: Quat -> Quat
normaliseQuat (Quat w x y z) = let n = sqrt (w*w + x*x + y*y + z*z) in Quat (w/n) (x/n) (y/n) (z/n)

-- | The transform with the rotation of a quaternion (normalised first) and translation p.
fromQuat :: V3 -> Quat -> Tf
fromQuat (V3 px py pz) q0 =
  let Quat w x y z = normaliseQuat q0
  in Tf (1 - 2*(y*y + z*z)) (2*(x*y - z*w)) (2*(x*z + y*w)) px
        (2*(x*y + z*w)) (1 - 2*(x*x + z*z)) (2*(y*z - x*w)) py
        (2*(x*z - y*w)) (2*(y*z + x*w)) (1 - 2*(x*x + y*y)) pz

-- | The rotation vector (axis × angle, angle in [0, π]) of the rotation part: the logarithm map.
-- Accurate near 0 and near π.
rotationLog :: Tf -> V3
rotationLog Tf{..}
  | c > 1 - 1e-6 =
      -- small angle: sinθ/θ ≈ 1 − θ²/6
      let k = 0.5 * (1 + (1 - c) / 3) in V3 (k * vx) (k * vy) (k * vz)
  | c < -0.99 =
      -- near π: axis from the symmetric part, sign from the skew part
      let a = rotationAngle' c s
          xx = sqrt (max 0 ((r00 - c) / (1 - c)))
          yy = sqrt (max 0 ((r11 - c) / (1 - c)))
          zz = sqrt (max 0 ((r22 - c) / (1 - c)))
          (ux, uy, uz)
            | xx >= yy && xx >= zz = let x = sgn vx xx in (x, (r01 + r10) / (2 * (1 - c) * x), (r02 + r20) / (2 * (1 - c) * x))
            | yy >= zz = let y = sgn vy yy in ((r01 + r10) / (2 * (1 - c) * y), y, (r12 + r21) / (2 * (1 - c) * y))
            | otherwise = let z = sgn vz zz in ((r02 + r20) / (2 * (1 - c) * z), (r12 + r21) / (2 * (1 - c) * z), z)
          n = sqrt (ux*ux + uy*uy + uz*uz)
      in V3 (a * ux / n) (a * uy / n) (a * uz / n)
  | otherwise = let a = rotationAngle' c s; k = a / (2 * s) in V3 (k * vx) (k * vy) (k * vz)
  where
    vx = r21 - r12
    vy = r02 - r20
    vz = r10 - r01
    c = max (-1) (min 1 ((r00 + r11 + r22 - 1) / 2))
    s = 0.5 * sqrt (vx*vx + vy*vy + vz*vz)
    sgn v m = if v < 0 then -m else m

rotationAngle' :: Double -> Double -> Double
rotationAngle' c s = atan2 s c

-- | The angle (in [0, π]) of the rotation part.
rotationAngle :: Tf -> Double
rotationAngle Tf{..} =
  let vx = r21 - r12; vy = r02 - r20; vz = r10 - r01
  in atan2 (0.5 * sqrt (vx*vx + vy*vy + vz*vz)) ((r00 + r11 + r22 - 1) / 2)

-- | A rotation taking the unit z axis onto the given unit vector (the shortest one).
rotationBetween :: V3 -> Tf
rotationBetween (V3 x y z)
  | z > 1 - 1e-15 = identity
  | z < -1 + 1e-15 = rotX pi
  | otherwise =
      -- axis k = ẑ × u normalised, angle acos z (Rodrigues)
      let s = sqrt (x*x + y*y); kx = -y / s; ky = x / s; c = z; v = 1 - c
      in Tf (c + kx*kx*v) (kx*ky*v) (ky*s) 0
            (kx*ky*v) (c + ky*ky*v) (-kx*s) 0
            (-ky*s) (kx*s) c 0

-- | The rotation part is orthonormal with determinant +1 (to tol) and all entries finite.
isRigid :: Double -> Tf -> Bool
isRigid tol Tf{..} =
  fin r00 && fin r01 && fin r02 && fin r10 && fin r11 && fin r12 && fin r20 && fin r21 && fin r22
    && fin tx && fin ty && fin tz
    && near (r00*r00 + r10*r10 + r20*r20) 1 && near (r01*r01 + r11*r11 + r21*r21) 1 && near (r02*r02 + r12*r12 + r22*r22) 1
    && near (r00*r01 + r10*r11 + r20*r21) 0 && near (r00*r02 + r10*r12 + r20*r22) 0 && near (r01*r02 + r11*r12 + r21*r22) 0
    && near det 1
  where
    fin = finite
    near x y = abs (x - y) <= tol
    det = r00 * (r11*r22 - r12*r21) - r01 * (r10*r22 - r12*r20) + r02 * (r10*r21 - r11*r20)

v3Norm :: V3 -> Double
v3Norm (V3 x y z) = sqrt (x*x + y*y + z*z)

v3Sub, v3Add, v3Cross :: V3 -> V3 -> V3
v3Sub (V3 a b c) (V3 x y z) = V3 (a - x) (b - y) (c - z)
v3Add (V3 a b c) (V3 x y z) = V3 (a + x) (b + y) (c + z)
v3Cross (V3 a b c) (V3 x y z) = V3 (b*z - c*y) (c*x - a*z) (a*y - b*x)

v3Dot :: V3 -> V3 -> Double
v3Dot (V3 a b c) (V3 x y z) = a*x + b*y + c*z

v3Scale :: Double -> V3 -> V3
v3Scale k (V3 x y z) = V3 (k*x) (k*y) (k*z)
{-# INLINE v3Norm #-}
{-# INLINE v3Sub #-}
{-# INLINE v3Add #-}
{-# INLINE v3Cross #-}
{-# INLINE v3Dot #-}
{-# INLINE v3Scale #-}
