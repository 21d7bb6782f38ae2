-- | The knot fit and its parts: the line partition start, the joint refinement of waypoint
-- times and positions, the exchanges, and the whole fit's contract (k points, pinned ends,
-- strictly increasing times, never worse than its start, a known path recovered); with the
-- ends fitted, the end positions checked as least-squares optima by perturbation.
module VProf.Compress.KnotFitSpec (spec) where

import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import VProf.Compress.KnotFit
import VProf.Compress.Metrics
import VProf.Compress.KnotTimes
import VProf.Compress.Objective
import VProf.Compress.Partition
import VProf.Compress.Types
import VProf.Geometry.Polyline (polylineAt)
import VProf.Geometry.Quaternion
import VProf.Geometry.Vec
import Support.Recordings (loadTum)

-- | A random walk of n samples (steps up to 2 cm, 10 ms apart with jitter), turning slowly.
genWalk :: Int -> Gen Prepared
genWalk n = do
  dts <- vectorOf (n - 1) (choose (0.008, 0.012))
  steps <- vectorOf (n - 1) (P3 <$> choose (-0.02, 0.02) <*> choose (-0.02, 0.02) <*> choose (-0.02, 0.02))
  drift <- P3 <$> choose (-0.01, 0.01) <*> choose (-0.01, 0.01) <*> choose (-0.01, 0.01)
  rots <- vectorOf (n - 1) (P3 <$> choose (-0.02, 0.02) <*> choose (-0.02, 0.02) <*> choose (-0.02, 0.02))
  t0 <- choose (0, 1.0e9)
  let ts = scanl (+) t0 dts
      ps = scanl (\p s -> p ^+^ s ^+^ drift) (P3 0 0 0) steps
      qs = scanl (\q r -> qnormalize (qmul (qexp r) q)) (Q4 1 0 0 0) rots
  pure (prepareRecording (either error id (recordingFromArrays (U.fromList ts) (pfromList ps) (pfromList qs))))

-- | A true path of K waypoints (segments 1–2.5 s, positions in a 1 m cube) sampled every
-- 20 ms with uniform position noise of 1 mm.
genKnown :: Gen (U.Vector Double, Prepared)
genKnown = do
  k <- choose (3, 8)
  durs <- vectorOf (k - 1) (choose (1.0, 2.5))
  ps <- vectorOf k (P3 <$> choose (-0.5, 0.5) <*> choose (-0.5, 0.5) <*> choose (-0.5, 0.5))
  let tv = U.fromList (scanl (+) 0 durs)
      pv = pfromList ps :: V3s
      qv = pfromList (replicate k (Q4 1 0 0 0)) :: Qs
      n = floor (U.last tv / 0.02) + 1 :: Int
      st = [ 0.02 * fromIntegral i | i <- [0 .. n - 1] ]
  noise <- vectorOf n (P3 <$> choose (-1e-3, 1e-3) <*> choose (-1e-3, 1e-3) <*> choose (-1e-3, 1e-3))
  let pts = zipWith (\t e -> fst (polylineAt tv pv qv t) ^+^ e) st noise
      rec = either error id (recordingFromArrays (U.fromList st) (pfromList pts) (pfromList (replicate n (Q4 1 0 0 0))))
  pure (tv, prepareRecording rec)

strictlyIncreasing :: U.Vector Double -> Bool
strictlyIncreasing v = U.and (U.zipWith (<) v (U.tail v))

-- | The objective never falls when the first or the last waypoint's position moves by ±h
-- along any axis (an optimality check independent of the solver: the objective is a
-- quadratic in each position, so this holds at its minimum and fails away from it).
endsAreOptimal :: (PathA -> Double) -> PathA -> Double -> Property
endsAreOptimal cost pa@(PathA t p q) h =
  conjoin [ counterexample (show (j, d, c0, c)) (c >= c0 - 1e-9 * c0 - 1e-15)
          | j <- [0, plength p - 1], d <- dirs, let c = cost (PathA t (pupdate p [(j, pindex p j ^+^ d)]) q) ]
  where
    c0 = cost pa
    dirs = [ s *^ e | s <- [h, negate h], e <- [P3 1 0 0, P3 0 1 0, P3 0 0 1] ]

positionSse :: Prepared -> PathA -> Double
positionSse pr (PathA t p _) = knotSse pr (Knots t p)

spec :: Spec
spec = do
  describe "linePartition" $ do
    it "gives exactly m groups of at least 2 samples, from 0 to n" $
      property $ forAll (choose (40, 400)) $ \n -> forAll (choose (1, n `div` 3)) $ \m -> forAllBlind (genWalk n) $ \pr ->
        let b = linePartition (rcT pr) (rcP pr) m (4 * ((n + m - 1) `div` m))
            sizes = U.zipWith (-) (U.tail b) b
        in counterexample (show (U.toList b)) $
             U.length b === m + 1 .&&. U.head b === 0 .&&. U.last b === n .&&. U.all (>= 2) sizes
    it "its SSE is at most that of m equal groups" $
      property $ forAll (choose (40, 400)) $ \n -> forAll (choose (1, n `div` 3)) $ \m -> forAllBlind (genWalk n) $ \pr ->
        let s = prefixSums (rcT pr) (rcP pr)
            b = linePartition (rcT pr) (rcP pr) m (4 * ((n + m - 1) `div` m))
            sse v = sum [ groupSse s (v U.! g) (v U.! (g + 1)) | g <- [0 .. U.length v - 2] ]
            eq = U.generate (m + 1) (\g -> (g * n) `div` m)
        in sse b <= sse eq * (1 + 1e-9) + 1e-12

    it "on a coarser grid (a long recording's dynamic program: boundaries every r samples, then each moved within r): still m groups of at least 2 samples, never worse than equal groups" $
      property $ forAll (choose (40, 400)) $ \n -> forAll (choose (1, n `div` 3)) $ \m -> forAll (choose (50, 5000)) $ \work ->
        forAllBlind (genWalk n) $ \pr ->
          let s = prefixSums (rcT pr) (rcP pr)
              w = 4 * ((n + m - 1) `div` m)
              b = linePartitionWith (fromIntegral (work :: Int)) (rcT pr) (rcP pr) m w
              sizes = U.zipWith (-) (U.tail b) b
              sse v = sum [ groupSse s (v U.! g) (v U.! (g + 1)) | g <- [0 .. U.length v - 2] ]
              eq = U.generate (m + 1) (\g -> (g * n) `div` m)
          in counterexample (show (U.toList b)) $
               U.length b === m + 1 .&&. U.head b === 0 .&&. U.last b === n .&&. U.all (>= 2) sizes
               .&&. property (sse b <= sse eq * (1 + 1e-9) + 1e-12)
  describe "refineAll (waypoint times with positions)" $
    it "never raises the position error of the least-squares positions at the start times; ends held, times increasing" $
      property $ forAll (choose (60, 400)) $ \n -> forAll (choose (3, n `div` 10)) $ \k -> forAllBlind (genWalk n) $ \pr ->
        let st = rcT pr
            ts = U.generate k (\j -> st U.! ((j * (n - 1)) `div` (k - 1)))
            kn0 = solveStretchPositions pr (Knots ts (pgenerate k (const (P3 0 0 0)))) 0 (k - 1)
            (kn, f) = refineAll pr 50 kn0
            f0 = knotSse pr kn0
        in counterexample (show (f0, f)) $
             f <= f0 * (1 + 1e-12) .&&. strictlyIncreasing (kT kn)
               .&&. U.head (kT kn) === U.head st .&&. U.last (kT kn) === U.last st
               .&&. abs (knotSse pr kn - f) <= 1e-9 * max 1e-12 f

  describe "free ends (--ends free)" $ do
    it "at fixed times: never a higher position error than pinned ends, the end positions the least-squares ones" $
      property $ forAll (choose (30, 300)) $ \n -> forAll (choose (2, n `div` 5)) $ \k -> forAllBlind (genWalk n) $ \pr ->
        let st = rcT pr
            ts = U.generate k (\j -> st U.! ((j * (n - 1)) `div` (k - 1)))
            kn0 = Knots ts (pgenerate k (\j -> fst (polylineAt st (rcP pr) (rcQ pr) (ts U.! j))))
            prF = pr { rcEnds = EndsFree }
            pinned = solveStretchPositions pr kn0 0 (k - 1)
            free = solveStretchPositions prF kn0 0 (k - 1)
            sse = knotSse pr
            asPath (Knots t p) = PathA t p (pgenerate (U.length t) (const (Q4 1 0 0 0)))
            scale = sqrt (sse free / fromIntegral n) + 1e-6
        in counterexample (show (sse pinned, sse free)) $
             sse free <= sse pinned * (1 + 1e-9) + 1e-15
               .&&. kT free === ts
               .&&. endsAreOptimal (positionSse pr) (asPath free) (0.01 * scale)
    it "the optimised knots: end positions least-squares, never worse than the start; the fit: k points, end times the first and last sample's, times increasing" $
      property $ forAll (choose (30, 300)) $ \n -> forAll (choose (2, n `div` 4)) $ \k -> forAllBlind (genWalk n) $ \pr ->
        let prF = pr { rcEnds = EndsFree }
            start = solveStretchPositions prF (startKnots defaultKnotConfig prF k) 0 (k - 1)
            kn = optimiseKnots defaultKnotConfig prF start
            asPath (Knots t p) = PathA t p (pgenerate (U.length t) (const (Q4 1 0 0 0)))
            scale = sqrt (knotSse pr kn / fromIntegral n) + 1e-6
            PathA t p _ = fitKnots defaultKnotConfig prF defaultWeights k
        in counterexample (show (U.toList (kT kn), knotSse pr start, knotSse pr kn)) $
             knotSse pr kn <= knotSse pr start * (1 + 1e-9) + 1e-15
               .&&. endsAreOptimal (positionSse pr) (asPath kn) (0.01 * scale)
               .&&. U.length t === k .&&. plength p === k .&&. strictlyIncreasing t
               .&&. U.head t === U.head (rcT pr) .&&. U.last t === U.last (rcT pr)
    it "on freiburg1_xyz at 0.5 %: lower position and orientation error than pinned ends, and the first waypoint is not the first sample" $ do
      pr <- prepareRecording <$> loadTum "freiburg1_xyz-groundtruth.txt"
      let k = 15
          pinned = fitKnots defaultKnotConfig pr defaultWeights k
          free = fitKnots defaultKnotConfig pr { rcEnds = EndsFree } defaultWeights k
          m = computeMetrics pr
      mPositionRmse (m free) `shouldSatisfy` (< mPositionRmse (m pinned))
      mOrientationRmse (m free) `shouldSatisfy` (< mOrientationRmse (m pinned))
      phead (paP free) `shouldNotBe` phead (rcP pr)

  describe "fitKnots" $ do
    it "k points, ends pinned to the first and last sample, times strictly increasing" $
      property $ forAll (choose (30, 300)) $ \n -> forAll (choose (2, n `div` 4)) $ \k -> forAllBlind (genWalk n) $ \pr ->
        let pa@(PathA t p q) = fitKnots defaultKnotConfig pr defaultWeights k
        in counterexample (show (U.toList t)) $
             U.length t === k .&&. plength p === k .&&. plength q === k .&&. strictlyIncreasing t
               .&&. U.head t === U.head (rcT pr) .&&. U.last t === U.last (rcT pr)
               .&&. phead p === phead (rcP pr) .&&. plast p === plast (rcP pr)
               .&&. qangle (phead q) (phead (rcQ pr)) < 1e-9 .&&. qangle (plast q) (plast (rcQ pr)) < 1e-9
               .&&. U.length (paT pa) === k
    it "no two waypoints closer than half the median sample step (or half the shortest, where the start has them so), at any number of points, with or without the wider search (were microseconds apart: segments hundreds of times faster than the recording)" $
      property $ forAll (choose (20, 200)) $ \n -> forAll (choose (2, n - 1)) $ \k -> forAll (choose (0, 3)) $ \r -> forAllBlind (genWalk n) $ \pr ->
        let PathA t _ _ = fitKnots defaultKnotConfig { kcSearch = r } pr defaultWeights k
            gaps = U.zipWith (-) (U.tail t) t
            -- (the start puts waypoints at the ends and midway between samples: half a step)
            least = min (rcMinGap pr) (0.5 * U.minimum (rcDt pr))
        in counterexample (show (rcMinGap pr, least, U.minimum gaps)) $
             U.length t === k .&&. U.minimum gaps >= least * (1 - 1e-9)
    it "the first 100 samples of freiburg1_xyz at 50 and 70 points: no segment faster than twice the recording's fastest step (one was 476 m/s against 0.56 m/s)" $ do
      Recording (Track ts ps qs) <- loadTum "freiburg1_xyz-groundtruth.txt"
      let n = 100
          ps' = pgenerate n (pindex ps) :: V3s
          qs' = pgenerate n (pindex qs) :: Qs
          pr = prepareRecording (either error id (recordingFromArrays (U.take n ts) ps' qs'))
          speeds t p = [ distance (pindex p i) (pindex p (i + 1)) / (t U.! (i + 1) - t U.! i) | i <- [0 .. U.length t - 2] ]
          fastest = maximum (speeds (rcT pr) (rcP pr))
      mapM_ (\k -> let PathA t p _ = fitKnots defaultKnotConfig pr defaultWeights k
                   in maximum (speeds t p) `shouldSatisfy` (<= 2 * fastest)) [50, 70]
    it "is never worse in position error than its start (position weight only; the worst-error polish, which may give up to 0.5 % of it, left out)" $
      property $ forAll (choose (60, 300)) $ \n -> forAll (choose (3, n `div` 6)) $ \k -> forAllBlind (genWalk n) $ \pr ->
        let start = solveStretchPositions pr (startKnots defaultKnotConfig pr k) 0 (k - 1)
            fitted = fitKnots defaultKnotConfig { kcWorstBudget = 0 } pr (Weights 1 0 0) k
        in counterexample (show (knotSse pr start, positionSse pr fitted)) $
             positionSse pr fitted <= knotSse pr start * (1 + 1e-9) + 1e-15
    it "with a wider search: still k points, pinned ends, increasing times, and never a higher position error than without" $
      property $ forAll (choose (60, 300)) $ \n -> forAll (choose (4, n `div` 6)) $ \k -> forAll (choose (1, 6)) $ \r -> forAllBlind (genWalk n) $ \pr ->
        let cfg = defaultKnotConfig { kcSearch = r }
            base = optimiseKnots defaultKnotConfig pr (startKnots defaultKnotConfig pr k)
            wide = searchKnots cfg pr base
            PathA t p _ = fitKnots cfg pr (Weights 1 0 0) k
        in counterexample (show (knotSse pr base, knotSse pr wide)) $
             knotSse pr wide <= knotSse pr base .&&. U.length (kT wide) === k .&&. strictlyIncreasing (kT wide)
               .&&. U.head (kT wide) === U.head (rcT pr) .&&. U.last (kT wide) === U.last (rcT pr)
               .&&. U.length t === k .&&. strictlyIncreasing t .&&. phead p === phead (rcP pr) .&&. plast p === plast (rcP pr)
    it "a wider search finds the known path's waypoint times from random starts too (search rounds only, no partition start)" $
      property $ forAllBlind genKnown $ \(truth, pr) ->
        let k = U.length truth
            st = rcT pr
            -- a poor start: equal times, then the search
            even' = Knots (U.generate k (\j -> U.head st + (U.last st - U.head st) * fromIntegral j / fromIntegral (k - 1))) (pgenerate k (const (P3 0 0 0)))
            kn = searchKnots defaultKnotConfig { kcSearch = 6 } pr (solveStretchPositions pr even' 0 (k - 1))
            base = optimiseKnots defaultKnotConfig pr (startKnots defaultKnotConfig pr k)
        in counterexample (show (knotSse pr kn, knotSse pr base)) $ k < 4 || knotSse pr kn <= 1.05 * knotSse pr base
    it "recovers the waypoint times of a known K-waypoint path with 1 mm noise (within 2 sample intervals)" $
      property $ forAllBlind genKnown $ \(truth, pr) ->
        let k = U.length truth
            PathA t _ _ = fitKnots defaultKnotConfig pr defaultWeights k
            err = U.maximum (U.zipWith (\a b -> abs (a - b)) t truth)
        in counterexample (show (U.toList truth, U.toList t)) $ err < 0.04
