{-# LANGUAGE BangPatterns #-}
-- | Exact distances between a segment (a capsule's axis) and a triangle, and between two
-- segments; capsule queries against a 'Bvh' of a mesh. The derivation is in docs/collision.md.
--
-- Segment–triangle: if the segment crosses the (non-degenerate) triangle the distance is 0;
-- otherwise a closest pair has at least one point on the boundary of its set (two interior points
-- can only be closest when the segment is parallel to the plane, and then a boundary pair is
-- closest too), so the distance is the least of: the two endpoints against the triangle, and the
-- segment against each of the three edges. Every candidate is a real pair of points, so the
-- result never undercuts the true distance and rounding can only make it larger by a few ulps.
module VProf.Geometry.Distance
  ( Closest (..)
  , pointSegment
  , pointTriangle
  , segmentSegment
  , segmentTriangle
    -- * Capsules against a mesh
  , Capsule (..)
  , Hit (..)
  , minimumDistance
  , clearanceAtLeast
  , capsuleDistance
    -- * Re-exported
  , Bvh
  , buildBvh
  ) where

import qualified Data.Vector.Unboxed as U

import VProf.Geometry.Bvh
import VProf.Kinematics.Model (Capsule (..))
import VProf.Kinematics.Transform (V3 (..), v3Add, v3Cross, v3Dot, v3Scale, v3Sub)

-- | The squared distance and a closest pair: the point on the first set, the point on the second.
data Closest = Closest {clSquared :: !Double, clFirst :: !V3, clSecond :: !V3}
  deriving (Eq, Show)

-- the vector operations of "VProf.Kinematics.Transform", under short names
sub, add, cross :: V3 -> V3 -> V3
sub = v3Sub
add = v3Add
cross = v3Cross
{-# INLINE sub #-}
{-# INLINE add #-}
{-# INLINE cross #-}

scale :: Double -> V3 -> V3
scale = v3Scale
{-# INLINE scale #-}

dot :: V3 -> V3 -> Double
dot = v3Dot
{-# INLINE dot #-}

q2 :: V3 -> Double
q2 v = dot v v
{-# INLINE q2 #-}

clamp01 :: Double -> Double
clamp01 t
  | t < 0 = 0
  | t > 1 = 1
  | otherwise = t
{-# INLINE clamp01 #-}

better :: Closest -> Closest -> Closest
better a b = if clSquared b < clSquared a then b else a
{-# INLINE better #-}

-- | Point p against segment [a, b] (a point when a = b).
pointSegment :: V3 -> V3 -> V3 -> Closest
pointSegment p a b =
  let d = sub b a
      dd = q2 d
      t = if dd > 0 then clamp01 (dot (sub p a) d / dd) else 0
      x = add a (scale t d)
  in Closest (q2 (sub p x)) p x
{-# INLINE pointSegment #-}

-- | Point p against triangle abc: the Voronoi-region method (vertex, edge or face region from the
-- signs of dot products, Ericson 2005 §5.1.5). A degenerate triangle (area below 1e-12 of its
-- longest edge squared) is its three edges.
pointTriangle :: V3 -> V3 -> V3 -> V3 -> Closest
pointTriangle p a b c
  | degenerate a b c = pointSegment p a b `better` pointSegment p b c `better` pointSegment p c a
  | otherwise =
      let ab = sub b a; ac = sub c a; ap = sub p a
          d1 = dot ab ap; d2 = dot ac ap
      in if d1 <= 0 && d2 <= 0 then at a else
         let bp = sub p b; d3 = dot ab bp; d4 = dot ac bp
         in if d3 >= 0 && d4 <= d3 then at b else
            let vc = d1 * d4 - d3 * d2
            in if vc <= 0 && d1 >= 0 && d3 <= 0 then pointSegment p a b else
               let cp = sub p c; d5 = dot ab cp; d6 = dot ac cp
               in if d6 >= 0 && d5 <= d6 then at c else
                  let vb = d5 * d2 - d1 * d6
                  in if vb <= 0 && d2 >= 0 && d6 <= 0 then pointSegment p a c else
                     let va = d3 * d6 - d5 * d4
                     in if va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0 then pointSegment p b c else
                        let den = 1 / (va + vb + vc)
                            v = vb * den; w = vc * den
                        in at (add a (add (scale v ab) (scale w ac)))
  where
    at x = Closest (q2 (sub p x)) p x

degenerate :: V3 -> V3 -> V3 -> Bool
degenerate a b c =
  let ab = sub b a; ac = sub c a; bc = sub c b
      l = max (q2 ab) (max (q2 ac) (q2 bc))
  in q2 (cross ab ac) <= 1e-24 * l * l
{-# INLINE degenerate #-}

-- | Segment [p1, q1] against segment [p2, q2]: the clamped closed form (Ericson 2005 §5.1.9),
-- then the four endpoint-against-segment candidates, which are exact whenever the segments are
-- parallel or nearly so (there an endpoint is always among the closest points).
segmentSegment :: V3 -> V3 -> V3 -> V3 -> Closest
segmentSegment p1 e1 p2 e2 =
  let d1 = sub e1 p1; d2 = sub e2 p2; r = sub p1 p2
      a = q2 d1; e = q2 d2; f = dot d2 r
      (s, t)
        | a <= 0 && e <= 0 = (0, 0)
        | a <= 0 = (0, clamp01 (f / e))
        | otherwise =
            let c = dot d1 r
            in if e <= 0 then (clamp01 (negate c / a), 0) else
               let b = dot d1 d2
                   den = a * e - b * b
                   s0 = if den > 1e-14 * a * e then clamp01 ((b * f - c * e) / den) else 0
                   t0 = (b * s0 + f) / e
               in if t0 < 0 then (clamp01 (negate c / a), 0)
                  else if t0 > 1 then (clamp01 ((b - c) / a), 1)
                  else (s0, t0)
      x = add p1 (scale s d1); y = add p2 (scale t d2)
      main = Closest (q2 (sub x y)) x y
      swap (Closest d u v) = Closest d v u
  in main `better` pointSegment p1 p2 e2 `better` pointSegment e1 p2 e2
       `better` swap (pointSegment p2 p1 e1) `better` swap (pointSegment e2 p1 e1)

-- | Segment [p, q] against triangle abc (first point on the segment, second on the triangle).
segmentTriangle :: V3 -> V3 -> V3 -> V3 -> V3 -> Closest
segmentTriangle p q a b c =
  case crossing of
    Just x -> Closest 0 x x
    Nothing ->
      pointTriangle p a b c `better` pointTriangle q a b c
        `better` segmentSegment p q a b `better` segmentSegment p q b c `better` segmentSegment p q c a
  where
    n = cross (sub b a) (sub c a)
    dp = dot n (sub p a)
    dq = dot n (sub q a)
    crossing
      | degenerate a b c = Nothing
      | (dp > 0 && dq > 0) || (dp < 0 && dq < 0) || dp == dq = Nothing
      | otherwise =
          let t = dp / (dp - dq)
              x = add p (scale t (sub q p))
              inside = dot n (cross (sub b a) (sub x a)) >= 0
                    && dot n (cross (sub c b) (sub x b)) >= 0
                    && dot n (cross (sub a c) (sub x c)) >= 0
          in if inside then Just x else Nothing

--------------------------------------------------------------------------------------------------
-- Capsules against a mesh

-- | The nearest triangle to a capsule.
data Hit = Hit
  { hitDistance :: !Double  -- ^ capsule surface to the mesh: axis distance − radius (negative: overlap)
  , hitAxisDistance :: !Double  -- ^ the capsule's axis (segment) to the mesh
  , hitTriangle :: !Int     -- ^ index of the triangle in the mesh
  , hitOnAxis :: !V3        -- ^ closest point on the capsule's axis
  , hitOnMesh :: !V3        -- ^ closest point on the triangle
  }
  deriving (Eq, Show)

-- | The exact distance from the capsule's axis to triangle k of the mesh under the BVH.
capsuleDistance :: Bvh -> Capsule -> Int -> Closest
capsuleDistance bvh (Capsule p q _) k =
  let (a, b, c) = bvhTriangle bvh k in segmentTriangle p q a b c

-- | The nearest triangle (branch and bound over the BVH, nearer child first, a node skipped when
-- its lower bound is no better than the best so far). Nothing for an empty mesh.
minimumDistance :: Bvh -> Capsule -> Maybe Hit
minimumDistance bvh cap@(Capsule p q r)
  | bvhNodeCount bvh == 0 = Nothing
  | otherwise =
      let (d2, k, Closest _ x y) = go 0 (1 / 0, -1, Closest (1 / 0) p p)
          d = sqrt d2
      in Just (Hit (d - r) d k x y)
  where
    go node best@(bd, _, _)
      | lowerBound bvh p q node ^ (2 :: Int) >= bd && bd < 1 / 0 = best
      | otherwise = case bvhChildren bvh node of
          Left (s, n) -> leaf s (s + n) best
          Right (l, rr) ->
            let bl = lowerBound bvh p q l; br = lowerBound bvh p q rr
            in if bl <= br then go rr (go l best) else go l (go rr best)
    leaf !i !e best@(bd, _, _)
      | i >= e = best
      | otherwise =
          let k = bvhOrder bvh i
              cl = capsuleDistance bvh cap k
          in if clSquared cl < bd then leaf (i + 1) e (clSquared cl, k, cl) else leaf (i + 1) e best

-- | Whether the capsule's surface keeps at least d from every triangle (axis distance ≥ d + radius);
-- stops at the first triangle closer than that. True for an empty mesh.
clearanceAtLeast :: Bvh -> Capsule -> Double -> Bool
clearanceAtLeast bvh cap@(Capsule p q r) d
  | bvhNodeCount bvh == 0 = True
  | otherwise = go 0
  where
    need = d + r
    go node
      | need < 0 = True
      | lowerBound bvh p q node >= need = True
      | otherwise = case bvhChildren bvh node of
          -- the same arithmetic as 'minimumDistance' (axis distance − r), so that the two agree
          -- at equality
          Left (s, n) -> U.all (\i -> sqrt (clSquared (capsuleDistance bvh cap (bvhOrder bvh i))) - r >= d) (U.enumFromN s n)
          Right (l, rr) -> go l && go rr
