-- | The driver of @bench/compare-compress@'s global search (benchmark
-- @vprof-compress-global@): @vprof-compress-global FILE.tum BEAM pinned|free K …@ reads a TUM
-- recording and, for each K, prints one JSON line with the position RMSE (mm) of the knot
-- fit's optimised knots (steps 1–3 of docs/compress.md, from the line partition) and of the
-- same optimisation started from the continuous dynamic program searched at every sample
-- (no band; segments up to 8 mean groups; BEAM functions per state), the start's own RMSE and
-- the seconds each took. A diagnostic, not a method: it asks whether a global search over the
-- waypoint times finds a continuous path that the default misses.
module Main (main) where

import Control.Exception (evaluate)
import qualified Data.ByteString as B
import qualified Data.Vector.Unboxed as U
import GHC.Clock (getMonotonicTimeNSec)
import System.Environment (getArgs)
import System.Exit (exitFailure)
import System.IO (hPutStrLn, stderr)
import Text.Printf (printf)

import VProf.Compress.Format.Tum (parseTum)
import VProf.Compress.KnotFit
import VProf.Compress.KnotTimes
import VProf.Compress.Objective
import VProf.Compress.Types

timed :: a -> IO (a, Double)
timed x = do
  t0 <- getMonotonicTimeNSec
  y <- evaluate x
  t1 <- getMonotonicTimeNSec
  pure (y, fromIntegral (t1 - t0) * 1e-9)

main :: IO ()
main = do
  args <- getArgs
  case args of
    (file : beamS : endsS : ks@(_ : _)) | [(beam, "")] <- reads beamS, endsS `elem` ["pinned", "free"] -> do
      src <- B.readFile file
      tr <- either (\e -> hPutStrLn stderr (file ++ ": " ++ e) >> exitFailure) pure (parseTum src)
      let pr0 = prepareRecording (Recording tr)
          pr = pr0 { rcEnds = if endsS == "free" then EndsFree else EndsPinned }
          n = U.length (rcT pr)
          rmse kn = 1000 * sqrt (knotSse pr kn / fromIntegral n)
          cfg = defaultKnotConfig
      mapM_ (\kS -> do
               let k = read kS :: Int
               (d, td) <- timed (optimiseKnots cfg pr (startKnots cfg pr k))
               (s, ts) <- timed (continuousStart cfg 0 beam pr k)
               (g, tg) <- timed (optimiseKnots cfg pr s)
               printf "{\"k\": %d, \"default_mm\": %.6f, \"default_seconds\": %.3f, \"start_mm\": %.6f, \"start_seconds\": %.3f, \"global_mm\": %.6f, \"global_seconds\": %.3f}\n"
                 k (rmse d) td (rmse s) ts (rmse g) (ts + tg)) ks
    _ -> hPutStrLn stderr "usage: vprof-compress-global FILE.tum BEAM pinned|free K [K ...]" >> exitFailure
