{-# LANGUAGE FlexibleContexts #-}
-- | The baseline: 3-D Ramer–Douglas–Peucker on the positions. Waypoints are samples (their
-- time, position and orientation), so the result is a 'Path' like the thesis method's.
-- Implemented as greedy insertion of the farthest sample (the order in which recursive
-- RDP splits), which can stop either at a distance epsilon (classic RDP) or at an exact
-- number of points.
module VProf.Compress.Rdp
  ( RdpStop (..)
  , rdpIndices
  , rdpPath
  ) where

import Data.List (sort)
import qualified Data.Set as S
import qualified Data.Vector.Unboxed as U

import VProf.Geometry.Polyline (pointSegmentDistance)
import VProf.Compress.Objective (PathA (..), Prepared (..))
import VProf.Geometry.Vec

data RdpStop
  = RdpPoints !Int      -- ^ exactly this many waypoints (at most the number of samples)
  | RdpEpsilon !Double  -- ^ m: every sample within epsilon of the polyline
  deriving (Show, Eq)

-- | Indices of the kept samples, ascending, always including the first and the last.
rdpIndices :: V3s -> RdpStop -> [Int]
rdpIndices ps stop
  | n <= 2 = [0 .. n - 1]
  | otherwise = sort (go (S.singleton (far 0 (n - 1))) [0, n - 1] 2)
  where
    n = plength ps
    -- (negated max distance, a, b, index of farthest)
    far a b
      | b - a < 2 = (1, a, b, -1)
      | otherwise =
          let pa = pindex ps a; pb = pindex ps b
              (d, i) = U.foldl' (\acc@(bd, _) j -> let dj = pointSegmentDistance pa pb (pindex ps j)
                                                   in if dj > bd then (dj, j) else acc)
                                (-1, -1) (U.enumFromN (a + 1) (b - a - 1))
          in (negate d, a, b, i)
    go q kept cnt = case S.minView q of
      Nothing -> kept
      Just ((nd, a, b, i), q')
        | i < 0 -> kept
        | done (negate nd) cnt -> kept
        | otherwise -> go (S.insert (far a i) (S.insert (far i b) q')) (i : kept) (cnt + 1)
    done d cnt = case stop of
      RdpPoints k -> cnt >= k
      RdpEpsilon e -> d <= e

rdpPath :: Prepared -> RdpStop -> PathA
rdpPath pr stop = PathA (pick (rcT pr)) (pick (rcP pr)) (pick (rcQ pr))
  where
    idx = U.fromList (rdpIndices (rcP pr) stop)
    pick :: Packed v e => v -> v
    pick v = pbackpermute v idx
