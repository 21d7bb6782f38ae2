-- | The nearest-segment index gives exactly the brute-force minimum over all segments.
module VProf.Geometry.NearestSegmentSpec (spec) where

import Test.Hspec
import Test.QuickCheck

import VProf.Geometry.NearestSegment
import VProf.Geometry.Polyline (pointSegmentDistance)
import VProf.Geometry.Vec

genP3 :: Gen P3
genP3 = P3 <$> choose (-2, 2) <*> choose (-2, 2) <*> choose (-2, 2)

spec :: Spec
spec = describe "nearestSegmentDistance" $
  it "equals the minimum of pointSegmentDistance over every segment (random polylines of 2-200 vertices, clustered or spread)" $
    property $ forAll (choose (2, 200)) $ \k -> forAll (elements [0.01, 1]) $ \step ->
      forAll (vectorOf k genP3) $ \raw -> forAll (vectorOf 20 genP3) $ \qs ->
        let vs = pfromList (scanl1 (\a b -> a ^+^ step *^ b) raw) :: V3s
            idx = buildSegIndex vs
            brute x = minimum [ pointSegmentDistance (pindex vs j) (pindex vs (j + 1)) x | j <- [0 .. k - 2] ]
        in conjoin [ counterexample (show x) (nearestSegmentDistance idx (1 / 0) x === brute x) | x <- qs ]
