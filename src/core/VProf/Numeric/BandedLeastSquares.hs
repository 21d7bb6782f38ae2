{-# LANGUAGE BangPatterns #-}
-- | Weighted linear least squares whose normal equations are a symmetric positive
-- definite band matrix: each observation touches a few consecutive unknowns (a sample
-- touches the two waypoints of its segment). Assembly and band Cholesky in O(n·b²),
-- three right-hand sides (x, y, z) at once.
module VProf.Numeric.BandedLeastSquares
  ( BandSystem
  , newBand
  , addObs
  , addObs2
  , pinValue
  , solveBand
  ) where

import Control.Monad (forM_, when)
import Control.Monad.ST (ST)
import qualified Data.Vector.Unboxed as U
import qualified Data.Vector.Unboxed.Mutable as MU


import VProf.Geometry.Vec (P3 (..), V3s (..), (*^), (^+^), (^-^))

data BandSystem s = BandSystem
  { bsN :: !Int
  , bsB :: !Int                        -- ^ half bandwidth
  , bsA :: !(MU.MVector s Double)      -- ^ lower band: (i, j), i-b <= j <= i, at i*(b+1) + j-i+b
  , bsR :: !(MU.MVector s Double)      -- ^ right-hand sides, x y z interleaved
  }

newBand :: Int -> Int -> ST s (BandSystem s)
newBand n b = BandSystem n b <$> MU.replicate (n * (b + 1)) 0 <*> MU.replicate (3 * n) 0

rdR :: BandSystem s -> Int -> ST s (P3)
rdR bs i = P3 <$> MU.unsafeRead (bsR bs) (3 * i) <*> MU.unsafeRead (bsR bs) (3 * i + 1) <*> MU.unsafeRead (bsR bs) (3 * i + 2)
{-# INLINE rdR #-}

wrR :: BandSystem s -> Int -> P3 -> ST s ()
wrR bs i (P3 x y z) = do
  MU.unsafeWrite (bsR bs) (3 * i) x
  MU.unsafeWrite (bsR bs) (3 * i + 1) y
  MU.unsafeWrite (bsR bs) (3 * i + 2) z
{-# INLINE wrR #-}

modR :: BandSystem s -> (P3 -> P3) -> Int -> ST s ()
modR bs f i = rdR bs i >>= wrR bs i . f
{-# INLINE modR #-}

ix :: BandSystem s -> Int -> Int -> Int
ix bs i j = i * (bsB bs + 1) + j - i + bsB bs
{-# INLINE ix #-}

-- | Add the observation  w · |Σ c_k x_{i_k} − target|²  (indices within the band).
addObs :: BandSystem s -> Double -> [(Int, Double)] -> P3 -> ST s ()
addObs bs w cs target =
  forM_ cs $ \(i, ci) -> do
    modR bs (^+^ (w * ci) *^ target) i
    forM_ cs $ \(j, cj) ->
      when (j <= i) $ MU.unsafeModify (bsA bs) (+ w * ci * cj) (ix bs i j)
{-# INLINE addObs #-}

-- | 'addObs' for the common two-unknown observation (i, ci), (i+1, cj).
addObs2 :: BandSystem s -> Double -> Int -> Double -> Double -> P3 -> ST s ()
addObs2 bs w i ci cj target = do
  modR bs (^+^ (w * ci) *^ target) i
  modR bs (^+^ (w * cj) *^ target) (i + 1)
  MU.unsafeModify (bsA bs) (+ w * ci * ci) (ix bs i i)
  MU.unsafeModify (bsA bs) (+ w * cj * cj) (ix bs (i + 1) (i + 1))
  MU.unsafeModify (bsA bs) (+ w * ci * cj) (ix bs (i + 1) i)
{-# INLINE addObs2 #-}

-- | Fix unknown p to value v (eliminated exactly; the matrix stays symmetric).
pinValue :: BandSystem s -> Int -> P3 -> ST s ()
pinValue bs p v = do
  let n = bsN bs; b = bsB bs
  forM_ [max 0 (p - b) .. min (n - 1) (p + b)] $ \r -> when (r /= p) $ do
    let k = if r > p then ix bs r p else ix bs p r
    a <- MU.unsafeRead (bsA bs) k
    modR bs (^-^ a *^ v) r
    MU.unsafeWrite (bsA bs) k 0
  MU.unsafeWrite (bsA bs) (ix bs p p) 1
  wrR bs p v

-- | Solve by band Cholesky; Left when the matrix is not positive definite.
solveBand :: BandSystem s -> ST s (Either String V3s)
solveBand bs = do
  let n = bsN bs; b = bsB bs; a = bsA bs
  okRef <- MU.replicate 1 (-1 :: Int)
  -- factor in place: A = L Lᵀ
  forM_ [0 .. n - 1] $ \i ->
    forM_ [max 0 (i - b) .. i] $ \j -> do
      aij <- MU.unsafeRead a (ix bs i j)
      let k0 = max 0 (max (i - b) (j - b))
          go !k !s | k >= j = pure s
                   | otherwise = do
                       lik <- MU.unsafeRead a (ix bs i k)
                       ljk <- MU.unsafeRead a (ix bs j k)
                       go (k + 1) (s - lik * ljk)
      s <- go k0 aij
      if j == i
        then if s > 0 then MU.unsafeWrite a (ix bs i i) (sqrt s)
             else do MU.unsafeWrite okRef 0 i; MU.unsafeWrite a (ix bs i i) 1
        else do ljj <- MU.unsafeRead a (ix bs j j); MU.unsafeWrite a (ix bs i j) (s / ljj)
  bad <- MU.unsafeRead okRef 0
  if bad >= 0
    then pure (Left ("least-squares system is singular at unknown " ++ show bad))
    else do
      forM_ [0 .. n - 1] $ \i -> do
        let go !k !s | k >= i = pure s
                     | otherwise = do
                         lik <- MU.unsafeRead a (ix bs i k)
                         yk <- rdR bs k
                         go (k + 1) (s ^-^ lik *^ yk)
        ri <- rdR bs i
        s <- go (max 0 (i - b)) ri
        lii <- MU.unsafeRead a (ix bs i i)
        wrR bs i ((1 / lii) *^ s)
      forM_ [n - 1, n - 2 .. 0] $ \i -> do
        let go !k !s | k > min (n - 1) (i + b) = pure s
                     | otherwise = do
                         lki <- MU.unsafeRead a (ix bs k i)
                         xk <- rdR bs k
                         go (k + 1) (s ^-^ lki *^ xk)
        yi <- rdR bs i
        s <- go (i + 1) yi
        lii <- MU.unsafeRead a (ix bs i i)
        wrR bs i ((1 / lii) *^ s)
      Right . V3s <$> U.freeze (bsR bs)
