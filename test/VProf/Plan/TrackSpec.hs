-- | The joint path's slopes at the tracked samples: the derivative of the polynomial through a
-- sample and its four nearest samples, taken within the stretch between stops. Checked against
-- polynomials differentiated by hand: any quartic joint motion gets its exact slope at every
-- sample, over grids whose steps range from a micrometre to centimetres, and at a stop each side
-- takes the slope of its own side's motion.
module VProf.Plan.TrackSpec (spec) where

import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import VProf.Plan.Track

-- | A polynomial by its coefficients about a centre: Σ c_k (x − x0)^k.
data Poly = Poly Double [Double] deriving (Show)

evalP, slopeP :: Poly -> Double -> Double
evalP (Poly x0 cs) x = sum [ c * (x - x0) ^ k | (k, c) <- zip [0 :: Int ..] cs ]
slopeP (Poly x0 cs) x = sum [ fromIntegral k * c * (x - x0) ^ (k - 1) | (k, c) <- zip [1 :: Int ..] (drop 1 cs) ]

genPoly :: Int -> Double -> Gen Poly
genPoly degree x0 = Poly x0 <$> vectorOf (degree + 1) (oneof [choose (-3, 3), choose (-300, 300)])

-- | Steps of a route grid: from a micrometre (a refined stretch near a singularity, a blend of a
-- fraction of a millimetre cut by degrees of its turn) to a centimetre, any mix.
genSteps :: Int -> Gen [Double]
genSteps m = vectorOf m (frequency [(5, choose (1e-4, 1e-3)), (2, choose (1e-3, 2e-2)), (1, choose (1e-6, 1e-5))])

-- | Steps graded as the tracking's refinement makes them (a step halved, and its halves again):
-- each within a factor of four of the one before, from a micrometre to two centimetres.
genGradedSteps :: Int -> Gen [Double]
genGradedSteps m = do
  h0 <- choose (-6, -1.7)
  us <- vectorOf m (frequency [(4, pure 0), (1, choose (-2, 2))])
  pure (map (10 **) (drop 1 (scanl (\e u -> max (-6) (min (-1.7) (e + u * logBase 10 2))) h0 us)))

-- | The derivative weights at the node x_k of the polynomial through the nodes xs, by the
-- barycentric differentiation matrix (D_kj = (λ_j/λ_k)/(x_k − x_j), D_kk = −Σ_{j≠k} D_kj,
-- λ_j = 1/Π_{m≠j}(x_j − x_m)): here only to size the rounding a slope from these nodes carries.
diffWeights :: [Double] -> Int -> [Double]
diffWeights xs k = [ if j == k then negate (sum off) else d | (j, d) <- zip [0 ..] offAll ]
  where
    lam j = 1 / product [ xs !! j - xm | (m, xm) <- zip [0 :: Int ..] xs, m /= j ]
    offAll = [ if j == k then 0 else (lam j / lam k) / (xs !! k - xs !! j) | j <- [0 .. length xs - 1] ]
    off = [ d | (j, d) <- zip [0 ..] offAll, j /= k ]

-- | The tolerance of a slope from samples whose nearest two are h apart, of values up to y:
-- rounding in the differences of values over h, on a graded grid.
slopeTolerance :: Double -> Double -> Double
slopeTolerance h y = 1e-11 * (1 + y) / h + 1e-9

spec :: Spec
spec = describe "VProf.Plan.Track" $ do
  it "lagrangeWeights give the exact slope of any polynomial of degree below the number of nodes, at each node" $
    property $ forAll (choose (2, 5)) $ \m -> forAll (genSteps (m - 1)) $ \hs -> forAll (choose (0, 10)) $ \x0 ->
      forAll (genPoly (m - 1) x0) $ \p -> forAll (choose (0, m - 1)) $ \at ->
        let xs = scanl (+) x0 hs
            x = xs !! at
            got = sum (zipWith (*) (lagrangeWeights xs x) (map (evalP p) xs))
            want = slopeP p x
            -- the rounding of weights as large as these (an end's slope from a cluster of nodes
            -- far from it has weights of 1e10 and more)
            scale = sum [ abs (w * evalP p xj) | (w, xj) <- zip (diffWeights xs at) xs ]
        in counterexample (show (xs, x, got, want)) $ abs (got - want) <= 1e-13 * scale + 1e-12 * abs want

  it "jointPath: a quartic motion of every joint gets its exact slope at every sample, seen from either side" $
    property $ forAll (choose (5, 60)) $ \nS -> forAll (genGradedSteps (nS - 1)) $ \hs -> forAll (choose (1, 7)) $ \n ->
      forAll (vectorOf n (genPoly 4 0.3)) $ \ps ->
        let ss = U.fromList (scanl (+) 0 hs)
            tk = Tracked ss (U.concat [ U.fromList [ evalP p s | p <- ps ] | s <- U.toList ss ]) n
            jp = jointPath [] tk
            y = maximum [ abs (evalP p s) | p <- ps, s <- U.toList ss ]
        in conjoin [ counterexample ("sample " ++ show k ++ ", joint " ++ show i ++ ": " ++ show (side U.! (k * n + i), slopeP p s)) $
                       abs (side U.! (k * n + i) - slopeP p s) <= slopeTolerance (minimum hs) y + 1e-9 * abs (slopeP p s)
                   | (k, s) <- zip [0 ..] (U.toList ss), (i, p) <- zip [0 ..] ps, side <- [jpLeft jp, jpRight jp] ]

  it "jointPath: at a stop each side's slope is that of its own side's motion (the path keeps its corner)" $
    property $ forAll (choose (10, 60)) $ \nS -> forAll (choose (4, nS - 5)) $ \kStop -> forAll (genGradedSteps (nS - 1)) $ \hs ->
      let ss = U.fromList (scanl (+) 0 hs)
          sStop = ss U.! kStop
      in forAll (genPoly 4 0.2) $ \before -> forAll (genPoly 4 sStop) $ \after0 ->
        -- the motion after the stop starts where the one before it ends
        let Poly c0 (_ : cs) = after0
            after = Poly c0 (evalP before sStop : cs)
            motion s = if s <= sStop then evalP before s else evalP after s
            tk = Tracked ss (U.map motion ss) 1
            jp = jointPath [sStop] tk
            y = U.maximum (U.map (abs . motion) ss)
            tol w = slopeTolerance (minimum hs) y + 1e-9 * abs w
            expect k side = if k < kStop || (k == kStop && side == "left") then slopeP before (ss U.! k) else slopeP after (ss U.! k)
        in conjoin [ counterexample ("sample " ++ show k ++ " (stop " ++ show kStop ++ "), " ++ side ++ ": " ++ show (v U.! k, expect k side)) $
                       abs (v U.! k - expect k side) <= tol (expect k side)
                   | k <- [0 .. nS - 1], (side, v) <- [("left", jpLeft jp), ("right", jpRight jp)] ]

  it "jointPathAt passes through every sample" $
    property $ forAll (choose (2, 40)) $ \nS -> forAll (genSteps (nS - 1)) $ \hs -> forAll (vectorOf nS (choose (-3, 3))) $ \qs ->
      let ss = U.fromList (scanl (+) 0 hs)
          jp = jointPath [] (Tracked ss (U.fromList qs) 1)
      in conjoin [ abs (jointPathAt jp s U.! 0 - x) <= 1e-12 * (1 + abs x) | (s, x) <- zip (U.toList ss) qs ]
