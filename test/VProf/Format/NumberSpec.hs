-- | The fast double printer over the whole range of doubles (random bit patterns, numbers
-- of every magnitude, the edges of fixed notation, signed zeros, subnormals, non-finite
-- values): what it writes reads back to the same double, is never longer than 'show''s
-- text, and has 'show''s layout (sign, fixed or scientific notation, exponent).
module VProf.Format.NumberSpec (spec) where

import Data.Word (Word64)
import GHC.Float (castWord64ToDouble)
import Test.Hspec
import Test.QuickCheck

import VProf.Format.Number (showDouble)

-- | Any double, by its bits.
anyDouble :: Gen Double
anyDouble = castWord64ToDouble <$> (arbitrary :: Gen Word64)

-- | Numbers of every magnitude QuickCheck draws, scaled by 10^-20 .. 10^19.
scaled :: Gen Double
scaled = (\x e -> x * 10 ^^ (e `mod` 40 - 20 :: Int)) <$> arbitrary <*> arbitrary

-- | The sign, whether the notation is scientific, and the exponent if so.
layout :: String -> (Bool, Bool, Maybe Int)
layout s = (take 1 s == "-", 'e' `elem` s, case dropWhile (/= 'e') s of ('e' : ex) -> Just (read ex); _ -> Nothing)

exact :: Double -> Property
exact x = counterexample (showDouble x ++ " vs show " ++ show x) $
  (isNaN x .||. read (showDouble x) === x)
  .&&. length (showDouble x) <= length (show x)
  .&&. layout (showDouble x) === layout (show x)

spec :: Spec
spec = do
  it "reads back exactly, no longer than show, in show's layout: random bit patterns" $
    withMaxSuccess 100000 (forAll anyDouble exact)
  it "the same for numbers of every magnitude" $ withMaxSuccess 20000 (forAll scaled exact)
  it "is show's text on the edges of fixed notation and on special values" $
    mapM_ (\x -> showDouble x `shouldBe` show x)
      ([0, -0.0, 0.1, 0.09999999999999999, 1e7, 9999999.999999998, 1, 2, 10, 100, 1234567, 0.125, 5e-324
       , 2.2250738585072014e-308, 1.7976931348623157e308, 1 / 0, -1 / 0, 0 / 0, 123.456, 1e21, 1e22, 0.3, 2 / 3]
       ++ map negate [0.1, 1e7, 3.0e-2])
