module VProf.Format.MisspeltSpec (spec) where

import Test.Hspec
import Test.QuickCheck

import VProf.Format.Misspelt (editDistance, misspelt)

-- | Short words over a few letters, so that near and equal words are drawn often.
word :: Gen String
word = do
  n <- choose (0, 8)
  vectorOf n (elements "abc_")

-- | The distance by its definition: the least cost over every first edit (exponential; short
-- words only).
naive :: String -> String -> Int
naive [] b = length b
naive a [] = length a
naive (x : xs) (y : ys) = minimum [naive xs (y : ys) + 1, naive (x : xs) ys + 1, naive xs ys + fromEnum (x /= y)]

spec :: Spec
spec = do
  it "editDistance is the Levenshtein distance (against its recursive definition)" $
    forAll word $ \a -> forAll word $ \b -> editDistance a b === naive a b
  it "editDistance is a metric: zero only between equal words, symmetric, the triangle inequality" $
    forAll word $ \a -> forAll word $ \b -> forAll word $ \c ->
      (editDistance a b == 0) === (a == b) .&&. editDistance a b === editDistance b a
        .&&. editDistance a c <= editDistance a b + editDistance b c
  it "misspelt names the field a key is nearest to within two letters (case, _ and - aside); nothing for a known or a far key" $ do
    let fields = ["time_step", "end_velocity", "velocity", "start_distance"]
    misspelt fields "time_stpe" `shouldBe` Just "time_step"
    misspelt fields "TimeStep" `shouldBe` Just "time_step"
    misspelt fields "end-velocity" `shouldBe` Just "end_velocity"
    misspelt fields "velocty" `shouldBe` Just "velocity"
    misspelt fields "velocities" `shouldBe` Nothing  -- three letters from velocity
    misspelt fields "time_step" `shouldBe` Nothing
    misspelt fields "name" `shouldBe` Nothing
    misspelt fields "note" `shouldBe` Nothing
    misspelt fields "ruckig_optimal_s" `shouldBe` Nothing
