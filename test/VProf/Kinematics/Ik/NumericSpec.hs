-- | The numerical solver's step and its budget: the Levenberg–Marquardt step in both its forms
-- against a singular-value oracle (hmatrix), over Jacobians of wide scales, dampings and masks of
-- frozen joints; a chain of a thousand joints is solved (checked by forward kinematics) and its
-- wall-time budget holds when no solution exists.
module VProf.Kinematics.Ik.NumericSpec (spec) where

import Control.Monad (forM_)
import Data.List (isInfixOf)
import qualified Data.Vector.Unboxed as U
import GHC.Clock (getMonotonicTimeNSec)
import qualified Numeric.LinearAlgebra as LA
import Test.Hspec
import Test.QuickCheck

import Support.Gen (genQ, libraryChains, planarSnake, snake)
import VProf.Kinematics
import VProf.Kinematics.Ik.Numeric (Wrist (..), lmStepDual, lmStepPrimal, reachBound, refineOnto, solveNumericIO, wristCheck, wrists)
import Support.PlanChecker (oracleTcpMatrix)
import VProf.Kinematics.Library (libraryRobots)

-- | δ = V·diag(σ/(σ² + λ))·Uᵀ·e for J with its masked columns zeroed: the damped least-squares
-- step from the singular values, independent of either normal-equation form; with it the
-- condition numbers of the two forms' matrices, (σ₁² + λ)/(σ_m² + λ) with m = 6 for JJᵀ + λI and
-- m = n for JᵀJ + λI (σ_m = 0 past the rank).
oracleStep :: Int -> U.Vector Double -> [Double] -> Double -> U.Vector Bool -> ([Double], Double, Double)
oracleStep n j e lam mask =
  let jm = LA.build (6, n) (\r k -> let r' = round r; k' = round k in if mask U.! k' then 0 else j U.! (6 * k' + r')) :: LA.Matrix Double
      (u, s, v) = LA.svd jm
      ut = LA.tr u
      sv = LA.toList s
      c = LA.toList (ut LA.#> LA.fromList e)
      w = zipWith (\si ci -> si * ci / (si * si + lam)) sv c
      vk = LA.takeColumns (length sv) v
      sigma m = if m <= length sv then sv !! (m - 1) else 0
      kappa m = (sigma 1 ^ (2 :: Int) + lam) / (sigma m ^ (2 :: Int) + lam)
  in (LA.toList (vk LA.#> LA.fromList w), kappa 6, kappa n)

-- | The damping the step uses: the one asked, at least 1e-13 of the trace of JᵀJ (the sum of the
-- squares of J's unmasked entries), which keeps the normal equations' condition number within
-- what the factorisation resolves (its contract, 'lmStep').
floored :: Int -> U.Vector Double -> Double -> U.Vector Bool -> Double
floored n j lam mask = max lam (1e-13 * sum [ (j U.! (6 * k + r)) ^ (2 :: Int) | k <- [0 .. n - 1], not (mask U.! k), r <- [0 .. 5] ])

data Case = Case Int (U.Vector Double) [Double] Double (U.Vector Bool)

instance Show Case where
  show (Case n j e lam mask) =
    "n = " ++ show n ++ ", λ = " ++ show lam ++ ", e = " ++ show e ++ ", mask = " ++ show (U.toList mask)
      ++ ", J = " ++ show (U.toList j)

-- | Jacobians of 1 to 60 columns whose entries span twelve decades (a column's scale is a
-- lever arm from a millimetre to a kilometre, or a rotation axis), errors from a micrometre to
-- ten metres, dampings from 1e-12 to 1e3, a few columns masked.
genCase :: Int -> Int -> Gen Case
genCase nlo nhi = do
  n <- choose (nlo, nhi)
  cols <- vectorOf n $ do
    sc <- (10 **) <$> choose (-3, 3)
    vectorOf 6 ((* sc) <$> choose (-1, 1))
  e <- vectorOf 6 ((\m x -> x * 10 ** m) <$> choose (-6, 1) <*> choose (-1, 1))
  lam <- (10 **) <$> choose (-12, 3)
  mask <- U.fromList <$> vectorOf n (frequency [(5, pure False), (1, pure True)])
  pure (Case n (U.fromList (concat cols)) e lam mask)

-- | Jacobians of less than full rank, of 1 to 30 columns in a random subspace of 1 to 5
-- dimensions, with columns up to a kilometre's lever arm and dampings from 1e-16 to 1e-8: JᵀJ +
-- λI (or JJᵀ + λI) is singular to rounding, the case of a solve near a singular configuration.
genDeficient :: Gen Case
genDeficient = do
  n <- choose (1, 30)
  rank <- choose (1, 5)
  basis <- vectorOf rank (vectorOf 6 (choose (-1, 1)))
  cols <- vectorOf n $ do
    sc <- (10 **) <$> choose (0, 3)
    ws <- vectorOf rank (choose (-1, 1))
    pure [ sc * sum (zipWith (*) ws [ b !! r | b <- basis ]) | r <- [0 .. 5] ]
  e <- vectorOf 6 ((\m x -> x * 10 ** m) <$> choose (-6, 1) <*> choose (-1, 1))
  lam <- (10 **) <$> choose (-16, -8)
  mask <- U.fromList <$> vectorOf n (frequency [(5, pure False), (1, pure True)])
  pure (Case n (U.fromList (concat cols)) e lam mask)

-- | A step δ that any damping λ > 0 allows: finite, zero at the masked joints, and no worse in
-- the linear model than no step, |J·δ − e| ≤ |e| (δ minimises |J·δ − e|² + λ|δ|², which is
-- |e|² at δ = 0), to rounding of J·δ.
sound :: Case -> U.Vector Double -> Property
sound (Case n j e _ mask) d =
  counterexample ("step " ++ show (U.toList d) ++ "\n|Jδ − e| = " ++ show resid ++ ", |e| = " ++ show en) $
    U.all (\x -> not (isNaN x || isInfinite x)) d
      .&&. U.and (U.zipWith (\m x -> not m || x == 0) mask d)
      .&&. resid <= en + 1e-12 * jn * dn
  where
    jd = [ sum [ j U.! (6 * k + r) * d U.! k | k <- [0 .. n - 1] ] | r <- [0 .. 5] ]
    norm xs = sqrt (sum (map (^ (2 :: Int)) xs))
    resid = norm (zipWith (-) jd e)
    en = norm e
    jn = norm (U.toList j)
    dn = norm (U.toList d)

-- | Within what a backward-stable solve of a system of condition number κ owes: a relative error
-- of a hundred times κ·ε, and never worse than 1e-9 of the step's size otherwise.
closeTo :: Double -> [Double] -> [Double] -> Property
closeTo kappa got want =
  let scale = maximum (1e-300 : map abs want)
      err = maximum (0 : zipWith (\a b -> abs (a - b)) got want)
      tol = scale * (1e-9 + 100 * kappa * 2.2e-16)
  in counterexample ("step " ++ show got ++ "\noracle " ++ show want ++ "\nκ " ++ show kappa ++ ", largest difference " ++ show err ++ ", allowed " ++ show tol)
       (err <= tol)

asTuple :: [Double] -> (Double, Double, Double, Double, Double, Double)
asTuple [a, b, c, d, e, f] = (a, b, c, d, e, f)
asTuple _ = error "six values"

-- | Random serial arms of 1 to 8 links in every geometry the model has: standard and modified DH,
-- URDF joints about random axes; revolute and prismatic joints, couplings; links whose offset
-- lies on their axis (a column, where the reach bound's fixed point moves up the chain) as often
-- as not.
genRobot :: Gen Robot
genRobot = do
  n <- choose (1, 8)
  kinds <- vectorOf n (frequency [(4, pure Revolute), (1, pure Prismatic)])
  geos <- mapM geometry [0 .. n - 1]
  drives <- mapM (\i -> frequency [(4, pure (directDrive i 1 0)), (1, (\c j -> Drive 0.1 [(j, c)]) <$> choose (-2, 2) <*> choose (0, n - 1))]) [0 .. n - 1]
  base <- frequency [(1, pure identity), (1, fromRpy <$> v3 0.5 <*> v3 3)]
  tool <- frequency [(1, pure identity), (1, fromRpy <$> v3 0.2 <*> v3 3)]
  pure (emptyRobot "random")
    { robotJoints = [Joint ("j" ++ show i) k (if k == Revolute then Limits (-3) 3 else Limits (-0.2) 0.4) Nothing Nothing | (i, k) <- zip [0 :: Int ..] kinds]
    , robotLinks = [Link ("l" ++ show i) (Just k) g d [] | (i, k, g, d) <- zip4' [0 :: Int ..] kinds geos drives]
    , robotBase = base, robotTool = tool }
  where
    v3 r = V3 <$> choose (-r, r) <*> choose (-r, r) <*> choose (-r, r)
    len = frequency [(1, pure 0), (3, choose (-0.5, 0.5))]
    ang = frequency [(1, pure 0), (1, elements [pi / 2, -pi / 2, pi]), (2, choose (-pi, pi))]
    geometry :: Int -> Gen Geometry
    geometry _ = oneof
      [ DhStandard <$> ang <*> len <*> len <*> ang
      , DhModified <$> ang <*> len <*> ang <*> len
      , do ax <- v3 1 `suchThat` (\v -> v3Norm v > 0.1)
           o <- frequency [(1, pure (V3 0 0 0)), (1, (\k -> v3Scale k ax) <$> choose (-1, 1)), (2, v3 0.4)]
           r <- v3 3
           pure (UrdfJoint (fromRpy o r) ax) ]
    zip4' (a : as) (b : bs) (c : cs) (d : ds) = (a, b, c, d) : zip4' as bs cs ds
    zip4' _ _ _ _ = []

-- | The default solve finds a solution, within the limits, whose forward kinematics meets the
-- target to the default tolerances.
solvesByFk :: Chain -> Kinematics -> Tf -> Property
solvesByFk ch k target = case solveIk defaultIkOptions k target Nothing of
  Left f -> counterexample (describeFailure f) False
  Right [] -> counterexample "no solution" False
  Right (s : _) ->
    let (pe, re) = residual (forward ch (solJoints s)) target
    in counterexample (show (pe, re)) (pe <= 1.0001e-6 && re <= 1.0001e-6 && withinLimits 1e-9 ch (solJoints s))

spec :: Spec
spec = do
  describe "the Levenberg–Marquardt step against the singular-value oracle" $ do
    it "the 6×6 form, 1 to 60 joints" $
      property $ withMaxSuccess 500 $ forAll (genCase 1 60) $ \(Case n j e lam mask) ->
        let (want, k6, _) = oracleStep n j e (floored n j lam mask) mask
        in checkCoverage $ cover 30 (k6 < 1e8) "well conditioned" $
             closeTo k6 (U.toList (lmStepDual n j (asTuple e) lam mask)) want
    it "the n×n form, 1 to 12 joints (the chains it serves)" $
      property $ withMaxSuccess 500 $ forAll (genCase 1 12) $ \(Case n j e lam mask) ->
        let (want, _, kn) = oracleStep n j e (floored n j lam mask) mask
        in checkCoverage $ cover 30 (kn < 1e8) "well conditioned" $
             closeTo kn (U.toList (lmStepPrimal n j (asTuple e) lam mask)) want
    it "a masked joint does not move in either form, and the step is finite and no worse than none in the linear model" $
      property $ withMaxSuccess 300 $ forAll (genCase 1 30) $ \c@(Case n j e lam mask) ->
        conjoin [sound c (lmStepDual n j (asTuple e) lam mask), sound c (lmStepPrimal n j (asTuple e) lam mask)]
    it "so on Jacobians of less than full rank with a damping too small for the rounding (the factorisation breaks down and the damping is raised)" $
      property $ withMaxSuccess 500 $ forAll genDeficient $ \c@(Case n j e lam mask) ->
        conjoin [sound c (lmStepDual n j (asTuple e) lam mask), sound c (lmStepPrimal n j (asTuple e) lam mask)]

  describe "refineOnto (a joint path's sample projected onto its pose)" $ do
    let -- the distance (m) and the angle (rad) between the tool poses of two configurations, by
        -- the textbook matrices
        apart r a b =
          let ma = oracleTcpMatrix r (U.toList a); mb = oracleTcpMatrix r (U.toList b)
              d = sqrt (sum [ (ma !! i !! 3 - mb !! i !! 3) ^ (2 :: Int) | i <- [0 .. 2] ])
              -- |R_a − R_b| (Frobenius) = 2√2·sin(θ/2): the angle without acos's loss near 1
              f = sqrt (sum [ (ma !! i !! j - mb !! i !! j) ^ (2 :: Int) | i <- [0 .. 2], j <- [0 .. 2] ])
          in (d, 2 * asin (min 1 (f / (2 * sqrt 2))))
    it "lands a library robot's configuration 1 µrad to 1 mrad off on the target pose where the arm is not near a singularity, and never moves it further off" $
      conjoin
        [ counterexample name $ forAll (genQ ch) $ \q ->
            forAll (elements [1e-6, 1e-4, 1e-3]) $ \off ->
            forAll (U.fromList <$> vectorOf (chainDof ch) (choose (-off, off))) $ \dq ->
              let q0 = U.zipWith (+) q dq
                  q1 = refineOnto ch (forward ch q) q0
                  (d0, a0) = apart r q q0
                  (d1, a1) = apart r q q1
                  sigma = minimum (1 : singularValues (chainDof ch) (snd (jacobian ch q)))
              in counterexample ("before " ++ show (d0, a0) ++ ", after " ++ show (d1, a1) ++ ", smallest singular value " ++ show sigma) $
                   (d1 + a1 <= d0 + a0 + 1e-14)
                   .&&. (sigma < 1e-2 || off > 1e-4 || (d1 < 1e-11 && a1 < 1e-11))
        | (name, Right r) <- libraryRobots, let ch = compile r, chainDof ch >= 6 ]
    it "keeps a configuration already on its pose" $
      conjoin [ counterexample name $ forAll (genQ ch) $ \q ->
                  let q1 = refineOnto ch (forward ch q) q
                  in counterexample (show (U.toList (U.zipWith (-) q1 q))) (U.maximum (U.map abs (U.zipWith (-) q1 q)) < 1e-12)
              | (name, Right ch) <- libraryChains ]
  describe "the reach bound" $ do
    let holds ch q =
          let (centre, bound) = reachBound ch
              d = v3Norm (v3Sub (translation (forward ch q)) centre)
          in counterexample ("distance " ++ show d ++ " m, bound " ++ show bound ++ " m from " ++ show centre) (d <= bound * (1 + 1e-12) + 1e-12)
    it "no configuration of a random arm takes the tool beyond it (standard and modified DH, URDF, slides, couplings)" $
      property $ withMaxSuccess 2000 $ forAll genRobot $ \r -> let ch = compile r in forAll (genQ ch) (holds ch)
    it "no configuration of a library robot does either" $
      conjoin [ counterexample name (forAll (genQ ch) (holds ch)) | (name, Right ch) <- libraryChains ]
    it "is measured from the shoulder when the column lies on the first axis: the LBR iiwa's at (0, 0, 0.36) m, 0.946 m (0.42 + 0.4 + 0.126), met stretched upright" $ do
      let Just (Right iiwa) = lookup "kuka-lbr-iiwa14" libraryChains
          (V3 x y z, bound) = reachBound iiwa
      (x, y) `shouldBe` (0, 0)
      z `shouldSatisfy` (\h -> abs (h - 0.36) < 1e-9)
      bound `shouldSatisfy` (\b -> abs (b - 0.946) < 1e-9)
      -- stretched straight up, the flange is exactly the bound away from the shoulder
      let up = forward iiwa (U.replicate 7 0)
      abs (v3Norm (v3Sub (translation up) (V3 x y z)) - bound) `shouldSatisfy` (< 1e-9)

  describe "the wrist bound" $ do
    -- every wrist point: moving any one of the links it claims (through that link's drive
    -- offset, so couplings do not matter) leaves it where it is, and no configuration puts it
    -- beyond its bound from the shoulder
    let wristHolds ch q = conjoin
          [ counterexample ("wrist " ++ show (wristInTool w) ++ " in the tool, " ++ show (wristAxes w) ++ " axes, bound " ++ show (wristBound w)) $
              counterexample ("moved by its own links: " ++ show moves) (all (<= 1e-9 * (1 + v3Norm p)) moves)
              .&&. counterexample ("distance " ++ show d) (d <= wristBound w * (1 + 1e-12) + 1e-12)
          | w <- wrists ch
          , let p = applyPoint (forward ch q) (wristInTool w)
                d = v3Norm (v3Sub p (wristShoulder w))
                off = chainOffset ch
                moved k = applyPoint (forward ch {chainOffset = off U.// [(k, off U.! k + 0.7)]} q) (wristInTool w)
                moves = [ v3Norm (v3Sub (moved k) p) | k <- [chainLinks ch - wristAxes w .. chainLinks ch - 1] ] ]
        axesMeeting ch = let ws = wrists ch in if null ws then "none" else show (maximum (map wristAxes ws))
    it "a random arm's wrist points stay put as their links move and within their bounds at 20 configurations (standard and modified DH, URDF, slides, couplings)" $
      property $ withMaxSuccess 300 $ checkCoverage $ forAll genRobot $ \r ->
        let ch = compile r
        in tabulate "most axes meeting at a wrist point" [axesMeeting ch] $
             cover 5 (any ((>= 2) . wristAxes) (wrists ch)) "two or more axes meet" $
               forAll (vectorOf 20 (genQ ch)) (conjoin . map (wristHolds ch))
    it "so do a library robot's" $
      conjoin [ counterexample name (forAll (genQ ch) (wristHolds ch)) | (name, Right ch) <- libraryChains ]
    it "finds the spherical wrists: three axes meet in the iiwa, the IRB 140 and 1600, the KR 5 and the PUMA 560" $
      sequence_ [ (name, maximum (0 : map wristAxes (wrists ch))) `shouldSatisfy` ((>= 3) . snd)
                | (name, Right ch) <- libraryChains, name `elem` ["kuka-lbr-iiwa14", "abb-irb140", "abb-irb1600-6-1.2", "kuka-kr5-arc", "puma560"] ]
    it "is tight and allows the tolerances: the LBR iiwa stretched upright puts its wrist 0.82 m above the shoulder; 1 µm higher passes, 11.2 µm higher does not" $ do
      let Just (Right iiwa) = lookup "kuka-lbr-iiwa14" libraryChains
          up = forward iiwa (U.replicate 7 0)
          raised h = trans 0 0 h `compose` up
      [ wristBound w | w <- wrists iiwa, wristAxes w == 3 ] `shouldSatisfy` (\case [b] -> abs (b - 0.82) < 1e-9; _ -> False)
      wristCheck defaultIkOptions iiwa up `shouldBe` Nothing
      -- the default tolerances: 1 µm and 1 µrad, which moves the wrist point 0.126 m from the
      -- flange by 0.126 µm more
      wristCheck defaultIkOptions iiwa (raised 1e-6) `shouldBe` Nothing
      wristCheck defaultIkOptions iiwa (raised 1.12e-6) `shouldBe` Nothing
      case wristCheck defaultIkOptions iiwa (raised 11.2e-6) of
        Just (Unreachable what excess) -> do
          excess `shouldSatisfy` (\e -> abs (e - 11.2e-6) < 1e-9)
          what `shouldSatisfy` ("where the last 3 joint axes meet" `isInfixOf`)
        other -> expectationFailure (show other)
    it "a target tipped over at arm's length: within the tool's reach, beyond the wrist's, refused without a descent" $ do
      let Just (Right iiwa) = lookup "kuka-lbr-iiwa14" libraryChains
          -- 0.9 m out at the shoulder's height, pointing away: the flange within 0.946 m, the
          -- wrist point 0.126 m behind it at 0.9 - 0.126 = 0.774 m: reachable; pointing back at
          -- the robot, the wrist point 1.026 m out: not
          away = trans 0.9 0 0.36 `compose` rotY (pi / 2)
          back = trans 0.9 0 0.36 `compose` rotY (negate (pi / 2))
      wristCheck defaultIkOptions iiwa away `shouldBe` Nothing
      case solveIk defaultIkOptions (prepareChain iiwa) back Nothing of
        Left (Unreachable what excess) -> do
          excess `shouldSatisfy` (\e -> abs (e - (1.026 - 0.82)) < 1e-9)
          what `shouldSatisfy` ("the wrist point" `isInfixOf`)
        other -> expectationFailure (show other)

  describe "a chain of a thousand joints" $ do
    let ch = compile (snake 1000 3)
        k = prepareChain ch
    it "IK of FK(q) converges (random q; the answer checked by forward kinematics)" $
      property $ withMaxSuccess 5 $ forAll (U.fromList <$> vectorOf 1000 (choose (-0.3, 0.3))) $ \q ->
        solvesByFk ch k (forward ch q)
    it "a planar chain of 500 joints reaches poses in its plane (from its straight seed, a singular configuration)" $ do
      -- every start but the seed was a uniform draw, which crumples a chain of hundreds of joints,
      -- and the straight seed is singular for a target off its line: (3, 1, 0) m was "not
      -- converged, best residual 2384 mm"; a long chain's starts now include the seed bent a little
      let pl = compile (planarSnake 500 3)
          kp = prepareChain pl
      property $ withMaxSuccess 30 $ forAll ((,,) <$> elements [0.5, 1, 2, 3, 3.16, 4, 4.5] <*> elements [0, 0.32, 1, -2, pi / 2, 3] <*> elements [0, 0, 0.5, -1, pi]) $ \(r, phi, yaw) ->
        solvesByFk pl kp (trans (r * cos phi) (r * sin phi) 0 `compose` rotZ yaw)
    it "a pose no solution reaches (joints held within ±0.001 rad) stops at the budget, not one descent later" $ do
      -- the old solver looked at the clock between restarts only: one restart of this chain took
      -- seconds (an n×n step a iteration); the budget is now looked at between iterations. With
      -- every joint within ±0.001 rad the 10 m snake bends on a radius of 10 m or more, so its
      -- tip stays over 9.5 m from its base: a target 5 m out along the straight snake is out of
      -- its range though within its reach bound
      let tight = compile (snake 1000 0.001)
          target = (forward ch (U.replicate 1000 0)) {tx = 5}
      forM_ [0.05, 0.3] $ \budget -> do
        t0 <- getMonotonicTimeNSec
        r <- solveNumericIO budget defaultIkOptions tight target Nothing
        t1 <- getMonotonicTimeNSec
        let took = fromIntegral (t1 - t0) / 1e9 :: Double
        case r of
          Left _ -> pure ()
          Right sols -> expectationFailure ("solutions of an unreachable pose: " ++ show (length sols))
        -- a generous allowance over the budget: one iteration of this chain is milliseconds
        took `shouldSatisfy` (< budget + 1.5)
