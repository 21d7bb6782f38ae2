-- | An independent brute-force distance, written apart from "VProf.Geometry.Distance" and the
-- BVH: plain tuples, its own point–segment and point–triangle distances (projection onto the
-- plane with an inside test by edge cross products, else the nearest edge), and the segment's
-- distance as the minimum over the segment parameter t of the convex function
-- t ↦ dist(p + t (q − p), triangle), found by golden-section search (plus both ends). Meshes are
-- scanned triangle by triangle, no pruning.
module Support.DistanceOracle
  ( Pt
  , oPointSegment
  , oPointTriangle
  , oSegmentTriangle
  , oSegmentSegment
  , oSegmentMesh
  , oSegmentMeshBounded
  ) where

import Data.List (sortOn)

type Pt = (Double, Double, Double)

minus :: Pt -> Pt -> Pt
minus (a, b, c) (x, y, z) = (a - x, b - y, c - z)

dotP :: Pt -> Pt -> Double
dotP (a, b, c) (x, y, z) = a * x + b * y + c * z

crossP :: Pt -> Pt -> Pt
crossP (a, b, c) (x, y, z) = (b * z - c * y, c * x - a * z, a * y - b * x)

along :: Pt -> Pt -> Double -> Pt
along (a, b, c) (x, y, z) t = (a + t * (x - a), b + t * (y - b), c + t * (z - c))

len :: Pt -> Double
len v = sqrt (dotP v v)

oPointSegment :: Pt -> Pt -> Pt -> Double
oPointSegment p a b =
  let ab = minus b a
      l2 = dotP ab ab
      t | l2 == 0 = 0
        | otherwise = max 0 (min 1 (dotP (minus p a) ab / l2))
  in len (minus p (along a b t))

oPointTriangle :: Pt -> Pt -> Pt -> Pt -> Double
oPointTriangle p a b c =
  let n = crossP (minus b a) (minus c a)
      nn = dotP n n
      edges = minimum [oPointSegment p a b, oPointSegment p b c, oPointSegment p c a]
  in if nn == 0 then edges else
       let h = dotP (minus p a) n / nn
           (nx, ny, nz) = n
           (px, py, pz) = p
           x = (px - h * nx, py - h * ny, pz - h * nz)
           side u v = dotP (crossP (minus v u) (minus x u)) n >= 0
       in if side a b && side b c && side c a then min edges (abs h * sqrt nn) else edges

-- | Golden-section minimum over t ∈ [0, 1] of a convex function, with both ends.
golden :: (Double -> Double) -> Double
golden f = go (0 :: Int) 0 1 (f 0 `min` f 1)
  where
    g = (sqrt 5 - 1) / 2
    go k lo hi best
      | k >= 100 || hi - lo <= 0 = best
      | otherwise =
          let c = hi - g * (hi - lo); d = lo + g * (hi - lo)
              fc = f c; fd = f d
              best' = minimum [best, fc, fd]
          in if fc <= fd then go (k + 1) lo d best' else go (k + 1) c hi best'

oSegmentTriangle :: Pt -> Pt -> Pt -> Pt -> Pt -> Double
oSegmentTriangle p q a b c = golden (\t -> oPointTriangle (along p q t) a b c)

oSegmentSegment :: Pt -> Pt -> Pt -> Pt -> Double
oSegmentSegment p q a b = golden (\t -> oPointSegment (along p q t) a b)

-- | (distance, index of a nearest triangle) over every triangle.
oSegmentMesh :: Pt -> Pt -> [(Pt, Pt, Pt)] -> (Double, Int)
oSegmentMesh p q ts = minimum [(oSegmentTriangle p q a b c, k) | (k, (a, b, c)) <- zip [0 ..] ts]

-- | The same minimum over every triangle, faster: each triangle first gets the lower bound
-- dist(midpoint, triangle) − half the segment's length (a distance to a convex set is 1-Lipschitz),
-- and triangles are searched in increasing bound until the bound exceeds the best distance found.
oSegmentMeshBounded :: Pt -> Pt -> [(Pt, Pt, Pt)] -> (Double, Int)
oSegmentMeshBounded p q ts =
  let m = along p q 0.5
      h = 0.5 * len (minus q p)
      bounds = sortOn fst [(oPointTriangle m a b c - h, (k, t)) | (k, t@(a, b, c)) <- zip [0 ..] ts]
      go best [] = best
      go best@(bd, _) ((lb, (k, (a, b, c))) : rest)
        | lb > bd = best
        | otherwise = go (min best (oSegmentTriangle p q a b c, k)) rest
  in go (1 / 0, -1) bounds
