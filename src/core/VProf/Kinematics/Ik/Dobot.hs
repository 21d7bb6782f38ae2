{-# LANGUAGE RecordWildCards #-}
-- | The closed-form inverse kinematics of the Dobot Magician and Magician Lite (seed 002, finished).
--
-- The arm has four motors; a parallel linkage keeps the forearm's end plate level, so the modified
-- DH rows take θ = offset + [q1, q2, q3 − q2, −q3, q4] (q3 measured from the horizontal). The flange
-- position is then r = a1 + L2·sin q2 + L3·cos q3 + a5 radially and z = d1 + L2·cos q2 − L3·sin q3 − d5,
-- and the tool turns about the vertical by q1 + q4 (the flange z points down, so the sign of q4 is
-- read from the model). Solving: q1 = atan2(y, x) or that + π (reaching back), the shoulder–elbow
-- pair by the law of cosines written with atan2 (both elbows), q4 from the tool angle.
-- Invariant: every returned solution is within the limits and its forward kinematics matches the
-- target; targets out of reach, tilted or outside the limits get a failure saying by how much.
module VProf.Kinematics.Ik.Dobot
  ( DobotGeometry (..)
  , dobotModel
  , dobotGeometry
  , solveDobot
  , levelTarget
  ) where

import Data.List (nubBy)
import qualified Data.Vector.Unboxed as U

import VProf.Kinematics.Forward
import VProf.Kinematics.Ik.Types
import VProf.Kinematics.Model
import VProf.Kinematics.Transform

-- | The lengths of the planar problem (m) and the flange's orientation at q = 0.
data DobotGeometry = DobotGeometry
  { dgD1, dgA1, dgL2, dgL3, dgA5, dgD5 :: Double
  , dgHome :: Tf       -- ^ flange rotation at q = 0 (without base and tool)
  , dgToolSign :: Double  -- ^ +1 if q4 turns the tool like q1, −1 if the other way
  }
  deriving (Show)

-- | A Dobot arm from its five modified DH rows (α, a, d, θ-offset; m and rad) and the limits of its
-- four motors (rad). Row 4 is the passive link of the parallel linkage.
dobotModel :: String -> [(Double, Double, Double, Double)] -> [(Double, Double)] -> Robot
dobotModel name rows lims =
  (emptyRobot name)
    { robotJoints = [Joint ("J" ++ show i) Revolute (Limits lo hi) Nothing Nothing | (i, (lo, hi)) <- zip [1 :: Int ..] lims]
    , robotLinks =
        [ Link ("link" ++ show i) (Just Revolute) (DhModified al a th d) (Drive 0 terms) []
        | (i, (al, a, d, th), terms) <- zip3 [1 :: Int ..] rows couplings ]
    , robotClosedForm = Just DobotLinkage
    }
  where
    couplings = [[(0, 1)], [(1, 1)], [(2, 1), (1, -1)], [(2, -1)], [(3, 1)]]

-- | The planar lengths read off a Dobot model, checked against its forward kinematics at a few
-- configurations (so a model that is not this linkage is refused).
dobotGeometry :: Robot -> Either String DobotGeometry
dobotGeometry robot = case map linkGeometry (robotLinks robot) of
  [DhModified _ _ _ d1, DhModified _ a1 _ _, DhModified _ l2 _ _, DhModified _ l3 _ _, DhModified _ a5 _ d5]
    | length (robotJoints robot) == 4 ->
        let bare = compile robot {robotBase = identity, robotTool = identity}
            home = forward bare (U.fromList [0, 0, 0, 0])
            turned = forward bare (U.fromList [0, 0, 0, 0.5])
            sign = if r10 (compose turned (inverse home)) > 0 then 1 else -1
            g = DobotGeometry d1 a1 l2 l3 a5 d5 home {tx = 0, ty = 0, tz = 0} sign
            probes = [[0.3, 0.2, 0.1, -0.4], [-1, 0.7, -0.1, 1.1], [2, -0.05, 0.8, 0.3]]
            ok q = let (pe, re) = residual (forward bare (U.fromList q)) (formula g q) in pe < 1e-9 && re < 1e-9
        in if all ok probes then Right g else Left "the model is not the Dobot parallel linkage (its forward kinematics differs from the closed form's)"
  _ -> Left "a Dobot model has five modified-DH links driven by four joints"

-- | The flange pose by the closed-form geometry (bare chain).
formula :: DobotGeometry -> [Double] -> Tf
formula DobotGeometry{..} qs = case qs of
  [q1, q2, q3, q4] ->
    let r = dgA1 + dgL2 * sin q2 + dgL3 * cos q3 + dgA5
        z = dgD1 + dgL2 * cos q2 - dgL3 * sin q3 - dgD5
        rot = rotZ (q1 + dgToolSign * q4) `compose` dgHome
    in rot {tx = r * cos q1, ty = r * sin q1, tz = z}
  _ -> identity

-- | A level target: flange position (m) and tool angle about the vertical (rad), as the seed's
-- @moveToCord(x, y, z, angle)@, for a bare chain (base and tool identity).
levelTarget :: DobotGeometry -> V3 -> Double -> Tf
levelTarget g (V3 x y z) phi = (rotZ phi `compose` dgHome g) {tx = x, ty = y, tz = z}

-- | Every closed-form solution within the limits, sorted by distance to the seed (mid-limits when
-- none is given).
solveDobot :: IkOptions -> Chain -> DobotGeometry -> Tf -> Maybe (U.Vector Double) -> Either IkFailure [IkSolution]
solveDobot IkOptions{..} ch DobotGeometry{..} target seedM
  | tilt > max ikTolRotation 1e-9 = Left (OrientationUnreachable tilt)
  | not (null within) = Right (sortBySeed within)
  | dForward < eps && reachMin < eps = Left (Singular "the target is at the shoulder: the elbow angle is undetermined")
  | null planar = Left (if dForward > reachMax then BeyondReach dForward reachMax else InsideReach dForward reachMin)
  | otherwise = Left (OutsideLimits [[(names !! i, v) | (i, v) <- limitViolations ikLimitTolerance ch q] | q <- candidates])
  where
    robot = chainRobot ch
    names = map jointName (robotJoints robot)
    seed = maybe (midLimits ch) id seedM
    -- the target in the bare chain's frame
    bare = inverse (robotBase robot) `compose` target `compose` inverse (robotTool robot)
    m = compose bare (inverse dgHome) {tx = 0, ty = 0, tz = 0}
    tilt = atan2 (sqrt (r02 m * r02 m + r12 m * r12 m)) (r22 m)
    phi = atan2 (r10 m) (r00 m)
    x = tx bare; y = ty bare; z = tz bare
    rho = sqrt (x * x + y * y)
    q1s
      | rho < 1e-12 = [(seed U.! 0, 0)]
      | otherwise = [(atan2 y x, rho), (wrap (atan2 y x + pi), -rho)]
    v = z - dgD1 + dgD5
    reachMax = dgL2 + dgL3
    reachMin = abs (dgL2 - dgL3)
    eps = 1e-12
    planarFor (q1, r) =
      let h = r - dgA1 - dgA5
          d = sqrt (h * h + v * v)
      in if d > reachMax + eps || d < reachMin - eps || d < eps then []
         else
           let c = max (-1) (min 1 ((d * d + dgL2 * dgL2 - dgL3 * dgL3) / (2 * dgL2 * d)))
               s = sqrt (max 0 (1 - c * c))
               gam = atan2 v h
           in [ (q1, wrap (pi / 2 - al), wrap (negate (atan2 (v - dgL2 * sin al) (h - dgL2 * cos al))))
              | sgn <- [1, -1], let al = gam + sgn * atan2 s c ]
    planar = nubBy close (concatMap planarFor q1s)
    close (a, b, c) (a', b', c') = abs (a - a') + abs (b - b') + abs (c - c') < 1e-12
    -- the shoulder-to-flange distance of the branch reaching forward (for the reach failures)
    dForward = let h = rho - dgA1 - dgA5 in sqrt (h * h + v * v)
    q4For q1 = dgToolSign * (phi - q1)
    candidates = [U.fromList [q1', q2, q3, bestTurn 3 (q4For q1')] | (q1, q2, q3) <- planar, let q1' = bestTurn 0 q1]
    -- of the turns by 2π of a joint value, the one within limits nearest the seed
    bestTurn j a =
      let lo = chainLo ch U.! j; hi = chainHi ch U.! j
          base = wrap a
          opts = [base + 2 * pi * fromIntegral k | k <- [-2 .. 2 :: Int], base + 2 * pi * fromIntegral k >= lo - ikLimitTolerance, base + 2 * pi * fromIntegral k <= hi + ikLimitTolerance]
      in case opts of
           [] -> base
           _ -> snd (minimum [(abs (o - seed U.! j), o) | o <- opts])
    within =
      [ IkSolution q pe re (seedDistance q seed) Nothing
      | q <- candidates
      , withinLimits ikLimitTolerance ch q
      , let (pe, re) = residual (forward ch q) target
      , pe <= max ikTolPosition 1e-9 && re <= max ikTolRotation 1e-9 ]

wrap :: Double -> Double
wrap a = a - 2 * pi * fromIntegral (round (a / (2 * pi)) :: Integer)
