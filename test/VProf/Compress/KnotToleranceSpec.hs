-- | The knot fit to a tolerance: the search for the fewest points (the count it answers
-- meets the tolerance, one fewer breaks it, no count it tried is reported with a larger
-- error than the knot fit's there) and its exchanges for the largest error (same count,
-- times in order and apart, ends held, the largest error lower). Errors are measured
-- independently: the path interpolated at every sample's time.
module VProf.Compress.KnotToleranceSpec (spec) where

import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.Hspec.QuickCheck (modifyMaxSuccess)
import Test.QuickCheck

import VProf.Compress.KnotFit
import VProf.Compress.KnotTimes
import VProf.Compress.KnotTolerance
import VProf.Compress.Objective
import VProf.Compress.Types
import Support.PathError (worstPositionError)
import Support.Walks (genKickWalk)
import VProf.Geometry.Vec

-- | Largest distance from a sample to the positions interpolated linearly in time.
worstOf :: Prepared -> U.Vector Double -> V3s -> Double
worstOf pr t p = worstPositionError (Track t p (still (U.length t))) (Track (rcT pr) (rcP pr) (still (U.length (rcT pr))))
  where still m = pgenerate m (const (Q4 1 0 0 0)) :: Qs

spec :: Spec
spec = do
  describe "fitKnotsTolerance" $
    it "answers the fewest count it tried within the tolerance (measured here), one fewer tried and above it, no try's error above the knot fit's as measured here" $
      property $ forAll (choose (60, 200)) $ \n -> forAllBlind (genKickWalk 1 n) $ \pr ->
        forAll (choose (-2, -0.3)) $ \e -> forAll (frequency [(3, pure 2), (1, choose (2, n `div` 4))]) $ \kMin ->
          let tol = 10 ** e :: Double
              r = fitKnotsTolerance defaultKnotConfig pr defaultWeights kMin tol
              PathA t p _ = tfPath r
              k = U.length t
              worst = worstOf pr t p
              -- a try's largest error is the knot fit's, or lower where the exchanges for the
              -- largest error lowered it
              measured (kk, ek) | kk >= n = ek == 0
                                | otherwise = let PathA t' p' _ = fitKnots defaultKnotConfig pr defaultWeights kk
                                              in ek <= worstOf pr t' p' * (1 + 1e-9)
              tried = tfTried r
          in counterexample (show (tol, k, worst, tried)) $
               cover 30 (k > kMin && k < n) "between" $
               worst <= tol * (1 + 1e-9) .&&. abs (tfMaxError r - worst) <= 1e-9 * max 1 worst
               .&&. k >= kMin
               .&&. (k == kMin || any (\(kk, ek) -> kk == k - 1 && ek > tol) tried)
               .&&. (k == n || any (\(kk, ek) -> kk == k && ek <= tol) tried)
               .&&. conjoin [ counterexample (show t') (measured t') | t'@(kk, _) <- tried, kk /= k ]
  describe "fitKnotsTolerance, a bound far below any error" $ modifyMaxSuccess (min 12) $
    it "halves its way to the recording itself in a few dozen fits at most (a bound of 1e-36 mm overflowed the next count's Int, and the search walked up one count a fit)" $
      property $ forAll (choose (60, 120)) $ \n -> forAllBlind (genKickWalk 1 n) $ \pr -> forAll (elements [1e-39, 1e-100, 5e-324]) $ \tol ->
        let r = fitKnotsTolerance defaultKnotConfig pr defaultWeights 2 tol
        in counterexample (show (tfTried r)) $
             length (tfTried r) <= 2 * ceiling (logBase 2 (fromIntegral n :: Double)) + 4 .&&. tfMaxError r <= tol
  describe "repairWorst" $
    it "keeps the count, the ends and times in order at least the least gap apart, and lowers the largest error when it changes the knots" $
      property $ forAll (choose (60, 400)) $ \n -> forAll (choose (4, n `div` 10)) $ \k -> forAllBlind (genKickWalk 1 n) $ \pr ->
        let kn0 = optimiseKnots defaultKnotConfig pr (startKnots defaultKnotConfig pr k)
            w0 = worstOf pr (kT kn0) (kP kn0)
        in case repairWorst pr (kcIterations defaultKnotConfig) 0 kn0 of
             Nothing -> label "no exchange kept" True
             Just kn ->
               let ts = kT kn
               in label "exchanged" $ counterexample (show (w0, worstOf pr ts (kP kn))) $
                    U.length ts === k .&&. U.head ts === U.head (kT kn0) .&&. U.last ts === U.last (kT kn0)
                    .&&. pindex (kP kn) 0 === pindex (kP kn0) 0 .&&. pindex (kP kn) (k - 1) === pindex (kP kn0) (k - 1)
                    .&&. U.and (U.zipWith (\a b -> b - a >= rcMinGap pr * (1 - 1e-9)) ts (U.tail ts))
                    .&&. worstOf pr ts (kP kn) < w0
