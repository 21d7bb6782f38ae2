-- | Plain CSV of poses in SI units, with a header: @time,x,y,z,qw,qx,qy,qz@.
module VProf.Compress.Format.Csv
  ( renderCsv
  ) where

import qualified Data.ByteString.Builder as BB
import qualified Data.ByteString.Lazy as BL
import Data.List (intercalate)
import qualified Data.Vector.Unboxed as U
import Numeric (showFFloat)

import VProf.Compress.Types
import VProf.Compress.Vec

renderCsv :: Track -> BL.ByteString
renderCsv (Track ts ps qs) = BB.toLazyByteString $
  BB.string7 "time,x,y,z,qw,qx,qy,qz\n" <>
  mconcat [ line t p q | (t, p, q) <- zip3 (U.toList ts) (ptoList ps) (ptoList qs) ]
  where
    line t (P3 x y z) (Q4 w a b c) =
      BB.string7 (intercalate "," (showFFloat (Just 6) t "" : map num [x, y, z, w, a, b, c])) <> BB.char7 '\n'
    num v = showFFloat (Just 9) v ""
