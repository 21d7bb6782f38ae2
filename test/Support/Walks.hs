-- | Random recordings for the compression tests: a walk with a few sharp turns, where a
-- path of few straight moves has corners to cut and a largest error well above its RMSE.
module Support.Walks
  ( genKickWalk
  , genWalkCase
  ) where

import qualified Data.Vector.Unboxed as U
import Test.QuickCheck

import VProf.Compress.Objective
import VProf.Compress.Types
import VProf.Geometry.Quaternion
import VProf.Geometry.Vec

-- | A random walk of n samples (steps up to 2 cm times @scale@, 10 ms apart with jitter)
-- with a few sharp turns (kicks up to 30 cm times @scale@), turning slowly in orientation.
genKickWalk :: Double -> Int -> Gen Prepared
genKickWalk scale n = do
  dts <- vectorOf (n - 1) (choose (0.008, 0.012))
  steps <- vectorOf (n - 1) (P3 <$> choose (-0.02, 0.02) <*> choose (-0.02, 0.02) <*> choose (-0.02, 0.02))
  kicks <- vectorOf (n - 1) (frequency [(40, pure (P3 0 0 0)), (1, P3 <$> choose (-0.3, 0.3) <*> choose (-0.3, 0.3) <*> choose (-0.3, 0.3))])
  rots <- vectorOf (n - 1) (P3 <$> choose (-0.02, 0.02) <*> choose (-0.02, 0.02) <*> choose (-0.02, 0.02))
  t0 <- choose (0, 1.0e9)
  let ts = scanl (+) t0 dts
      ps = map (scale *^) (scanl (\p (s, kk) -> p ^+^ s ^+^ kk) (P3 0 0 0) (zip steps kicks))
      qs = scanl (\q r -> qnormalize (qmul (qexp r) q)) (Q4 1 0 0 0) rots
  pure (prepareRecording (either error id (recordingFromArrays (U.fromList ts) (pfromList ps) (pfromList qs))))

-- | A case for the knot fit's last steps: a walk of 60-400 samples with its positions scaled
-- by 1 mm to 1 km, ends pinned or fitted, and a waypoint count from 3 to a fifth of the
-- samples; with the scale drawn.
genWalkCase :: Gen (Prepared, Int, Double)
genWalkCase = do
  n <- choose (60, 400)
  scale <- (10 **) <$> choose (-3, 3)
  pr0 <- genKickWalk scale n
  ends <- elements [EndsPinned, EndsFree]
  k <- choose (3, n `div` 5)
  pure (pr0 { rcEnds = ends }, k, scale)
