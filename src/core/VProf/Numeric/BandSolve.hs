{-# LANGUAGE BangPatterns #-}
-- | A symmetric positive definite band system A x = r with one right-hand side, scalar
-- unknowns, solved by band Cholesky in O(n·b²). "VProf.Numeric.BandedLeastSquares" solves
-- three decoupled coordinates at once; this one is for systems whose unknowns of different
-- kinds are coupled (the knot-time Gauss–Newton step of "VProf.Compress.KnotTimes", where a
-- waypoint's time and its three coordinates share one block).
module VProf.Numeric.BandSolve
  ( solveBandSPD
  ) where

import Control.Monad (forM_)
import Control.Monad.ST (ST, runST)
import qualified Data.Vector.Unboxed as U
import qualified Data.Vector.Unboxed.Mutable as MU

-- | @solveBandSPD n b a r@: @a@ holds the lower band row by row, entry (i, j) with
-- i−b <= j <= i at @i*(b+1) + j-i+b@; @r@ the right-hand side. Nothing when the matrix is
-- not (numerically) positive definite.
solveBandSPD :: Int -> Int -> U.Vector Double -> U.Vector Double -> Maybe (U.Vector Double)
solveBandSPD n b a0 r0 = runST $ do
  a <- U.thaw a0
  x <- U.thaw r0
  ok <- factor a
  if not ok then pure Nothing else do
    forM_ [0 .. n - 1] $ \i -> do
      let go !k !s | k >= i = pure s
                   | otherwise = do
                       lik <- MU.unsafeRead a (ix i k)
                       xk <- MU.unsafeRead x k
                       go (k + 1) (s - lik * xk)
      ri <- MU.unsafeRead x i
      s <- go (max 0 (i - b)) ri
      lii <- MU.unsafeRead a (ix i i)
      MU.unsafeWrite x i (s / lii)
    forM_ [n - 1, n - 2 .. 0] $ \i -> do
      let hi = min (n - 1) (i + b)
          go !k !s | k > hi = pure s
                   | otherwise = do
                       lki <- MU.unsafeRead a (ix k i)
                       xk <- MU.unsafeRead x k
                       go (k + 1) (s - lki * xk)
      yi <- MU.unsafeRead x i
      s <- go (i + 1) yi
      lii <- MU.unsafeRead a (ix i i)
      MU.unsafeWrite x i (s / lii)
    Just <$> U.unsafeFreeze x
  where
    ix i j = i * (b + 1) + j - i + b
    factor :: MU.MVector s Double -> ST s Bool
    factor a = loopI 0
      where
        loopI i
          | i >= n = pure True
          | otherwise = loopJ i (max 0 (i - b))
        loopJ i j
          | j > i = loopI (i + 1)
          | otherwise = do
              aij <- MU.unsafeRead a (ix i j)
              let k0 = max 0 (max (i - b) (j - b))
                  go !k !s | k >= j = pure s
                           | otherwise = do
                               lik <- MU.unsafeRead a (ix i k)
                               ljk <- MU.unsafeRead a (ix j k)
                               go (k + 1) (s - lik * ljk)
              s <- go k0 aij
              if j == i
                then if s > 0 && not (isNaN s)
                       then MU.unsafeWrite a (ix i i) (sqrt s) >> loopJ i (j + 1)
                       else pure False
                else do
                  ljj <- MU.unsafeRead a (ix j j)
                  MU.unsafeWrite a (ix i j) (s / ljj)
                  loopJ i (j + 1)
