-- | The standard protobuf "delimited" framing: every message is preceded by its length as
-- a base-128 varint (C++ @SerializeDelimitedToOstream@, Java @writeDelimitedTo@, Python
-- @_VarintBytes@ / @_DecodeVarint32@).
--
-- Reading is done from a 'Source' (a socket or a handle) through a small buffer, so that
-- a frame is read exactly, pipelined frames are not lost, and memory stays bounded by
-- the largest frame allowed: the length is checked against the limit before a single
-- byte of the body is read, and the body is accumulated only as it arrives.
module VProf.Wire.Framing
  ( -- * Varints (re-exported from "VProf.Wire.Varint")
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

import qualified Data.ByteString as B
import qualified Data.ByteString.Builder as BB
import qualified Data.ByteString.Lazy as BL
import Data.IORef
import Data.Word (Word64)

import VProf.Wire.Varint

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
