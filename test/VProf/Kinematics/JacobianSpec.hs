-- | The geometric Jacobian against central finite differences of forward kinematics, for every
-- library robot; manipulability and condition number at known configurations.
module VProf.Kinematics.JacobianSpec (spec) where

import Control.Monad (forM_)
import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import Support.Gen
import VProf.Kinematics
import VProf.Kinematics.Library

-- | Column k by central differences: linear velocity of the tool origin, angular velocity from
-- log(R(q+h)·R(q−h)ᵀ)/2h.
numericColumn :: Chain -> U.Vector Double -> Int -> [Double]
numericColumn ch q k =
  let h = 1e-6
      qp = q U.// [(k, q U.! k + h)]
      qm = q U.// [(k, q U.! k - h)]
      tp = forward ch qp
      tm = forward ch qm
      V3 vx vy vz = v3Scale (1 / (2 * h)) (v3Sub (translation tp) (translation tm))
      rel = compose tp (inverse tm) 
      V3 wx wy wz = v3Scale (1 / (2 * h)) (rotationLog rel {tx = 0, ty = 0, tz = 0})
  in [vx, vy, vz, wx, wy, wz]

spec :: Spec
spec = do
  describe "jacobian" $ do
    forM_ libraryChains $ \(name, ech) -> it (name ++ ": agrees with finite differences") $
      case ech of
        Left e -> property (counterexample (unlines e) False)
        Right ch -> property $ forAllQ ch $ \q ->
          let (t, j) = jacobian ch q
              n = chainDof ch
              worst = maximum [abs (j U.! (6 * k + r) - c) | k <- [0 .. n - 1], (r, c) <- zip [0 ..] (numericColumn ch q k)]
          in counterexample ("worst " ++ show worst) (worst < 1e-6 && t == forward ch q)

  describe "manipulability and condition number" $ do
    it "UR5 fully stretched (q2 = q3 = 0: elbow straight) is singular" $ do
      let Right r = lookupRobot "ur5"
          ch = compile r
          (_, j) = jacobian ch (U.fromList [0, 0, 0, 0, 0.4, 0])
      manipulability 6 j `shouldSatisfy` (< 1e-9)
      conditionNumber 6 j `shouldSatisfy` (> 1e8)
    it "UR5 at an elbow-bent pose is well conditioned, and the figures are invariant to joint 1" $ do
      let Right r = lookupRobot "ur5"
          ch = compile r
          q = U.fromList [0, -1.2, 1.5, -0.6, 1.3, 0.2]
          (_, j) = jacobian ch q
          (_, j') = jacobian ch (q U.// [(0, 2.1)])
      manipulability 6 j `shouldSatisfy` (> 1e-3)
      conditionNumber 6 j `shouldSatisfy` (< 1e3)
      abs (manipulability 6 j - manipulability 6 j') `shouldSatisfy` (< 1e-12)
    it "manipulability is the product of the singular values and equals √det(J·Jᵀ) for a six-axis arm" $ do
      let Right r = lookupRobot "abb-irb140"
          ch = compile r
          (_, j) = jacobian ch (U.fromList [0.2, 0.3, -0.5, 0.7, 0.9, -0.4])
          rows = jacobianRows 6 j
          jjt = [[sum (zipWith (*) a b) | b <- rows] | a <- rows]
      abs (manipulability 6 j - sqrt (det jjt)) `shouldSatisfy` (< 1e-9)
    it "manipulabilityQr is 0 at the UR5's stretched singularity too" $ do
      let Right ur5 = lookupRobot "ur5"
          (_, js) = jacobian (compile ur5) (U.fromList [0, 0, 0, 0, 0.4, 0])
      manipulabilityQr 6 js `shouldSatisfy` (< 1e-9)
    forM_ libraryChains $ \(name, ech) -> case ech of
      Left _ -> pure ()
      Right ch -> it (name ++ ": manipulabilityQr equals manipulability to 1e-12 at random q") $
        property $ withMaxSuccess 100 $ forAllQ ch $ \q ->
          let (_, j) = jacobian ch q
              n = chainDof ch
          in counterexample (show (manipulability n j, manipulabilityQr n j))
               (abs (manipulability n j - manipulabilityQr n j) <= 1e-12 * (1 + manipulability n j))
    forM_ libraryChains $ \(name, ech) -> case ech of
      Left _ -> pure ()
      Right ch -> it (name ++ ": smallestSingularValueAbove agrees with the SVD at random q and thresholds either side of σ_min") $
        property $ withMaxSuccess 100 $ forAllQ ch $ \q -> forAll (choose (-6, 0 :: Double)) $ \e ->
          let (_, j) = jacobian ch q
              n = chainDof ch
              sv = singularValues n j
              smin = minimum sv
              scale = maximum sv
              -- thresholds 10^e (1e-6 .. 1) and just either side of σ_min (0.1 % of σ_max apart)
              ts = [10 ** e, smin + 1e-3 * scale, max 0 (smin - 1e-3 * scale)]
              clear t = abs (smin - t) > 1e-6 * scale
          in conjoin [ counterexample (show (t, smin, smallestSingularValueAbove n j t))
                         (smallestSingularValueAbove n j t == (smin > t)) | t <- ts, clear t ]
    it "smallestSingularValueAbove is False at the UR5's stretched singularity for any t > 0" $ do
      let Right ur5 = lookupRobot "ur5"
          (_, js) = jacobian (compile ur5) (U.fromList [0, 0, 0, 0, 0.4, 0])
      map (smallestSingularValueAbove 6 js) [1e-6, 1e-3, 1] `shouldBe` [False, False, False]
  where
    det :: [[Double]] -> Double
    det [[a]] = a
    det m = sum [(-1) ^ i * head row * det (minor i) | (i, row) <- zip [0 :: Int ..] m]
      where minor i = [tail r | (k, r) <- zip [0 ..] m, k /= i]
