-- | The LP solver: hand-made problems with known answers, random feasible problems
-- built around a known point (optimality against it and against the dual LP),
-- random infeasible problems (certificates checked), the certificate checker on its
-- own (it must never accept a certificate for a problem with a known feasible point),
-- and velocity-chain problems shaped like the real use.
module VProf.Numeric.LinearProgramSpec (spec) where

import Control.Monad (replicateM)
import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import VProf.Numeric.LinearProgram

inf :: Double
inf = 1 / 0

mkLp :: [(Double, Double)] -> [Row] -> [Double] -> Lp
mkLp cols rows obj = Lp
  { lpCols = length cols
  , lpColLo = U.fromList (map fst cols)
  , lpColHi = U.fromList (map snd cols)
  , lpRows = rows
  , lpObjective = U.fromList obj
  }

objectiveAt :: Lp -> U.Vector Double -> Double
objectiveAt lp x = U.sum (U.zipWith (*) (lpObjective lp) x)

-- | Optimal, feasible to 1e-9, objective within 1e-9 of the expected value.
shouldBeOptimalAt :: Lp -> Double -> Expectation
shouldBeOptimalAt lp expected = case solve lp of
  Optimal x -> do
    residuals lp x `shouldSatisfy` (<= 1e-9)
    objectiveAt lp x `shouldSatisfy` (\o -> abs (o - expected) <= 1e-9 * max 1 (abs expected))
  other -> expectationFailure ("expected Optimal, got " ++ show other)

shouldBeInfeasible :: Lp -> Expectation
shouldBeInfeasible lp = case solve lp of
  Infeasible y -> certifies lp y `shouldBe` True
  other -> expectationFailure ("expected Infeasible, got " ++ show other)

isUnbounded, isUndecided :: LpResult -> Bool
isUnbounded = \case Unbounded -> True; _ -> False
isUndecided = \case Undecided _ -> True; _ -> False

------------------------------------------------------------------------------------
-- Hand-made problems

-- | max x + y, x + 2y ≤ 4, 3x + y ≤ 6, x, y ≥ 0: (1.6, 1.2), value 2.8.
twoD :: Lp
twoD = mkLp [(0, inf), (0, inf)]
  [Row [(0, 1), (1, 2)] (-inf) 4, Row [(0, 3), (1, 1)] (-inf) 6] [-1, -1]

-- | x + y ≤ 1 and x + y ≥ 2 on [0, 10]².
contradiction :: Lp
contradiction = mkLp [(0, 10), (0, 10)]
  [Row [(0, 1), (1, 1)] (-inf) 1, Row [(0, 1), (1, 1)] 2 inf] [0, 0]

-- | Beale's example, which cycles under the textbook rules without anti-cycling.
beale :: Lp
beale = mkLp [(0, inf), (0, inf), (0, inf), (0, inf)]
  [ Row [(0, 0.25), (1, -8), (2, -1), (3, 9)] (-inf) 0
  , Row [(0, 0.5), (1, -12), (2, -0.5), (3, 3)] (-inf) 0
  , Row [(2, 1)] (-inf) 1 ]
  [-0.75, 20, -0.5, 6]

-- | Klee–Minty cube of dimension d: max Σ 2^(d−j) x_j, optimum 5^d.
kleeMinty :: Int -> Lp
kleeMinty d = mkLp (replicate d (0, inf))
  [ Row ([(j, 2 * 2 ^^ (i - j)) | j <- [0 .. i - 1]] ++ [(i, 1)]) (-inf) (5 ^^ (i + 1))
  | i <- [0 .. d - 1] ]
  [negate (2 ^^ (d - 1 - j)) | j <- [0 .. d - 1]]

handMade :: Spec
handMade = do
  it "solves a 2-D LP at the vertex (1.6, 1.2)" $ do
    twoD `shouldBeOptimalAt` (-2.8)
    case solve twoD of
      Optimal x -> U.toList x `shouldSatisfy` \[a, b] -> abs (a - 1.6) < 1e-12 && abs (b - 1.2) < 1e-12
      _ -> pure ()

  it "solves an equality-constrained LP (min 2x + 3y + z, x + y + z = 10, x − y = 2)" $
    mkLp [(0, inf), (0, inf), (0, inf)]
      [Row [(0, 1), (1, 1), (2, 1)] 10 10, Row [(0, 1), (1, -1)] 2 2] [2, 3, 1]
      `shouldBeOptimalAt` 12

  it "respects a fixed column (x = 3, y − x ≥ −1, min y)" $
    mkLp [(3, 3), (0, 10)] [Row [(1, 1), (0, -1)] (-1) inf] [0, 1] `shouldBeOptimalAt` 2

  it "handles free and half-infinite columns" $ do
    mkLp [(-inf, inf), (-inf, inf)]
      [Row [(0, 1), (1, -1)] (-1) 1, Row [(0, 1), (1, 1)] 3 inf] [1, 1] `shouldBeOptimalAt` 3
    mkLp [(-inf, inf), (-inf, inf)]
      [Row [(0, 1), (1, 1)] 5 5, Row [(0, 1), (1, -1)] 1 1] [0, 0] `shouldBeOptimalAt` 0
    case solve (mkLp [(-inf, inf), (-inf, inf)]
                  [Row [(0, 1), (1, 1)] 5 5, Row [(0, 1), (1, -1)] 1 1] [0, 0]) of
      Optimal x -> U.toList x `shouldSatisfy` \[a, b] -> abs (a - 3) < 1e-12 && abs (b - 2) < 1e-12
      other -> expectationFailure (show other)
    mkLp [(-inf, -2)] [] [-1] `shouldBeOptimalAt` 2
    mkLp [(-1, 1)] [] [1] `shouldBeOptimalAt` (-1)

  it "sums repeated terms of a row" $
    mkLp [(0, inf)] [Row [(0, 1), (0, 1)] (-inf) 4] [-1] `shouldBeOptimalAt` (-2)

  it "does not cycle on Beale's example (optimum −1.25)" $ beale `shouldBeOptimalAt` (-1.25)

  it "solves the Klee–Minty cube of dimension 8 (optimum 5^8)" $
    kleeMinty 8 `shouldBeOptimalAt` (-(5 ^ (8 :: Int)))

  it "finds contradicting rows infeasible, with a certificate" $ do
    shouldBeInfeasible contradiction
    -- the same with free columns: the multipliers must cancel exactly
    shouldBeInfeasible contradiction { lpColLo = U.replicate 2 (-inf), lpColHi = U.replicate 2 inf }

  it "finds a row against the column box infeasible (x + y ≥ 3 on [0, 1]²)" $
    shouldBeInfeasible (mkLp [(0, 1), (0, 1)] [Row [(0, 1), (1, 1)] 3 inf] [1, 0])

  it "finds an empty row with 0 outside its bounds infeasible" $ do
    shouldBeInfeasible (mkLp [(0, 1)] [Row [] 1 2] [0])
    shouldBeInfeasible (mkLp [] [Row [] (-inf) (-1)] [])
    mkLp [] [Row [] (-1) 1] [] `shouldBeOptimalAt` 0
    mkLp [] [] [] `shouldBeOptimalAt` 0

  it "recognises an unbounded LP" $ do
    solve (mkLp [(0, inf), (0, inf)] [Row [(0, 1), (1, -1)] (-inf) 1] [-1, -1])
      `shouldSatisfy` isUnbounded
    solve (mkLp [(-inf, inf)] [] [1]) `shouldSatisfy` isUnbounded
    solve (mkLp [(-inf, 0), (0, 5)] [Row [(0, 1), (1, 1)] (-inf) 3] [1, 0])
      `shouldSatisfy` isUnbounded

  it "does not flip-flop between the phases on boxes at the tolerance's scale" $ do
    -- v_k ∈ [0, 1e-9], distance exactly 0, maximise Σv: once looped to the iteration
    -- cap (a Harris step ended exactly on the tolerance, rounding put it beyond)
    let c = Chain 40 0.1 1e-9 (-7.5e-4, 9.8e-4) (-3.4e-4, 3.2e-4) (0, 0)
    chainLp c (Just (0, 0)) (replicate 41 (-1)) `shouldBeOptimalAt` 0
    chainLp c (Just (0, 0)) (replicate 41 0) `shouldBeOptimalAt` 0

  it "answers malformed problems Undecided" $ do
    solve (mkLp [(0, 1)] [Row [(0, 1)] 2 1] [0]) `shouldSatisfy` isUndecided
    solve (mkLp [(1, 0)] [] [0]) `shouldSatisfy` isUndecided
    solve (mkLp [(0, 1)] [Row [(1, 1)] 0 1] [0]) `shouldSatisfy` isUndecided
    solve (mkLp [(0, 1)] [Row [(0, 0 / 0)] 0 1] [0]) `shouldSatisfy` isUndecided
    solve (mkLp [(0, 1)] [] [0, 1]) `shouldSatisfy` isUndecided

  it "measures residuals relative to max 1 |bound|" $ do
    let lp = mkLp [(0, 10), (-inf, inf)] [Row [(0, 1), (1, 1)] (-inf) 100] [0, 0]
    residuals lp (U.fromList [5, 0]) `shouldBe` 0
    residuals lp (U.fromList [-0.5, 0]) `shouldBe` 0.5
    residuals lp (U.fromList [12, 0]) `shouldBe` 0.2
    residuals lp (U.fromList [5, 105]) `shouldBe` 0.1
    residuals lp (U.fromList [5]) `shouldBe` inf

  describe "certifies" $ do
    it "accepts the textbook certificate and its positive multiples" $ do
      certifies contradiction (Farkas (U.fromList [1, -1])) `shouldBe` True
      certifies contradiction (Farkas (U.fromList [3, -3])) `shouldBe` True
    it "rejects a perturbed, wrong-sign, zero or wrong-length certificate" $ do
      certifies contradiction (Farkas (U.fromList [1, -0.5])) `shouldBe` False
      certifies contradiction (Farkas (U.fromList [-1, 1])) `shouldBe` False
      certifies contradiction (Farkas (U.fromList [0, 0])) `shouldBe` False
      certifies contradiction (Farkas (U.fromList [1, -1, 0])) `shouldBe` False
      certifies contradiction (Farkas (U.fromList [1, 0 / 0])) `shouldBe` False
    it "rejects a certificate using an infinite bound" $
      certifies contradiction (Farkas (U.fromList [1, 1])) `shouldBe` False
    it "rejects multipliers that leave a free column uncancelled" $ do
      let free = contradiction { lpColLo = U.replicate 2 (-inf), lpColHi = U.replicate 2 inf }
      certifies free (Farkas (U.fromList [1, -1])) `shouldBe` True
      certifies free (Farkas (U.fromList [1, -1 - 1e-9])) `shouldBe` False
    it "rejects near-cancelling multipliers on a free column of a feasible problem" $ do
      -- two equalities through a free column meet at x* = (−3.4375, 0.125), on x1's
      -- lower bound; multipliers that cancel on column 0 only to rounding leave a gap
      -- of r_0·3.4375 ≈ 1e-17: accepting it (dropping the free column, no wide gap)
      -- would call a feasible problem infeasible
      let lp = mkLp [(-inf, -0.453125), (0.125, inf)]
                 [ Row [(0, 0.6875), (1, -1)] (-2.48828125) (-2.48828125)
                 , Row [(0, 0.8125), (1, 0.4375)] (-2.73828125) (-2.73828125) ] [0, 0]
      residuals lp (U.fromList [-3.4375, 0.125]) `shouldBe` 0
      certifies lp (Farkas (U.fromList [-0.7697368421052632, 0.6513157894736843])) `shouldBe` False
      lp `shouldBeOptimalAt` 0

    it "is exact at the boundary (x ≤ 1 and x ≥ 1 + 2^-52 is infeasible, x ≥ 1 is not)" $ do
      let edge lo2 = mkLp [(-inf, inf)] [Row [(0, 1)] (-inf) 1, Row [(0, 1)] lo2 inf] [0]
      certifies (edge (1 + 2 ** (-52))) (Farkas (U.fromList [1, -1])) `shouldBe` True
      certifies (edge 1) (Farkas (U.fromList [1, -1])) `shouldBe` False
      -- the solver works to 1e-9: a contradiction of 2^-52 is feasible to it, 1e-6 is not
      edge (1 + 2 ** (-52)) `shouldBeOptimalAt` 0
      shouldBeInfeasible (edge (1 + 1e-6))

------------------------------------------------------------------------------------
-- Random problems around a known point

-- | A problem and a point known to satisfy it (to rounding).
data Feasible = Feasible Lp (U.Vector Double) deriving Show

-- | How random numbers are drawn: 'Real' anywhere, or 'Dyadic': points and slacks on
-- multiples of 1/64, coefficients on multiples of 1/16, so that every activity and
-- bound below is computed exactly and the known point is exactly feasible (what the
-- soundness properties of 'certifies' need; elsewhere it is feasible to rounding).
data Draw = Real | Dyadic deriving (Eq, Show)

quantize :: Draw -> Double -> Double -> Double
quantize Real _ v = v
quantize Dyadic unit v = fromIntegral (round (v / unit) :: Integer) * unit

value :: Draw -> (Double, Double) -> Gen Double
value dr r = quantize dr (1 / 64) <$> choose r

slack :: Draw -> Gen Double
slack dr = frequency [(1, pure 0), (4, value dr (0, 3))]

coefficient :: Draw -> Gen Double
coefficient dr = oneof
  [ fromIntegral <$> elements [-3, -2, -1, 1, 2, 3 :: Int]
  , quantize dr (1 / 16) <$> choose (-3, 3) `suchThat` ((> 0.07) . abs) ]

-- | A column box around x: finite only when boxed.
genCol :: Draw -> Bool -> Double -> Gen (Double, Double)
genCol dr boxed x = frequency $
  [ (1, pure (x, x))
  , (6, (\a b -> (x - a, x + b)) <$> slack dr <*> slack dr) ]
  ++ if boxed then [] else
  [ (2, (\a -> (x - a, inf)) <$> slack dr)
  , (1, (\b -> (-inf, x + b)) <$> slack dr)
  , (1, pure (-inf, inf)) ]

-- | Terms on a few random columns (sometimes on all of them).
genTerms :: Draw -> Int -> Gen [(Int, Double)]
genTerms dr n = do
  k <- frequency [(6, choose (1, min n 4)), (1, pure n)]
  js <- take k <$> shuffle [0 .. n - 1]
  as <- vectorOf k (coefficient dr)
  pure (zip js as)

activity :: [(Int, Double)] -> U.Vector Double -> Double
activity ts x = sum [a * x U.! j | (j, a) <- ts]

genRow :: Draw -> Int -> U.Vector Double -> Gen Row
genRow dr n x = do
  ts <- genTerms dr n
  let act = activity ts x
  (lo, hi) <- frequency
    [ (2, pure (act, act))
    , (5, (\a b -> (act - a, act + b)) <$> slack dr <*> slack dr)
    , (1, (\a -> (act - a, inf)) <$> slack dr)
    , (1, (\b -> (-inf, act + b)) <$> slack dr) ]
  pure (Row ts lo hi)

-- | A random feasible problem; boxed: every column box finite; objective: random
-- coefficients (else all zero).
genFeasible :: Bool -> Bool -> Gen Feasible
genFeasible = genFeasibleWith Real

genFeasibleWith :: Draw -> Bool -> Bool -> Gen Feasible
genFeasibleWith dr boxed withObjective = do
  n <- choose (1, 12)
  m <- choose (0, 16)
  x <- U.fromList <$> vectorOf n (value dr (-5, 5))
  cols <- mapM (genCol dr boxed) (U.toList x)
  rows <- replicateM m (genRow dr n x)
  obj <- if withObjective then vectorOf n (choose (-2, 2)) else pure (replicate n 0)
  pure (Feasible (mkLp cols rows obj) x)

-- | Objective slack allowed against the known point.
objTol :: Lp -> U.Vector Double -> Double
objTol lp x = 1e-7 * (1 + U.sum (U.zipWith (\c v -> abs c * (abs v + 10)) (lpObjective lp) x))

optimalAgainst :: Lp -> U.Vector Double -> Property
optimalAgainst lp xStar = case solve lp of
  Optimal x ->
    counterexample ("residual " ++ show (residuals lp x)) (residuals lp x <= 1e-9)
    .&&. counterexample ("objective " ++ show (objectiveAt lp x) ++ " vs " ++ show (objectiveAt lp xStar))
           (objectiveAt lp x <= objectiveAt lp xStar + objTol lp xStar)
  other -> counterexample ("expected Optimal, got " ++ show other) False

-- | The dual of a problem with finite column boxes:
-- max Σ (L_i λ_i − U_i μ_i) + Σ (l_j α_j − u_j β_j)
-- s.t. Aᵀ(λ − μ) + α − β = c, all ≥ 0 (λ_i absent when L_i = −∞, μ_i when U_i = +∞),
-- written as a minimisation: its optimum is minus the primal one.
dualOf :: Lp -> Lp
dualOf Lp{..} = mkLp cols rows obj
  where
    m = length lpRows
    n = lpCols
    use b = if isInfinite b then (0, 0) else (0, inf)
    cols = map (use . rowLo) lpRows ++ map (use . rowHi) lpRows
           ++ replicate (2 * n) (0, inf)
    obj = [if isInfinite (rowLo r) then 0 else negate (rowLo r) | r <- lpRows]
          ++ [if isInfinite (rowHi r) then 0 else rowHi r | r <- lpRows]
          ++ map negate (U.toList lpColLo) ++ U.toList lpColHi
    rows = [ Row ( [(i, a) | (i, r) <- zip [0 ..] lpRows, (j', a) <- rowTerms r, j' == j]
                ++ [(m + i, negate a) | (i, r) <- zip [0 ..] lpRows, (j', a) <- rowTerms r, j' == j]
                ++ [(2 * m + j, 1), (2 * m + n + j, -1)] )
                 (lpObjective U.! j) (lpObjective U.! j)
           | j <- [0 .. n - 1] ]

-- | Adds a·x ≤ b and (κa)·x ≥ κ(b + δ); second, the same with κa·x ≥ κ(a·x* − s'),
-- s' > 0, which x* satisfies (exactly, with 'Dyadic' draws).
pairContradiction :: Draw -> Feasible -> Gen (Lp, Lp)
pairContradiction dr (Feasible lp x) = do
  ts <- genTerms dr (lpCols lp)
  s <- slack dr
  delta <- value dr (1 / 64, 2)
  kappa <- quantize dr (1 / 8) <$> choose (0.125, 10)
  s' <- value dr (1 / 64, 3)
  let b = activity ts x + s
      upper = Row ts (-inf) b
      contra = Row [(j, kappa * a) | (j, a) <- ts] (kappa * (b + delta)) inf
      relaxed = Row [(j, kappa * a) | (j, a) <- ts] (kappa * (activity ts x - s')) inf
  pure (lp { lpRows = lpRows lp ++ [upper, contra] }, lp { lpRows = lpRows lp ++ [upper, relaxed] })

-- | Adds a·x ≤ b, c·x ≤ d and (a + c)·x ≥ b + d + δ.
tripleContradiction :: Feasible -> Gen Lp
tripleContradiction (Feasible lp x) = do
  let n = lpCols lp
  t1 <- genTerms Real n
  t2 <- genTerms Real n
  s1 <- slack Real
  s2 <- slack Real
  delta <- choose (0.01, 2)
  let b = activity t1 x + s1
      d = activity t2 x + s2
  pure lp { lpRows = lpRows lp ++
    [Row t1 (-inf) b, Row t2 (-inf) d, Row (t1 ++ t2) (b + d + delta) inf] }

-- | Adds a·x ≥ (the largest a·x over the finite column box) + δ.
boxContradiction :: Feasible -> Gen Lp
boxContradiction (Feasible lp _) = do
  ts <- genTerms Real (lpCols lp)
  delta <- choose (0.01, 2)
  let top = sum [max (a * lpColLo lp U.! j) (a * lpColHi lp U.! j) | (j, a) <- ts]
  pure lp { lpRows = lpRows lp ++ [Row ts (top + delta) inf] }

infeasibleCertified :: Lp -> Property
infeasibleCertified lp = case solve lp of
  Infeasible y -> counterexample ("certificate " ++ show y ++ " rejected") (certifies lp y)
  other -> counterexample ("expected Infeasible, got " ++ show other) False

randomProblems :: Spec
randomProblems = do
  it "random boxed problems: Optimal, feasible, no worse than the known point" $
    withMaxSuccess 200 $ forAll (genFeasible True True) $ \(Feasible lp x) -> optimalAgainst lp x

  it "random problems with infinite bounds, feasibility only: Optimal and feasible" $
    withMaxSuccess 200 $ forAll (genFeasible False False) $ \(Feasible lp x) -> optimalAgainst lp x

  it "random problems with infinite bounds and an objective: Optimal, or Unbounded and \
     \then a ±1e6 box gives far better than the known point" $
    withMaxSuccess 200 $ forAll (genFeasible False True) $ \(Feasible lp x) ->
      case solve lp of
        Unbounded ->
          let boxed = lp { lpColLo = U.map (max (-1e6)) (lpColLo lp)
                         , lpColHi = U.map (min 1e6) (lpColHi lp) }
          in case solve boxed of
               Optimal xb -> counterexample "the boxed problem is not much better"
                               (objectiveAt lp xb < objectiveAt lp x - 1e-3)
               other -> counterexample ("boxed: " ++ show other) False
        _ -> optimalAgainst lp x

  it "random boxed problems: the optimum equals minus the optimum of the dual LP" $
    withMaxSuccess 200 $ forAll (genFeasible True True) $ \(Feasible lp _) ->
      case (solve lp, solve (dualOf lp)) of
        (Optimal x, Optimal y) ->
          let p = objectiveAt lp x
              d = negate (objectiveAt (dualOf lp) y)
          in counterexample (show (p, d)) (abs (p - d) <= 1e-7 * (1 + abs p))
        other -> counterexample (show other) False

  it "random problems plus a·x ≤ b and κa·x ≥ κ(b + δ): Infeasible, certified" $
    withMaxSuccess 200 $ forAll (genFeasible False True >>= pairContradiction Real) $
      infeasibleCertified . fst

  it "random problems plus a·x ≤ b, c·x ≤ d, (a + c)·x ≥ b + d + δ: Infeasible, certified" $
    withMaxSuccess 200 $ forAll (genFeasible False False >>= tripleContradiction)
      infeasibleCertified

  it "random boxed problems plus a row beyond the box: Infeasible, certified" $
    withMaxSuccess 200 $ forAll (genFeasible True False >>= boxContradiction)
      infeasibleCertified

  describe "certifies" $ do
    it "never accepts random multipliers for a problem with a known feasible point" $
      withMaxSuccess 200 $ forAll (genFeasibleWith Dyadic False False) $ \(Feasible lp _) ->
        forAll (vectorOf (length (lpRows lp))
                  (frequency [(1, pure 0), (3, choose (-10, 10))])) $ \ys ->
          not (certifies lp (Farkas (U.fromList ys)))

    it "never accepts random multipliers for boxed problems with a known feasible point" $
      withMaxSuccess 200 $ forAll (genFeasibleWith Dyadic True False) $ \(Feasible lp _) ->
        forAll (vectorOf (length (lpRows lp))
                  (frequency [(1, pure 0), (3, choose (-10, 10))])) $ \ys ->
          not (certifies lp (Farkas (U.fromList ys)))

    it "a solver certificate: kept by positive scaling; rejected negated, without the \
       \contradicting row, or on the relaxed (feasible) problem" $
      withMaxSuccess 200 $ forAll (genFeasibleWith Dyadic False True >>= \f ->
                                     (,) f <$> pairContradiction Dyadic f) $
        \(Feasible _ x, (bad, relaxed)) -> case solve bad of
          Infeasible (Farkas y) ->
            let lastOut = U.imap (\i v -> if i == U.length y - 1 then 0 else v) y
            in counterexample "the relaxed problem is not feasible at x*" (residuals relaxed x == 0)
               .&&. counterexample "3.7·y rejected" (certifies bad (Farkas (U.map (* 3.7) y)))
               .&&. counterexample "−y accepted" (not (certifies bad (Farkas (U.map negate y))))
               .&&. counterexample "y without the contradicting row accepted"
                      (not (certifies bad (Farkas lastOut)))
               .&&. counterexample "y accepted on the relaxed problem"
                      (not (certifies relaxed (Farkas y)))
          other -> counterexample ("expected Infeasible, got " ++ show other) False

------------------------------------------------------------------------------------
-- Velocity chains (the real use)

-- | Parameters of a chain: velocities v_0..v_N at steps of dt.
data Chain = Chain
  { cN :: Int, cDt :: Double, cVmax :: Double
  , cAcc :: (Double, Double), cJerk :: (Double, Double)
  , cEnds :: (Double, Double) }
  deriving Show

-- | v_0, v_N fixed, v_k ∈ [0, vmax], v_{k+1} − v_k ∈ dt·[aMin, aMax],
-- v_{k+2} − 2v_{k+1} + v_k ∈ dt²·[jMin, jMax], and (if given) the trapezoid distance
-- Σ (v_k + v_{k+1})·dt/2 ∈ [lo, hi].
chainLp :: Chain -> Maybe (Double, Double) -> [Double] -> Lp
chainLp Chain{..} dist obj = mkLp cols rows obj
  where
    (aMin, aMax) = cAcc
    (jMin, jMax) = cJerk
    (v0, vN) = cEnds
    cols = [if k == 0 then (v0, v0) else if k == cN then (vN, vN) else (0, cVmax) | k <- [0 .. cN]]
    rows = [Row [(k, -1), (k + 1, 1)] (aMin * cDt) (aMax * cDt) | k <- [0 .. cN - 1]]
        ++ [Row [(k, 1), (k + 1, -2), (k + 2, 1)] (jMin * cDt * cDt) (jMax * cDt * cDt)
           | k <- [0 .. cN - 2]]
        ++ [Row (distanceTerms cN cDt) lo hi | Just (lo, hi) <- [dist]]

distanceTerms :: Int -> Double -> [(Int, Double)]
distanceTerms n dt = [(k, if k == 0 || k == n then dt / 2 else dt) | k <- [0 .. n]]

distanceOf :: Int -> Double -> U.Vector Double -> Double
distanceOf n dt v = activity (distanceTerms n dt) v

-- | A chain and a legal profile for it: a random smooth profile (a ramp between the
-- end speeds plus sin² bumps), with limits at or beyond what it uses.
genChain :: Gen (Chain, U.Vector Double)
genChain = do
  n <- choose (10, 60)
  dt <- oneof [elements [0.01, 0.02, 0.05, 0.1, 0.25], choose (0.005, 0.3)]
  v0 <- frequency [(2, pure 0), (1, choose (0, 2))]
  vN <- frequency [(2, pure 0), (1, choose (0, 2))]
  bumps <- vectorOf 3 (frequency [(1, pure 0), (2, choose (0, 3))])
  let fn = fromIntegral n
      v = U.generate (n + 1) $ \k ->
        if k == 0 then v0 else if k == n then vN else
          let t = fromIntegral k / fn
          in v0 + (vN - v0) * t + sum [c * sin (fromIntegral p * pi * t) ^ (2 :: Int)
                                       | (p, c) <- zip [1 :: Int ..] bumps]
      d1 = [(v U.! (k + 1) - v U.! k) / dt | k <- [0 .. n - 1]]
      d2 = [(v U.! (k + 2) - 2 * v U.! (k + 1) + v U.! k) / (dt * dt) | k <- [0 .. n - 2]]
      widen xs = do
        s1 <- frequency [(1, pure 0), (2, choose (0, 1))]
        s2 <- frequency [(1, pure 0), (2, choose (0, 1))]
        let lo = minimum (0 : xs); hi = maximum (0 : xs); w = hi - lo + 1e-3
        -- a relative hair beyond the profile so that rounding in it does not matter
        pure (lo - s1 * w - 1e-12 * abs lo, hi + s2 * w + 1e-12 * abs hi)
  acc <- widen d1
  jerk <- widen d2
  sv <- frequency [(1, pure 0), (2, choose (0, 1))]
  -- vmax at the profile's top (tight) or above; a profile standing still gets a real one
  vmax <- if U.maximum v < 0.05 then choose (0.1, 3) else pure (U.maximum v * (1 + sv))
  pure (Chain n dt vmax acc jerk (v0, vN), v)

chainProblems :: Spec
chainProblems = do
  it "chains built around a legal profile: Optimal, feasible, and max Σv no worse" $
    withMaxSuccess 150 $ forAll genChain $ \(c, v) -> do
      tolRel <- elements [0, 1e-9, 1e-6, 1e-3]
      let l = distanceOf (cN c) (cDt c) v
          tol = tolRel * l
          feas = chainLp c (Just (l - tol, l + tol)) (replicate (cN c + 1) 0)
          fast = chainLp c (Just (l - tol, l + tol)) (replicate (cN c + 1) (-1))
      pure $ counterexample "the generated profile is not legal" (residuals feas v <= 1e-9)
        .&&. optimalAgainst feas v
        .&&. optimalAgainst fast v

  it "chains asked for a distance beyond vmax·N·dt: Infeasible, certified" $
    withMaxSuccess 150 $ forAll genChain $ \(c, _) -> do
      factor <- choose (1.01, 3)
      tolRel <- elements [0, 1e-6, 1e-3]
      let l = cVmax c * fromIntegral (cN c) * cDt c * factor
      pure $ infeasibleCertified (chainLp c (Just (l - tolRel * l, l + tolRel * l))
                                          (replicate (cN c + 1) 0))

  it "chains just beyond the longest reachable distance are Infeasible, just inside Optimal" $
    withMaxSuccess 100 $ forAll genChain $ \(c, _) ->
      let n = cN c
          w = map snd (distanceTerms n (cDt c))
          extreme sign = case solve (chainLp c Nothing (map (* sign) w)) of
            Optimal x -> Just (distanceOf n (cDt c) x)
            _ -> Nothing
      in case (extreme (-1), extreme 1) of
           (Just lMax, Just lMin) ->
             let over = lMax + 1e-6 * max 1 lMax
                 inside = lMax - 1e-6 * (lMax - lMin)
             in counterexample (show (lMin, lMax)) $
                  infeasibleCertified (chainLp c (Just (over, over)) (replicate (n + 1) 0))
                  .&&. (lMax - lMin > 1e-3 * max 1 lMax ==>
                          case solve (chainLp c (Just (inside, inside)) (replicate (n + 1) 0)) of
                            Optimal _ -> property True
                            other -> counterexample (show other) False)
           other -> counterexample ("extremes: " ++ show other) False

spec :: Spec
spec = do
  describe "hand-made problems" handMade
  describe "random problems" randomProblems
  describe "velocity chains" chainProblems
