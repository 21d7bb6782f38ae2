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
  , nearestWithin
  , probeDistance
  , clearanceAtLeast
  , triangleLowerBound2
  , capsuleDistance
    -- * Re-exported
  , Bvh
  , buildBvh
  ) where


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
minimumDistance bvh cap = nearestWithin bvh cap (1 / 0)
{-# INLINE minimumDistance #-}

-- | The best triangle so far in a branch and bound: its squared axis distance, index, closest pair.
data Best = Best !Double !Int !V3 !V3

-- | The nearest triangle among those whose axis distance is below the bound (m), by the same
-- branch and bound as 'minimumDistance' started from the bound instead of infinity; Nothing when
-- no triangle is that near (or the mesh is empty). A triangle found is the one 'minimumDistance'
-- finds: the search visits the same nodes in the same order, less those that cannot hold a
-- triangle nearer than the bound. Used to find the nearest of several capsules, each searched
-- only below the nearest so far ("VProf.Kinematics.Collision").
nearestWithin :: Bvh -> Capsule -> Double -> Maybe Hit
nearestWithin bvh (Capsule p q r) bound
  | bvhNodeCount bvh == 0 = Nothing
  | otherwise =
      let b2 = bound * bound
          Best d2 k x y = go 0 (lowerBound bvh p q 0) (Best b2 (-1) p p)
          d = sqrt d2
      in if k < 0 then Nothing else Just (Hit (d - r) d k x y)
  where
    -- lb: the node's lower bound, computed once by its parent (the children's order needs it)
    go !node !lb best@(Best bd _ _ _)
      | lb * lb >= bd && bd < 1 / 0 = best
      | otherwise = case bvhChildren bvh node of
          Left (s, n) -> leaf s (s + n) best
          Right (l, rr) ->
            let bl = lowerBound bvh p q l; br = lowerBound bvh p q rr
            in if bl <= br then go rr br (go l bl best) else go l bl (go rr br best)
    leaf !i !e best@(Best bd _ _ _)
      | i >= e = best
      | otherwise =
          let k = bvhOrder bvh i
              (a, b, c) = bvhTriangle bvh k
          in if triangleLowerBound2 p q a b c >= bd then leaf (i + 1) e best
             else let Closest d2 x y = segmentTriangle p q a b c
                  in if d2 < bd then leaf (i + 1) e (Best d2 k x y) else leaf (i + 1) e best

-- | An upper bound of the capsule's axis distance to the mesh, cheaply: the nearest triangle of
-- the one leaf reached by always stepping into the child with the smaller lower bound (infinity
-- for an empty mesh). It orders several capsules so that the nearest is searched first.
probeDistance :: Bvh -> Capsule -> Double
probeDistance bvh (Capsule p q _)
  | bvhNodeCount bvh == 0 = 1 / 0
  | otherwise = go 0
  where
    go node = case bvhChildren bvh node of
      Left (s, n) -> sqrt (minimum [ clSquared (segmentTriangle p q a b c)
                                   | i <- [s .. s + n - 1], let (a, b, c) = bvhTriangle bvh (bvhOrder bvh i) ])
      Right (l, rr) -> if lowerBound bvh p q l <= lowerBound bvh p q rr then go l else go rr

-- | A lower bound of the squared distance from segment [p, q] to triangle abc, a few operations
-- instead of 'segmentTriangle''s dozens: the larger of the squared gap between the two bounding
-- boxes and, when both ends of the segment lie strictly on one side of the triangle's plane, the
-- nearer end's height above it. The height is used only for a well-shaped triangle (its area at
-- least 1e-3 of its longest edge squared, so that the computed normal is accurate) and less an
-- allowance for rounding (1e-9 of the lengths involved); the whole is shrunk by a relative 1e-9,
-- so that it never exceeds what 'segmentTriangle' computes. A triangle whose bound already
-- reaches the best so far (or the clearance asked) is skipped without the exact test.
triangleLowerBound2 :: V3 -> V3 -> V3 -> V3 -> V3 -> Double
triangleLowerBound2 p@(V3 px py pz) q@(V3 qx qy qz) a@(V3 ax ay az) b@(V3 bx by bz) c@(V3 cx cy cz) =
  let gap u w t0 t1 t2 =
        let lo = min t0 (min t1 t2); hi = max t0 (max t1 t2)
        in max 0 (max (lo - max u w) (min u w - hi))
      gx = gap px qx ax bx cx; gy = gap py qy ay by cy; gz = gap pz qz az bz cz
      box2 = gx * gx + gy * gy + gz * gz
      ab = sub b a; ac = sub c a
      n = cross ab ac
      nn = dot n n
      l2 = max (q2 ab) (max (q2 ac) (q2 (sub c b)))
      ap = sub p a; aq = sub q a
      dp = dot n ap
      dq = dot n aq
      plane2
        | nn >= 1e-6 * l2 * l2 && ((dp > 0 && dq > 0) || (dp < 0 && dq < 0)) =
            let h = min (abs dp) (abs dq) / sqrt nn - 1e-9 * (l1 ap + l1 aq + 3 * sqrt l2)
            in if h > 0 then h * h else 0
        | otherwise = 0
  in (1 - 1e-9) * max box2 plane2
  where
    l1 (V3 x y z) = abs x + abs y + abs z
{-# INLINE triangleLowerBound2 #-}

-- | Whether the capsule's surface keeps at least d from every triangle (axis distance ≥ d + radius);
-- stops at the first triangle closer than that, the nearer child first. True for an empty mesh.
clearanceAtLeast :: Bvh -> Capsule -> Double -> Bool
clearanceAtLeast bvh (Capsule p q r) d
  | bvhNodeCount bvh == 0 = True
  | need < 0 = True
  | otherwise = go 0 (lowerBound bvh p q 0)
  where
    need = d + r
    need2 = need * need
    go !node !lb
      | lb >= need = True
      | otherwise = case bvhChildren bvh node of
          Left (s, n) -> leaf s (s + n)
          Right (l, rr) ->
            let bl = lowerBound bvh p q l; br = lowerBound bvh p q rr
            in if bl <= br then go l bl && go rr br else go rr br && go l bl
    -- the same arithmetic as 'minimumDistance' (axis distance − r), so that the two agree at
    -- equality; a triangle whose lower bound already reaches d + r passes without it
    leaf !i !e
      | i >= e = True
      | otherwise =
          let (a, b, c) = bvhTriangle bvh (bvhOrder bvh i)
          in (triangleLowerBound2 p q a b c >= need2 || sqrt (clSquared (segmentTriangle p q a b c)) - r >= d)
               && leaf (i + 1) e
