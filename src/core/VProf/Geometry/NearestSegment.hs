{-# LANGUAGE BangPatterns #-}
-- | The distance from a point to the nearest segment of a polyline, regardless of time (the
-- compression's geometric error), in about O(log k) a query instead of O(k): a bounding-volume
-- hierarchy over the k−1 segments (axis-aligned boxes, median split of the segments' midpoints
-- along the longest side, leaves of at most 4 segments) searched branch and bound, the nearer
-- child first, a subtree skipped when its box is farther than the best distance so far. The
-- answer is the same minimum of 'pointSegmentDistance' over all segments (boxes contain their
-- segments, so no skipped segment is nearer).
module VProf.Geometry.NearestSegment
  ( SegIndex
  , buildSegIndex
  , nearestSegmentDistance
  ) where

import Data.List (sortOn)
import qualified Data.Vector.Unboxed as U

import VProf.Geometry.Polyline (pointSegmentDistance)
import VProf.Geometry.Vec

data Box = Box !Double !Double !Double !Double !Double !Double

data Tree = Empty | Leaf !Box !(U.Vector Int) | Node !Box Tree Tree

-- | The hierarchy over the segments (j, j+1) of a polyline's vertices.
data SegIndex = SegIndex !V3s Tree

buildSegIndex :: V3s -> SegIndex
buildSegIndex ps = SegIndex ps (build [0 .. plength ps - 2])
  where
    build [] = Empty
    build ix
      | length ix <= 4 = Leaf (boxOf ix) (U.fromList ix)
      | otherwise =
          let mids = [ (j, mid j) | j <- ix ]
              P3 lx ly lz = foldr1 pmin (map snd mids)
              P3 hx hy hz = foldr1 pmax (map snd mids)
              key (P3 x y z) | hx - lx >= hy - ly && hx - lx >= hz - lz = x
                             | hy - ly >= hz - lz = y
                             | otherwise = z
              sorted = map fst (sortOn (key . snd) mids)
              (l, r) = splitAt (length ix `div` 2) sorted
          in Node (boxOf ix) (build l) (build r)
    mid j = 0.5 *^ (pindex ps j ^+^ pindex ps (j + 1))
    boxOf ix = let vs = concat [ [pindex ps j, pindex ps (j + 1)] | j <- ix ]
                   P3 ax ay az = foldr1 pmin vs
                   P3 bx by bz = foldr1 pmax vs
               in Box ax ay az bx by bz
    pmin (P3 a b c) (P3 d e f) = P3 (min a d) (min b e) (min c f)
    pmax (P3 a b c) (P3 d e f) = P3 (max a d) (max b e) (max c f)

-- | The smaller of @bound@ and the distance from the point to the nearest segment.
nearestSegmentDistance :: SegIndex -> Double -> P3 -> Double
nearestSegmentDistance (SegIndex ps tree) bound p = go tree bound
  where
    far b best = boxDist2 b > best * best * (1 + 1e-12)
    go Empty best = best
    go (Leaf b ix) best
      | far b best = best
      | otherwise = U.foldl' (\m j -> min m (pointSegmentDistance (pindex ps j) (pindex ps (j + 1)) p)) best ix
    go (Node b l r) best
      | far b best = best
      | boxOfT l `nearer` boxOfT r = go r (go l best)
      | otherwise = go l (go r best)
    nearer (Just a) (Just b') = boxDist2 a <= boxDist2 b'
    nearer (Just _) Nothing = True
    nearer Nothing _ = False
    boxOfT Empty = Nothing
    boxOfT (Leaf b _) = Just b
    boxOfT (Node b _ _) = Just b
    P3 px py pz = p
    boxDist2 (Box ax ay az bx by bz) =
      let d lo hi v = if v < lo then lo - v else if v > hi then v - hi else 0
          !dx = d ax bx px; !dy = d ay by py; !dz = d az bz pz
      in dx * dx + dy * dy + dz * dz
