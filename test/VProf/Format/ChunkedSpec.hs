{-# LANGUAGE OverloadedStrings #-}
-- | Output rendered in pieces on every core ("VProf.Format.Chunked") is byte for byte the
-- output of one builder: for random pieces, and for the CSV and JSON of profiles long
-- enough to be cut into several pieces (8192 rows, 32768 numbers a column), against
-- renderings written here row by row with the number printer alone.
module VProf.Format.ChunkedSpec (spec) where

import qualified Data.Aeson as A
import Data.Aeson.Types (parseMaybe, (.:))
import qualified Data.ByteString.Builder as BB
import qualified Data.ByteString.Lazy.Char8 as BLC
import Data.List (intercalate)
import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import VProf.Format.Chunked (chunkRanges, renderChunked)
import VProf.Format.Number (showDouble)
import VProf.Profile.Format.Json (profileJson)
import VProf.Profile.Format.Text (csv)
import VProf.Profile.Generate
import VProf.Profile.Request (Algorithm (..))
import VProf.Profile.Sampled

-- | A profile of n samples with the full digits of real ones.
wave :: Int -> Profile
wave n = Profile 0.05 (U.generate n (\k -> 1.2 + 0.7 * sin (fromIntegral k * 7.0e-4) + fromIntegral (k `mod` 5) * 1.0e-4)) 0 0

spec :: Spec
spec = do
  it "the pieces' bytes in order, whatever the pieces (empty ones too)" $ property $ \pieces ->
    let bs = map BB.string7 (pieces :: [String])
    in renderChunked bs === BB.toLazyByteString (mconcat bs)
  it "the ranges cover [0, n) in order, each of 1 to size indices" $ property $ \(Positive size) (NonNegative n) ->
    let rs = chunkRanges size n
    in concat [ [i .. i + m - 1] | (i, m) <- rs ] === [0 .. n - 1] .&&. all (\(_, m) -> m >= 1 && m <= size) rs
  it "a CSV of 20000 rows (three pieces) is the rows written one by one" $ do
    let p = wave 20000
        Columns{..} = columns p
        row k = intercalate "," [ showDouble (c U.! k) | c <- [colTime, colDistance, colVelocity, colAcceleration, colJerk] ]
    BLC.unpack (csv p) `shouldBe` unlines ("t,s,v,a,j" : map row [0 .. 19999])
  it "a JSON of 33000 samples (two pieces a column) reads back as the profile's columns" $ do
    let p = wave 33000
        Columns{..} = columns p
        r = Result Generated (Just p) [] 1 True Band 0.05 (1 / 1024) 0
        names = ["time", "distance", "velocity", "acceleration", "jerk"]
        cols = A.decode (profileJson r) >>= parseMaybe (A.withObject "profile" (\o -> mapM (o .:) names))
    cols `shouldBe` Just (map U.toList [colTime, colDistance, colVelocity, colAcceleration, colJerk] :: [[Double]])
