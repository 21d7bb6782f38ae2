{-# LANGUAGE BangPatterns, RecordWildCards #-}
-- | Forward kinematics: the tool pose of a compiled 'Chain' for a joint vector, and every link
-- frame.
--
-- The inner loop walks the unboxed constants of the chain with a strict twelve-double
-- accumulator: per moving link one rotation about z (two columns updated) or one translation along
-- z, then one constant 3×4 product. No lists and no boxed doubles in the loop. Invariant: the
-- result equals the product of 'VProf.Kinematics.Model.linkTransform' over the links between the
-- base and tool transforms (the tests check this against an independent textbook formula).
module VProf.Kinematics.Forward
  ( Pose (..)
  , forward
  , forwardPose
  , linkFrames
  , linkVariables
  , poseFromTf
  , poseToTf
  , constAt
  , linkVar
  , motion
  , stepLink
  ) where

import Control.DeepSeq (NFData (..))
import qualified Data.Vector.Unboxed as U

import VProf.Kinematics.Model
import VProf.Kinematics.Transform

-- | A pose: position (m) and unit quaternion (w ≥ 0).
data Pose = Pose {posePosition :: !V3, poseOrientation :: !Quat}
  deriving (Eq, Show)

instance NFData Pose where rnf !_ = ()

poseFromTf :: Tf -> Pose
poseFromTf t = Pose (translation t) (toQuat t)

poseToTf :: Pose -> Tf
poseToTf (Pose p q) = fromQuat p q

-- | Constant i of the chain.
constAt :: U.Vector Double -> Int -> Tf
constAt c i =
  let b = 12 * i
      e k = U.unsafeIndex c (b + k)
  in Tf (e 0) (e 1) (e 2) (e 3) (e 4) (e 5) (e 6) (e 7) (e 8) (e 9) (e 10) (e 11)
{-# INLINE constAt #-}

-- | The variable of moving link i.
linkVar :: Chain -> U.Vector Double -> Int -> Double
linkVar Chain{..} q i = go (U.unsafeIndex chainTermStart i) (U.unsafeIndex chainOffset i)
  where
    end = U.unsafeIndex chainTermStart (i + 1)
    go !t !acc
      | t >= end = acc
      | otherwise = go (t + 1) (acc + U.unsafeIndex chainTermCoeff t * U.unsafeIndex q (U.unsafeIndex chainTermJoint t))
{-# INLINE linkVar #-}

-- | Every moving link's variable (DH θ or d, URDF angle or displacement).
linkVariables :: Chain -> U.Vector Double -> U.Vector Double
linkVariables ch q = U.generate (chainLinks ch) (linkVar ch q)

-- | acc · M_z(v): a rotation about z (revolute) or a translation along z (prismatic).
motion :: Bool -> Double -> Tf -> Tf
motion False v (Tf a00 a01 a02 ax a10 a11 a12 ay a20 a21 a22 az) =
  let c = cos v; s = sin v
  in Tf (a00*c + a01*s) (a01*c - a00*s) a02 ax
        (a10*c + a11*s) (a11*c - a10*s) a12 ay
        (a20*c + a21*s) (a21*c - a20*s) a22 az
motion True v (Tf a00 a01 a02 ax a10 a11 a12 ay a20 a21 a22 az) =
  Tf a00 a01 a02 (ax + v*a02) a10 a11 a12 (ay + v*a12) a20 a21 a22 (az + v*a22)
{-# INLINE motion #-}

-- | The tool pose (base·links·tool) as a rigid transform. The joint vector is not checked here
-- (length n assumed); see 'VProf.Kinematics.Validate.checkJointVector'.
forward :: Chain -> U.Vector Double -> Tf
forward ch q =
  let Tf b00 b01 b02 bx b10 b11 b12 by b20 b21 b22 bz = constAt (chainConst ch) 0
  in go 0 b00 b01 b02 bx b10 b11 b12 by b20 b21 b22 bz
  where
    -- twelve strict doubles rather than a Tf, so that GHC keeps them unboxed through the loop
    go :: Int -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Tf
    go !i !a00 !a01 !a02 !ax !a10 !a11 !a12 !ay !a20 !a21 !a22 !az
      | i >= chainLinks ch = Tf a00 a01 a02 ax a10 a11 a12 ay a20 a21 a22 az
      | otherwise = stepLink ch q i a00 a01 a02 ax a10 a11 a12 ay a20 a21 a22 az (go (i + 1))

-- | One moving link on an unboxed accumulator: acc · M_z(v_i) · C_{i+1}, passed to the
-- continuation (the shared step of 'forward' and the Jacobian's sweep).
stepLink
  :: Chain -> U.Vector Double -> Int
  -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double
  -> (Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> r)
  -> r
stepLink ch@Chain{..} q i a00 a01 a02 ax a10 a11 a12 ay a20 a21 a22 az k =
  let !v = linkVar ch q i
      !pr = U.unsafeIndex chainPrismatic i
      !c = if pr then 1 else cos v
      !s = if pr then 0 else sin v
      !t = if pr then v else 0
      -- acc · M_z(v): columns 0 and 1 turned by v, or the translation moved along column 2
      !m00 = a00*c + a01*s; !m01 = a01*c - a00*s
      !m10 = a10*c + a11*s; !m11 = a11*c - a10*s
      !m20 = a20*c + a21*s; !m21 = a21*c - a20*s
      !mx = ax + t*a02; !my = ay + t*a12; !mz = az + t*a22
      !b = 12 * (i + 1)
      e j = U.unsafeIndex chainConst (b + j)
      !c00 = e 0; !c01 = e 1; !c02 = e 2; !cx = e 3
      !c10 = e 4; !c11 = e 5; !c12 = e 6; !cy = e 7
      !c20 = e 8; !c21 = e 9; !c22 = e 10; !cz = e 11
  in k (m00*c00 + m01*c10 + a02*c20) (m00*c01 + m01*c11 + a02*c21) (m00*c02 + m01*c12 + a02*c22) (m00*cx + m01*cy + a02*cz + mx)
       (m10*c00 + m11*c10 + a12*c20) (m10*c01 + m11*c11 + a12*c21) (m10*c02 + m11*c12 + a12*c22) (m10*cx + m11*cy + a12*cz + my)
       (m20*c00 + m21*c10 + a22*c20) (m20*c01 + m21*c11 + a22*c21) (m20*c02 + m21*c12 + a22*c22) (m20*cx + m21*cy + a22*cz + mz)
{-# INLINE stepLink #-}

forwardPose :: Chain -> U.Vector Double -> Pose
forwardPose ch = poseFromTf . forward ch

-- | The base frame, the frame of every moving link (DH frame i, or the URDF child link's frame),
-- and the tool frame, in the world.
linkFrames :: Chain -> U.Vector Double -> [Tf]
linkFrames ch@Chain{..} q = robotBase (chainRobot) : go 0 (constAt chainConst 0)
  where
    go i acc
      | i >= chainLinks = [acc]
      | otherwise =
          let acc' = motion (chainPrismatic U.! i) (linkVar ch q i) acc
          in compose acc' (constAt chainFrameFix i) : go (i + 1) (compose acc' (constAt chainConst (i + 1)))
