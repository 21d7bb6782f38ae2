module Main (main) where

import Criterion.Main (defaultMain)

import CompressBench (compressBenchmarks)

-- Temporary in the compress branch; the lead's Bench.hs includes compressBenchmarks.
main :: IO ()
main = compressBenchmarks >>= defaultMain
