-- | The Polhemus-style CSV log of the thesis (figure 33, @lesLog.m@): one sample a line,
-- comma-separated: time (ms), x, y, z (mm), quaternion w, x, y, z, then any further
-- columns (ignored). Blank lines and lines starting with @#@ are skipped.
module VProf.Compress.Format.Log
  ( parseLog
  , readLog
  , logTimeScale
  ) where

import qualified Data.ByteString.Char8 as B

import VProf.Compress.Format.Common (dataLines, numberFields, poseFields, trackFromRows)
import VProf.Compress.Clean (Sample (..))
import VProf.Compress.Types
import VProf.Geometry.Vec

-- | Seconds per unit of the log's time column (the sensor writes milliseconds).
logTimeScale :: Double
logTimeScale = 1e-3

-- | A strictly valid track (increasing times, no duplicates); real recordings go through
-- 'readLog' and "VProf.Compress.Clean".
parseLog :: B.ByteString -> Either String Track
parseLog src = readLog src >>= trackFromRows "log"

-- | The samples of a log as written (SI units), each with its line number (from 1); an
-- empty or @nan@ pose value is read as NaN, for the cleaning to drop.
readLog :: B.ByteString -> Either String [Sample]
readLog src = traverse row (dataLines (\c -> c == '|' || c == ' ') src)
  where
    row (i, l) =
      let cols = map B.strip (B.split ',' l)
      in if length cols < 8
           then Left ("log line " ++ show i ++ ": expected at least 8 comma-separated numbers "
                      ++ "(time ms, x y z mm, qw qx qy qz), got " ++ show (length cols))
           else do
             ts <- numberFields "log" i (take 1 cols)
             vs <- poseFields "log" i 2 (take 7 (drop 1 cols))
             case ts ++ vs of
               [t, x, y, z, qw, qx, qy, qz] ->
                 Right (Sample i (t * logTimeScale) (P3 (x * 1e-3) (y * 1e-3) (z * 1e-3)) (Q4 qw qx qy qz))
               _ -> Left "impossible"
