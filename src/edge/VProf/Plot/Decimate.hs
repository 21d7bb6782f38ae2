-- | Fewer points for a line that is drawn a few thousand pixels wide: of every run of
-- consecutive points the first, the lowest, the highest and the last are kept (M4, Jugel et
-- al. 2014), in their order. Drawn at a width of at most the number of runs, the line looks
-- the same as with every point, while a 200,000-sample recording no longer costs the plot
-- hundreds of megabytes.
module VProf.Plot.Decimate
  ( decimate
  , plotRuns
  ) where

import Data.List (sortOn)

-- | How many runs a line of a plot is cut into: twice the widest plot's pixels.
plotRuns :: Int
plotRuns = 2000

-- | The points (x, y) of a line, at most 4 of every run when there are more than 4 × runs
-- of them (runs of equal count, in the given order); the line as given otherwise.
decimate :: Int -> [(Double, Double)] -> [(Double, Double)]
decimate runs pts
  | runs < 1 || n <= 4 * runs = pts
  | otherwise = concatMap m4 (chunks pts)
  where
    n = length pts
    size = (n + runs - 1) `div` runs
    chunks [] = []
    chunks xs = let (a, b) = splitAt size xs in a : chunks b
    m4 run = map snd (dedupe (sortOn fst [ (i, p) | (i, p) <- [first, lowest, highest, final] ]))
      where
        indexed = zip [0 :: Int ..] run
        first = head indexed
        final = last indexed
        lowest = foldr1 (\a b -> if snd (snd a) <= snd (snd b) then a else b) indexed
        highest = foldr1 (\a b -> if snd (snd a) >= snd (snd b) then a else b) indexed
    dedupe (a : b : rest) | fst a == fst b = dedupe (a : rest)
                          | otherwise = a : dedupe (b : rest)
    dedupe xs = xs
