-- | Doubles as text, fast and exact: the shortest digits that read back to the same
-- double (from the double-conversion library, instead of 'floatToDigits', which is many
-- times slower), laid out as Haskell's 'show' lays them out: fixed notation for
-- 0.1 <= |x| < 10^7 ("123.456", "2.0"), otherwise scientific ("1.0e-2", "1.2345e7");
-- "0.0", "-0.0", "NaN", "Infinity". The digits are 'show''s but in two rare cases: where
-- 'show' is not the shortest ("4.0507431968278096e16" is also "4.05074319682781e16"), and
-- where two shortest candidates are equally near and 'show' takes the upper one.
module VProf.Format.Number
  ( doubleBuilder
  , showDouble
  ) where

import qualified Data.ByteString.Builder as BB
import qualified Data.ByteString.Char8 as BC
import qualified Data.ByteString.Lazy.Char8 as BLC
import Data.Double.Conversion.ByteString (toExponential, toShortest)

-- | A double as text that reads back exactly, in 'show''s layout.
doubleBuilder :: Double -> BB.Builder
doubleBuilder x
  | isNaN x = BB.string7 "NaN"
  | isInfinite x = BB.string7 (if x > 0 then "Infinity" else "-Infinity")
  | x == 0 = BB.string7 (if isNegativeZero x then "-0.0" else "0.0")
  | x < 0 = BB.char7 '-' <> positive (negate x)
  | otherwise = positive x
  where
    positive y
      -- the common case, in one call: double-conversion's shortest form is already the
      -- fixed layout there (it writes decimals from 1e-7 to 1e21), short of "2" for "2.0"
      | y >= 0.1 && y < 1e7 =
          let s = toShortest y
          in if BC.elem '.' s then BB.byteString s else BB.byteString s <> BB.string7 ".0"
      | otherwise = general y
    general y =
      -- "d.ddddeN" (or "deN"): the shortest digits d ddddd and y = 0.dddddd · 10^(N+1)
      let s = toExponential (-1) y
          (mant, ex) = BC.break (== 'e') s
          digits = BC.filter (/= '.') mant
          e = maybe 0 fst (BC.readInt (BC.dropWhile (== '+') (BC.drop 1 ex))) + 1
      in if y >= 0.1 && y < 1e7 then fixed digits e else scientific digits e
    fixed ds e
      | e <= 0 = BB.string7 "0." <> BB.string7 (replicate (negate e) '0') <> BB.byteString ds
      | otherwise =
          let (int, frac) = BC.splitAt e ds
              intPart = int <> BC.replicate (e - BC.length int) '0'
          in BB.byteString intPart <> BB.char7 '.' <> (if BC.null frac then BB.char7 '0' else BB.byteString frac)
    scientific ds e = case BC.uncons ds of
      Just (d, rest) -> BB.char7 d <> BB.char7 '.' <> (if BC.null rest then BB.char7 '0' else BB.byteString rest)
                        <> BB.char7 'e' <> BB.intDec (e - 1)
      Nothing -> BB.string7 "0.0e0"

-- | 'doubleBuilder' as a string (for tests and small outputs).
showDouble :: Double -> String
showDouble = BLC.unpack . BB.toLazyByteString . doubleBuilder
