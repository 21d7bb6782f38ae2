{-# LANGUAGE BangPatterns, RecordWildCards #-}
-- | The robot model: a serial chain of links, each either fixed or moved by one revolute or
-- prismatic joint variable, whose transforms come from standard DH, modified (Craig) DH or a URDF
-- origin and axis; the actuated joints in the controller's convention (position, velocity and
-- acceleration limits); linear couplings from actuated joints to link variables (signs, offsets,
-- the Dobot's parallel linkage, URDF mimic); base and tool transforms; payload, reach and collision
-- capsules.
--
-- Invariant: every quantity is stored in SI units (m, rad, m/s, rad/s, kg); a link's variable is
-- @driveOffset + Σ coefficient·q_joint@ over actuated joints, and the link's transform at variable
-- v is 'linkTransform'. 'compile' turns a model into a flat, unboxed 'Chain' for the hot loops
-- (forward kinematics, Jacobian, IK); it assumes a model 'VProf.Kinematics.Validate' accepts.
module VProf.Kinematics.Model
  ( -- * Model
    Robot (..)
  , Joint (..)
  , JointKind (..)
  , Limits (..)
  , Link (..)
  , Geometry (..)
  , Drive (..)
  , Capsule (..)
  , ClosedForm (..)
  , emptyRobot
  , directDrive
  , linkTransform
  , dof
    -- * Units at the boundary
  , revoluteLimits
  , prismaticLimits
  , angularVelocityLimit
  , payloadMass
  , reachLength
  , jointLimitsInUnits
    -- * Compiled chain
  , Chain (..)
  , compile
  , midLimits
  , withinLimits
  , limitViolations
  ) where

import Control.DeepSeq (NFData (..))
import qualified Data.Vector.Unboxed as U
import qualified Numeric.Units.Dimensional.Prelude as D
import Numeric.Units.Dimensional.Prelude (PlaneAngle, Length, Mass, AngularVelocity, (*~), (/~))

import VProf.Kinematics.Transform

data JointKind = Revolute | Prismatic
  deriving (Eq, Show)

-- | Closed lower and upper bound of a joint position (rad or m). Infinite bounds mean a
-- continuous joint.
data Limits = Limits {limMin, limMax :: !Double}
  deriving (Eq, Show)

-- | An actuated joint, in the controller's convention (the value its pendant shows).
data Joint = Joint
  { jointName :: String
  , jointKind :: JointKind
  , jointLimits :: Limits
  , jointMaxVelocity :: Maybe Double      -- ^ rad/s or m/s; Nothing: not published
  , jointMaxAcceleration :: Maybe Double  -- ^ rad/s² or m/s²; Nothing: not published
  }
  deriving (Eq, Show)

-- | Where a link's transform comes from. Constant parts only; the variable is added by the drive.
data Geometry
  = DhStandard {dhTheta, dhD, dhA, dhAlpha :: Double}
    -- ^ Rz(θ)·Dz(d)·Dx(a)·Rx(α); a revolute variable adds to θ, a prismatic one to d
  | DhModified {dhAlpha, dhA, dhTheta, dhD :: Double}
    -- ^ Rx(α_{i−1})·Dx(a_{i−1})·Rz(θ_i)·Dz(d_i)
  | UrdfJoint {urdfOrigin :: Tf, urdfAxis :: V3}
    -- ^ origin · (rotation about / translation along the unit axis)
  | FixedTransform Tf
    -- ^ no variable (URDF fixed joints folded, or a constant offset)
  deriving (Eq, Show)

-- | The link variable: offset + Σ coefficient · q_j (j indexes the actuated joints, 0-based).
-- A direct joint has one term with coefficient ±1 (the sign between DH and controller).
data Drive = Drive {driveOffset :: Double, driveTerms :: [(Int, Double)]}
  deriving (Eq, Show)

-- | A collision capsule in the link's frame: the segment from capA to capB swept by a sphere.
data Capsule = Capsule {capA :: V3, capB :: V3, capRadius :: Double}
  deriving (Eq, Show)

data Link = Link
  { linkName :: String
  , linkJointKind :: Maybe JointKind   -- ^ Nothing for a fixed link
  , linkGeometry :: Geometry
  , linkDrive :: Drive                 -- ^ ignored for a fixed link
  , linkCapsules :: [Capsule]
  }
  deriving (Eq, Show)

-- | A robot-specific closed-form IK the model is known to admit.
data ClosedForm = DobotLinkage
  deriving (Eq, Show)

data Robot = Robot
  { robotName :: String
  , robotDescription :: String
  , robotSources :: [String]
  , robotJoints :: [Joint]
  , robotLinks :: [Link]
  , robotBase :: Tf
  , robotTool :: Tf
  , robotPayload :: Maybe Double  -- ^ kg
  , robotReach :: Maybe Double    -- ^ m
  , robotClosedForm :: Maybe ClosedForm
  }
  deriving (Eq, Show)

emptyRobot :: String -> Robot
emptyRobot n = Robot n "" [] [] [] identity identity Nothing Nothing Nothing

-- | A link moved directly by joint j: variable = offset + sign·q_j.
directDrive :: Int -> Double -> Double -> Drive
directDrive j sign off = Drive off [(j, sign)]

dof :: Robot -> Int
dof = length . robotJoints

-- | The transform of one link at link variable v (the textbook form, used by tests and frames).
linkTransform :: Link -> Double -> Tf
linkTransform Link{..} v = case (linkGeometry, linkJointKind) of
  (FixedTransform t, _) -> t
  (DhStandard th d a al, k) ->
    let (th', d') = var k th d in rotZ th' `compose` trans 0 0 d' `compose` trans a 0 0 `compose` rotX al
  (DhModified al a th d, k) ->
    let (th', d') = var k th d in rotX al `compose` trans a 0 0 `compose` rotZ th' `compose` trans 0 0 d'
  (UrdfJoint o _, Nothing) -> o
  (UrdfJoint o ax, Just Revolute) -> let r = rotationBetween (unit ax) in o `compose` r `compose` rotZ v `compose` inverse r
  (UrdfJoint o ax, Just Prismatic) -> let V3 x y z = unit ax in o `compose` trans (v*x) (v*y) (v*z)
  where
    var (Just Revolute) th d = (th + v, d)
    var (Just Prismatic) th d = (th, d + v)
    var Nothing th d = (th, d)

unit :: V3 -> V3
unit a = v3Scale (1 / v3Norm a) a

--------------------------------------------------------------------------------------------------
-- Units

revoluteLimits :: PlaneAngle Double -> PlaneAngle Double -> Limits
revoluteLimits lo hi = Limits (lo /~ D.radian) (hi /~ D.radian)

prismaticLimits :: Length Double -> Length Double -> Limits
prismaticLimits lo hi = Limits (lo /~ D.meter) (hi /~ D.meter)

-- | A revolute joint's speed limit as a quantity.
angularVelocityLimit :: Joint -> Maybe (AngularVelocity Double)
angularVelocityLimit j = case jointKind j of
  Revolute -> (*~ (D.radian D./ D.second)) <$> jointMaxVelocity j
  Prismatic -> Nothing

payloadMass :: Robot -> Maybe (Mass Double)
payloadMass r = (*~ D.kilo D.gram) <$> robotPayload r

reachLength :: Robot -> Maybe (Length Double)
reachLength r = (*~ D.meter) <$> robotReach r

-- | A joint's limits: Left in angle for revolute, Right in length for prismatic.
jointLimitsInUnits :: Joint -> Either (PlaneAngle Double, PlaneAngle Double) (Length Double, Length Double)
jointLimitsInUnits Joint{..} = case jointKind of
  Revolute -> Left (limMin jointLimits *~ D.radian, limMax jointLimits *~ D.radian)
  Prismatic -> Right (limMin jointLimits *~ D.meter, limMax jointLimits *~ D.meter)

--------------------------------------------------------------------------------------------------
-- Compiled chain

-- | The model flattened for the hot loops. With m moving links, the tool pose is
-- C_0 · M_1(v_1) · C_1 · … · M_m(v_m) · C_m, where every M is a rotation about or translation along
-- z (URDF axes are rotated onto z and the rotation folded into the constants), C_0 holds the base
-- and C_m the tool. Fixed links are folded into the constants.
data Chain = Chain
  { chainRobot :: Robot
  , chainDof :: !Int                        -- ^ actuated joints n
  , chainLinks :: !Int                      -- ^ moving links m
  , chainConst :: !(U.Vector Double)        -- ^ 12·(m+1): C_0 … C_m, row-major 3×4
  , chainPrismatic :: !(U.Vector Bool)      -- ^ m
  , chainOffset :: !(U.Vector Double)       -- ^ m: drive offsets
  , chainTermStart :: !(U.Vector Int)       -- ^ m+1: link i's terms are [start_i, start_{i+1})
  , chainTermJoint :: !(U.Vector Int)
  , chainTermCoeff :: !(U.Vector Double)
  , chainFrameFix :: !(U.Vector Double)     -- ^ 12·m: from the moved frame to link i's own frame
  , chainLinkIndex :: !(U.Vector Int)       -- ^ m: index of the moving link in robotLinks
  , chainLo, chainHi :: !(U.Vector Double)  -- ^ n: joint limits
  , chainRevoluteJoint :: !(U.Vector Bool)  -- ^ n: the joint is revolute
  }

instance NFData Chain where
  rnf Chain{..} = chainConst `seq` chainLo `seq` chainHi `seq` chainFrameFix `seq` ()

-- | Split each moving link into Pre · M_z(v) · Post.
splitLink :: Link -> Either Tf (Tf, Bool, Tf)
splitLink Link{..} = case (linkJointKind, linkGeometry) of
  (Nothing, g) -> Left (fixedOf g)
  (Just _, FixedTransform t) -> Left t
  (Just k, DhStandard th d a al) -> case k of
    Revolute -> Right (rotZ th, False, trans 0 0 d `compose` trans a 0 0 `compose` rotX al)
    Prismatic -> Right (rotZ th `compose` trans 0 0 d, True, trans a 0 0 `compose` rotX al)
  (Just k, DhModified al a th d) -> case k of
    Revolute -> Right (rotX al `compose` trans a 0 0 `compose` rotZ th, False, trans 0 0 d)
    Prismatic -> Right (rotX al `compose` trans a 0 0 `compose` rotZ th `compose` trans 0 0 d, True, identity)
  (Just k, UrdfJoint o ax) ->
    let r = rotationBetween (unit ax) in Right (o `compose` r, k == Prismatic, inverse r)
  where
    fixedOf (FixedTransform t) = t
    fixedOf g = linkTransform Link{linkGeometry = g, ..} 0

compile :: Robot -> Chain
compile robot@Robot{..} =
  Chain
    { chainRobot = robot
    , chainDof = n
    , chainLinks = m
    , chainConst = U.fromList (concatMap toRows consts)
    , chainPrismatic = U.fromList [p | (_, (_, p, _), _) <- moving]
    , chainOffset = U.fromList [driveOffset (linkDrive l) | (_, _, l) <- moving]
    , chainTermStart = U.fromList (scanl (+) 0 [length (driveTerms (linkDrive l)) | (_, _, l) <- moving])
    , chainTermJoint = U.fromList [j | (_, _, l) <- moving, (j, _) <- driveTerms (linkDrive l)]
    , chainTermCoeff = U.fromList [c | (_, _, l) <- moving, (_, c) <- driveTerms (linkDrive l)]
    , chainFrameFix = U.fromList (concat [toRows post | (_, (_, _, post), _) <- moving])
    , chainLinkIndex = U.fromList [i | (i, _, _) <- moving]
    , chainLo = U.fromList (map (limMin . jointLimits) robotJoints)
    , chainHi = U.fromList (map (limMax . jointLimits) robotJoints)
    , chainRevoluteJoint = U.fromList [jointKind j == Revolute | j <- robotJoints]
    }
  where
    n = length robotJoints
    parts = zip [0 :: Int ..] (map (\l -> (l, splitLink l)) robotLinks)
    moving = [(i, s, l) | (i, (l, Right s)) <- parts]
    m = length moving
    -- fold: running constant k; emit k·pre at each moving link, continue with post
    consts = go robotBase (map (snd . snd) parts)
    go k [] = [k `compose` robotTool]
    go k (Left t : rest) = go (k `compose` t) rest
    go k (Right (pre, _, post) : rest) = (k `compose` pre) : go post rest

-- | The middle of each joint's range (0 for an unbounded side).
midLimits :: Chain -> U.Vector Double
midLimits ch = U.zipWith mid (chainLo ch) (chainHi ch)
  where
    mid lo hi
      | isInfinite lo || isInfinite hi = 0
      | otherwise = 0.5 * (lo + hi)

withinLimits :: Double -> Chain -> U.Vector Double -> Bool
withinLimits tol ch q =
  U.length q == chainDof ch
    && U.and (U.zipWith3 (\x lo hi -> x >= lo - tol && x <= hi + tol) q (chainLo ch) (chainHi ch))

-- | (joint index, signed amount beyond the limit: negative below min, positive above max).
limitViolations :: Double -> Chain -> U.Vector Double -> [(Int, Double)]
limitViolations tol ch q =
  [ (i, if x < lo then x - lo else x - hi)
  | i <- [0 .. U.length q - 1]
  , let x = q U.! i; lo = chainLo ch U.! i; hi = chainHi ch U.! i
  , x < lo - tol || x > hi + tol
  ]
