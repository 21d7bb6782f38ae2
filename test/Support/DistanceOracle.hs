{-# OPTIONS_GHC -O2 #-}
-- | An independent brute-force distance, written apart from "VProf.Geometry.Distance" and the
-- BVH: plain tuples, its own point–segment and point–triangle distances (the foot of the point in
-- an orthonormal frame of the triangle's plane built on its longest edge, a 2-D inside test, else
-- the nearest edge), and the segment's
-- distance as the minimum over the segment parameter t of the convex function
-- t ↦ dist(p + t (q − p), triangle), found by golden-section search (plus both ends). Meshes are
-- scanned triangle by triangle ('oSegmentMesh'); the pruned scans ('oSegmentMeshBounded',
-- 'oSegmentMeshNear') skip a triangle only by a lower bound of its distance, no hierarchy.
module Support.DistanceOracle
  ( Pt
  , oPointSegment
  , oPointTriangle
  , oSegmentTriangle
  , oSegmentSegment
  , oSegmentMesh
  , oSegmentMeshBounded
  , OMesh
  , oMesh
  , oSegmentMeshNear
  ) where

import Data.List (sortOn)
import qualified Data.Vector as V
import qualified Data.Vector.Unboxed as U

type Pt = (Double, Double, Double)

minus :: Pt -> Pt -> Pt
minus (a, b, c) (x, y, z) = (a - x, b - y, c - z)

dotP :: Pt -> Pt -> Double
dotP (a, b, c) (x, y, z) = a * x + b * y + c * z

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

-- | Point–triangle in the triangle's own orthonormal frame: e1 along the longest edge, e2 the rest
-- of the third corner by Gram–Schmidt (well conditioned even for a sliver, unlike a normal vector
-- or the normal equations); the foot of p is inside when the 2-D orientations agree, and then the
-- distance is the residual out of the plane; otherwise the nearest edge.
oPointTriangle :: Pt -> Pt -> Pt -> Pt -> Double
oPointTriangle p a0 b0 c0 =
  let l2 u v = let d = minus v u in dotP d d
      (a, b, c) = snd (maximum [ (l2 a0 b0, (a0, b0, c0)), (l2 b0 c0, (b0, c0, a0)), (l2 c0 a0, (c0, a0, b0)) ])
      edges = minimum [oPointSegment p a b, oPointSegment p b c, oPointSegment p c a]
      ab = minus b a; ac = minus c a; ap = minus p a
      lab = len ab
  in if lab == 0 then edges else
       let e1 = scaleP (1 / lab) ab
           r = minus ac (scaleP (dotP ac e1) e1)
           lr = len r
       in if lr == 0 then edges else
            let e2 = scaleP (1 / lr) r
                -- 2-D corners: a = (0, 0), b = (lab, 0), c = (cx, cy) with cy > 0
                cx = dotP ac e1; cy = dotP ac e2
                px = dotP ap e1; py = dotP ap e2
                orient (ux, uy) (vx, vy) (wx, wy) = (vx - ux) * (wy - uy) - (vy - uy) * (wx - ux)
                inside = orient (0, 0) (lab, 0) (px, py) >= 0
                      && orient (lab, 0) (cx, cy) (px, py) >= 0
                      && orient (cx, cy) (0, 0) (px, py) >= 0
                out = minus ap (plusP (scaleP px e1) (scaleP py e2))
            in if inside then min edges (len out) else edges
  where
    scaleP k (x, y, z) = (k * x, k * y, k * z)
    plusP (x, y, z) (u, v, w) = (x + u, y + v, z + w)

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
-- and triangles are searched in increasing bound until the bound exceeds the best distance found;
-- a triangle that passes is sampled at nine equally spaced t (the minimum of the samples less a
-- sixteenth of the length is again a lower bound) before the full search.
oSegmentMeshBounded :: Pt -> Pt -> [(Pt, Pt, Pt)] -> (Double, Int)
oSegmentMeshBounded p q ts =
  let m = along p q 0.5
      h = 0.5 * len (minus q p)
      bounds = sortOn fst [(oPointTriangle m a b c - h, (k, t)) | (k, t@(a, b, c)) <- zip [0 ..] ts]
      go best [] = best
      go best@(bd, _) ((lb, (k, (a, b, c))) : rest)
        | lb > bd = best
        | minimum [oPointTriangle (along p q (fromIntegral i / 8)) a b c | i <- [0 .. 8 :: Int]] - h / 8 > bd = go best rest
        | otherwise = go (min best (oSegmentTriangle p q a b c, k)) rest
  in go (1 / 0, -1) bounds

-- | A mesh with every triangle's bounding sphere: its centroid and the largest distance from
-- the centroid to a corner.
data OMesh = OMesh (U.Vector (Double, Double, Double, Double)) (V.Vector (Pt, Pt, Pt))

oMesh :: [(Pt, Pt, Pt)] -> OMesh
oMesh ts = OMesh (U.fromList (map sphere ts)) (V.fromList ts)
  where
    sphere (a@(ax, ay, az), b@(bx, by, bz), c@(cx, cy, cz)) =
      let o = ((ax + bx + cx) / 3, (ay + by + cy) / 3, (az + bz + cz) / 3)
          (ox, oy, oz) = o
      in (ox, oy, oz, maximum [len (minus a o), len (minus b o), len (minus c o)])

-- | The minimum of 'oSegmentMeshBounded' over a mesh of many triangles, faster: a triangle
-- lies in its bounding sphere, so the segment's distance to it is at least the segment's
-- distance to the centre less the radius, and at most that plus twice the radius (the distance
-- to a corner). The triangles are searched in increasing lower bound until it exceeds the best
-- distance found, each first sampled at nine equally spaced points of the segment (their least
-- distance less a sixteenth of the segment's length is again a lower bound) before the full
-- search.
oSegmentMeshNear :: Pt -> Pt -> OMesh -> (Double, Int)
oSegmentMeshNear p q (OMesh spheres ts)
  | U.null spheres = (1 / 0, -1)
  | otherwise =
      let lbs = U.map (\(ox, oy, oz, r) -> oPointSegment (ox, oy, oz) p q - r) spheres
          ub = U.minimum (U.zipWith (\lb (_, _, _, r) -> lb + 2 * r) lbs spheres)
          cands = sortOn fst [ (lbs U.! i, i) | i <- U.toList (U.findIndices (<= ub) lbs) ]
          slack = len (minus q p) / 16
          go best [] = best
          go best@(bd, _) ((lb, i) : rest)
            | lb > bd = best
            | otherwise =
                let (a, b, c) = ts V.! i
                in if minimum [oPointTriangle (along p q (fromIntegral k / 8)) a b c | k <- [0 .. 8 :: Int]] - slack > bd
                     then go best rest
                     else go (min best (oSegmentTriangle p q a b c, i)) rest
      in go (1 / 0, -1) cands
