-- | Long outputs (a profile's million rows) rendered in pieces on every core. The pieces
-- are built into strict byte strings by sparks a few pieces ahead of the one being
-- consumed, so the bytes come out in order and stream as they are ready; a runtime with
-- one capability renders them one after the other, as a plain builder would. The bytes are
-- exactly those of the pieces' builders concatenated.
module VProf.Format.Chunked
  ( renderChunked
  , chunkRanges
  ) where

import qualified Data.ByteString as B
import qualified Data.ByteString.Builder as BB
import qualified Data.ByteString.Builder.Extra as BE
import qualified Data.ByteString.Lazy as BL
import GHC.Conc (numCapabilities, par, pseq)

-- | The pieces' bytes, in order; up to twice the capabilities' count of pieces (at most 16)
-- are being rendered ahead of the one consumed.
renderChunked :: [BB.Builder] -> BL.ByteString
renderChunked builders = BL.fromChunks (ahead (min 16 (2 * max 1 numCapabilities)) pieces)
  where
    pieces = map render builders
    render b = BL.toStrict (BE.toLazyByteStringWith (BE.untrimmedStrategy 65536 65536) BL.empty b)

-- | The list with its elements sparked n ahead of the one consumed. The sparks are the
-- list's own elements (not new thunks), so a spark the garbage collector meets is still
-- wanted and a piece is never rendered twice.
ahead :: Int -> [B.ByteString] -> [B.ByteString]
ahead n xs = sparkAll (take n xs) `pseq` go xs (drop n xs)
  where
    sparkAll = foldr par ()
    go (x : rest) (y : ys) = y `par` (x : go rest ys)
    go rest [] = rest
    go [] _ = []

-- | [0, n) split into consecutive ranges (start, length) of at most @size@ indices.
chunkRanges :: Int -> Int -> [(Int, Int)]
chunkRanges size n = [ (i, min size (n - i)) | i <- [0, size .. n - 1] ]
