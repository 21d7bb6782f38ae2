-- | Small parsing helpers shared by the recording formats.
module VProf.Compress.Format.Common
  ( readDouble
  , trackFromRows
  ) where

import qualified Data.ByteString.Char8 as B
import qualified Data.Text.Encoding as TE
import qualified Data.Text.Read as TR
import qualified Data.Vector.Unboxed as U

import VProf.Compress.Types
import VProf.Compress.Vec

-- | The recording made of parsed data lines (time, position, orientation); a problem
-- with it names the format and counts samples by data line.
trackFromRows :: String -> [(Double, P3, Q4)] -> Either String Track
trackFromRows format rows =
  case recordingFromArrays (U.fromList [t | (t, _, _) <- rows])
                           (pfromList [p | (_, p, _) <- rows])
                           (pfromList [q | (_, _, q) <- rows]) of
    Left e -> Left (format ++ ": " ++ e ++ " (sample k is the k-th data line, counting from 0)")
    Right (Recording tr) -> Right tr

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
