-- | TUM trajectory format: one pose a line, @timestamp tx ty tz qx qy qz qw@ (s, m, unit
-- quaternion with the scalar last); @#@ starts a comment line.
module VProf.Compress.Format.Tum
  ( parseTum
  , renderTum
  ) where

import qualified Data.ByteString.Char8 as B
import qualified Data.ByteString.Builder as BB
import qualified Data.ByteString.Lazy as BL
import qualified Data.Vector.Unboxed as U
import Numeric (showFFloat)

import VProf.Compress.Format.Common (readDouble, trackFromRows)
import VProf.Compress.Types
import VProf.Compress.Vec

-- | Parse a TUM file; errors name the line number and the offending text.
parseTum :: B.ByteString -> Either String Track
parseTum src = do
  rows <- traverse row [ (i, l) | (i, l) <- zip [1 :: Int ..] (B.lines src)
                                , let s = B.strip l, not (B.null s), B.head s /= '#' ]
  trackFromRows "TUM" rows
  where
    row (i, l) = case B.words l of
      ws@[_, _, _, _, _, _, _, _] -> do
        vs <- traverse (field i) (zip [1 :: Int ..] ws)
        case vs of
          [t, x, y, z, qx, qy, qz, qw] -> pure (t, P3 x y z, Q4 qw qx qy qz)
          _ -> Left "impossible"
      ws -> Left ("TUM line " ++ show i ++ ": expected 8 numbers (timestamp tx ty tz qx qy qz qw), got "
                  ++ show (length ws) ++ ": " ++ show (B.unpack (B.take 80 l)))
    field i (c, w) = case readDouble w of
      Just d -> Right d
      Nothing -> Left ("TUM line " ++ show i ++ ", column " ++ show c ++ ": not a number: " ++ show (B.unpack w))

renderTum :: Track -> BL.ByteString
renderTum (Track ts ps qs) = BB.toLazyByteString $
  BB.string7 "# timestamp tx ty tz qx qy qz qw\n" <>
  mconcat [ line t p q | (t, p, q) <- zip3 (U.toList ts) (ptoList ps) (ptoList qs) ]
  where
    line t (P3 x y z) (Q4 w a b c) =
      BB.string7 (unwords (showFFloat (Just 6) t "" : map num [x, y, z, a, b, c, w])) <> BB.char7 '\n'
    num v = showFFloat (Just 9) v ""
