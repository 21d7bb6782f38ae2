-- | Inverse kinematics: for every library robot IK of FK(q) returns solutions within the limits
-- whose FK matches the target; the Dobot closed form recovers q; seed 002's worked example;
-- unreachable, tilted and out-of-limit targets get the right failure; bad requests are refused.
module VProf.Kinematics.IkSpec (spec) where

import Control.Monad (forM_)
import Data.Either (isLeft)
import Data.List (isInfixOf)
import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import Support.Gen
import Support.RobotOracle (oracleTool, poseGap)
import VProf.Kinematics
import VProf.Kinematics.Ik.Numeric (orientationTilt)
import VProf.Kinematics.Library

deg :: Double -> Double
deg = (* (pi / 180))

lib :: String -> Kinematics
lib n = either error kinematicsFor (lookupRobot n)

-- | The solution's tool pose by the independent FK ("Support.RobotOracle") is the pose of q
-- to 1e-9 in every entry (m for the position): the solver's own error fields are not
-- trusted (a wrapped variant's are copied from its principal solution).
reachesByOracle :: String -> U.Vector Double -> IkSolution -> Bool
reachesByOracle n q s =
  let r = either error id (lookupRobot n)
  in poseGap (oracleTool r (U.toList (solJoints s))) (oracleTool r (U.toList q)) < 1e-9

spec :: Spec
spec = do
  describe "IK of FK(q) for every library robot (random q within the limits)" $
    forM_ libraryChains $ \(name, ech) -> it name $
      case ech of
        Left e -> property (counterexample (unlines e) False)
        Right ch -> do
          let k = prepareChain ch
              opts = defaultIkOptions
          property $ withMaxSuccess 60 $ forAllQ ch $ \q ->
            let target = forward ch q
            in case solveIk opts k target Nothing of
                 Left f -> counterexample (describeFailure f) False
                 Right sols ->
                   conjoin
                     [ counterexample ("solution " ++ show (U.toList (solJoints s))) $
                         withinLimits 1e-9 ch (solJoints s)
                           && fst (residual (forward ch (solJoints s)) target) <= 1e-6
                           && snd (residual (forward ch (solJoints s)) target) <= 1e-6
                     | s <- sols ]
                     .&&. not (null sols)
                     .&&. (map solSeedDistance sols == foldr insertSorted [] (map solSeedDistance sols))

  describe "six-axis closed forms through the general model" $ do
    let sixAxis = [ "ur3", "ur5", "ur10", "ur5e", "ur10e", "abb-irb120", "abb-irb140", "abb-irb1600-6-1.2"
                  , "abb-irb6700-200-2.60", "puma560", "kuka-kr5-arc" ]
    forM_ sixAxis $ \name -> do
      it (name ++ ": uses the closed form") $
        case kinMethod (lib name) of
          ClosedFormSixAxis _ -> pure ()
          _ -> expectationFailure "another solver chosen"
      it (name ++ ": the original q is among the solutions, each labelled, exact and within limits") $ do
        let k = lib name
            ch = kinChain k
        property $ withMaxSuccess 300 $ forAllQ ch $ \q ->
          case solveIk defaultIkOptions k (forward ch q) Nothing of
            Left f -> counterexample (describeFailure f) False
            Right sols ->
              counterexample (show (map (U.toList . solJoints) sols)) $
                any (\s -> U.maximum (U.map abs (U.zipWith (-) (solJoints s) q)) < 1e-7) sols
                  && all (\s -> solPositionError s < 1e-9 && solRotationError s < 1e-9 && withinLimits 1e-9 ch (solJoints s)
                                 && maybe False ((== 3) . length) (solBranch s) && reachesByOracle name q s) sols

  describe "Dobot closed form" $ do
    forM_ ["dobot-magician-lite", "dobot-magician"] $ \name -> do
      it (name ++ ": uses the closed form") $
        case kinMethod (lib name) of
          ClosedFormDobot _ -> pure ()
          _ -> expectationFailure "another solver chosen"
      it (name ++ ": the original q is among the solutions, and every solution is exact") $ do
        let k = lib name
            ch = kinChain k
        property $ withMaxSuccess 500 $ forAllQ ch $ \q ->
          case solveIk defaultIkOptions k (forward ch q) Nothing of
            Left f -> counterexample (describeFailure f) False
            Right sols ->
              counterexample (show (map (U.toList . solJoints) sols)) $
                any (\s -> U.maximum (U.map abs (U.zipWith (-) (solJoints s) q)) < 1e-7) sols
                  && all (\s -> solPositionError s < 1e-9 && solRotationError s < 1e-9 && reachesByOracle name q s) sols
      it (name ++ ": a seed orders the solutions (nearest first)") $ do
        let k = lib name
            ch = kinChain k
        property $ withMaxSuccess 100 $ forAllQ ch $ \q ->
          case solveIk defaultIkOptions k (forward ch q) (Just q) of
            Left _ -> False
            Right (s : _) -> solSeedDistance s < 1e-7
            Right [] -> False

    let k = lib "dobot-magician-lite"
        ch = kinChain k
        Right g = dobotGeometry (chainRobot ch)
    it "seed 002's move to (300, −100, 0) mm at 50°: the report's formulas give one of the solutions" $ do
      -- the report's closed form (its Figure 22), with the data sheet's lengths in place of its
      -- inconsistent 30/60/90 mm: radial offset a1 + a5 = 54.72 mm. Its formulas measure the height
      -- from the shoulder to the end plate (no base height, no flange drop), so its z = 0 is our
      -- flange at 107 − 15 = 92 mm above the base frame.
      let (px, py, pz, vinkel) = (300, -100, 0, 50) :: (Double, Double, Double, Double)
          l2 = 150; l4 = 150
          theta1 = atan2 py px
          l6 = sqrt (px * px + py * py) - 20 - 34.72
          pz' = pz
          l7 = sqrt (pz' * pz' + l6 * l6)
          phi1 = atan2 pz' l6
          phi2 = acos ((l7 * l7 + l2 * l2 - l4 * l4) / (2 * l7 * l2))
          phi3 = acos ((l4 * l4 + l2 * l2 - l7 * l7) / (2 * l2 * l4))
          theta2 = pi / 2 - phi1 - phi2
          theta4 = pi / 2 + theta2 - phi3
          theta6 = deg vinkel - theta1
          -- RoboDK's data turn the flange by q1 − q4 about the vertical: its J4 counts the other way
          -- from the report's (see docs/kinematics.md), so the report's θ6 is −q4 here
          qReport = U.fromList [theta1, theta2, theta4, -theta6]
          -- so the report's angle (θ1 + θ6) is the flange's turn about the vertical from home
          target = levelTarget g (V3 0.3 (-0.1) 0.092) (deg vinkel)
      residual (forward ch qReport) target `shouldSatisfy` (\(a, b) -> a < 1e-12 && b < 1e-12)
      case solveIk defaultIkOptions k target Nothing of
        Left f -> expectationFailure (describeFailure f)
        Right sols -> do
          any (\s -> U.maximum (U.map abs (U.zipWith (-) (solJoints s) qReport)) < 1e-9) sols `shouldBe` True
          map (round . (* 1000) . (/ deg 1) . (U.! 0) . solJoints) sols `shouldSatisfy` all (== (-18435 :: Int))
      -- then the report reads the pose back, multiplies by its transformation(0, 0, 0, −100, 40, 40)
      -- (a translation in its tool frame, whose x and z are our flange's −x and −z) and moves there
      let m = forward ch qReport
          moved = compose m (trans 0.1 0.04 (-0.04))
          V3 x y z = translation moved
          phi = deg vinkel
          ex = 0.3 + cos phi * (-0.1) - sin phi * 0.04
          ey = -0.1 + sin phi * (-0.1) + cos phi * 0.04
      (abs (x - ex), abs (y - ey), abs (z - 0.132)) `shouldSatisfy` (\(a, b, c) -> a < 1e-12 && b < 1e-12 && c < 1e-12)
      case solveIk defaultIkOptions k moved Nothing of
        Left f -> expectationFailure (describeFailure f)
        Right sols -> do
          sols `shouldSatisfy` (not . null)
          forM_ sols $ \s -> do
            fst (residual (forward ch (solJoints s)) moved) `shouldSatisfy` (< 1e-9)
            -- the tool angle is kept: q1 − q4 is still 50°
            abs ((solJoints s U.! 0 - solJoints s U.! 3) - phi) `shouldSatisfy` (< 1e-9)
    it "seed 002's transformation example: (4, 2, 0) turned 30° about z and moved by (5, 2, 0) is (7.464, 5.732, 0)" $ do
      let V3 x y z = applyPoint (compose (trans 5 2 0) (rotZ (deg 30))) (V3 4 2 0)
      (abs (x - 7.464) < 1e-3, abs (y - 5.732) < 1e-3, z) `shouldBe` (True, True, 0)
    it "a target beyond reach says by how much" $
      case solveIk defaultIkOptions k (levelTarget g (V3 0.5 0 0.1) 0) Nothing of
        Left (BeyondReach d r) -> do
          r `shouldSatisfy` (\x -> abs (x - 0.3) < 1e-12)
          d `shouldSatisfy` (\x -> abs (x - sqrt ((0.5 - 0.05472) ** 2 + (0.1 - 0.092) ** 2)) < 1e-12)
        other -> expectationFailure (show other)
    it "a target at the shoulder (the elbow angle undetermined) is singular" $
      case solveIk defaultIkOptions k (levelTarget g (V3 (0.02 + 0.03472) 0 (0.107 - 0.015)) 0) Nothing of
        Left (Singular _) -> pure ()
        other -> expectationFailure (show other)
    it "a tilted target names the tilt" $
      case solveIk defaultIkOptions k (compose (levelTarget g (V3 0.2 0 0.1) 0) (rotX (deg 10))) Nothing of
        Left (OrientationUnreachable t) -> t `shouldSatisfy` (\x -> abs (x - deg 10) < 1e-9)
        other -> expectationFailure (show other)
    it "a pose reachable only outside the limits names the joint and the amount" $ do
      -- J2 at 85° is 5° past the Lite's limit (80°)
      let q = U.fromList [0, deg 85, deg 10, 0]
      case solveIk defaultIkOptions k (forward ch q) Nothing of
        Left f@(OutsideLimits sols) -> do
          any (any (\(j, v) -> j == "J2" && abs (v - deg 5) < 1e-9)) sols `shouldBe` True
          -- in the joint's unit: a revolute joint's in rad and degrees
          describeFailureFor (chainRobot ch) f `shouldSatisfy` isInfixOf "J2 above its maximum by 0.087266 rad (5.0000°)"
        other -> expectationFailure (show other)
    it "several solutions' limit misses are numbered one by one (they ran together as [..][..])" $ do
      let many = OutsideLimits [[("J2", deg 40), ("J4", deg (-35))], [("J2", deg (-111))]]
          one = OutsideLimits [[("J3", deg (-9)), ("J4", deg (-35))]]
      describeFailureFor (chainRobot ch) many `shouldBe`
        "every one of the 2 solutions breaks a joint limit: (1) J2 above its maximum by 0.698132 rad (40.0000°), J4 below its minimum by 0.610865 rad (35.0000°); (2) J2 below its minimum by 1.937315 rad (111.0000°)"
      describeFailureFor (chainRobot ch) one `shouldBe`
        "every solution breaks a joint limit: J3 below its minimum by 0.157080 rad (9.0000°), J4 below its minimum by 0.610865 rad (35.0000°)"
      describeFailure many `shouldSatisfy` isInfixOf "(1) J2 by 0.698132, J4 by -0.610865; (2) J2 by -1.937315"
    it "a search that did not converge gives its nearest pose's residual, and says when none was reached (not 'Infinity mm')" $ do
      describeFailure (NotConverged 0.166385 (deg 1.0416)) `shouldBe`
        "not converged: best residual 166.385 mm, 1.0416° (the nearest pose the search reached; the target may be out of reach at this orientation)"
      describeFailure (NotConverged 2e-5 (deg 0.01)) `shouldSatisfy` isInfixOf "best residual 0.02 mm, 0.0100° (the nearest pose the search reached, just outside the tolerance)"
      describeFailure (NotConverged (1 / 0) (1 / 0)) `shouldBe` "not converged: no pose was reached (no attempt of the search finished)"

  describe "numerical IK, all solutions" $
    it "UR5: several distinct solutions of one pose, each exact and within limits, nearest the seed first" $ do
      let k = lib "ur5"
          ch = kinChain k
          q = U.fromList [0.4, -1.1, 1.3, -0.7, 1.2, 0.5]
          t = forward ch q
      case solveIk defaultIkOptions {ikAllSolutions = True, ikMaxRestarts = 300} k t (Just q) of
        Left f -> expectationFailure (describeFailure f)
        Right sols -> do
          length sols `shouldSatisfy` (>= 4)
          solSeedDistance (head sols) `shouldSatisfy` (< 1e-4)
          forM_ sols $ \s -> do
            withinLimits 1e-9 ch (solJoints s) `shouldBe` True
            residual (forward ch (solJoints s)) t `shouldSatisfy` (\(a, b) -> a <= 1e-6 && b <= 1e-6)
          -- distinct: no two closer than 1e-4 rad
          and [seedDistance (solJoints a) (solJoints b) > 1e-4 | (i, a) <- zip [0 :: Int ..] sols, (j, b) <- zip [0 ..] sols, i < j] `shouldBe` True

  describe "numerical IK failures" $ do
    it "Panda (numerical): a target 2 m away is beyond reach" $ do
      let k = lib "franka-panda"
      case solveIk defaultIkOptions k (trans 2 0 0.5) Nothing of
        -- the bound is the chain's total length from the shoulder: above the data sheet's 0.855 m
        Left (BeyondReach d r) -> (d > r, r > 0.8 && r < 1.6) `shouldBe` (True, True)
        other -> expectationFailure (show other)
    it "UR5 (closed form): a target 2 m away is unreachable, by how far" $ do
      let k = lib "ur5"
      case solveIk defaultIkOptions k (trans 2 0 0.5) Nothing of
        -- the wrist point lies 2 m out less the last links; the arm reaches about 0.85 m
        Left (Unreachable _ d) -> d `shouldSatisfy` (\x -> x > 0.9 && x < 1.3)
        other -> expectationFailure (show other)
    it "Cobra 600: a pose needing the quill 0.3 m down (limit 0.21 m) names J3 and 0.09 m" $ do
      let k = lib "adept-cobra600"
          ch = kinChain k
          q = U.fromList [0.2, 0.4, 0.3, 0.1]
      case solveIk defaultIkOptions k (forward ch q) Nothing of
        Left f@(OutsideLimits (s : _)) -> do
          any (\(j, v) -> j == "J3" && abs (v - 0.09) < 1e-6) s `shouldBe` True
          -- a prismatic joint's in mm
          describeFailureFor (chainRobot ch) f `shouldSatisfy` isInfixOf "J3 above its maximum by 90.000 mm"
        other -> expectationFailure (show other)
    it "Cobra 600: a tilted tool (a SCARA cannot tilt) fails at once, naming the tilt" $ do
      let k = lib "adept-cobra600"
          ch = kinChain k
          t = compose (forward ch (U.fromList [0.2, 0.4, 0.1, 0.1])) (rotX 0.3)
      case solveIk defaultIkOptions {ikMaxRestarts = 20} k t Nothing of
        Left (OrientationUnreachable tilt) -> tilt `shouldSatisfy` (\x -> abs (x - 0.3) < 1e-9)
        other -> expectationFailure (show other)
    it "the orientation check applies to the SCARA only (its revolute axes are parallel)" $
      forM_ libraryChains $ \(name, ech) -> case ech of
        Left e -> expectationFailure (unlines e)
        Right ch -> (name, orientationTilt ch (forward ch (midLimits ch)) /= Nothing) `shouldBe` (name, name == "adept-cobra600")
    it "the orientation check: a pose the SCARA reaches is tilted by 0" $ do
      let ch = kinChain (lib "adept-cobra600")
      property $ withMaxSuccess 100 $ forAllQ ch $ \q ->
        let tilt = orientationTilt ch (forward ch q) in counterexample (show tilt) (maybe False (< 1e-9) tilt)

  describe "bad requests" $ do
    let k = lib "ur5"
        ch = kinChain k
        t = forward ch (U.replicate 6 0.3)
    it "a seed of the wrong length" $
      solveIk defaultIkOptions k t (Just (U.fromList [0, 0])) `shouldSatisfy` isInvalid
    it "a NaN in the seed" $
      solveIk defaultIkOptions k t (Just (U.fromList [0, 0, 0 / 0, 0, 0, 0])) `shouldSatisfy` isInvalid
    it "a NaN in the target" $
      solveIk defaultIkOptions k t {tx = 0 / 0} Nothing `shouldSatisfy` isInvalid
    it "a non-rigid target rotation" $
      solveIk defaultIkOptions k t {r00 = 2} Nothing `shouldSatisfy` isInvalid
    it "a zero quaternion" $
      solvePose defaultIkOptions k (Pose (V3 0.3 0 0.3) (Quat 0 0 0 0)) Nothing `shouldSatisfy` isInvalid
    it "an infinite position in a pose" $
      solvePose defaultIkOptions k (Pose (V3 (1 / 0) 0 0.3) (Quat 1 0 0 0)) Nothing `shouldSatisfy` isLeft
    it "the Dobot with a bad seed" $
      solveIk defaultIkOptions (lib "dobot-magician") t (Just (U.fromList [1])) `shouldSatisfy` isInvalid
  where
    isInvalid (Left (InvalidRequest (_ : _))) = True
    isInvalid _ = False
    insertSorted x [] = [x]
    insertSorted x (y : ys) = if x <= y then x : y : ys else y : insertSorted x ys
