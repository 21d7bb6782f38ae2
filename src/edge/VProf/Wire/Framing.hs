-- | The standard protobuf "delimited" framing: every message is preceded by its length as
-- a base-128 varint (C++ @SerializeDelimitedToOstream@, Java @writeDelimitedTo@, Python
-- @_VarintBytes@ / @_DecodeVarint32@).
--
-- Reading is done from a 'Source' (a socket or a handle) through a small buffer, so that
-- a frame is read exactly, pipelined frames are not lost, and memory stays bounded by
-- the largest frame allowed: the length is checked against the limit before a single
-- byte of the body is read, and the body is accumulated only as it arrives.
module VProf.Wire.Framing
  ( -- * Varints
    encodeVarint
  , decodeVarint
  , VarintResult (..)
  , maxVarintBytes
    -- * Writing
  , frame
    -- * Reading
  , Source
  , newSource
  , sourceFromRecv
  , awaitData
  , hasBuffered
  , FrameResult (..)
  , readFrame
  ) where

import Data.Bits ((.&.), (.|.), shiftL, shiftR, testBit)
import qualified Data.ByteString as B
import qualified Data.ByteString.Builder as BB
import qualified Data.ByteString.Lazy as BL
import Data.IORef
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

-- | A message with its length prefix.
frame :: B.ByteString -> B.ByteString
frame body = BL.toStrict . BB.toLazyByteString $
  BB.byteString (encodeVarint (fromIntegral (B.length body))) <> BB.byteString body

-- | A byte source with a look-ahead buffer. The action returns an empty string at end of
-- input.
data Source = Source
  { srcRecv :: IO B.ByteString
  , srcBuf  :: IORef B.ByteString
  , srcEof  :: IORef Bool
  }

newSource :: IO B.ByteString -> IO Source
newSource recv = Source recv <$> newIORef B.empty <*> newIORef False

sourceFromRecv :: IO B.ByteString -> IO Source
sourceFromRecv = newSource

-- | Read more bytes into the buffer; False at end of input.
fill :: Source -> IO Bool
fill src = do
  eof <- readIORef (srcEof src)
  if eof then pure False else do
    chunk <- srcRecv src
    if B.null chunk
      then writeIORef (srcEof src) True >> pure False
      else modifyIORef' (srcBuf src) (<> chunk) >> pure True

-- | Block until at least one byte is buffered; False at end of input.
awaitData :: Source -> IO Bool
awaitData src = do
  buf <- readIORef (srcBuf src)
  if not (B.null buf) then pure True else fill src

-- | Are bytes of a next frame already buffered (received but not yet read)?
hasBuffered :: Source -> IO Bool
hasBuffered src = not . B.null <$> readIORef (srcBuf src)

data FrameResult
  = Frame !B.ByteString !Int   -- ^ body, and bytes consumed including the prefix
  | EndOfInput                 -- ^ clean end between frames
  | Truncated !Int             -- ^ input ended inside a frame; bytes that had arrived
  | TooLarge !Word64           -- ^ a length prefix above the limit (the body is not read)
  | BadVarint                  -- ^ a length prefix longer than 10 bytes
  deriving (Eq, Show)

-- | Read one frame whose body may be at most the given number of bytes.
readFrame :: Int -> Source -> IO FrameResult
readFrame limit src = prefix
  where
    prefix = do
      buf <- readIORef (srcBuf src)
      case decodeVarint buf of
        VarintMalformed -> pure BadVarint
        VarintIncomplete -> do
          more <- fill src
          if more then prefix
            else pure (if B.null buf then EndOfInput else Truncated (B.length buf))
        VarintOk n used
          | n > fromIntegral limit -> do
              modifyIORef' (srcBuf src) (B.drop used)
              pure (TooLarge n)
          | otherwise -> do
              modifyIORef' (srcBuf src) (B.drop used)
              body (fromIntegral n) used
    body n used = do
      buf <- readIORef (srcBuf src)
      if B.length buf >= n
        then do
          let (b, rest) = B.splitAt n buf
          writeIORef (srcBuf src) (B.copy rest)
          pure (Frame (B.copy b) (n + used))
        else do
          more <- fill src
          if more then body n used else pure (Truncated (used + B.length buf))
