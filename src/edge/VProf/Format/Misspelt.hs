-- | Keys a reader does not know that are near one it does: @time_stpe@ beside @time_step@. A
-- reader that passes over unknown keys (a profile request's @name@ and @note@, as the
-- examples carry) would lose such a key's value without a word and run with the field's
-- default; it refuses it instead, naming the field meant.
module VProf.Format.Misspelt
  ( misspelt
  , editDistance
  ) where

import Data.Char (isAlphaNum, toLower)
import Data.List (minimumBy)
import Data.Ord (comparing)

-- | For a key that is not one of the known ones, the known key it is nearest to, when they
-- differ by at most two letters once case, @_@ and @-@ are set aside (@TimeStep@, @time-step@
-- and @time_stpe@ are all @time_step@); Nothing for a known key or one far from all of them.
misspelt :: [String] -> String -> Maybe String
misspelt known k
  | k `elem` known || null known = Nothing
  | otherwise =
      let scored = [ (editDistance (plain k) (plain f), f) | f <- known ]
          (d, f) = minimumBy (comparing fst) scored
      in if d <= 2 && length (plain k) > 2 then Just f else Nothing
  where plain = map toLower . filter isAlphaNum

-- | The Levenshtein distance: the fewest insertions, deletions and substitutions of single
-- characters that turn one string into the other.
editDistance :: String -> String -> Int
editDistance a b = last (foldl step [0 .. length a] b)
  where
    step prev@(p0 : _) c = scanl compute (p0 + 1) (zip3 a prev (tail prev))
      where compute left (x, diag, up) = minimum [left + 1, up + 1, diag + fromEnum (x /= c)]
    step [] _ = []
