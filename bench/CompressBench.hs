-- | Path compression benchmarks: the real recordings to 3 % of their samples, the knot fit
-- (the default), the thesis method and the RDP baseline; and a scaling series of the knot fit
-- at 3 %: freiburg1_xyz concatenated with itself 1, 2, 4, 7 and 13 times (3,000 to 39,000
-- samples; each copy shifted in time by the recording's span and in position by its end
-- minus its start, so the motion is continuous). Targets (issue 16): 3,000 samples in at
-- most 0.3 s, 20,000 in at most 2 s, and time growing no worse than n log n. And to a
-- tolerance of 10 mm: the knot fit's search for the fewest points (freiburg1_xyz and seven
-- copies of it) beside the thesis method's own stop.
module CompressBench (compressBenchmarks) where

import Criterion (Benchmark, bench, bgroup, nf, whnf)
import qualified Data.ByteString.Char8 as B
import System.Directory (doesFileExist)
import System.Environment (lookupEnv)
import System.FilePath ((</>))

import qualified Data.Vector.Unboxed as U

import VProf.Compress
import VProf.Compress.Format.Tum (parseTum)
import VProf.Compress.KnotFit (defaultKnotConfig, fitKnots)
import VProf.Compress.Objective (PathA (..), prepareRecording)
import VProf.Geometry.Vec
import VProf.Units (meter, (*~))

findData :: FilePath -> IO FilePath
findData name = do
  env <- lookupEnv "VPROF_SHARED"
  let cands = maybe [] (\d -> [d </> "data" </> name, d </> name]) env
              ++ ["../shared/data" </> name]
  ok <- mapM doesFileExist cands
  case [ c | (c, True) <- zip cands ok ] of
    (c : _) -> pure c
    [] -> fail ("benchmark data " ++ name ++ " not found in " ++ show cands)

load :: FilePath -> IO Recording
load name = do
  f <- findData name
  src <- B.readFile f
  either (fail . ((f ++ ": ") ++)) (pure . Recording) (parseTum src)

-- | Metrics of the result, so that 'nf' forces the whole computation.
run :: Method -> Int -> Recording -> Metrics
run m k rec = either (error . show) oMetrics (compress defaultSettings { sMethod = m, sPoints = Just k } rec)

-- | The same to a tolerance (m).
toTolerance :: Method -> Double -> Recording -> Metrics
toTolerance m tol rec = either (error . show) oMetrics (compress defaultSettings { sMethod = m, sTolerance = Just (tol *~ meter) } rec)

-- | The recording followed by r−1 copies of itself, each shifted in time by the span plus one
-- step and in position by end minus start.
concatenated :: Int -> Recording -> Recording
concatenated r (Recording (Track t (V3s p) q)) =
  either (error . show) id (recordingFromArrays t' (V3s p') (Qs (U.concat (replicate r qv))))
  where
    Qs qv = q
    n = U.length t
    span' = U.last t - U.head t + (t U.! 1 - t U.! 0)
    d = U.generate 3 (\c -> p U.! (3 * (n - 1) + c) - p U.! c)
    t' = U.concat [ U.map (+ (fromIntegral c * span')) t | c <- [0 .. r - 1] ]
    p' = U.concat [ U.imap (\i x -> x + fromIntegral c * U.unsafeIndex d (i `mod` 3)) p | c <- [0 .. r - 1] ]

compressBenchmarks :: IO [Benchmark]
compressBenchmarks = do
  fr <- load "freiburg1_xyz-groundtruth.txt"
  v1 <- load "V101_gt.txt"
  let pts :: Recording -> Int
      pts (Recording tr) = round (0.03 * fromIntegral (trackLength tr) :: Double)
      series = [ (r, concatenated r fr) | r <- [1, 2, 4, 7, 13] ]
  pure
    [ bgroup "compress"
        [ bench "freiburg1_xyz 3000 samples -> 90, knots" $ nf (run MethodKnots (pts fr)) fr
        , bench "V101 2895 samples -> 87, knots" $ nf (run MethodKnots (pts v1)) v1
        , bench "freiburg1_xyz 3000 samples -> 90, thesis" $ nf (run MethodThesis (pts fr)) fr
        , bench "freiburg1_xyz 3000 samples -> 90, rdp" $ nf (run MethodRdp (pts fr)) fr
        , bench "V101 2895 samples -> 87, thesis" $ nf (run MethodThesis (pts v1)) v1
        , bench "V101 2895 samples -> 87, rdp" $ nf (run MethodRdp (pts v1)) v1
        ]
    , bgroup "compress-tolerance"
        [ bench "freiburg1_xyz 3000 samples to 10 mm, knots" $ nf (toTolerance MethodKnots 10e-3) fr
        , bench "freiburg1_xyz 3000 samples to 10 mm, thesis" $ nf (toTolerance MethodThesis 10e-3) fr
        , bench "21000 samples to 10 mm, knots" $ nf (toTolerance MethodKnots 10e-3) (concatenated 7 fr)
        ]
    , bgroup "compress-scaling"
        [ bench (show (3000 * r) ++ " samples -> " ++ show (pts rec) ++ ", knots") $ nf (run MethodKnots (pts rec)) rec
        | (r, rec) <- series ]
    -- the fit alone (the recording prepared outside, no metrics): the metrics' geometric
    -- distance (every sample to every segment) is O(samples × points) and dominates above
    -- about 20,000 samples
    , bgroup "compress-scaling-fit"
        [ bench (show (3000 * r) ++ " samples -> " ++ show (pts rec) ++ ", knot fit only") $ whnf (fitOnly (pts rec)) (prepareRecording rec)
        | (r, rec) <- series ]
    ]
  where
    fitOnly k pr = let PathA t (V3s p) (Qs q) = fitKnots defaultKnotConfig pr defaultWeights k
                   in U.sum t + U.sum p + U.sum q
