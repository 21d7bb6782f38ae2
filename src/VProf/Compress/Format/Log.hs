-- | The Polhemus-style CSV log of the thesis (figure 33, @lesLog.m@): one sample a line,
-- comma-separated: time (ms), x, y, z (mm), quaternion w, x, y, z, then any further
-- columns (ignored). Blank lines and lines starting with @#@ are skipped.
module VProf.Compress.Format.Log
  ( parseLog
  , logTimeScale
  ) where

import qualified Data.ByteString.Char8 as B

import VProf.Compress.Format.Common (readDouble, trackFromRows)
import VProf.Compress.Types
import VProf.Compress.Vec

-- | Seconds per unit of the log's time column (the sensor writes milliseconds).
logTimeScale :: Double
logTimeScale = 1e-3

parseLog :: B.ByteString -> Either String Track
parseLog src = do
  rows <- traverse row [ (i, s) | (i, l) <- zip [1 :: Int ..] (B.lines src)
                                , let s = B.dropWhile (\c -> c == '|' || c == ' ') (B.strip l)
                                , not (B.null s), B.head s /= '#' ]
  trackFromRows "log" rows
  where
    row (i, l) =
      let cols = map B.strip (B.split ',' l)
      in if length cols < 8
           then Left ("log line " ++ show i ++ ": expected at least 8 comma-separated numbers "
                      ++ "(time ms, x y z mm, qw qx qy qz), got " ++ show (length cols))
           else do
             vs <- traverse (field i) (zip [1 :: Int ..] (take 8 cols))
             case vs of
               [t, x, y, z, qw, qx, qy, qz] ->
                 Right (t * logTimeScale, P3 (x * 1e-3) (y * 1e-3) (z * 1e-3), Q4 qw qx qy qz)
               _ -> Left "impossible"
    field i (c, w) = case readDouble w of
      Just d -> Right d
      Nothing -> Left ("log line " ++ show i ++ ", column " ++ show c ++ ": not a number: " ++ show (B.unpack w))
