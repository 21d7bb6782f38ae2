-- | TUM trajectory format: one pose a line, @timestamp tx ty tz qx qy qz qw@ (s, m, unit
-- quaternion with the scalar last); @#@ starts a comment line.
module VProf.Compress.Format.Tum
  ( parseTum
  , readTum
  , renderTum
  ) where

import qualified Data.ByteString.Char8 as B
import qualified Data.ByteString.Lazy as BL

import VProf.Compress.Format.Common (dataLines, numberFields, poseFields, renderPoseLines, trackFromRows)
import VProf.Compress.Clean (Sample (..))
import VProf.Compress.Types
import VProf.Geometry.Vec

-- | Parse a TUM file into a strictly valid track (as 'VProf.Compress.Types.mkTrack'
-- checks: increasing times, no duplicates); for reading back files vprof wrote. Real
-- recordings go through 'readTum' and "VProf.Compress.Clean".
parseTum :: B.ByteString -> Either String Track
parseTum src = readTum src >>= trackFromRows "TUM"

-- | The samples of a TUM file as written, each with its line number (from 1); blank
-- lines, @#@ comments, CRLF line ends and any whitespace between fields are accepted; a
-- pose value written @nan@ (the tracker lost the body) is read as NaN, for the cleaning to
-- drop. Errors name the line number and the offending text.
readTum :: B.ByteString -> Either String [Sample]
readTum src = traverse row (dataLines (const False) src)
  where
    row (i, l) = case B.words l of
      w0 : ws@[_, _, _, _, _, _, _] -> do
        ts <- numberFields "TUM" i [w0]
        vs <- poseFields "TUM" i 2 ws
        case ts ++ vs of
          [t, x, y, z, qx, qy, qz, qw] -> pure (Sample i t (P3 x y z) (Q4 qw qx qy qz))
          _ -> Left "impossible"
      ws -> Left ("TUM line " ++ show i ++ ": expected 8 numbers (timestamp tx ty tz qx qy qz qw), got "
                  ++ show (length ws) ++ ": " ++ show (B.unpack (B.take 80 l)))

renderTum :: Track -> BL.ByteString
renderTum = renderPoseLines "# timestamp tx ty tz qx qy qz qw" " " (\(P3 x y z) (Q4 w a b c) -> [x, y, z, a, b, c, w])
