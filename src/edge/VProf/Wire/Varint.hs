-- | Protobuf's base-128 varints, pure: encode a 64-bit value, decode one from the start
-- of a buffer (or say that more bytes are needed, or that the bytes are malformed).
module VProf.Wire.Varint
  ( encodeVarint
  , decodeVarint
  , VarintResult (..)
  , maxVarintBytes
  ) where

import Data.Bits ((.&.), (.|.), shiftL, shiftR, testBit)
import qualified Data.ByteString as B
import Data.Word (Word64, Word8)

-- | A varint longer than this is malformed (a 64-bit value needs at most 10 bytes).
maxVarintBytes :: Int
maxVarintBytes = 10

encodeVarint :: Word64 -> B.ByteString
encodeVarint = B.pack . go
  where
    go n | n < 0x80 = [fromIntegral n]
         | otherwise = (fromIntegral (n .&. 0x7f) .|. 0x80) : go (n `shiftR` 7)

data VarintResult
  = VarintOk !Word64 !Int  -- ^ value, bytes used
  | VarintIncomplete       -- ^ more bytes needed
  | VarintMalformed        -- ^ longer than 10 bytes or above 64 bits
  deriving (Eq, Show)

-- | Decode a varint from the start of a buffer.
decodeVarint :: B.ByteString -> VarintResult
decodeVarint bs = go 0 0 0
  where
    go :: Int -> Int -> Word64 -> VarintResult
    go i sh acc
      | i >= maxVarintBytes = VarintMalformed
      | i >= B.length bs = VarintIncomplete
      | otherwise =
          let b = B.index bs i :: Word8
              low = fromIntegral (b .&. 0x7f) :: Word64
          in if i == maxVarintBytes - 1 && b > 1
               then VarintMalformed  -- the 10th byte may hold only the 64th bit
               else let acc' = acc .|. (low `shiftL` sh)
                    in if testBit b 7 then go (i + 1) (sh + 7) acc' else VarintOk acc' (i + 1)
