-- | TUM trajectory format: one pose a line, @timestamp tx ty tz qx qy qz qw@ (s, m, unit
-- quaternion with the scalar last); @#@ starts a comment line.
module VProf.Compress.Format.Tum
  ( parseTum
  , renderTum
  ) where

import qualified Data.ByteString.Char8 as B
import qualified Data.ByteString.Lazy as BL

import VProf.Compress.Format.Common (dataLines, numberFields, renderPoseLines, trackFromRows)
import VProf.Compress.Types
import VProf.Geometry.Vec

-- | Parse a TUM file; errors name the line number and the offending text.
parseTum :: B.ByteString -> Either String Track
parseTum src = do
  rows <- traverse row (dataLines (const False) src)
  trackFromRows "TUM" rows
  where
    row (i, l) = case B.words l of
      ws@[_, _, _, _, _, _, _, _] -> do
        vs <- numberFields "TUM" i ws
        case vs of
          [t, x, y, z, qx, qy, qz, qw] -> pure (t, P3 x y z, Q4 qw qx qy qz)
          _ -> Left "impossible"
      ws -> Left ("TUM line " ++ show i ++ ": expected 8 numbers (timestamp tx ty tz qx qy qz qw), got "
                  ++ show (length ws) ++ ": " ++ show (B.unpack (B.take 80 l)))

renderTum :: Track -> BL.ByteString
renderTum = renderPoseLines "# timestamp tx ty tz qx qy qz qw" " " (\(P3 x y z) (Q4 w a b c) -> [x, y, z, a, b, c, w])
