{-# LANGUAGE BangPatterns, LambdaCase, RecordWildCards #-}
-- | The vocabulary of the closed-form inverse kinematics: a small strict rigid-transform
-- type ('Pose', rotation plus translation, no matrices library in the hot path), the
-- six-axis standard-DH table it solves ('SixAxisDh'), the branch labels ('Branch') with
-- their compact text form, solutions and the reasons a solve fails. The geometric meaning
-- of each label is in @docs/closed-form-ik.md@; 'dhLink' and 'forwardPose' are the solver's
-- own forward kinematics (the tests check against a separate oracle).
module VProf.Kinematics.ClosedForm.Types
  ( -- * Vectors, rotations, poses
    V3 (..), Rot (..), Pose (..)
  , vadd, vsub, vscale, dot, cross, norm3
  , rotMul, rotT, rotApply, rotCol, identityRot
  , identityPose, composePose, inversePose, applyPose
  , poseFromRowMajor, poseToRowMajor
  , rotZ, rotX, dhLink
    -- * Robot table
  , SixAxisDh (..), mkSixAxisDh, forwardPose
    -- * Families, branches, solutions, failures
  , Family (..)
  , Shoulder (..), Elbow (..), Wrist (..), Branch (..)
  , branchText, branchCfx, parseBranch, allBranches
  , Singularity (..), Solution (..), IkFailure (..)
  ) where

import Control.DeepSeq (NFData (..), rnf)
import Data.Char (toUpper, isDigit)
import qualified Data.Vector.Unboxed as U

-- | A strict 3-vector.
data V3 = V3 {-# UNPACK #-} !Double {-# UNPACK #-} !Double {-# UNPACK #-} !Double
  deriving (Eq, Show)

-- | A rotation matrix stored by rows.
data Rot = Rot !V3 !V3 !V3
  deriving (Eq, Show)

-- | A rigid transform: @x ↦ R x + t@.
data Pose = Pose { poseR :: !Rot, poseT :: !V3 }
  deriving (Eq, Show)

instance NFData V3 where rnf (V3 _ _ _) = ()
instance NFData Rot where rnf (Rot _ _ _) = ()
instance NFData Pose where rnf (Pose _ _) = ()

vadd, vsub, cross :: V3 -> V3 -> V3
vadd (V3 a b c) (V3 x y z) = V3 (a + x) (b + y) (c + z)
vsub (V3 a b c) (V3 x y z) = V3 (a - x) (b - y) (c - z)
cross (V3 a b c) (V3 x y z) = V3 (b * z - c * y) (c * x - a * z) (a * y - b * x)
{-# INLINE vadd #-}
{-# INLINE vsub #-}
{-# INLINE cross #-}

vscale :: Double -> V3 -> V3
vscale k (V3 a b c) = V3 (k * a) (k * b) (k * c)
{-# INLINE vscale #-}

dot :: V3 -> V3 -> Double
dot (V3 a b c) (V3 x y z) = a * x + b * y + c * z
{-# INLINE dot #-}

norm3 :: V3 -> Double
norm3 v = sqrt (dot v v)

identityRot :: Rot
identityRot = Rot (V3 1 0 0) (V3 0 1 0) (V3 0 0 1)

rotT :: Rot -> Rot
rotT (Rot (V3 a b c) (V3 d e f) (V3 g h i)) = Rot (V3 a d g) (V3 b e h) (V3 c f i)
{-# INLINE rotT #-}

rotApply :: Rot -> V3 -> V3
rotApply (Rot r0 r1 r2) v = V3 (dot r0 v) (dot r1 v) (dot r2 v)
{-# INLINE rotApply #-}

-- | Column @j@ (0, 1 or 2) of a rotation: the image of the @j@-th unit vector.
rotCol :: Int -> Rot -> V3
rotCol 0 (Rot (V3 a _ _) (V3 d _ _) (V3 g _ _)) = V3 a d g
rotCol 1 (Rot (V3 _ b _) (V3 _ e _) (V3 _ h _)) = V3 b e h
rotCol _ (Rot (V3 _ _ c) (V3 _ _ f) (V3 _ _ i)) = V3 c f i
{-# INLINE rotCol #-}

rotMul :: Rot -> Rot -> Rot
rotMul (Rot r0 r1 r2) m =
  let Rot c0 c1 c2 = rotT m
      row r = V3 (dot r c0) (dot r c1) (dot r c2)
  in Rot (row r0) (row r1) (row r2)
{-# INLINE rotMul #-}

identityPose :: Pose
identityPose = Pose identityRot (V3 0 0 0)

composePose :: Pose -> Pose -> Pose
composePose (Pose ra ta) (Pose rb tb) = Pose (rotMul ra rb) (vadd (rotApply ra tb) ta)
{-# INLINE composePose #-}

inversePose :: Pose -> Pose
inversePose (Pose r t) = let rt = rotT r in Pose rt (vscale (-1) (rotApply rt t))
{-# INLINE inversePose #-}

applyPose :: Pose -> V3 -> V3
applyPose (Pose r t) v = vadd (rotApply r v) t

-- | From a 4×4 homogeneous matrix in row-major order (16 numbers; the last row is ignored).
poseFromRowMajor :: [Double] -> Maybe Pose
poseFromRowMajor [a, b, c, x, d, e, f, y, g, h, i, z, _, _, _, _] =
  Just (Pose (Rot (V3 a b c) (V3 d e f) (V3 g h i)) (V3 x y z))
poseFromRowMajor _ = Nothing

poseToRowMajor :: Pose -> [Double]
poseToRowMajor (Pose (Rot (V3 a b c) (V3 d e f) (V3 g h i)) (V3 x y z)) =
  [a, b, c, x, d, e, f, y, g, h, i, z, 0, 0, 0, 1]

rotZ :: Double -> Rot
rotZ t = let c = cos t; s = sin t in Rot (V3 c (-s) 0) (V3 s c 0) (V3 0 0 1)
{-# INLINE rotZ #-}

rotX :: Double -> Rot
rotX t = let c = cos t; s = sin t in Rot (V3 1 0 0) (V3 0 c (-s)) (V3 0 s c)

-- | One standard-DH link, Rz(θ)·Dz(d)·Dx(a)·Rx(α), from θ, d, a and (cos α, sin α).
dhLink :: Double -> Double -> Double -> Double -> Double -> Pose
dhLink th d a ca sa =
  let c = cos th; s = sin th
  in Pose (Rot (V3 c (-s * ca) (s * sa)) (V3 s (c * ca) (-c * sa)) (V3 0 sa ca)) (V3 (a * c) (a * s) d)
{-# INLINE dhLink #-}

-- | A six-axis arm in standard DH: per row a, α, d and the offset with θ_i = q_i + offset_i
-- (all joints revolute), the joint limits on q, and the base and tool transforms
-- (flange pose = base · A1 ⋯ A6 · tool).
data SixAxisDh = SixAxisDh
  { sdA, sdAlpha, sdD, sdOffset :: !(U.Vector Double)
  , sdLower, sdUpper :: !(U.Vector Double)
  , sdBase, sdTool :: !Pose
  } deriving (Eq, Show)

instance NFData SixAxisDh where
  rnf (SixAxisDh a b c d e f g h) = a `seq` b `seq` c `seq` d `seq` e `seq` f `seq` rnf g `seq` rnf h

-- | Build a table from lists of six numbers each (a, α, d, offset, lower, upper), with
-- identity base and tool; 'Nothing' unless every list has six finite entries.
mkSixAxisDh :: [Double] -> [Double] -> [Double] -> [Double] -> [Double] -> [Double] -> Maybe SixAxisDh
mkSixAxisDh a al d o lo up
  | all ok [a, al, d, o, lo, up] = Just (SixAxisDh (v a) (v al) (v d) (v o) (v lo) (v up) identityPose identityPose)
  | otherwise = Nothing
  where ok xs = length xs == 6 && all (\x -> not (isNaN x || isInfinite x)) xs
        v = U.fromListN 6

-- | The solver's forward kinematics: base · A1(q1) ⋯ A6(q6) · tool.
forwardPose :: SixAxisDh -> U.Vector Double -> Pose
forwardPose SixAxisDh{..} q = composePose (go 0 sdBase) sdTool
  where
    go !i !acc
      | i >= 6 = acc
      | otherwise =
          let al = sdAlpha U.! i
          in go (i + 1) (composePose acc (dhLink (q U.! i + sdOffset U.! i) (sdD U.! i) (sdA U.! i) (cos al) (sin al)))

-- | The two kinematic families with a closed form here (see 'VProf.Kinematics.ClosedForm.classify').
data Family
  = SphericalWrist   -- ^ axes 4, 5, 6 meet in a point, axes 2 and 3 parallel (Pieper)
  | ThreeParallel    -- ^ axes 2, 3, 4 parallel (the Universal Robots arms)
  deriving (Eq, Ord, Show, Enum, Bounded)

instance NFData Family where rnf x = x `seq` ()

-- | Shoulder: 'ShoulderRight' when the wrist point lies in front of axis 1, along the
-- direction x₁ of link 1 (ABB: "in front of axis 1"; Puma: righty), 'ShoulderLeft' behind it.
data Shoulder = ShoulderRight | ShoulderLeft deriving (Eq, Ord, Show, Enum, Bounded)
-- | Elbow: seen with x₁ to the right and axis 1 upwards, 'ElbowUp' when the elbow lies above
-- the line from axis 2 to the wrist point.
data Elbow = ElbowUp | ElbowDown deriving (Eq, Ord, Show, Enum, Bounded)
-- | Wrist: 'WristNoFlip' when sin θ5 ≥ 0, 'WristFlip' when sin θ5 < 0 (ABB: axis 5 negative).
data Wrist = WristNoFlip | WristFlip deriving (Eq, Ord, Show, Enum, Bounded)

data Branch = Branch { brShoulder :: !Shoulder, brElbow :: !Elbow, brWrist :: !Wrist }
  deriving (Eq, Ord, Show)

instance NFData Branch where rnf x = x `seq` ()

allBranches :: [Branch]
allBranches = [Branch s e w | s <- [minBound ..], e <- [minBound ..], w <- [minBound ..]]

-- | ABB's cfx digit: 4·(shoulder left) + 2·(elbow down) + (wrist flip), 0..7.
branchCfx :: Branch -> Int
branchCfx (Branch s e w) = 4 * fromEnum s + 2 * fromEnum e + fromEnum w

-- | Three letters, e.g. @"RUN"@ (right, up, no flip) or @"LDF"@.
branchText :: Branch -> String
branchText (Branch s e w) =
  [ case s of ShoulderRight -> 'R'; ShoulderLeft -> 'L'
  , case e of ElbowUp -> 'U'; ElbowDown -> 'D'
  , case w of WristNoFlip -> 'N'; WristFlip -> 'F' ]

-- | Reads 'branchText' (any case) or a cfx digit (@"3"@, @"cfx3"@).
parseBranch :: String -> Maybe Branch
parseBranch str = case map toUpper str of
  [s, e, w] | Just s' <- lookup s [('R', ShoulderRight), ('L', ShoulderLeft)]
            , Just e' <- lookup e [('U', ElbowUp), ('D', ElbowDown)]
            , Just w' <- lookup w [('N', WristNoFlip), ('F', WristFlip)] -> Just (Branch s' e' w')
  'C' : 'F' : 'X' : rest -> digit rest
  rest -> digit rest
  where
    digit [c] | isDigit c, n <- fromEnum c - fromEnum '0', n < 8 =
      Just (Branch (toEnum (n `div` 4)) (toEnum ((n `div` 2) `mod` 2)) (toEnum (n `mod` 2)))
    digit _ = Nothing

-- | A degenerate configuration met by a solution, and the documented choice made there.
data Singularity
  = WristSingular      -- ^ sin θ5 ≈ 0: only θ4 ± θ6 is determined; q4 = 0 (Pieper) or q6 = 0 (UR) is chosen
  | ShoulderSingular   -- ^ the wrist point on axis 1 (θ1 free: q1 = 0 and its opposite are chosen), or on
                       --   the cylinder of radius |K| around it (the two shoulders coincide; returned once)
  | ElbowStretched     -- ^ the two elbow solutions coincide (arm stretched or folded); returned once
  deriving (Eq, Ord, Show, Enum, Bounded)

instance NFData Singularity where rnf x = x `seq` ()

-- | One solution: joint values q (within the limits; wrapped variants are separate
-- solutions), its branch and the singularities it sits on (empty for a regular pose).
data Solution = Solution
  { solQ :: !(U.Vector Double)
  , solBranch :: !Branch
  , solSingular :: ![Singularity]
  } deriving (Eq, Show)

instance NFData Solution where rnf (Solution q b s) = q `seq` b `seq` rnf s

data IkFailure
  = UnknownFamily String        -- ^ the table fits neither family; says which condition fails
  | BadTarget String            -- ^ a NaN or infinite number in the target
  | OutOfReach String Double    -- ^ what cannot be reached, and by how much (m): positive
                                --   beyond the reach, negative closer in than the arm folds
  | OutsideLimits Int Int Double -- ^ solutions found, the joint (1-based) and radians by which the nearest misses its limit
  deriving (Eq, Show)

instance NFData IkFailure where
  rnf = \case
    UnknownFamily s -> rnf s
    BadTarget s -> rnf s
    OutOfReach s d -> rnf s `seq` rnf d
    OutsideLimits a b c -> a `seq` b `seq` rnf c
