-- | Recordings sampled from a known K-waypoint path are recovered with K points.
module VProf.Compress.PropertySpec (spec) where

import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import VProf.Compress
import VProf.Geometry.Polyline
import VProf.Geometry.Quaternion
import VProf.Compress.KnotFit (fitKnots)
import VProf.Compress.Objective
import VProf.Geometry.Vec
import Support.PathError (worstPositionError)
import Numeric.Units.Dimensional.Prelude (metre, (*~))

-- | A random path: K waypoints, segment durations 1–2.5 s, positions in a 1 m cube,
-- orientations turning up to 0.8 rad per segment.
data Truth = Truth { trT :: [Double], trP :: [P3], trQ :: [Q4] } deriving Show

genTruth :: Gen Truth
genTruth = do
  k <- choose (3, 7)
  t0 <- choose (0, 2000)
  durs <- vectorOf (k - 1) (choose (1.0, 2.5))
  ps <- vectorOf k (P3 <$> choose (-0.5, 0.5) <*> choose (-0.5, 0.5) <*> choose (-0.5, 0.5))
  q0 <- qnormalize <$> (Q4 <$> choose (-1, 1) <*> choose (-1, 1) <*> choose (-1, 1) <*> choose (-1, 1))
  rots <- vectorOf (k - 1) (P3 <$> choose (-0.45, 0.45) <*> choose (-0.45, 0.45) <*> choose (-0.45, 0.45))
  let qs = scanl (\q r -> qnormalize (qmul (qexp r) q)) q0 rots
  pure (Truth (scanl (+) t0 durs) ps qs)

-- | Sample every 50 ms, with uniform noise of the given amplitude (m, rad) if any.
sampleTruth :: Truth -> Maybe (Double, Double) -> Gen Recording
sampleTruth (Truth ts ps qs) noise = do
  let tv = U.fromList ts
      pv = pfromList ps :: V3s
      qv = pfromList qs :: Qs
      n = floor ((last ts - head ts) / 0.05) + 1 :: Int
      st = [ head ts + 0.05 * fromIntegral i | i <- [0 .. n - 1] ]
      clean = [ polylineAt tv pv qv t | t <- st ]
  noisy <- case noise of
    Nothing -> pure clean
    Just (ap, ao) -> mapM (\(p, q) -> do
        dp <- P3 <$> choose (-ap, ap) <*> choose (-ap, ap) <*> choose (-ap, ap)
        dq <- P3 <$> choose (-ao, ao) <*> choose (-ao, ao) <*> choose (-ao, ao)
        pure (p ^+^ dp, qnormalize (qmul (qexp dq) q))) clean
  pure (either error id (recordingFromArrays (U.fromList st) (pfromList (map fst noisy)) (pfromList (map snd noisy))))

cleanOf :: Truth -> Recording
cleanOf tr = case sampleTruthClean tr of r -> r
  where sampleTruthClean (Truth ts ps qs) =
          let tv = U.fromList ts; pv = pfromList ps :: V3s; qv = pfromList qs :: Qs
              n = floor ((last ts - head ts) / 0.05) + 1 :: Int
              st = [ head ts + 0.05 * fromIntegral i | i <- [0 .. n - 1] ]
              clean = [ polylineAt tv pv qv t | t <- st ]
          in either error id (recordingFromArrays (U.fromList st) (pfromList (map fst clean)) (pfromList (map snd clean)))

fitK :: Weights -> Int -> Recording -> Compressed
fitK w k rec = either (error . show) id (compress defaultSettings { sWeights = w, sPoints = Just k } rec)

-- | Metrics of a path against the noise-free samples of the truth.
againstTruth :: Truth -> Compressed -> Metrics
againstTruth tr o = computeMetrics (prepareRecording (cleanOf tr)) (toPathA (oPath o))

spec :: Spec
spec = describe "recovery of a known K-waypoint path" $ do
  it "noise-free: K points, position RMSE < 0.05 mm, orientation RMSE < 0.005 deg" $
    property $ forAll genTruth $ \tr -> forAllBlind (sampleTruth tr Nothing) $ \rec ->
      let k = length (trT tr)
          m = oMetrics (fitK defaultWeights k rec)
      in counterexample (show m) $
           mPoints m === k .&&. mPositionRmse m < 5e-5 .&&. mOrientationRmse m < 0.005 * pi / 180
  it "with small noise (1 mm, 0.2 deg): K points, closer to the noise-free motion than the samples are" $
    property $ forAll genTruth $ \tr -> forAllBlind (sampleTruth tr (Just (1e-3, 0.2 * pi / 180))) $ \rec ->
      let k = length (trT tr)
          o = fitK defaultWeights k rec
          m = againstTruth tr o
          Recording noisy = rec
          Recording clean = cleanOf tr
          n = trackLength clean
          rms xs = sqrt (sum (map (^ (2 :: Int)) xs) / fromIntegral (length xs))
          noiseP = rms [ distance (pindex (tPos noisy) i) (pindex (tPos clean) i) | i <- [0 .. n - 1] ]
          noiseO = rms [ qangle (pindex (tRot noisy) i) (pindex (tRot clean) i) | i <- [0 .. n - 1] ]
      in counterexample (show (mPositionRmse m, noiseP, mOrientationRmse m, noiseO)) $
           mPoints m === k .&&. mPositionRmse m < noiseP .&&. mOrientationRmse m < noiseO
  describe "raising a weight lowers that error (1 -> 10 -> 100, the other two weights 1, K points, noise 1 mm, 0.2 deg)" $
    mapM_ raiseOne [("position", \x -> thesisWeights x 1 1, mPositionRmse)
                   , ("orientation", \x -> thesisWeights 1 x 1, mOrientationRmse)
                   , ("velocity", \x -> thesisWeights 1 1 x, mVelocityRmse)]
  toleranceMet
  it "raising a weight lowers that error (orientation weight 0 -> 30 at K points with noise)" $
    property $ forAll genTruth $ \tr -> forAllBlind (sampleTruth tr (Just (1e-3, 0.2 * pi / 180))) $ \rec ->
      let k = length (trT tr)
          e w = oMetrics (fitK w k rec)
          o0 = e (thesisWeights 1 0 1)
          o30 = e (thesisWeights 1 30 1)
      in counterexample (show (map mOrientationRmse [o0, o30])) $
           mOrientationRmse o30 < mOrientationRmse o0

-- | The largest time-synchronous position error of a path against a recording's samples,
-- measured here by interpolating the path at each sample's time.
worstError :: Recording -> Compressed -> Double
worstError (Recording raw) o = worstPositionError (pathTrack (oPath o)) raw

-- | Any tolerance, from far below the noise to above the motion. The thesis method says it
-- is met exactly when the largest time-synchronous error, measured here from the path and
-- the samples, is within it (and then has no more points than samples). The knot fit (the
-- default) always meets it, and its count is the fewest it found: the knot fit to one
-- point fewer, fitted as the search fits a count ('knotConfigFor' the same settings),
-- breaks the tolerance.
toleranceMet :: Spec
toleranceMet = do
  it "knot fit: a tolerance (1e-7 m to 0.3 m, log-uniform; noise up to 5 mm) is always met, measured independently, and one point fewer breaks it" $
    checkCoverage $ forAll genTruth $ \tr -> forAll (choose (0, 5e-3)) $ \amp -> forAllBlind (sampleTruth tr (Just (amp, 0.2 * pi / 180))) $ \rec ->
      forAll (choose (-7, log 0.3 / log 10)) $ \e ->
        let tol = 10 ** e :: Double
            Recording raw = rec
            settings = defaultSettings { sTolerance = Just (tol *~ metre) }
            o = either (error . show) id (compress settings rec)
            k = trackLength (pathTrack (oPath o))
            n = trackLength raw
            PathA ft fp fq = fitKnots (knotConfigFor settings) (prepareRecording rec) defaultWeights (k - 1)
            worstFewer = worstPositionError (Track ft fp fq) raw
            worst = worstError rec o
        in cover 10 (k == n) "every sample a waypoint" $ cover 20 (k > 2 && k < n) "between" $
           counterexample (show (tol, worst, k, n, if k > 2 then worstFewer else 0)) $
             oToleranceMet o .&&. worst <= tol * (1 + 1e-9) .&&. abs (mPositionMax (oMetrics o) - worst) <= 1e-9 * max 1 worst
               .&&. (k <= 2 || worstFewer > tol)
  it "thesis method: a tolerance (1e-7 m to 0.3 m, log-uniform; noise up to 5 mm) is reported met exactly when the largest error at the samples, measured independently, is within it" $
    checkCoverage $ forAll genTruth $ \tr -> forAll (choose (0, 5e-3)) $ \amp -> forAllBlind (sampleTruth tr (Just (amp, 0.2 * pi / 180))) $ \rec ->
      forAll (choose (-7, log 0.3 / log 10)) $ \e ->
        let tol = 10 ** e :: Double
            Recording raw = rec
            o = either (error . show) id (compress defaultSettings { sMethod = MethodThesis, sTolerance = Just (tol *~ metre) } rec)
            worst = worstError rec o
        in cover 10 (oToleranceMet o) "met" $ cover 10 (not (oToleranceMet o)) "not met" $
           counterexample (show (tol, worst, oToleranceMet o, trackLength (pathTrack (oPath o)), trackLength raw)) $
             if oToleranceMet o then worst <= tol * (1 + 1e-9) .&&. trackLength (pathTrack (oPath o)) <= trackLength raw
             else property (worst > tol * (1 - 1e-9)) .&&. abs (mPositionMax (oMetrics o) - worst) <= 1e-9 * max 1 worst

-- | Raising weight c from 1 to 10 to 100 never raises error c by more than 'raiseTolerance'.
raiseOne :: (String, Double -> Weights, Metrics -> Double) -> Spec
raiseOne (name, weightsAt, err) =
  it (name ++ " error") $ property $ forAll genTruth $ \tr -> forAllBlind (sampleTruth tr (Just (1e-3, 0.2 * pi / 180))) $ \rec ->
    let k = length (trT tr)
        es = [ err (oMetrics (fitK (weightsAt x) k rec)) | x <- [1, 10, 100] ]
    in counterexample (name ++ " RMSE at weights 1, 10, 100: " ++ show es) $
         conjoin [ e' <= e * (1 + raiseTolerance) | (e, e') <- zip es (tail es) ]

-- | Why a tolerance at all: for the exact optima of the objective at weights w and w'
-- (w' = w with component c raised by d > 0) the error can only fall:
-- E_w(x) <= E_w(x') and E_w'(x') <= E_w'(x) add up to d·E_c(x') <= d·E_c(x). The fit
-- finds each optimum only to the precision of its stopping rule, and a run within ε of
-- its optimum gives E_c(x') <= E_c(x) + (ε + ε')/d. Here the truth has K waypoints and
-- the fit uses K, so both runs land in the same basin (one waypoint a corner) and only
-- that precision is left: 1e-3 of the RMSE (2e-3 of its square) is well above the
-- residual drift of the converged update and well below the effects being tested
-- (raising a weight tenfold moves its RMSE by percents).
raiseTolerance :: Double
raiseTolerance = 1e-3
