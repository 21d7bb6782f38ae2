{-# LANGUAGE OverloadedStrings #-}
module VProf.Wire.FramingSpec (spec) where

import qualified Data.ByteString as B
import Data.IORef
import Data.Word (Word8)
import Test.Hspec
import Test.QuickCheck

import VProf.Wire.Framing

-- | A source that hands out the given chunks, then end of input.
chunked :: [B.ByteString] -> IO Source
chunked cs = do
  ref <- newIORef cs
  newSource (atomicModifyIORef' ref (\case [] -> ([], B.empty); x : xs -> (xs, x)))

splitEvery :: Int -> B.ByteString -> [B.ByteString]
splitEvery n b | B.null b = [] | otherwise = B.take n b : splitEvery n (B.drop n b)

spec :: Spec
spec = do
  describe "varint" $ do
    it "matches protobuf's encoding of known values" $ do
      encodeVarint 0 `shouldBe` B.pack [0]
      encodeVarint 1 `shouldBe` B.pack [1]
      encodeVarint 127 `shouldBe` B.pack [0x7f]
      encodeVarint 128 `shouldBe` B.pack [0x80, 0x01]
      encodeVarint 300 `shouldBe` B.pack [0xac, 0x02]
      encodeVarint maxBound `shouldBe` B.pack (replicate 9 0xff ++ [0x01])
    it "round-trips every Word64" $ property $ \w ->
      decodeVarint (encodeVarint w <> "tail") === VarintOk w (B.length (encodeVarint w))
    it "says incomplete for a prefix of a varint" $
      decodeVarint (B.pack [0x80, 0x80]) `shouldBe` VarintIncomplete
    it "rejects 11 bytes and a 10th byte above 1" $ do
      decodeVarint (B.replicate 11 0xff) `shouldBe` VarintMalformed
      decodeVarint (B.replicate 9 0xff <> B.pack [0x02]) `shouldBe` VarintMalformed

  describe "readFrame" $ do
    it "reads pipelined frames whatever the chunking" $ property $
      \(bodies :: [[Word8]]) (Positive k) -> ioProperty $ do
        let bs = map (B.pack) bodies
        src <- chunked (splitEvery (k `mod` 7 + 1) (B.concat (map frame bs)))
        got <- mapM (const (readFrame 1000 src)) bs
        end <- readFrame 1000 src
        pure (got === [Frame b (B.length (frame b)) | b <- bs] .&&. end === EndOfInput)
    it "reports a zero-length frame as an empty body" $ do
      src <- chunked [B.pack [0]]
      readFrame 10 src `shouldReturn` Frame B.empty 1
    it "refuses a prefix above the limit without reading the body" $ do
      reads' <- newIORef (0 :: Int)
      ref <- newIORef [encodeVarint 11, B.replicate 11 1]
      src <- newSource (modifyIORef' reads' (+ 1) >> atomicModifyIORef' ref (\case [] -> ([], B.empty); x : xs -> (xs, x)))
      readFrame 10 src `shouldReturn` TooLarge 11
      readIORef reads' `shouldReturn` 1
    it "reports truncation inside the prefix and inside the body" $ do
      (chunked [B.pack [0x80]] >>= readFrame 10) `shouldReturn` Truncated 1
      (chunked [B.pack [5, 1, 2]] >>= readFrame 10) `shouldReturn` Truncated 3
    it "reports an overlong prefix" $
      (chunked [B.replicate 12 0x80] >>= readFrame 10) `shouldReturn` BadVarint

