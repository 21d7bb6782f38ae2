{-# LANGUAGE BangPatterns #-}
-- | The start of the knot fit (docs/compress.md, "Start: a line partition"): the samples
-- split into m consecutive groups, each fitted by its own least-squares line in time, the
-- sum of the groups' residual SSE as small as the search finds. Its minimum over all
-- partitions is the floor of bench/COMPRESSION.md (no path of m+1 waypoints does better), and
-- the boundaries of a good partition are where a path's waypoints belong. Exact minimisation
-- over m groups costs O(n²m); here each group holds at most w samples and the group count is
-- priced instead of fixed (Lagrangian relaxation: minimise SSE + λ·groups, one O(n·w) dynamic
-- program per λ, λ by bisection), then groups are split or merged greedily to exactly m.
-- A group's line-fit SSE is O(1) from prefix sums.
module VProf.Compress.Partition
  ( linePartition
  , linePartitionWith
  , groupSse
  , PrefixSums (..)
  , prefixSums
  ) where

import Control.Monad (forM_)
import Control.Monad.ST (runST)
import Data.List (foldl')
import qualified Data.Vector.Unboxed as U
import qualified Data.Vector.Unboxed.Mutable as MU

import VProf.Geometry.Vec

-- | Prefix sums of 1, t, t², x, tx, x² (per coordinate), time and positions centred.
data PrefixSums = PrefixSums
  { psT, psTT, psX, psY, psZ, psTX, psTY, psTZ, psXX :: !(U.Vector Double) }

prefixSums :: U.Vector Double -> V3s -> PrefixSums
prefixSums ts ps = PrefixSums (sc tc) (sc (U.map (^ (2 :: Int)) tc)) (sc xs) (sc ys) (sc zs)
                              (sc (U.zipWith (*) tc xs)) (sc (U.zipWith (*) tc ys)) (sc (U.zipWith (*) tc zs))
                              (sc (U.zipWith3 (\x y z -> x * x + y * y + z * z) xs ys zs))
  where
    n = U.length ts
    t0 = U.head ts
    tc = U.map (subtract t0) ts
    P3 mx my mz = (foldl' (^+^) (P3 0 0 0) [ pindex ps i | i <- [0 .. n - 1] ]) ^/ fromIntegral (max 1 n)
    xs = U.generate n (\i -> let P3 x _ _ = pindex ps i in x - mx)
    ys = U.generate n (\i -> let P3 _ y _ = pindex ps i in y - my)
    zs = U.generate n (\i -> let P3 _ _ z = pindex ps i in z - mz)
    sc = U.scanl' (+) 0

-- | Group evaluations a dynamic program of the line partition may make before its
-- boundaries go on a coarser grid (about a second on the machines of bench/).
gridWork :: Double
gridWork = 4e7

-- | Residual SSE of the least-squares line in time (each coordinate) through samples a .. b−1.
groupSse :: PrefixSums -> Int -> Int -> Double
groupSse s a b
  | b - a <= 2 = 0
  | otherwise = max 0 (vx - (cx * cx + cy * cy + cz * cz) / vt')
  where
    c = fromIntegral (b - a)
    d v = U.unsafeIndex v b - U.unsafeIndex v a
    st = d (psT s)
    vt = d (psTT s) - st * st / c
    vt' = max 1e-300 vt
    sx = d (psX s); sy = d (psY s); sz = d (psZ s)
    cx = d (psTX s) - st * sx / c
    cy = d (psTY s) - st * sy / c
    cz = d (psTZ s) - st * sz / c
    vx = d (psXX s) - (sx * sx + sy * sy + sz * sz) / c   -- Σ|p − p̄|² over the three coordinates
{-# INLINE groupSse #-}

-- | Boundaries 0 = b_0 < b_1 < … < b_m = n of m groups (group g holds samples
-- b_g .. b_{g+1}−1), each group at least 2 samples, at most w, unless n < 2m (then equal
-- groups). The window w is widened to ⌈n/m⌉ when it is shorter. Never worse than m equal
-- groups: the search is a heuristic (a priced count and greedy repairs), so it keeps the
-- equal split when that is better, or when the repairs cannot reach m groups.
linePartition :: U.Vector Double -> V3s -> Int -> Int -> U.Vector Int
linePartition = linePartitionWith gridWork

-- | 'linePartition' with another limit on the dynamic program's work (for tests of the grid).
linePartitionWith :: Double -> U.Vector Double -> V3s -> Int -> Int -> U.Vector Int
linePartitionWith work ts ps m w0
  | m <= 1 = U.fromList [0, n]
  | n < 2 * m = equal
  | groups found == m && sse found <= sse equal = found
  | otherwise = equal
  where
    equal = U.generate (m + 1) (\g -> (g * n) `div` m)
    found = refine (adjust (bracket lam0 (dp lam0) (12 :: Int)))
    -- The dynamic program costs about n·w group evaluations per λ. Beyond 'gridWork' of
    -- them (long recordings at few points: 60,000 samples at 20 points is 7.6e8, and the
    -- start took minutes) its boundaries lie on a grid of r samples, which divides the cost
    -- by r²; 'refine' then moves each boundary to its best sample within r of it. Below the
    -- limit (every recording of bench/COMPRESSION.md) r = 1: the search is unchanged.
    r = max 1 (ceiling (sqrt (fromIntegral n * fromIntegral w / work :: Double)))
    pos g = min n (g * r)
    nGrid = (n + r - 1) `div` r
    sse v = sum [ groupSse s (v U.! g) (v U.! (g + 1)) | g <- [0 .. U.length v - 2] ]
    n = U.length ts
    w = max w0 ((n + m - 1) `div` m + 1)
    s = prefixSums ts ps
    -- a guess at the price of a group: the mean group SSE of m equal groups
    lam0 = max 1e-30 (sum [ groupSse s ((g * n) `div` m) (((g + 1) * n) `div` m) | g <- [0 .. m - 1] ] / fromIntegral m)
    -- minimise Σ SSE + λ·groups; ties to fewer groups. Boundaries of the optimum.
    dp :: Double -> U.Vector Int
    dp lam = runST $ do
      f <- MU.replicate (nGrid + 1) (1 / 0 :: Double)
      cnt <- MU.replicate (nGrid + 1) (0 :: Int)
      arg <- MU.replicate (nGrid + 1) (0 :: Int)
      MU.write f 0 0
      forM_ [1 .. nGrid] $ \gb -> do
        let bb = pos gb
            lo = max 0 ((bb - w + r - 1) `div` r)
            go !ga !bestF !bestC !bestA
              | ga >= gb || pos ga > bb - 2 = pure (bestF, bestC, bestA)
              | otherwise = do
                  fa <- MU.unsafeRead f ga
                  ca <- MU.unsafeRead cnt ga
                  let v = fa + groupSse s (pos ga) bb + lam
                  if v < bestF || (v == bestF && ca + 1 < bestC)
                    then go (ga + 1) v (ca + 1) ga
                    else go (ga + 1) bestF bestC bestA
        (bf, bc, ba) <- go lo (1 / 0) maxBound 0
        -- an end no group reaches (one sample in) keeps F = ∞
        if isInfinite bf then pure () else do
          MU.unsafeWrite f gb bf
          MU.unsafeWrite cnt gb bc
          MU.unsafeWrite arg gb ba
      args <- U.unsafeFreeze arg
      let back g acc | g == 0 = 0 : acc
                     | otherwise = back (args U.! g) (pos g : acc)
      pure (U.fromList (back nGrid []))
    -- each interior boundary moved to the sample within r of it (groups of at least two
    -- samples) where its two groups' SSE is least, pass after pass from the first until
    -- none moves (at most 5); nothing to do on the full grid (r = 1)
    refine v0
      | r == 1 = v0
      | otherwise = passes (5 :: Int) v0
      where
        passes 0 v = v
        passes k v = let v' = U.fromList (go (U.toList v)) in if v' == v then v else passes (k - 1) v'
        go (a : b : c : rest) =
          let cands = [max (a + 2) (b - r) .. min (c - 2) (b + r)]
              cost b' = groupSse s a b' + groupSse s b' c
              best = if null cands then b else snd (minimum [ (cost b', b') | b' <- cands ])
          in a : go (best : c : rest)
        go xs = xs
    groups v = U.length v - 1
    close v = abs (groups v - m) <= max 1 (m `div` 50)
    -- find λ with too few groups and one with too many (steps of ×30 from the guess), then
    -- bisect on log λ (more groups as λ falls) until within m/50 groups; the greedy
    -- adjustment below does the rest
    bracket lam v tries
      | close v || tries <= 0 = v
      | groups v > m = let lam' = lam * 30; v' = dp lam' in
          if groups v' <= m then bisect lam v lam' v' (20 :: Int) else bracket lam' v' (tries - 1)
      | otherwise = let lam' = lam / 30; v' = dp lam' in
          if groups v' >= m then bisect lam' v' lam v (20 :: Int) else bracket lam' v' (tries - 1)
    -- lo gives >= m groups, hi <= m
    bisect lo vlo hi vhi iters
      | close vlo = vlo
      | close vhi = vhi
      | iters <= 0 = if groups vlo - m <= m - groups vhi then vlo else vhi
      | otherwise =
          let mid = sqrt (lo * hi); vm = dp mid
          in if close vm then vm
             else if groups vm > m then bisect mid vm hi vhi (iters - 1)
             else bisect lo vlo mid vm (iters - 1)
    -- greedy: split the group whose best split gains most, or merge the adjacent pair
    -- whose merge costs least, until exactly m groups
    adjust v
      | groups v == m = v
      | groups v < m =
          let cands = [ (gain, g, c) | g <- [0 .. groups v - 1]
                                     , let a = v U.! g; b = v U.! (g + 1), b - a >= 4
                                     , (gain, c) <- [bestSplit a b] ]
          in case cands of
               [] -> v
               _ -> let (_, _, c) = maximum cands
                    in adjust (U.fromList (insertSorted c (U.toList v)))
      | otherwise =
          let costs = [ (groupSse s (v U.! (g - 1)) (v U.! (g + 1)) - groupSse s (v U.! (g - 1)) (v U.! g)
                           - groupSse s (v U.! g) (v U.! (g + 1)), g) | g <- [1 .. groups v - 1] ]
              (_, g) = minimum costs
          in adjust (U.fromList [ x | (i, x) <- zip [0 :: Int ..] (U.toList v), i /= g ])
    bestSplit a b = maximum [ (groupSse s a b - groupSse s a c - groupSse s c b, c) | c <- [a + 2 .. b - 2] ]
    insertSorted x (y : ys) | x < y = x : y : ys
                            | otherwise = y : insertSorted x ys
    insertSorted x [] = [x]
