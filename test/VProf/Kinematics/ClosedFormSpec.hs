{-# LANGUAGE BangPatterns, LambdaCase, ScopedTypeVariables #-}
-- | Closed-form IK (issue 13): the FK oracle against the reference files; recovery of
-- random joint vectors on every family robot of @robots.md@; solution counts against an
-- independent numerical count (regular, near-singular and IKFast-grid poses); labels,
-- wrapped variants, degenerate poses, and failures with reasons.
module VProf.Kinematics.ClosedFormSpec (spec) where

import Control.Monad (forM_, unless, when)
import Data.List (nub)
import Data.Maybe (fromMaybe, isJust)
import qualified Data.Vector.Unboxed as U
import System.Environment (lookupEnv)
import System.IO.Unsafe (unsafePerformIO)
import Data.List (isInfixOf)
import Test.Hspec
import Test.QuickCheck hiding (classify)
import Text.Read (readMaybe)

import Support.DhOracle
import Support.NumericIk
import Support.DhReference
import Support.Robots
import VProf.Kinematics.ClosedForm

-- | Random joint vectors per robot for the recovery property: @VPROF_CF_RECOVERY@, default 10 000.
recoveryCount :: Int
recoveryCount = unsafePerformIO $ do
  v <- lookupEnv "VPROF_CF_RECOVERY"
  pure (fromMaybe 10000 (v >>= readMaybe))
{-# NOINLINE recoveryCount #-}

matToPose :: Mat4 -> Pose
matToPose m = fromMaybe (error "4x4") (poseFromRowMajor (concat m))

poseToMat :: Pose -> Mat4
poseToMat = rowsToMatrix . poseToRowMajor

fkFix :: Fixture -> [Double] -> Mat4
fkFix f = fkOracle (fixtureRows f) ident4 ident4

genQ :: SixAxisDh -> Gen [Double]
genQ dh = mapM (\j -> choose (sdLower dh U.! j, sdUpper dh U.! j)) [0 .. 5]

withinLimits :: SixAxisDh -> U.Vector Double -> Bool
withinLimits dh q = U.and (U.zipWith3 (\l h x -> x >= l && x <= h) (sdLower dh) (sdUpper dh) q)

maxDiff :: [Double] -> [Double] -> Double
maxDiff a b = maximum (zipWith (\x y -> abs (x - y)) a b)

refNames :: [String]
refNames = ["Puma560", "UR3", "UR5", "UR10", "IRB140", "KR5"]

refDh :: RefRobot -> SixAxisDh
refDh r = SixAxisDh
  { sdA = v (map rowA rows), sdAlpha = v (map rowAlpha rows), sdD = v (map rowD rows)
  , sdOffset = v (map rowOffset rows)
  , sdLower = v (map head (refQlim r)), sdUpper = v (map (!! 1) (refQlim r))
  , sdBase = matToPose (rowsToMatrix (refBase r)), sdTool = matToPose (rowsToMatrix (refTool r)) }
  where rows = refRows r; v = U.fromListN 6

-- | The wrist point of a family (o4 for the spherical wrist, o5 for three parallel axes), by the oracle.
wristPointOracle :: Family -> Fixture -> [Double] -> [Double]
wristPointOracle fam f q =
  let frames = fkFrames (fixtureRows f) ident4 q
      m = frames !! (case fam of SphericalWrist -> 4; ThreeParallel -> 5)
  in [m !! i !! 3 | i <- [0 .. 2]]

-- | Do a numerical solution and a closed-form one describe the same solution? Equal
-- modulo 2π; on a wrist singularity only the joints the closed form fixes are compared
-- (q1–q3, q5 for the spherical wrist; q1, q5 for three parallel axes).
sameSolution :: Family -> [Double] -> Solution -> Bool
sameSolution fam n s =
  let c = U.toList (solQ s)
      idx | WristSingular `elem` solSingular s || abs (sin (c !! 4)) < 1e-6 = case fam of
                SphericalWrist -> [0, 1, 2, 4]
                ThreeParallel -> [0, 4]
          | otherwise = [0 .. 5]
      -- at a double root (elbow stretched or folded, shoulders coinciding) the numerical solutions converge only
      -- to about the square root of their residual
      tol = if any (`elem` solSingular s) [ElbowStretched, ShoulderSingular] then 1e-3 else 1e-5
  in angleDist [n !! i | i <- idx] [c !! i | i <- idx] < tol

-- | The closed-form principal solutions and the numerical ones match one to one (as classes).
countsAgree :: Fixture -> Mat4 -> Expectation
countsAgree f target = do
  let dh = fixtureDh f
      Right solver = solverFor dh
      fam = solverFamily solver
  case solvePrincipal solver (matToPose target) of
    Left e -> expectationFailure ("closed form failed: " ++ show e)
    Right cf -> do
      let nums = numericSolutions 1000 (fixtureRows f) target
          unmatchedN = [n | n <- nums, not (any (sameSolution fam n) cf)]
          unmatchedC = [s | s <- cf, not (any (\n -> sameSolution fam n s) nums)]
      forM_ cf $ \s -> poseError (fkFix f (U.toList (solQ s))) target `shouldSatisfy` (< 1e-10)
      unless (null unmatchedN && null unmatchedC) $
        expectationFailure (fxName f ++ ": numerical " ++ show (length nums) ++ ", closed form " ++ show (length cf)
          ++ "; numerical only " ++ show unmatchedN ++ "; closed form only " ++ show (map solQ unmatchedC))

-- | A deterministic pseudo-random joint vector (within limits) from an index.
pick :: SixAxisDh -> Int -> [Double]
pick dh k = [ let l = sdLower dh U.! j; h = sdUpper dh U.! j
                  u = fromIntegral ((k * 7919 + j * 104729 + k * j * 31) `mod` 997) / 997
              in l + (h - l) * (0.05 + 0.9 * u) | j <- [0 .. 5] ]

-- | A target whose wrist point is moved radially to distance |K| + eps from axis 1
-- (|K| the smallest distance the arm allows), keeping the orientation of FK(q).
nearAxisTarget :: Family -> Fixture -> Double -> [Double] -> Mat4
nearAxisTarget fam f eps q =
  let dh = fixtureDh f
      a i = sdA dh U.! i; d i = sdD dh U.! i; al i = sdAlpha dh U.! i
      m = fkFix f q
      rcol j = [m !! i !! j | i <- [0 .. 2]]
      dz = case fam of SphericalWrist -> d 1 + d 2 + cos (al 2) * d 3
                       ThreeParallel -> d 1 + d 2 + d 3 + cos (al 3) * d 4
      [wx, wy, wz] = wristPointOracle fam f q
      k = (cos (al 0) * (wz - d 0) - dz) / sin (al 0)
      rad = abs k + eps
      phi = atan2 wy wx
      w' = [rad * cos phi, rad * sin phi, wz]
      -- tool point = wrist point + d6 z + a6 x
      p' = zipWith3 (\w z x -> w + d 5 * z + a 5 * x) w' (rcol 2) (rcol 0)
  in [take 3 (m !! i) ++ [p' !! i] | i <- [0 .. 2]] ++ [[0, 0, 0, 1]]


-- | A pose of any rotation (a normalised random quaternion) at a position drawn by the given
-- generator, as a 4×4 matrix.
poseAt :: Gen (Double, Double, Double) -> Gen [[Double]]
poseAt position = do
  let unit = choose (-1, 1)
  (w, x, y, z) <- (,,,) <$> unit <*> unit <*> unit <*> unit
  (px, py, pz) <- position
  let n = sqrt (w * w + x * x + y * y + z * z) `max` 1e-9
      (a, b, c, d) = (w / n, x / n, y / n, z / n)
  pure [ [1 - 2 * (c * c + d * d), 2 * (b * c - a * d), 2 * (b * d + a * c), px]
       , [2 * (b * c + a * d), 1 - 2 * (b * b + d * d), 2 * (c * d - a * b), py]
       , [2 * (b * d - a * c), 2 * (c * d + a * b), 1 - 2 * (b * b + c * c), pz]
       , [0, 0, 0, 1] ]
spec :: Spec
spec = do
  describe "FK oracle (textbook standard DH, independent of the solver)" $
    forM_ refNames $ \name -> it ("reproduces every case of " ++ name ++ ".json to 1e-9") $ do
      r <- loadReference name
      refConvention r `shouldBe` "standard"
      refTypes r `shouldBe` replicate 6 "R"
      length (refCases r) `shouldSatisfy` (>= 40)
      forM_ (refCases r) $ \c ->
        poseError (fkOracle (refRows r) (rowsToMatrix (refBase r)) (rowsToMatrix (refTool r)) (caseQ c))
                  (rowsToMatrix (caseT c)) `shouldSatisfy` (< 1e-9)

  describe "the numerical count's own FK" $
    it "agrees with the oracle" $
      forM_ fixtures $ \f -> forM_ [1 .. 20] $ \k -> do
        let q = pick (fixtureDh f) k
        poseError (m34ToMat (fastFk (fixtureRows f) q)) (fkFix f q) `shouldSatisfy` (< 1e-12)

  describe "closed form on the reference files" $
    forM_ refNames $ \name -> it ("recovers every case of " ++ name ++ ".json from its pose") $ do
      r <- loadReference name
      let dh = refDh r
      classify dh `shouldSatisfy` isJust
      let Right solver = solverFor dh
      forM_ (refCases r) $ \c -> do
        poseError (poseToMat (forwardPose dh (U.fromList (caseQ c)))) (rowsToMatrix (caseT c)) `shouldSatisfy` (< 1e-9)
        case solvePrincipal solver (matToPose (rowsToMatrix (caseT c))) of
          Left e -> expectationFailure (show e)
          Right sols -> do
            any (\s -> angleDist (U.toList (solQ s)) (caseQ c) < 1e-6) sols `shouldBe` True
            forM_ sols $ \s -> poseError (fkOracle (refRows r) ident4 ident4 (U.toList (solQ s))) (rowsToMatrix (caseT c))
                                 `shouldSatisfy` (< 1e-10)

  describe "classify (from the DH table only)" $ do
    forM_ fixtures $ \f -> it (fxName f) $
      classify (fixtureDh f) `shouldBe` Just (if take 2 (fxName f) == "UR" then ThreeParallel else SphericalWrist)
    it "rejects a UR5 with α3 = 5°, an IRB 140 with a4 = 1 cm, a wrist with d5 ≠ 0, axes 1 ∥ 2" $ do
      let ur5 = fixtureDh (fixtureByName "UR5")
          irb = fixtureDh (fixtureByName "IRB 140")
          set v i x = v U.// [(i, x)]
      classify ur5 { sdAlpha = set (sdAlpha ur5) 2 (5 * pi / 180) } `shouldBe` Nothing
      classify irb { sdA = set (sdA irb) 3 0.01 } `shouldBe` Nothing
      classify irb { sdD = set (sdD irb) 4 0.05 } `shouldBe` Nothing
      classify irb { sdAlpha = set (sdAlpha irb) 0 0 } `shouldBe` Nothing
      solveAll irb { sdAlpha = set (sdAlpha irb) 0 0 } identityPose `shouldSatisfy` either (\case UnknownFamily _ -> True; _ -> False) (const False)

  describe ("recovery: " ++ show recoveryCount ++ " random q within limits per robot") $
    forM_ fixtures $ \f -> it (fxName f ++ ": q among the solutions, every solution reproduces the pose to 1e-10 and lies within limits") $ do
      let dh = fixtureDh f
          rows = fixtureRows f
          Right solver = solverFor dh
      property $ withMaxSuccess recoveryCount $ forAll (genQ dh) $ \q ->
        let target = fkFix f q
        in case (solveWith solver (matToPose target), solvePrincipal solver (matToPose target)) of
             (Left e, _) -> counterexample (show e) False
             (_, Left e) -> counterexample (show e) False
             (Right sols, Right prin) ->
               let principal = map solQ prin
                   -- the strict FK of the numerical count (checked against the oracle above)
                   errs = [poseError (m34ToMat (fastFk rows (U.toList p))) target | p <- principal]
                   qv = U.fromList q
                   hit = [s | s <- sols, U.maximum (U.map abs (U.zipWith (-) (solQ s) qv)) < 1e-6]
                   isVariant s = any (\p -> U.all (\x -> abs (wrapAngle x) < 1e-9) (U.zipWith (-) p (solQ s))) principal
               in counterexample (show (map solQ sols, errs)) $
                    not (null hit)
                    .&&. all (< 1e-10) errs
                    .&&. all isVariant sols
                    .&&. all (withinLimits dh . solQ) sols
                    .&&. (branchOf dh (U.fromList q) === Just (solBranch (head hit)))

  describe "branches" $ do
    it "text and cfx forms round-trip" $
      forM_ allBranches $ \b -> do
        parseBranch (branchText b) `shouldBe` Just b
        parseBranch ("cfx" ++ show (branchCfx b)) `shouldBe` Just b
    forM_ fixtures $ \f -> it (fxName f ++ ": eight distinct labels at a regular pose, each equal to branchOf, selectBranch picks one") $ do
      let dh = fixtureDh f
          Right solver = solverFor dh
          eight = [(q, sols) | k <- [1 .. 60], let q = pick dh k
                             , Right sols <- [solvePrincipal solver (matToPose (fkFix f q))], length sols == 8]
      eight `shouldSatisfy` (not . null)
      let (q, sols) = head eight
      length (nub (map solBranch sols)) `shouldBe` 8
      forM_ sols $ \s -> branchOf dh (solQ s) `shouldBe` Just (solBranch s)
      forM_ allBranches $ \b -> length (selectBranch b sols) `shouldBe` 1
      fmap solBranch (nearestInBranch (Branch ShoulderLeft ElbowDown WristFlip) (U.fromList q) sols)
        `shouldBe` Just (Branch ShoulderLeft ElbowDown WristFlip)

  describe "labels on the controller's terms" $
    it "an ABB arm at home (q5 > 0) is RUN, cfx 0; with q5 < 0, RUF, cfx 1" $
      forM_ (map fixtureByName ["IRB 120", "IRB 140", "IRB 1600", "IRB 6700"]) $ \f -> do
        let dh = fixtureDh f
        fmap branchText (branchOf dh (U.fromList [0, 0, 0, 0, 0.3, 0])) `shouldBe` Just "RUN"
        fmap branchCfx (branchOf dh (U.fromList [0, 0, 0, 0, -0.3, 0])) `shouldBe` Just 1

  describe "wrapped variants" $
    forM_ (map fixtureByName ["UR5", "IRB 140", "KR5 arc"]) $ \f -> it (fxName f ++ ": every q + 2πk within the limits, and no other") $ do
      let dh = fixtureDh f
          Right solver = solverFor dh
      forM_ [1 .. 20] $ \k -> do
        let target = matToPose (fkFix f (pick dh k))
            Right principal = solvePrincipal solver target
            nVariants s = product [ length [() | m <- [-3 .. 3 :: Int], let y = x + 2 * pi * fromIntegral m
                                                , y >= sdLower dh U.! j, y <= sdUpper dh U.! j]
                                  | (j, x) <- zip [0 ..] (U.toList (solQ s)) ]
        case solveWith solver target of
          Right sols -> do
            length sols `shouldBe` sum (map nVariants principal)
            length (nub (map (U.toList . solQ) sols)) `shouldBe` length sols
          Left (OutsideLimits _ _ _) -> sum (map nVariants principal) `shouldBe` 0
          Left e -> expectationFailure (show e)
      when (fxName f == "UR5") $ do
        let Right sols = solveWith solver (matToPose (fkFix f (pick dh 1)))
        length sols `shouldBe` 8 * 64

  describe "solution counts against a numerical count (LM from 1000 seeds)" $
    forM_ fixtures $ \f -> do
      let dh = fixtureDh f
          Just fam = classify dh
      it (fxName f ++ ": regular poses") $
        forM_ [11, 12] $ \k -> countsAgree f (fkFix f (pick dh k))
      it (fxName f ++ ": q5 near 0 (1e-3 rad)") $
        countsAgree f (fkFix f (take 4 (pick dh 5) ++ [1e-3, 0.7]))
      it (fxName f ++ ": wrist point 1 mm from its closest approach to axis 1") $ do
        let targets = [t | k <- [20 .. 40], let t = nearAxisTarget fam f 1e-3 (pick dh k)
                         , Right (_ : _) <- [solvePrincipal (either (error . show) id (solverFor dh)) (matToPose t)]]
        length targets `shouldSatisfy` (> 0)
        countsAgree f (head targets)
      it (fxName f ++ ": IKFast grid (every joint in 0, ±π/2, π), 6 samples") $
        forM_ [0 .. 5 :: Int] $ \k -> do
          let grid = [0, pi / 2, -pi / 2, pi]
              q = [grid !! ((k * 3 + j * (k + 1) + j * j) `mod` 4) | j <- [0 .. 5]]
              target = fkFix f q
              Right solver = solverFor dh
          case solvePrincipal solver (matToPose target) of
            Right sols -> any (\s -> sameSolution fam q s) sols `shouldBe` True
            Left e -> expectationFailure (show e)
          countsAgree f target

  describe "degenerate poses: a documented choice, never NaN" $ do
    it "wrist singular (q5 = 0): q4 = 0 kept on the spherical wrist, q6 = 0 on UR; pose reproduced" $
      forM_ fixtures $ \f -> do
        let dh = fixtureDh f
            Right solver = solverFor dh
            q = take 4 (pick dh 7) ++ [0, 0.3]
            target = fkFix f q
            Right sols = solvePrincipal solver (matToPose target)
            sing = [s | s <- sols, WristSingular `elem` solSingular s]
        sing `shouldSatisfy` (not . null)
        forM_ sols $ \s -> do
          U.all (\x -> not (isNaN x)) (solQ s) `shouldBe` True
          poseError (fkFix f (U.toList (solQ s))) target `shouldSatisfy` (< 1e-10)
        forM_ sing $ \s -> (if classify dh == Just SphericalWrist then solQ s U.! 3 else solQ s U.! 5) `shouldBe` 0
    it "wrist centre on axis 1 (IRB 120): q1 = 0 and q1 = π, pose reproduced" $ do
      let f = fixtureByName "IRB 120"
          dh = fixtureDh f
          Right solver = solverFor dh
          target = nearAxisTarget SphericalWrist f 0 [0, 0.2, -0.3, 0.4, 0.9, -0.5]
          Right sols = solvePrincipal solver (matToPose target)
          -- the wrist centre, tool point − d6·z (d6 = 0.072 m), lies on axis 1
          wc i = target !! i !! 3 - 0.072 * (target !! i !! 2)
      abs (wc 0) + abs (wc 1) `shouldSatisfy` (< 1e-12)
      sols `shouldSatisfy` (not . null)
      forM_ sols $ \s -> do
        solSingular s `shouldSatisfy` elem ShoulderSingular
        poseError (fkFix f (U.toList (solQ s))) target `shouldSatisfy` (< 1e-10)
      nub (map (\s -> round (abs (solQ s U.! 0) * 1e6) :: Int) sols) `shouldBe` [0, round (pi * 1e6 :: Double)]
    it "elbow stretched (UR5 q3 = 0, IRB 140 θ3 along the forearm): the pair returned once, pose reproduced" $
      forM_ [("UR5", [0.3, -1.0, 0, 0.5, 0.8, 0.2]), ("IRB 140", [0.3, 0.2, atan2 0.380 0 - pi, 0.5, 0.8, 0.2])] $ \(n, q) -> do
        let f = fixtureByName n
            dh = fixtureDh f
            Right solver = solverFor dh
            target = fkFix f q
            Right sols = solvePrincipal solver (matToPose target)
            stretched = [s | s <- sols, ElbowStretched `elem` solSingular s]
        stretched `shouldSatisfy` (not . null)
        any (\s -> angleDist (U.toList (solQ s)) q < 1e-6) sols `shouldBe` True
        forM_ sols $ \s -> poseError (fkFix f (U.toList (solQ s))) target `shouldSatisfy` (< 1e-9)

  describe "arbitrary poses (random rotation, position within ±1.5 reach): never NaN" $
    forM_ fixtures $ \f -> it (fxName f ++ ": every answer reproduces its pose, or says by how much it is out of reach") $ do
      let dh = fixtureDh f
          Right solver = solverFor dh
          reach = sum (map abs (fxA f)) + sum (map abs (fxD f))
          coord = choose (-1.5 * reach, 1.5 * reach)
          genPose = poseAt ((,,) <$> coord <*> coord <*> coord)
      property $ withMaxSuccess 2000 $ forAll genPose $ \target ->
        case solvePrincipal solver (matToPose target) of
          Left (OutOfReach _ d) -> counterexample (show d) (d /= 0 && abs d < 3 * reach)
          Left e -> counterexample (show e) False
          Right sols -> conjoin [ counterexample (show (solQ s)) (poseError (fkFix f (U.toList (solQ s))) target < 1e-9)
                                | s <- sols ]

  describe "out of reach is confirmed by the independent numerical IK (Support.NumericIk)" $
    forM_ fixtures $ \f -> it (fxName f ++ ": no pose it calls out of reach is reached from 15 seeds (positions within the ball of radius Σ|a|+Σ|d|, any rotation)") $ do
      let dh = fixtureDh f
          Right solver = solverFor dh
          reach = sum (map abs (fxA f)) + sum (map abs (fxD f))
          inBall = suchThat ((,,) <$> choose (-reach, reach) <*> choose (-reach, reach) <*> choose (-reach, reach))
                            (\(x, y, z) -> x * x + y * y + z * z <= reach * reach)
          genPose = poseAt inBall
      property $ withMaxSuccess 60 $ forAll genPose $ \target ->
        case solvePrincipal solver (matToPose target) of
          Left (OutOfReach _ _) -> let found = numericSolutions 15 (fixtureRows f) target
                                   in label "out of reach" $ counterexample ("reached by " ++ show found) (null found)
          Left e -> counterexample (show e) False
          Right _ -> label "reached" True

  describe "failures say why" $ do
    it "a pose out of reach gives OutOfReach with the distance, never NaN" $
      forM_ fixtures $ \f -> do
        let far = matToPose ([[1, 0, 0, 5], [0, 1, 0, 5], [0, 0, 1, 5], [0, 0, 0, 1]])
        case solveAll (fixtureDh f) far of
          Left (OutOfReach _ d) -> d `shouldSatisfy` (\x -> x > 1 && x < 10)
          other -> expectationFailure (show other)
    it "a wrist point inside the UR5's shoulder cylinder (radius d4 = 109.15 mm about axis 1) is too close, by the radius less its distance, not too far" $
      forM_ [0, 0.05, 0.1] $ \r -> do
        -- tool pointing down: the wrist point is the target raised by d6
        let target = matToPose [[1, 0, 0, r], [0, -1, 0, 0], [0, 0, -1, 0.3], [0, 0, 0, 1]]
        case solveAll (fixtureDh (fixtureByName "UR5")) target of
          Left (OutOfReach what d) -> do
            d `shouldSatisfy` (\x -> abs (x + (0.10915 - r)) < 1e-9)
            what `shouldSatisfy` ("closer" `isInfixOf`)
          other -> expectationFailure (show other)
    it "a NaN in the target gives BadTarget" $
      solveAll (fixtureDh (fixtureByName "UR5")) (matToPose [[0 / 0, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0.5], [0, 0, 0, 1]])
        `shouldSatisfy` either (\case BadTarget _ -> True; _ -> False) (const False)
    it "solutions all outside tight limits give OutsideLimits with the joint and the miss" $ do
      let f = fixtureByName "IRB 140"
          dh = (fixtureDh f) { sdLower = U.replicate 6 0.1, sdUpper = U.replicate 6 0.2 }
      case solveAll dh (matToPose (fkFix f [0, 0, 0, 0, 0.5, 0])) of
        Left (OutsideLimits n j d) -> do
          n `shouldSatisfy` (> 0)
          j `shouldSatisfy` (\x -> x >= 1 && x <= 6)
          d `shouldSatisfy` (> 0)
        other -> expectationFailure (show other)
    it "base and tool transforms are honoured" $ do
      let f = fixtureByName "IRB 140"
          base = [[0, -1, 0, 0.5], [1, 0, 0, -0.2], [0, 0, 1, 0.1], [0, 0, 0, 1]]
          tool = [[1, 0, 0, 0.01], [0, 0, -1, 0.02], [0, 1, 0, 0.15], [0, 0, 0, 1]]
          dh = (fixtureDh f) { sdBase = matToPose base, sdTool = matToPose tool }
          q = pick dh 4
          target = fkOracle (fixtureRows f) base tool q
          Right sols = solveAll dh (matToPose target)
      any (\s -> maxDiff (U.toList (solQ s)) q < 1e-6) sols `shouldBe` True
      forM_ sols $ \s -> poseError (fkOracle (fixtureRows f) base tool (U.toList (solQ s))) target `shouldSatisfy` (< 1e-10)
