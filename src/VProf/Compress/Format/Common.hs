-- | Small parsing helpers shared by the recording formats.
module VProf.Compress.Format.Common
  ( readDouble
  ) where

import qualified Data.ByteString.Char8 as B
import qualified Data.Text.Encoding as TE
import qualified Data.Text.Read as TR

-- | A decimal number (optional sign, fraction, exponent) filling the whole string.
readDouble :: B.ByteString -> Maybe Double
readDouble s0 =
  let s = B.strip s0
      s' = case B.uncons s of
        Just ('.', _) -> B.cons '0' s
        Just ('-', r) | Just ('.', _) <- B.uncons r -> B.append (B.pack "-0") r
        _ -> s
  in case TR.double (TE.decodeLatin1 s') of
       Right (d, rest) | rest == mempty, not (isNaN d || isInfinite d) -> Just d
       _ -> Nothing
