{-# LANGUAGE BangPatterns #-}
-- | A bounding-volume hierarchy over a mesh's triangles: a binary tree of axis-aligned boxes,
-- built once by median split, stored flat in unboxed vectors.
--
-- Build: a node over a set of triangles takes the bounding box of their centroids, sorts them by
-- centroid along its longest side and gives each child half (the median split); a set of at most
-- 'leafSize' triangles, or whose centroids coincide, is a leaf. Nodes are numbered in preorder
-- (the root is 0, an inner node's left child follows it). Invariant: every node's box contains
-- every triangle below it; the leaves' ranges of 'bvhOrder' partition the triangle indices.
module VProf.Geometry.Bvh
  ( Bvh
  , buildBvh
  , leafSize
  , bvhMesh
  , bvhNodeCount
  , bvhDepth
  , bvhChildren
  , bvhOrder
  , bvhTriangle
  , bvhBox
  , lowerBound
  ) where

import Control.DeepSeq (NFData (..))
import Control.Monad.ST (ST, runST)
import qualified Data.Vector.Unboxed.Mutable as MU
import qualified Data.Vector.Unboxed as U

import VProf.Geometry.Mesh
import VProf.Kinematics.Transform (V3 (..))

data Bvh = Bvh
  { bvhMesh :: !Mesh
  , bvhBoxes :: !(U.Vector Double)  -- ^ 6 a node: min x y z, max x y z
  , bvhA :: !(U.Vector Int)         -- ^ inner: left child; leaf: start in 'bvhOrderV'
  , bvhB :: !(U.Vector Int)         -- ^ inner: right child; leaf: −(count + 1)
  , bvhOrderV :: !(U.Vector Int)    -- ^ triangle indices, leaf by leaf
  , bvhDepth :: !Int
  }

instance NFData Bvh where
  rnf b = bvhBoxes b `seq` bvhA b `seq` bvhB b `seq` bvhOrderV b `seq` rnf (bvhMesh b)

leafSize :: Int
leafSize = 4

data Tree = Leaf !Box !Int !Int | Inner !Box Tree Tree

type Box = (Double, Double, Double, Double, Double, Double)

buildBvh :: Mesh -> Bvh
buildBvh mesh
  | n == 0 = Bvh mesh U.empty U.empty U.empty U.empty 0
  | otherwise =
      Bvh
        { bvhMesh = mesh
        , bvhBoxes = U.fromList (concat [[a, b, c, d, e, f] | ((a, b, c, d, e, f), _, _) <- flat])
        , bvhA = U.fromList [x | (_, x, _) <- flat]
        , bvhB = U.fromList [y | (_, _, y) <- flat]
        , bvhOrderV = U.concat chunks
        , bvhDepth = depth tree
        }
  where
    n = triangleCount mesh
    v = meshCoords mesh
    -- per triangle: centroid (3) and box (6), computed once
    cens = U.generate (3 * n) $ \i -> let k = i `div` 3; ax = i `mod` 3
                                      in (v U.! (9 * k + ax) + v U.! (9 * k + 3 + ax) + v U.! (9 * k + 6 + ax)) / 3
    tbox = U.generate (6 * n) $ \i ->
      let k = i `div` 6; j = i `mod` 6; ax = j `mod` 3
          a = v U.! (9 * k + ax); b = v U.! (9 * k + 3 + ax); c = v U.! (9 * k + 6 + ax)
      in if j < 3 then min a (min b c) else max a (max b c)
    cen k ax = U.unsafeIndex cens (3 * k + ax)
    (tree, order) = runST $ do
      ix <- U.thaw (U.enumFromN 0 n)
      t <- build ix 0 n
      o <- U.unsafeFreeze ix
      pure (t, o)
    chunks = [order]
    -- the node over positions [lo, hi) of the index array
    build :: MU.MVector s Int -> Int -> Int -> ST s Tree
    build ix lo hi = do
      ks <- U.freeze (MU.slice lo (hi - lo) ix)
      let m = hi - lo
          bx = boxOf ks
          ext ax = let cs = U.map (`cen` ax) ks in U.maximum cs - U.minimum cs
          (ex, ey, ez) = (ext 0, ext 1, ext 2)
          ax | ex >= ey && ex >= ez = 0
             | ey >= ez = 1
             | otherwise = 2
      if m <= leafSize || max ex (max ey ez) <= 0
        then pure (Leaf bx lo m)
        else do
          let mid = lo + m `div` 2
          select ix (`cen` ax) lo (hi - 1) mid
          l <- build ix lo mid
          r <- build ix mid hi
          pure (Inner bx l r)
    boxOf ix =
      let lo j = U.minimum (U.map (\k -> U.unsafeIndex tbox (6 * k + j)) ix)
          hi j = U.maximum (U.map (\k -> U.unsafeIndex tbox (6 * k + j)) ix)
      in (lo 0, lo 1, lo 2, hi 3, hi 4, hi 5)
    depth (Leaf {}) = 1 :: Int
    depth (Inner _ l r) = 1 + max (depth l) (depth r)
    -- preorder: (box, a, b)
    flat = fst (walk 0 tree) []
    walk :: Int -> Tree -> ([(Box, Int, Int)] -> [(Box, Int, Int)], Int)
    walk i (Leaf bx s c) = (((bx, s, negate (c + 1)) :), i + 1)
    walk i (Inner bx l r) =
      let (fl, il) = walk (i + 1) l
          (fr, ir) = walk il r
      in (((bx, i + 1, il) :) . fl . fr, ir)

bvhNodeCount :: Bvh -> Int
bvhNodeCount b = U.length (bvhA b)

-- | Left (start, count) of a leaf's range in 'bvhOrder'; Right (left, right) of an inner node.
bvhChildren :: Bvh -> Int -> Either (Int, Int) (Int, Int)
bvhChildren b i =
  let x = U.unsafeIndex (bvhA b) i; y = U.unsafeIndex (bvhB b) i
  in if y < 0 then Left (x, negate y - 1) else Right (x, y)
{-# INLINE bvhChildren #-}

-- | The triangle at position i of the leaf order.
bvhOrder :: Bvh -> Int -> Int
bvhOrder b i = U.unsafeIndex (bvhOrderV b) i
{-# INLINE bvhOrder #-}

bvhTriangle :: Bvh -> Int -> (V3, V3, V3)
bvhTriangle b = triangle (bvhMesh b)
{-# INLINE bvhTriangle #-}

-- | (min corner, max corner) of node i.
bvhBox :: Bvh -> Int -> (V3, V3)
bvhBox b i =
  let e k = U.unsafeIndex (bvhBoxes b) (6 * i + k)
  in (V3 (e 0) (e 1) (e 2), V3 (e 3) (e 4) (e 5))
{-# INLINE bvhBox #-}

-- | A lower bound on the distance from segment [p, q] to anything in node i's box: the larger of
-- the gap between the box and the segment's own box, and the distance from the segment's midpoint
-- to the box less half its length.
lowerBound :: Bvh -> V3 -> V3 -> Int -> Double
lowerBound b (V3 px py pz) (V3 qx qy qz) i =
  let e k = U.unsafeIndex (bvhBoxes b) (6 * i + k)
      gap lo hi u w = max 0 (max (lo - max u w) (min u w - hi))
      gx = gap (e 0) (e 3) px qx; gy = gap (e 1) (e 4) py qy; gz = gap (e 2) (e 5) pz qz
      boxGap = sqrt (gx * gx + gy * gy + gz * gz)
      mx = 0.5 * (px + qx); my = 0.5 * (py + qy); mz = 0.5 * (pz + qz)
      out lo hi u = max 0 (max (lo - u) (u - hi))
      ox = out (e 0) (e 3) mx; oy = out (e 1) (e 4) my; oz = out (e 2) (e 5) mz
      half = 0.5 * sqrt ((qx - px) ^ (2 :: Int) + (qy - py) ^ (2 :: Int) + (qz - pz) ^ (2 :: Int))
      mid = sqrt (ox * ox + oy * oy + oz * oz) - half
  in max boxGap mid
{-# INLINE lowerBound #-}

-- | Quickselect (Hoare partition, middle pivot): afterwards position k of [lo, hi] holds the
-- element of rank k by key, everything before it has a key ≤ and everything after a key ≥.
select :: MU.MVector s Int -> (Int -> Double) -> Int -> Int -> Int -> ST s ()
select v key = go
  where
    go lo hi k
      | lo >= hi = pure ()
      | otherwise = do
          p <- key <$> MU.unsafeRead v ((lo + hi) `div` 2)
          let part i j
                | i > j = pure (i, j)
                | otherwise = do
                    i' <- advance i
                    j' <- retreat j
                    if i' <= j'
                      then MU.unsafeSwap v i' j' >> part (i' + 1) (j' - 1)
                      else pure (i', j')
              advance i = do x <- key <$> MU.unsafeRead v i; if x < p then advance (i + 1) else pure i
              retreat j = do x <- key <$> MU.unsafeRead v j; if x > p then retreat (j - 1) else pure j
          (i, j) <- part lo hi
          if k <= j then go lo j k else if k >= i then go i hi k else pure ()
