-- | The continuous dynamic program of the knot fit's wider search: with every history kept it
-- is the exact best path with waypoints at sample times, checked against brute force over all
-- waypoint subsets (positions solved by the band least squares of "VProf.Compress.KnotTimes",
-- not by the program's quadratics), with the ends pinned and free; with a beam of one its
-- reported error is the error of the path it returns, its waypoints inside their bands; on
-- V1_01 at 1 % the first search round that starts from it finds a better path than the default.
module VProf.Compress.KnotDPSpec (spec) where

import Data.List (subsequences)
import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import VProf.Compress.KnotDP
import VProf.Compress.KnotFit
import VProf.Compress.KnotTimes
import VProf.Compress.Objective
import VProf.Compress.Types
import VProf.Geometry.Vec
import Support.Recordings (loadTum)

-- | n samples over a wide range of scales: sample spacing 1 ms to 0.5 s (uneven), steps of
-- 1 mm to 10 m, start time up to 1e9 s.
genWide :: Int -> Gen Prepared
genWide n = do
  dt <- elements [1e-3, 1e-2, 0.1, 0.5]
  scale <- elements [1e-3, 1e-1, 1, 10]
  dts <- vectorOf (n - 1) (choose (0.3 * dt, 1.7 * dt))
  steps <- vectorOf (n - 1) (P3 <$> choose (-scale, scale) <*> choose (-scale, scale) <*> choose (-scale, scale))
  t0 <- choose (0, 1.0e9)
  let ts = scanl (+) t0 dts
      ps = scanl (^+^) (P3 0 0 0) steps
      qs = replicate n (Q4 1 0 0 0)
  pure (prepareRecording (either error id (recordingFromArrays (U.fromList ts) (pfromList ps) (pfromList qs))))

-- | The path's position SSE with waypoints at the given samples, its positions the band least
-- squares of "VProf.Compress.KnotTimes" for those times.
sseAt :: Prepared -> [Int] -> Double
sseAt pr idx =
  let ts = U.fromList (map (rcT pr U.!) idx)
      k = length idx
      kn = solveStretchPositions pr (Knots ts (pfromList (map (pindex (rcP pr)) idx))) 0 (k - 1)
  in knotSse pr kn

close :: Double -> Double -> Property
close a b = counterexample (show (a, b)) (abs (a - b) <= 1e-6 * max a b + 1e-12)

-- | 'close' with the rounding floor of the program's arithmetic: it takes each quadratic's
-- minimum as γ − |β|²/α, which cancels to about 1e-16 of the positions' spread Σ|p − p̄|²
-- (5 samples fitted exactly by 5 waypoints, their spread some 1e4 m², came out at 3.5e-12 m²
-- where brute force found 8e-30).
closeFor :: Prepared -> Double -> Double -> Property
closeFor pr a b = counterexample (show (a, b, floor')) (abs (a - b) <= 1e-6 * max a b + floor')
  where
    ps = ptoList (rcP pr)
    m = fromIntegral (length ps) :: Double
    P3 cx cy cz = foldr (\(P3 x y z) (P3 a' b' c') -> P3 (x + a') (y + b') (z + c')) (P3 0 0 0) ps
    spread = sum [ (x - cx / m) ^ (2 :: Int) + (y - cy / m) ^ (2 :: Int) + (z - cz / m) ^ (2 :: Int) | P3 x y z <- ps ]
    floor' = 1e-12 + 1e-13 * spread

exactMatchesBruteForce :: Ends -> Property
exactMatchesBruteForce ends =
  forAll (choose (4, 11)) $ \n -> forAll (choose (3, min 5 n)) $ \k -> forAllBlind (genWide n) $ \pr0 ->
    let pr = pr0 { rcEnds = ends }
        (idx, v) = continuousKnots pr k 100000 (const (1, n - 2)) n
        subsets = [ [0] ++ s ++ [n - 1] | s <- subsequences [1 .. n - 2], length s == k - 2 ]
        brute = minimum (map (sseAt pr) subsets)
    in closeFor pr v brute .&&. closeFor pr (sseAt pr (U.toList idx)) brute

spec :: Spec
spec = do
  describe "continuousKnots" $ do
    it "keeping every history, is the best path with waypoints at samples (brute force over all subsets), ends pinned" $
      property (exactMatchesBruteForce EndsPinned)
    it "the same with the ends free" $
      property (exactMatchesBruteForce EndsFree)
    it "with a beam of one and a band: k increasing samples from first to last, each in its band, the reported error the path's own" $
      property $ forAll (choose (20, 400)) $ \n -> forAll (choose (3, n `div` 4)) $ \k -> forAll (choose (1, 3)) $ \spread ->
        forAll (elements [EndsPinned, EndsFree]) $ \ends -> forAllBlind (genWide n) $ \pr0 ->
          let pr = pr0 { rcEnds = ends }
              centre j = (j * (n - 1)) `div` (k - 1)
              g = max 1 (n `div` (k - 1))
              band j = (centre j - spread * g, centre j + spread * g)
              (idx, v) = continuousKnots pr k 1 band n
              inBand = and [ let (a, b) = band j in x >= a && x <= b | (j, x) <- zip [0 ..] (U.toList idx), j > 0, j < k - 1 ]
          in U.length idx === k .&&. U.head idx === 0 .&&. U.last idx === n - 1
               .&&. U.and (U.zipWith (<) idx (U.tail idx)) .&&. inBand .&&. close v (sseAt pr (U.toList idx))
  describe "the wider search's first round (the continuous start)" $
    it "on V1_01 at 1 % (29 points) finds a path at least 0.5 % lower in position error than the default" $ do
      pr <- prepareRecording <$> loadTum "V101_gt.txt"
      let k = 29
          base = optimiseKnots defaultKnotConfig pr (startKnots defaultKnotConfig pr k)
          wide = searchKnots defaultKnotConfig { kcSearch = 1 } pr base
      knotSse pr wide `shouldSatisfy` (< 0.995 * knotSse pr base)
