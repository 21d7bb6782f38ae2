-- | The plots' decimation: what is drawn keeps the line's shape (its first and last point,
-- each run's lowest and highest) and is a subsequence of the points given.
module VProf.Plot.DecimateSpec (spec) where

import Data.List (isSubsequenceOf)
import Test.Hspec
import Test.QuickCheck

import VProf.Plot.Decimate (decimate)

-- | A line of n points in time, the values anything from smooth to spiky.
genLine :: Gen [(Double, Double)]
genLine = do
  n <- oneof [choose (0, 50), choose (50, 5000)]
  ys <- oneof [ vectorOf n (choose (-1e3, 1e3))
              , (\f -> map (sin . (* f) . fromIntegral) [1 .. n]) <$> choose (0.001, 3)
              , pure (replicate n 7) ]
  pure (zip (map fromIntegral [0 .. n - 1 :: Int]) ys)

spec :: Spec
spec = describe "decimate" $ do
  it "leaves a line of at most 4 points a run alone" $ property $ forAll genLine $ \pts -> forAll (choose (1, 50)) $ \runs ->
    length pts <= 4 * runs ==> decimate runs pts === pts
  it "keeps at most 4 points a run, in order, each one of the line's, the first and the last, and every run's lowest and highest" $
    property $ forAll genLine $ \pts -> forAll (choose (1, 300)) $ \runs ->
      let out = decimate runs pts
          n = length pts
          size = (n + runs - 1) `div` runs
          chunk k = take size (drop (k * size) pts)
          runsOf = takeWhile (not . null) (map chunk [0 ..])
      in length pts > 4 * runs ==>
           counterexample (show (length out)) $
             property (length out <= 4 * runs) .&&. property (out `isSubsequenceOf` pts)
             .&&. head out === head pts .&&. last out === last pts
             .&&. conjoin [ property (any (\(_, y) -> y == minimum (map snd r)) (filter (`elem` r) out)
                                      && any (\(_, y) -> y == maximum (map snd r)) (filter (`elem` r) out)) | r <- runsOf ]
