-- | The output path at the sample cap's scale: a profile of 10⁶ samples written as CSV (the
-- exact-round-trip number format of "VProf.Format.Number"), as JSON (the CLI's
-- @--format json@) and as the protobuf ProfileResponse (the daemon's and @--format pb@),
-- each measured to the last byte (the lazy output's length forces all of it).
module OutputBench (outputBenchmarks, bigResult) where

import Control.Exception (evaluate)
import Criterion.Main
import qualified Data.Aeson as A
import qualified Data.ByteString as B
import qualified Data.ByteString.Lazy as BL
import qualified Data.Vector.Unboxed as U

import VProf.Profile.Format.Json (profileJson, profileToJson)
import VProf.Profile.Format.Text (csv)
import VProf.Profile.Generate
import VProf.Profile.Request (Algorithm (..))
import VProf.Profile.Sampled
import VProf.Wire.Messages (encodeBare)
import VProf.Wire.Profile (resultToMsg)

-- | A legal-looking result of n samples at dt = 0.125 s: a slow speed wave, so that the
-- numbers have the full digits of real profiles.
bigResult :: Int -> Result
bigResult n =
  let v = U.generate n (\k -> 1.5 + sin (fromIntegral k * 1.0e-3) * 0.75 + fromIntegral (k `mod` 7) * 3.0e-4)
      p = Profile 0.125 v 0 0
  in Result Generated (Just p) [] 1 True Band 0.125 (1 / 1024) 0

-- | The benchmarks, on a result built (and its samples forced) beforehand.
outputBenchmarks :: IO [Benchmark]
outputBenchmarks = do
  let r = bigResult 1000000
  _ <- evaluate (maybe 0 (U.sum . prVelocities) (resProfile r))
  pure
    [ bgroup "output-1e6-samples"
        [ bench "csv" (nf (BL.length . maybe BL.empty csv . resProfile) r)
        , bench "json" (nf (BL.length . profileJson) r)
        , bench "json-through-aeson-value" (nf (BL.length . A.encode . profileToJson) r)
        , bench "protobuf" (nf (B.length . encodeBare . resultToMsg 0) r)
        ]
    ]
