-- | The closed forms of six-axis arms ("VProf.Kinematics.ClosedForm") for robots of the
-- general model: a robot whose six links are standard-DH revolute joints, each driven by
-- its own joint with coefficient 1, is handed to the closed form when its table has a
-- spherical wrist or three parallel axes. Every solution it returns is checked here by
-- the model's own forward kinematics before it is returned, and carries its branch label.
module VProf.Kinematics.Ik.SixAxis
  ( sixAxisSolver
  , solveSixAxis
  , solveSixAxisDistinct
  ) where

import Data.Maybe (mapMaybe)
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

-- | Every solution within the limits, nearest the seed first. Each principal solution
-- (one per branch) is checked by forward kinematics to the options' tolerances; its 2π
-- variants within the limits reach the same pose and carry its residuals.
solveSixAxis :: IkOptions -> Chain -> CF.Solver -> Tf -> Maybe (U.Vector Double) -> Either IkFailure [IkSolution]
solveSixAxis = solveSixAxisWith (\solver _ ok -> CF.limitVariants solver ok)

-- | One solution per branch: of each principal solution's 2π variants within the limits only
-- the one nearest the seed (Euclidean, so joint by joint; on a tie the lower turn), nearest the
-- seed first. These are the solutions of 'solveSixAxis' that come first among their branch's,
-- without building the others (a UR's ±360° limits give 64 variants a branch); the failures
-- are the same.
solveSixAxisDistinct :: IkOptions -> Chain -> CF.Solver -> Tf -> Maybe (U.Vector Double) -> Either IkFailure [IkSolution]
solveSixAxisDistinct = solveSixAxisWith nearest
  where
    nearest solver from ok = case mapMaybe (nearestVariant solver from) ok of
      [] -> CF.limitVariants solver ok   -- no variant within the limits: limitVariants' failure
      vs -> Right vs

-- | The variant of a principal solution within the limits nearest the seed, as 'CF.limitVariants'
-- would build it (joint j at x + 2πk for k in the same range, put on a limit within 1e-12).
nearestVariant :: CF.Solver -> U.Vector Double -> CF.Solution -> Maybe CF.Solution
nearestVariant solver from sol = do
  let dh = CF.solverDh solver
      lo = CF.sdLower dh; hi = CF.sdUpper dh
      twoPi = 2 * pi
      pick j =
        let x = CF.solQ sol U.! j; l = lo U.! j; h = hi U.! j; s = from U.! j
            k0 = ceiling ((l - 1e-12 - x) / twoPi) :: Int
            k1 = floor ((h + 1e-12 - x) / twoPi) :: Int
            value k = min h (max l (x + twoPi * fromIntegral k))
            best = foldl (\b k -> if abs (value k - s) < abs (value b - s) then k else b) k0 [k0 + 1 .. k1]
        in if k1 < k0 then Nothing else Just (value best)
  q <- mapM pick [0 .. 5]
  pure sol {CF.solQ = U.fromListN 6 q}

-- | The principal solutions checked by forward kinematics, then expanded by the given rule.
solveSixAxisWith
  :: (CF.Solver -> U.Vector Double -> [CF.Solution] -> Either CF.IkFailure [CF.Solution])
  -> IkOptions -> Chain -> CF.Solver -> Tf -> Maybe (U.Vector Double) -> Either IkFailure [IkSolution]
solveSixAxisWith expand opts ch solver target seed = case CF.poseFromRowMajor (toRows4 target) of
  Nothing -> Left (InvalidRequest ["target: not a 4×4 transform"])
  Just pose -> case CF.solvePrincipal solver pose of
    Left e -> Left (failure e)
    Right principal ->
      let withResid = [ (s, residual (forward ch (CF.solQ s)) target) | s <- principal ]
          ok = [ sr | sr@(_, (pe, re)) <- withResid, pe <= ikTolPosition opts, re <= ikTolRotation opts ]
          from = maybe (midLimits ch) id seed
          solution s = let q = CF.solQ s; (pe, re) = residualOf ok s
                       in IkSolution q pe re (seedDistance q from) (Just (CF.branchText (CF.solBranch s)))
      in case (withResid, ok) of
           ([], _) -> Left (NotConverged (1 / 0) (1 / 0))
           (_, []) -> Left (NotConverged (minimum (map (fst . snd) withResid)) (minimum (map (snd . snd) withResid)))
           _ -> either (Left . failure) (Right . sortBySeed . map solution) (expand solver from (map fst ok))
  where
    failure = \case
      CF.BadTarget why -> InvalidRequest [why]
      CF.UnknownFamily why -> InvalidRequest [why]
      CF.OutOfReach what d -> Unreachable what d
      CF.OutsideLimits _ j by -> OutsideLimits [[(jointName (robotJoints (chainRobot ch) !! (j - 1)), by)]]
    -- a variant reaches its principal solution's pose: the same angles up to 2π
    residualOf ok s = case [ r | (p, r) <- ok, sameWrapped (CF.solQ p) (CF.solQ s) ] of
      (r : _) -> r
      [] -> residual (forward ch (CF.solQ s)) target
    sameWrapped a b = U.and (U.zipWith (\x y -> abs (wrapPi (x - y)) < 1e-9) a b)
    wrapPi x = x - 2 * pi * fromIntegral (round (x / (2 * pi)) :: Int)
