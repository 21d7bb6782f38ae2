{-# LANGUAGE ForeignFunctionInterface #-}
-- | Doubles as text, fast and exact: the shortest digits that read back to the same
-- double (from the double-conversion library, instead of 'floatToDigits', which is many
-- times slower), laid out as Haskell's 'show' lays them out: fixed notation for
-- 0.1 <= |x| < 10^7 ("123.456", "2.0"), otherwise scientific ("1.0e-2", "1.2345e7");
-- "0.0", "-0.0", "NaN", "Infinity". The digits are 'show''s but in two rare cases: where
-- 'show' is not the shortest ("4.0507431968278096e16" is also "4.05074319682781e16"), and
-- where two shortest candidates are equally near and 'show' takes the upper one.
--
-- The digits are written by double-conversion's C functions straight
-- into the builder's buffer (bounded primitives): no string or bytestring a number.
--
-- And text as a double ('readDouble'), correctly rounded, for every reader of numbers in
-- files and on the command line.
module VProf.Format.Number
  ( doubleBuilder
  , showDouble
  , readDouble
  ) where

import qualified Data.ByteString as BS
import qualified Data.ByteString.Builder as BB
import qualified Data.ByteString.Char8 as BC
import qualified Data.ByteString.Unsafe as BU
import qualified Data.ByteString.Builder.Prim as BP
import Data.ByteString.Builder.Prim.Internal (boundedPrim)
import qualified Data.ByteString.Lazy.Char8 as BLC
import Data.Word (Word8)
import Foreign.C.Types (CDouble (..), CInt (..))
import Foreign.Ptr (Ptr, plusPtr)
import Foreign.Storable (peekByteOff, pokeByteOff)

-- | double-conversion's shortest form (the C function behind its 'toShortest'): writes at
-- most 26 bytes and returns how many.
foreign import ccall unsafe "_hs_ToShortest"
  c_toShortest :: CDouble -> Ptr Word8 -> IO CInt

-- | double-conversion's shortest exponential form (the C function behind its
-- @toExponential (-1)@): "d.dddeN", or "deN" for a single digit; at most 26 bytes and a NUL.
foreign import ccall unsafe "_hs_ToExponential"
  c_toExponential :: CDouble -> Ptr Word8 -> CInt -> IO CInt

-- | The shortest exponential form in 'show''s layout ("d.0eN" for a single digit): at most
-- 27 + 2 bytes.
shortestExponential :: BP.BoundedPrim Double
shortestExponential = boundedPrim 32 $ \x p -> do
  n <- fromIntegral <$> c_toExponential (CDouble x) p (-1)
  let byte k = peekByteOff p k :: IO Word8
      findFrom k c = if k >= n then pure n else byte k >>= \b -> if b == c then pure k else findFrom (k + 1) c
  e <- findFrom 0 101          -- 'e'
  dot <- findFrom 0 46         -- '.'
  if dot < e
    then pure (p `plusPtr` n)
    else do
      -- "deN": move "eN" two bytes on and put ".0" before it
      let move k = if k < e then pure () else byte k >>= pokeByteOff p (k + 2) >> move (k - 1)
      move (n - 1)
      pokeByteOff p e (46 :: Word8)
      pokeByteOff p (e + 1) (48 :: Word8)
      pure (p `plusPtr` (n + 2))
{-# INLINE shortestExponential #-}

-- | The shortest form of a double in the fixed range, with ".0" after an integer: at most
-- 26 + 2 bytes.
shortestFixed :: BP.BoundedPrim Double
shortestFixed = boundedPrim 28 $ \x p -> do
  n <- fromIntegral <$> c_toShortest (CDouble x) p
  let hasPoint k
        | k >= n = pure False
        | otherwise = do
            c <- peekByteOff p k :: IO Word8
            if c == 46 then pure True else hasPoint (k + 1)
  dot <- hasPoint 0
  if dot
    then pure (p `plusPtr` n)
    else do
      pokeByteOff p n (46 :: Word8)
      pokeByteOff p (n + 1) (48 :: Word8)
      pure (p `plusPtr` (n + 2))
{-# INLINE shortestFixed #-}

-- | A double as text that reads back exactly, in 'show''s layout.
doubleBuilder :: Double -> BB.Builder
doubleBuilder x
  -- the common case, in one call: double-conversion's shortest form is already the
  -- fixed layout there (it writes decimals from 1e-7 to 1e21), short of "2" for "2.0"
  | y >= 0.1 && y < 1e7 = BP.primBounded shortestFixed x
  | isNaN x = BB.string7 "NaN"
  | isInfinite x = BB.string7 (if x > 0 then "Infinity" else "-Infinity")
  | x == 0 = BB.string7 (if isNegativeZero x then "-0.0" else "0.0")
  -- elsewhere show's exponential layout, "d.ddddeN", in one call too
  | otherwise = BP.primBounded shortestExponential x
  where
    y = abs x

-- | 'doubleBuilder' as a string (for tests and small outputs).
showDouble :: Double -> String
showDouble = BLC.unpack . BB.toLazyByteString . doubleBuilder

-- | A decimal number: [+-] digits [. digits] [e [+-] digits], or @nan@/@inf@/@infinity@ (any
-- case, read as such so that the caller can say it is not finite). Correctly rounded: up to 15
-- significant digits and a power of ten up to 22 in one exact floating operation, otherwise
-- through 'Rational'.
readDouble :: BS.ByteString -> Maybe Double
readDouble s0
  | BS.null s0 = Nothing
  | otherwise =
      let (neg, s1) = case BC.head s0 of
            '-' -> (True, BS.tail s0)
            '+' -> (False, BS.tail s0)
            _ -> (False, s0)
          sgn x = if neg then negate x else x
          low = BC.map toLower' s1
      in if low == BC.pack "nan" then Just (0 / 0)
         else if low `elem` map BC.pack ["inf", "infinity"] then Just (sgn (1 / 0))
         else sgn <$> unsigned s1
  where
    toLower' c = if c >= 'A' && c <= 'Z' then toEnum (fromEnum c + 32) else c

unsigned :: BS.ByteString -> Maybe Double
unsigned s =
  let (ip, r1) = BS.span isDigit s
      (fp, r2) = case BS.uncons r1 of
        Just (46, r) -> BS.span isDigit r
        _ -> (BS.empty, r1)
      hasDot = not (BS.null r1) && BU.unsafeHead r1 == 46
  in if BS.null ip && BS.null fp then Nothing else do
       e <- case BS.uncons (if hasDot then BS.drop (1 + BS.length fp) r1 else r2) of
         Nothing -> Just 0
         Just (c, r) | c == 101 || c == 69 ->
           let (negE, ds) = case BS.uncons r of
                 Just (45, t) -> (True, t)
                 Just (43, t) -> (False, t)
                 _ -> (False, r)
           in if BS.null ds || not (BS.all isDigit ds) then Nothing
              else if BS.length ds > 6 then Just (if negE then -100000 else 100000)
              else Just ((if negE then negate else id) (BS.foldl' (\a d -> a * 10 + fromIntegral (d - 48)) 0 ds))
         _ -> Nothing
       let digits = BS.dropWhile (== 48) (ip <> fp)
           nd = BS.length digits
           mant = BS.foldl' (\acc d -> acc * 10 + fromIntegral (d - 48)) 0 digits :: Integer
           ex = e - BS.length fp
       pure $
         if nd == 0 then 0
         else if ex + nd > 330 then 1 / 0
         else if ex + nd < -345 then 0
         else if nd <= 15 && ex >= 0 && ex <= 22 then fromIntegral mant * 10 ^^ ex
         else if nd <= 15 && ex < 0 && ex >= -22 then fromIntegral mant / 10 ^ negate ex
         else fromRational (fromIntegral mant * 10 ^^ ex)
  where
    isDigit :: Word8 -> Bool
    isDigit c = c >= 48 && c <= 57
