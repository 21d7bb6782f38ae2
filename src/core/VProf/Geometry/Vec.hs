{-# LANGUAGE FunctionalDependencies, FlexibleInstances, FlexibleContexts #-}
-- | The compressor's hot-loop numerics: monomorphic, unpacked 3-vectors ('P3') and
-- quaternions ('Q4'), and packed arrays of them (flat unboxed 'Double' vectors with
-- inlined accessors). linear's 'V3' and 'Quaternion' are used at the public boundary
-- ("VProf.Compress.Types"); inside the loops their polymorphic fields box every
-- component (measured on GHC 9.0.2: about 400 ns an element through linear's 'Unbox'
-- instances against about 30 ns here).
module VProf.Geometry.Vec
  ( P3 (..)
  , Q4 (..)
  , (^+^), (^-^), (*^), (^/)
  , dot, quadrance, norm, distance
  , fromV3, toV3, fromQuat, toQuat
  , Packed (..)
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

-- | A 3-vector (m, m/s or rad, by context).
data P3 = P3 {-# UNPACK #-} !Double {-# UNPACK #-} !Double {-# UNPACK #-} !Double
  deriving (Eq, Show)

-- | A quaternion w + xi + yj + zk.
data Q4 = Q4 {-# UNPACK #-} !Double {-# UNPACK #-} !Double {-# UNPACK #-} !Double {-# UNPACK #-} !Double
  deriving (Eq, Show)

infixl 6 ^+^, ^-^
infixl 7 *^, ^/

(^+^), (^-^) :: P3 -> P3 -> P3
P3 a b c ^+^ P3 x y z = P3 (a + x) (b + y) (c + z)
P3 a b c ^-^ P3 x y z = P3 (a - x) (b - y) (c - z)
{-# INLINE (^+^) #-}
{-# INLINE (^-^) #-}

(*^) :: Double -> P3 -> P3
k *^ P3 x y z = P3 (k * x) (k * y) (k * z)
{-# INLINE (*^) #-}

(^/) :: P3 -> Double -> P3
P3 x y z ^/ k = P3 (x / k) (y / k) (z / k)
{-# INLINE (^/) #-}

dot :: P3 -> P3 -> Double
dot (P3 a b c) (P3 x y z) = a * x + b * y + c * z
{-# INLINE dot #-}

quadrance :: P3 -> Double
quadrance v = dot v v
{-# INLINE quadrance #-}

norm :: P3 -> Double
norm = sqrt . quadrance
{-# INLINE norm #-}

distance :: P3 -> P3 -> Double
distance a b = norm (a ^-^ b)
{-# INLINE distance #-}

fromV3 :: V3 Double -> P3
fromV3 (V3 x y z) = P3 x y z

toV3 :: P3 -> V3 Double
toV3 (P3 x y z) = V3 x y z

fromQuat :: Quaternion Double -> Q4
fromQuat (Quaternion w (V3 x y z)) = Q4 w x y z

toQuat :: Q4 -> Quaternion Double
toQuat (Q4 w x y z) = Quaternion w (V3 x y z)

newtype V3s = V3s (U.Vector Double) deriving (Eq, Show)
newtype Qs = Qs (U.Vector Double) deriving (Eq, Show)

class Packed v e | v -> e where
  plength :: v -> Int
  pindex :: v -> Int -> e
  pgenerate :: Int -> (Int -> e) -> v
  pfromList :: [e] -> v

instance Packed V3s P3 where
  plength (V3s v) = U.length v `div` 3
  {-# INLINE plength #-}
  pindex (V3s v) i = P3 (U.unsafeIndex v (3 * i)) (U.unsafeIndex v (3 * i + 1)) (U.unsafeIndex v (3 * i + 2))
  {-# INLINE pindex #-}
  pgenerate n f = V3s $ U.create $ do
    m <- MU.unsafeNew (3 * n)
    forM_ [0 .. n - 1] $ \i -> do
      let P3 x y z = f i
      MU.unsafeWrite m (3 * i) x
      MU.unsafeWrite m (3 * i + 1) y
      MU.unsafeWrite m (3 * i + 2) z
    pure m
  {-# INLINE pgenerate #-}
  pfromList xs = V3s (U.fromList (concat [[x, y, z] | P3 x y z <- xs]))

instance Packed Qs Q4 where
  plength (Qs v) = U.length v `div` 4
  {-# INLINE plength #-}
  pindex (Qs v) i = Q4 (U.unsafeIndex v (4 * i)) (U.unsafeIndex v (4 * i + 1))
                       (U.unsafeIndex v (4 * i + 2)) (U.unsafeIndex v (4 * i + 3))
  {-# INLINE pindex #-}
  pgenerate n f = Qs $ U.create $ do
    m <- MU.unsafeNew (4 * n)
    forM_ [0 .. n - 1] $ \i -> do
      let Q4 w x y z = f i
      MU.unsafeWrite m (4 * i) w
      MU.unsafeWrite m (4 * i + 1) x
      MU.unsafeWrite m (4 * i + 2) y
      MU.unsafeWrite m (4 * i + 3) z
    pure m
  {-# INLINE pgenerate #-}
  pfromList xs = Qs (U.fromList (concat [[w, x, y, z] | Q4 w x y z <- xs]))

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
