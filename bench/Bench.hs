-- | Criterion benchmarks of the generator (every reference case, default and thesis
-- mode, two short routes solved by the exact join, and a scaling series) — each profile
-- is checked first and a failure fails the run.
--
-- > stack bench                                   criterion report
-- > stack bench --benchmark-arguments=--scaling   scaling series to bench/scaling.csv and .png
module Main (main) where

import Control.Exception (evaluate)
import Control.Monad (forM, forM_, when)
import Criterion.Main
import Data.Time.Clock (diffUTCTime, getCurrentTime)
import System.Environment (getArgs)
import System.Exit (exitFailure)
import Text.Printf (printf)
import Control.Lens ((.~), (&))
import Data.Colour (opaque)
import Data.Colour.Names (blue, red)
import Data.Default.Class (def)
import Graphics.Rendering.Chart
import Graphics.Rendering.Chart.Backend.Cairo

import CompressBench (compressBenchmarks)
import ClosedFormBench (closedFormBenchmarks)
import CollisionBench (collisionBenchmarks)
import KinematicsBench (kinematicsBenchmarks)
import OutputBench (outputBenchmarks)
import PlanBench (planBenchmarks)
import Routes
import VProf.Profile.Generate
import VProf.Profile.Sampled (duration, sampleCount)
import VProf.Profile.Request
import VProf.Units

-- | Generate once and insist on a legal profile.
certified :: String -> Request -> IO ()
certified name rq0 = do
  -- a precondition, not a timing: a generous budget, so that a loaded machine does not abort it
  let rq = rq0 { rqTimeBudget = Just (30 *~ second) }
  r <- generate rq
  case resOutcome r of
    Generated -> pure ()
    other -> do
      putStrLn ("bench: " ++ name ++ " did not give a legal profile: " ++ show other)
      exitFailure

main :: IO ()
main = do
  args <- getArgs
  if "--scaling" `elem` args then scaling else do
    cases <- loadCases
    let thesisCases = [ (n, rq { rqAlgorithm = Thesis }) | (n, rq) <- cases ]
    forM_ (cases ++ thesisCases) $ \(n, rq) -> certified n rq
    let series = [ (len, nz) | (len, nz) <- [(100, 1), (1000, 10), (2000, 100), (5000, 100), (20000, 100), (2000, 1000)] ]
    forM_ series $ \(len, nz) -> certified (show (len, nz)) (syntheticRoute len nz)
    -- the short routes: one legal, one proven infeasible
    forM_ shortRoutes $ \(n, rq) -> do
      r <- generate rq
      case (resOutcome r, n) of
        (Generated, "3118-legal") -> pure ()
        (Failed (InfeasibleRequest _ _), "8820-infeasible") -> pure ()
        (other, _) -> putStrLn ("bench: " ++ n ++ " gave " ++ show other) >> exitFailure
    compression <- compressBenchmarks
    output <- outputBenchmarks
    plans <- planBenchmarks
    defaultMain $
      [ bgroup "cases" [ bench n (nf (resIterations . generatePure) rq) | (n, rq) <- cases ]
      , bgroup "thesis" [ bench n (nf (resIterations . generatePure) rq) | (n, rq) <- thesisCases ]
      , bgroup "short-route" [ bench n (nf (show . resOutcome . generatePure) rq) | (n, rq) <- shortRoutes ]
      , bgroup "scaling" [ bench (show (round len :: Int) ++ "m-" ++ show nz ++ "limits")
                                  (nf (resIterations . generatePure) (syntheticRoute len nz))
                         | (len, nz) <- series ]
      ] ++ compression ++ kinematicsBenchmarks ++ closedFormBenchmarks ++ collisionBenchmarks ++ output ++ plans

-- | Wall-clock scaling series (best of 5 runs): route length and number of limits.
scaling :: IO ()
scaling = do
  let lengths = [ (len, max 1 (round (len / 20))) | len <- [100, 200, 500, 1000, 2000, 5000, 10000, 20000] ]
      limits = [ (2000, nz) | nz <- [1, 3, 10, 30, 100, 300, 1000] ]
  rowsL <- forM lengths (measure "length")
  rowsZ <- forM limits (measure "limits")
  let csv = "series,route_m,limits,samples,duration_s,compute_ms\n"
            ++ concat [ printf "%s,%.0f,%d,%d,%.3f,%.3f\n" s l z n d ms | (s, l, z, n, d, ms) <- rowsL ++ rowsZ ]
  writeFile "bench/scaling.csv" csv
  putStr csv
  let pts rows = [ (fromIntegral n :: Double, ms) | (_, _, _, n, _, ms) <- rows ]
      line name colour rows = toPlot $ def
        & plot_lines_title .~ name
        & plot_lines_style .~ solidLine 2 (opaque colour)
        & plot_lines_values .~ [pts rows]
      dots colour rows = toPlot $ def
        & plot_points_style .~ filledCircles 4 (opaque colour)
        & plot_points_values .~ pts rows
      layout = def
        & layout_title .~ "vprof default generator: compute time against profile size"
        & layout_x_axis . laxis_title .~ "samples in the profile (dt = 0.125 s)"
        & layout_y_axis . laxis_title .~ "compute time [ms], best of 5"
        & layout_plots .~ [ line "route 100 m - 20 km, 1 limit per 20 m" blue rowsL, dots blue rowsL
                          , line "2 km, 1 - 1000 limits" red rowsZ, dots red rowsZ ]
  _ <- renderableToFile (def & fo_size .~ (800, 500)) "bench/scaling.png" (toRenderable layout)
  putStrLn "wrote bench/scaling.csv and bench/scaling.png"
  where
    measure :: String -> (Double, Int) -> IO (String, Double, Int, Int, Double, Double)
    measure series (len, nz) = do
      let rq = syntheticRoute len nz
      times <- forM [1 :: Int .. 5] $ \_ -> do
        t0 <- getCurrentTime
        r <- generate rq
        _ <- evaluate (resIterations r)
        t1 <- getCurrentTime
        when (resOutcome r /= Generated) $ putStrLn ("scaling: not legal: " ++ show (len, nz, resOutcome r)) >> exitFailure
        pure (realToFrac (diffUTCTime t1 t0) * 1000 :: Double, r)
      let best = minimum (map fst times)
          Just p = resProfile (snd (head times))
      pure (series, len, nz, sampleCount p, duration p, best)
