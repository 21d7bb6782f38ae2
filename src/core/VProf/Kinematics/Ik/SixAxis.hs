-- | The closed forms of six-axis arms ("VProf.Kinematics.ClosedForm") for robots of the
-- general model: a robot whose six links are standard-DH revolute joints, each driven by
-- its own joint with coefficient 1, is handed to the closed form when its table has a
-- spherical wrist or three parallel axes. Every solution it returns is checked here by
-- the model's own forward kinematics before it is returned, and carries its branch label.
module VProf.Kinematics.Ik.SixAxis
  ( sixAxisSolver
  , solveSixAxis
  ) where

import qualified Data.Vector.Unboxed as U

import qualified VProf.Kinematics.ClosedForm as CF
import VProf.Kinematics.Forward (forward)
import VProf.Kinematics.Ik.Types
import VProf.Kinematics.Model
import VProf.Kinematics.Transform

-- | The closed-form solver of a chain, if its robot fits a family.
sixAxisSolver :: Chain -> Maybe CF.Solver
sixAxisSolver ch = do
  let r = chainRobot ch
      joints = robotJoints r
  rows <- mapM row (zip [0 ..] (robotLinks r))
  let (as, als, ds, offs) = unzip4 rows
  dh <- CF.mkSixAxisDh as als ds offs (map (limMin . jointLimits) joints) (map (limMax . jointLimits) joints)
  base <- CF.poseFromRowMajor (toRows4 (robotBase r))
  tool <- CF.poseFromRowMajor (toRows4 (robotTool r))
  if length joints == 6 && length rows == 6 && all ((== Revolute) . jointKind) joints
    then either (const Nothing) Just (CF.solverFor dh { CF.sdBase = base, CF.sdTool = tool })
    else Nothing
  where
    row (i, Link _ (Just Revolute) (DhStandard th d a al) (Drive o [(j, 1)]) _) | j == i = Just (a, al, d, th + o)
    row _ = Nothing
    unzip4 xs = (map (\(a, _, _, _) -> a) xs, map (\(_, b, _, _) -> b) xs, map (\(_, _, c, _) -> c) xs, map (\(_, _, _, d) -> d) xs)

-- | Every solution within the limits, nearest the seed first, each checked by forward
-- kinematics to the options' tolerances.
solveSixAxis :: IkOptions -> Chain -> CF.Solver -> Tf -> Maybe (U.Vector Double) -> Either IkFailure [IkSolution]
solveSixAxis opts ch solver target seed = case CF.poseFromRowMajor (toRows4 target) of
  Nothing -> Left (InvalidRequest ["target: not a 4×4 transform"])
  Just pose -> case CF.solveWith solver pose of
    Left (CF.BadTarget why) -> Left (InvalidRequest [why])
    Left (CF.UnknownFamily why) -> Left (InvalidRequest [why])
    Left (CF.OutOfReach what d) -> Left (Unreachable what d)
    Left (CF.OutsideLimits _ j by) -> Left (OutsideLimits [[(jointName (robotJoints (chainRobot ch) !! (j - 1)), by)]])
    Right sols ->
      let from = maybe (midLimits ch) id seed
          checked = [ IkSolution q pe re (seedDistance q from) (Just (CF.branchText (CF.solBranch s)))
                    | s <- sols, let q = CF.solQ s, let (pe, re) = residual (forward ch q) target
                    , pe <= ikTolPosition opts, re <= ikTolRotation opts ]
      in case checked of
           [] | null sols -> Left (NotConverged (1 / 0) (1 / 0))
           [] -> Left (NotConverged (minimum (map (fst . resid) sols)) (minimum (map (snd . resid) sols)))
           _ -> Right (sortBySeed checked)
      where resid s = residual (forward ch (CF.solQ s)) target
