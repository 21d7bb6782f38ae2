-- | Inverse kinematics, one API for every robot: a target pose and an optional seed give every
-- solution found within the joint limits, sorted by distance to the seed, or a failure saying why.
--
-- 'kinematicsFor' picks the solver once per robot: the Dobot closed form when the model is the Dobot
-- linkage ('VProf.Kinematics.Ik.Dobot'), the six-axis closed forms when the DH table has a
-- spherical wrist or three parallel axes ('VProf.Kinematics.Ik.SixAxis'), otherwise the
-- numerical solver ('VProf.Kinematics.Ik.Numeric'). Invariant: requests are checked first (finite target, rigid
-- rotation, seed of the right length, finite): a bad request gets 'InvalidRequest', never an
-- exception or a NaN.
module VProf.Kinematics.Ik
  ( Kinematics (..)
  , Method (..)
  , kinematicsFor
  , prepareChain
  , solveIk
  , solveIkDistinct
  , solveIkIO
  , solvePose
  , checkRequest
  , describeFailureFor
  , module VProf.Kinematics.Ik.Types
  ) where

import qualified Data.Vector.Unboxed as U
import Numeric (showFFloat)

import VProf.Kinematics.Forward (Pose (..), poseToTf)
import VProf.Kinematics.Ik.Dobot
import VProf.Kinematics.Ik.Numeric
import VProf.Kinematics.Ik.Types
import VProf.Kinematics.Model
import qualified VProf.Kinematics.ClosedForm as CF
import VProf.Kinematics.Ik.SixAxis
import VProf.Kinematics.Transform
import VProf.Validation (finite)

data Method = ClosedFormDobot DobotGeometry | ClosedFormSixAxis CF.Solver | NumericLM

-- | A robot ready for IK: its compiled chain, the solver chosen for it, and what the numerical
-- solver's checks before a descent need of the chain (worked out on first use).
data Kinematics = Kinematics {kinChain :: Chain, kinMethod :: Method, kinNumeric :: Prepared}

kinematicsFor :: Robot -> Kinematics
kinematicsFor = prepareChain . compile

prepareChain :: Chain -> Kinematics
prepareChain ch = Kinematics ch method (prepareNumeric ch)
  where
    method = case robotClosedForm (chainRobot ch) of
      Just DobotLinkage | Right g <- dobotGeometry (chainRobot ch) -> ClosedFormDobot g
      _ | Just solver <- sixAxisSolver ch -> ClosedFormSixAxis solver
      _ -> NumericLM


-- | 'describeFailure' with each joint's limit miss in its unit: a revolute joint's in rad and
-- degrees, a prismatic joint's in mm.
describeFailureFor :: Robot -> IkFailure -> String
describeFailureFor r = \case
  OutsideLimits sols ->
    limitMisses "" [[ nm ++ " " ++ side v ++ " by " ++ amount nm (abs v) | (nm, v) <- sol ] | sol <- sols]
  f -> describeFailure f
  where
    side v = if v < 0 then "below its minimum" else "above its maximum"
    amount nm v = case [ jointKind j | j <- robotJoints r, jointName j == nm ] of
      Prismatic : _ -> showFFloat (Just 3) (v * 1000) " mm"
      _ -> showFFloat (Just 6) v " rad (" ++ showFFloat (Just 4) (v * 180 / pi) "°)"

-- | Problems with a request (empty when it can be solved).
checkRequest :: Chain -> Tf -> Maybe (U.Vector Double) -> [String]
checkRequest ch target seed
  | isRigid 1e-6 target && maybe True (\s -> U.length s == chainDof ch && U.all finite s) seed = []
  | otherwise = problems ch target seed

problems :: Chain -> Tf -> Maybe (U.Vector Double) -> [String]
problems ch target seed =
  [ "target: " ++ show (length (filter (not . finite) (toRows target))) ++ " entries are not finite numbers" | not (all finite (toRows target)) ]
    ++ [ "target: the rotation is not orthonormal with determinant 1" | all finite (toRows target), not (isRigid 1e-6 target) ]
    ++ case seed of
      Nothing -> []
      Just s ->
        [ "seed: " ++ show (U.length s) ++ " joint values for a robot with " ++ show (chainDof ch) ++ " joints" | U.length s /= chainDof ch ]
          ++ [ "seed[" ++ show i ++ "]: " ++ show x ++ " is not a finite number" | (i, x) <- zip [0 :: Int ..] (U.toList s), not (finite x) ]

-- | Solve for a tool transform (pure: the numerical solver's budget is its iteration and restart
-- counts).
solveIk :: IkOptions -> Kinematics -> Tf -> Maybe (U.Vector Double) -> Either IkFailure [IkSolution]
solveIk = solveWith solveSixAxis

-- | The request checked, then the solver of the kinematics' method, with the given six-axis
-- closed-form solver.
solveWith :: (IkOptions -> Chain -> CF.Solver -> Tf -> Maybe (U.Vector Double) -> Either IkFailure [IkSolution])
          -> IkOptions -> Kinematics -> Tf -> Maybe (U.Vector Double) -> Either IkFailure [IkSolution]
solveWith sixAxis opts (Kinematics ch m prep) target seed = case checkRequest ch target seed of
  [] -> case m of
    ClosedFormDobot g -> solveDobot opts ch g target seed
    ClosedFormSixAxis solver -> sixAxis opts ch solver target seed
    NumericLM -> solveNumericWith prep opts ch target seed
  errs -> Left (InvalidRequest errs)

-- | Every solution ('solveIk' with 'ikAllSolutions'), but of solutions that differ only by whole
-- turns of joints the one nearest the seed: for the six-axis closed forms one solution a branch
-- (the first of its branch in 'solveIk''s answer, without building the other variants: a UR's
-- ±360° limits give 512 solutions, 8 branches), nearest the seed first; the Dobot closed form and
-- the numerical solver answer as 'solveIk' does. Same failures as 'solveIk'.
solveIkDistinct :: IkOptions -> Kinematics -> Tf -> Maybe (U.Vector Double) -> Either IkFailure [IkSolution]
solveIkDistinct opts = solveWith solveSixAxisDistinct opts {ikAllSolutions = True}

-- | Like 'solveIk' with a wall-time budget (seconds) for the numerical solver.
solveIkIO :: Double -> IkOptions -> Kinematics -> Tf -> Maybe (U.Vector Double) -> IO (Either IkFailure [IkSolution])
solveIkIO budget opts (Kinematics ch m prep) target seed = case checkRequest ch target seed of
  [] -> case m of
    ClosedFormDobot g -> pure (solveDobot opts ch g target seed)
    ClosedFormSixAxis solver -> pure (solveSixAxis opts ch solver target seed)
    NumericLM -> solveNumericIOWith prep budget opts ch target seed
  errs -> pure (Left (InvalidRequest errs))

-- | Solve for a pose (position, quaternion); a zero or non-finite quaternion is refused.
solvePose :: IkOptions -> Kinematics -> Pose -> Maybe (U.Vector Double) -> Either IkFailure [IkSolution]
solvePose opts k p@(Pose (V3 x y z) (Quat w a b c)) seed
  | not (all finite [x, y, z, w, a, b, c]) = Left (InvalidRequest ["pose: not every number is finite"])
  | w * w + a * a + b * b + c * c < 1e-12 = Left (InvalidRequest ["pose: the quaternion is zero"])
  | otherwise = solveIk opts k (poseToTf p) seed
