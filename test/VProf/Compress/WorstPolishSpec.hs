-- | The worst-error polish: it never raises the largest position error, keeps the sum of
-- squares and the position-and-velocity objective within its budget, moves no time,
-- orientation or pinned end, does nothing at budget 0, and on real recordings lowers the
-- largest error by a tenth or more and, to a tolerance, the number of points. Errors are measured independently of vprof's own code
-- (the path interpolated at every sample's time, "Support.PathError").
module VProf.Compress.WorstPolishSpec (spec) where

import qualified Data.Vector.Unboxed as U
import Numeric.Units.Dimensional.Prelude (metre, milli, (*~))
import Prelude
import Test.Hspec
import Test.QuickCheck

import VProf.Compress
import VProf.Compress.KnotFit
import VProf.Compress.Objective
import VProf.Compress.WorstPolish
import Support.PathError (positionErrorsOf, withinBudget)
import Support.Recordings (loadTum)
import Support.Walks (genWalkCase)

-- | Every sample's position error of a path, measured by the oracle.
errorsOf :: Prepared -> PathA -> [Double]
errorsOf pr (PathA t p q) = positionErrorsOf (Track t p q) (Track (rcT pr) (rcP pr) (rcQ pr))

sumSquares :: [Double] -> Double
sumSquares = sum . map (^ (2 :: Int))

-- | A recording, a knot fit of it without the polish, and the settings drawn: positions
-- scaled by 1 mm to 1 km, 60-400 samples, 3 to a fifth of them waypoints, ends pinned or
-- fitted, weights of position and velocity over four decades each.
data Case = Case Prepared Weights Int Double

genCase :: Gen Case
genCase = do
  (pr, k, _) <- genWalkCase
  wv <- (10 **) <$> choose (-8, -4)
  wp <- (10 **) <$> choose (-2, 2)
  budget <- elements [0.001, 0.01, 0.05]
  pure (Case pr (Weights wp 1e-3 wv) k budget)

instance Show Case where
  show (Case pr w k b) = show (U.length (rcT pr), rcEnds pr, w, k, b)

spec :: Spec
spec = describe "VProf.Compress.WorstPolish" $ do
  it "measures each sample's position error as the oracle does" $
    property $ forAll genCase $ \(Case pr w k _) ->
      let pa = fitKnots defaultKnotConfig { kcWorstBudget = 0 } pr w k
          ours = U.toList (positionErrors pr pa)
          oracle = errorsOf pr pa
          scale = maximum (map abs oracle) + 1e-300
      in conjoin [ counterexample (show (i, a, b)) (abs (a - b) <= 1e-9 * scale) | (i, a, b) <- zip3 [0 :: Int ..] ours oracle ]

  it "never raises the largest error, stays within its budget, and moves no time, orientation or pinned end" $
    property $ forAll genCase $ \c@(Case pr w k b) ->
      let pa0@(PathA t0 p0 q0) = fitKnots defaultKnotConfig { kcWorstBudget = 0 } pr w k
          pa@(PathA t p q) = polishWorst b pr w pa0
          e0 = errorsOf pr pa0
          e = errorsOf pr pa
          lowered = maximum e < maximum e0 * (1 - 1e-9)
      in counterexample (show (c, maximum e0, maximum e)) $
           cover 30 lowered "largest error lowered" $
           t === t0 .&&. q === q0
           .&&. maximum e <= maximum e0 * (1 + 1e-12)
           .&&. withinBudget pr w b pa0 pa
           .&&. (lowered || p == p0)

  it "leaves the path as it is at budget 0" $
    property $ forAll genCase $ \(Case pr w k _) ->
      let pa0 = fitKnots defaultKnotConfig { kcWorstBudget = 0 } pr w k
      in polishWorst 0 pr w pa0 === pa0

  it "on freiburg1_xyz at 1 % and V1_01 at 3 %: the largest error a tenth lower or more, the RMSE at most 0.25 % higher, the same waypoint times" $ do
    let check file k = do
          rec <- loadTum file
          let pr = prepareRecording rec
              -- the polish alone: the orientation balance, which moves times, left out of both
              fit b = fitKnots defaultKnotConfig { kcOrientBudget = 0, kcWorstBudget = b } pr defaultWeights k
              on@(PathA tOn _ _) = fit worstBudget
              off@(PathA tOff _ _) = fit 0
              measure pa = let e = errorsOf pr pa in (maximum e, sqrt (sumSquares e / fromIntegral (length e)))
              (mxOn, rmseOn) = measure on
              (mxOff, rmseOff) = measure off
          (file, mxOn <= 0.9 * mxOff, rmseOn <= 1.0025 * rmseOff, tOn == tOff) `shouldBe` (file, True, True, True)
    check "freiburg1_xyz-groundtruth.txt" 30
    check "V101_gt.txt" 87

  it "to a tolerance (V1_01 at 100 mm, freiburg1_xyz at 30 mm): fewer points than least squares alone, the tolerance kept" $ do
    let check file mm = do
          rec <- loadTum file
          let settings = defaultSettings { sTolerance = Just (mm *~ milli metre) }
              Right on = compress settings rec
              Right off = compress settings { sPolish = False } rec
              pr = prepareRecording rec
              worst o = maximum (errorsOf pr (toPathA (oPath o)))
              points o = let Path (Track t _ _) = oPath o in U.length t
          (file, points on < points off, worst on <= mm * 1e-3 * (1 + 1e-9), worst off <= mm * 1e-3 * (1 + 1e-9))
            `shouldBe` (file, True, True, True)
    check "V101_gt.txt" 100
    check "freiburg1_xyz-groundtruth.txt" 30
