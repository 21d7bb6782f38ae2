-- | Path compression benchmarks: the real recordings to 3 % of their samples, thesis
-- method and RDP baseline. Target: 3,000 samples -> 90 points in at most 0.5 s.
module CompressBench (compressBenchmarks) where

import Criterion (Benchmark, bench, bgroup, nf)
import qualified Data.ByteString.Char8 as B
import System.Directory (doesFileExist)
import System.Environment (lookupEnv)
import System.FilePath ((</>))

import VProf.Compress
import VProf.Compress.Format.Tum (parseTum)

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

compressBenchmarks :: IO [Benchmark]
compressBenchmarks = do
  fr <- load "freiburg1_xyz-groundtruth.txt"
  v1 <- load "V101_gt.txt"
  let pts (Recording tr) = round (0.03 * fromIntegral (trackLength tr) :: Double)
  pure
    [ bgroup "compress"
        [ bench "freiburg1_xyz 3000 samples -> 90, thesis" $ nf (run MethodThesis (pts fr)) fr
        , bench "freiburg1_xyz 3000 samples -> 90, rdp" $ nf (run MethodRdp (pts fr)) fr
        , bench "V101 2895 samples -> 87, thesis" $ nf (run MethodThesis (pts v1)) v1
        , bench "V101 2895 samples -> 87, rdp" $ nf (run MethodRdp (pts v1)) v1
        ]
    ]
