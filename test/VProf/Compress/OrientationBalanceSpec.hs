-- | The orientation balance: it never raises the orientation error, keeps the position sum of
-- squares and the position-and-velocity objective within its budget, keeps the number of
-- waypoints, the end times and pinned ends, does nothing at budget 0 or without an
-- orientation weight, and on real recordings (freiburg1_xyz at 1 % and 0.5 %, V1_01 at 3 %)
-- lowers the orientation error within a quarter of a per cent of position RMSE. Errors are
-- measured independently of vprof's own code ("Support.PathError").
module VProf.Compress.OrientationBalanceSpec (spec) where

import qualified Data.Vector.Unboxed as U
import Prelude
import Test.Hspec
import Test.QuickCheck

import VProf.Compress
import VProf.Compress.KnotFit
import VProf.Compress.Objective
import VProf.Compress.OrientationBalance
import Support.PathError (orientationErrorsOf, positionErrorsOf, withinBudget)
import Support.Recordings (loadTum)
import Support.Walks (genWalkCase)

-- | Every sample's (position, orientation) errors of a path, measured by the oracle.
errorsOf :: Prepared -> PathA -> ([Double], [Double])
errorsOf pr (PathA t p q) = (positionErrorsOf path rec, orientationErrorsOf path rec)
  where
    path = Track t p q
    rec = Track (rcT pr) (rcP pr) (rcQ pr)

sumSquares :: [Double] -> Double
sumSquares = sum . map (^ (2 :: Int))

rms :: [Double] -> Double
rms xs = sqrt (sumSquares xs / fromIntegral (length xs))

-- | A recording (a walk with sharp turns, turning slowly), a knot fit of it without the
-- balance and the worst-error polish, and the settings drawn: positions scaled by 1 mm to
-- 1 km, 60-400 samples, 3 to a fifth of them waypoints, ends pinned or fitted, the
-- orientation weight over eight decades (from almost nothing to ten times the position's
-- scale), budgets 0.1-5 %.
data Case = Case Prepared Weights Int Double

genCase :: Gen Case
genCase = do
  (pr, k, scale) <- genWalkCase
  wp <- (10 **) <$> choose (-2, 2)
  wo <- (* (wp * scale * scale)) . (10 **) <$> choose (-7, 1)
  wv <- (10 **) <$> choose (-8, -4)
  budget <- elements [0.001, 0.005, 0.01, 0.05]
  pure (Case pr (Weights wp wo wv) k budget)

instance Show Case where
  show (Case pr w k b) = show (U.length (rcT pr), rcEnds pr, w, k, b)

leastSquares :: Prepared -> Weights -> Int -> PathA
leastSquares = fitKnots defaultKnotConfig { kcOrientBudget = 0, kcWorstBudget = 0 }

spec :: Spec
spec = describe "VProf.Compress.OrientationBalance" $ do
  it "tries the orientation weight at m*/16 … m* for m* the ratio of the terms, those above 1, none for a zero term" $ do
    multipliers 64 1 `shouldBe` [4, 8, 16, 32, 64]
    multipliers 6 1 `shouldBe` [1.5, 3, 6]
    multipliers 1 1 `shouldBe` []
    multipliers 0 1 `shouldBe` []
    multipliers 1 0 `shouldBe` []
    multipliers (0 / 0) 1 `shouldBe` []

  it "never raises the orientation error, stays within its budget, and keeps the waypoint count, end times and pinned ends" $
    property $ forAll genCase $ \c@(Case pr w k b) ->
      let pa0@(PathA t0 _ _) = leastSquares pr w k
          pa@(PathA t _ _) = balanceOrientation b pr w pa0
          eo0 = snd (errorsOf pr pa0)
          eo = snd (errorsOf pr pa)
          lowered = sumSquares eo < sumSquares eo0 * (1 - 1e-9)
      in counterexample (show (c, sumSquares eo0, sumSquares eo)) $
           cover 20 lowered "orientation error lowered" $
           U.length t === U.length t0
           .&&. U.head t === U.head t0 .&&. U.last t === U.last t0
           .&&. U.and (U.zipWith (<) t (U.tail t))
           .&&. sumSquares eo <= sumSquares eo0 * (1 + 1e-9)
           .&&. withinBudget pr w b pa0 pa
           .&&. (lowered || pa == pa0)

  it "leaves the path as it is at budget 0 and without an orientation weight" $
    property $ forAll genCase $ \(Case pr w k b) ->
      let pa0 = leastSquares pr w k
      in balanceOrientation 0 pr w pa0 === pa0
         .&&. balanceOrientation b pr w { wOrientation = 0 } pa0 === pa0

  it "on freiburg1_xyz at 1 % and 0.5 % and V1_01 at 3 %: the orientation RMSE 0.5 % lower or more, the position RMSE at most 0.25 % higher" $ do
    let check file k = do
          rec <- loadTum file
          let pr = prepareRecording rec
              off = leastSquares pr defaultWeights k
              on = balanceOrientation orientationBudget pr defaultWeights off
              (epOff, eoOff) = errorsOf pr off
              (epOn, eoOn) = errorsOf pr on
          (file, k, rms eoOn <= 0.995 * rms eoOff, rms epOn <= 1.0025 * rms epOff) `shouldBe` (file, k, True, True)
    check "freiburg1_xyz-groundtruth.txt" 30
    check "freiburg1_xyz-groundtruth.txt" 15
    check "V101_gt.txt" 87

  it "is part of the default knot fit and left out by least squares only (sPolish False)" $ do
    rec <- loadTum "freiburg1_xyz-groundtruth.txt"
    let pr = prepareRecording rec
        ori s = rms (snd (errorsOf pr (toPathA (oPath (either (error . show) id (compress s rec))))))
        Right plain = compress defaultSettings { sPoints = Just 30, sPolish = False } rec
    ori defaultSettings { sPoints = Just 30 } `shouldSatisfy` (< ori defaultSettings { sPoints = Just 30, sPolish = False })
    toPathA (oPath plain) `shouldBe` leastSquares pr defaultWeights 30
