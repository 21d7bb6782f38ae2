{-# LANGUAGE FunctionalDependencies, FlexibleInstances, FlexibleContexts #-}
-- | Packed arrays of 3-vectors and quaternions: flat unboxed 'Double' vectors with
-- inlined accessors. (linear's own 'Data.Vector.Unboxed.Unbox' instances for 'V3' and
-- 'Quaternion' cost about 400 ns an element on GHC 9.0.2 here; these cost about 30.)
module VProf.Compress.Vec
  ( Packed (..)
  , V3s (..)
  , Qs (..)
  , ptoList
  , phead
  , plast
  , pbackpermute
  , pupdate
  , pifilter
  , pmap
  , pzipWith
  ) where

import Control.Monad (forM_)
import qualified Data.Vector.Unboxed as U
import qualified Data.Vector.Unboxed.Mutable as MU
import Linear (Quaternion (..), V3 (..))

newtype V3s = V3s (U.Vector Double) deriving (Eq, Show)
newtype Qs = Qs (U.Vector Double) deriving (Eq, Show)

class Packed v e | v -> e where
  plength :: v -> Int
  pindex :: v -> Int -> e
  pgenerate :: Int -> (Int -> e) -> v
  pfromList :: [e] -> v

instance Packed V3s (V3 Double) where
  plength (V3s v) = U.length v `div` 3
  {-# INLINE plength #-}
  pindex (V3s v) i = V3 (U.unsafeIndex v (3 * i)) (U.unsafeIndex v (3 * i + 1)) (U.unsafeIndex v (3 * i + 2))
  {-# INLINE pindex #-}
  pgenerate n f = V3s $ U.create $ do
    m <- MU.unsafeNew (3 * n)
    forM_ [0 .. n - 1] $ \i -> do
      let V3 x y z = f i
      MU.unsafeWrite m (3 * i) x
      MU.unsafeWrite m (3 * i + 1) y
      MU.unsafeWrite m (3 * i + 2) z
    pure m
  {-# INLINE pgenerate #-}
  pfromList xs = V3s (U.fromList (concat [[x, y, z] | V3 x y z <- xs]))

instance Packed Qs (Quaternion Double) where
  plength (Qs v) = U.length v `div` 4
  {-# INLINE plength #-}
  pindex (Qs v) i = Quaternion (U.unsafeIndex v (4 * i))
                      (V3 (U.unsafeIndex v (4 * i + 1)) (U.unsafeIndex v (4 * i + 2)) (U.unsafeIndex v (4 * i + 3)))
  {-# INLINE pindex #-}
  pgenerate n f = Qs $ U.create $ do
    m <- MU.unsafeNew (4 * n)
    forM_ [0 .. n - 1] $ \i -> do
      let Quaternion w (V3 x y z) = f i
      MU.unsafeWrite m (4 * i) w
      MU.unsafeWrite m (4 * i + 1) x
      MU.unsafeWrite m (4 * i + 2) y
      MU.unsafeWrite m (4 * i + 3) z
    pure m
  {-# INLINE pgenerate #-}
  pfromList xs = Qs (U.fromList (concat [[w, x, y, z] | Quaternion w (V3 x y z) <- xs]))

instance Packed (U.Vector Double) Double where
  pfromList = U.fromList
  plength = U.length
  pindex = U.unsafeIndex
  pgenerate = U.generate

ptoList :: Packed v e => v -> [e]
ptoList v = map (pindex v) [0 .. plength v - 1]

phead :: Packed v e => v -> e
phead v = pindex v 0

plast :: Packed v e => v -> e
plast v = pindex v (plength v - 1)

-- | Elements at the given indices.
pbackpermute :: Packed v e => v -> U.Vector Int -> v
pbackpermute v idx = pgenerate (U.length idx) (\k -> pindex v (U.unsafeIndex idx k))
{-# INLINE pbackpermute #-}

pupdate :: Packed v e => v -> [(Int, e)] -> v
pupdate v ups = pgenerate (plength v) (\i -> maybe (pindex v i) id (lookup i ups))

pifilter :: Packed v e => (Int -> Bool) -> v -> v
pifilter keep v = pbackpermute v (U.filter keep (U.enumFromN 0 (plength v)))

pmap :: (Packed v e, Packed w f) => (e -> f) -> v -> w
pmap f v = pgenerate (plength v) (f . pindex v)
{-# INLINE pmap #-}

pzipWith :: (Packed v e, Packed w f, Packed x g) => (e -> f -> g) -> v -> w -> x
pzipWith f a b = pgenerate (min (plength a) (plength b)) (\i -> f (pindex a i) (pindex b i))
{-# INLINE pzipWith #-}
