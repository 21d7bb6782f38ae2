{-# LANGUAGE BangPatterns #-}
-- | A triangle set (a scene's collision geometry): triangle k's corners are the nine doubles
-- @9k .. 9k+8@ of one flat unboxed vector (a, b, c, each x y z), in metres, in the world frame.
--
-- Invariant: the vector's length is a multiple of 9 and every coordinate is finite (the readers
-- check this; 'fromTriangles' does not).
module VProf.Geometry.Mesh
  ( Mesh (..)
  , fromTriangles
  , triangleCount
  , triangle
  , triangles
  , transformMesh
  , composeMeshes
  , ScenePart (..)
  , composeScene
  , meshBounds
  ) where

import Control.DeepSeq (NFData (..))
import qualified Data.Vector.Unboxed as U

import VProf.Kinematics.Transform (Tf, V3 (..), applyPoint)

newtype Mesh = Mesh {meshCoords :: U.Vector Double}
  deriving (Eq, Show)

instance NFData Mesh where rnf (Mesh v) = v `seq` ()

fromTriangles :: [(V3, V3, V3)] -> Mesh
fromTriangles ts = Mesh (U.fromList (concat [[ax, ay, az, bx, by, bz, cx, cy, cz] | (V3 ax ay az, V3 bx by bz, V3 cx cy cz) <- ts]))

triangleCount :: Mesh -> Int
triangleCount (Mesh v) = U.length v `div` 9
{-# INLINE triangleCount #-}

-- | Corners of triangle k (not bounds-checked).
triangle :: Mesh -> Int -> (V3, V3, V3)
triangle (Mesh v) k =
  let b = 9 * k
      e i = U.unsafeIndex v (b + i)
  in (V3 (e 0) (e 1) (e 2), V3 (e 3) (e 4) (e 5), V3 (e 6) (e 7) (e 8))
{-# INLINE triangle #-}

triangles :: Mesh -> [(V3, V3, V3)]
triangles m = map (triangle m) [0 .. triangleCount m - 1]

-- | Scale about the mesh's own origin, then place by the pose: p ↦ pose · (s p).
transformMesh :: Double -> Tf -> Mesh -> Mesh
transformMesh s t (Mesh v) = Mesh (U.generate (U.length v) at)
  where
    at i = let k = 3 * (i `div` 3)
               V3 x y z = applyPoint t (V3 (s * v U.! k) (s * v U.! (k + 1)) (s * v U.! (k + 2)))
           in case i - k of 0 -> x; 1 -> y; _ -> z

composeMeshes :: [Mesh] -> Mesh
composeMeshes = Mesh . U.concat . map meshCoords

-- | One mesh of a scene: its triangles in its own frame (as read), a uniform scale (e.g. 0.001
-- for a file in mm) and its pose in the world.
data ScenePart = ScenePart {spMesh :: Mesh, spScale :: Double, spPose :: Tf}

-- | Every part scaled, placed and appended, in order: triangle indices run through the parts.
composeScene :: [ScenePart] -> Mesh
composeScene ps = composeMeshes [transformMesh s t m | ScenePart m s t <- ps]

-- | (min corner, max corner); Nothing for an empty mesh.
meshBounds :: Mesh -> Maybe (V3, V3)
meshBounds (Mesh v)
  | U.null v = Nothing
  | otherwise = Just (V3 (mn 0) (mn 1) (mn 2), V3 (mx 0) (mx 1) (mx 2))
  where
    axis a = U.ifilter (\i _ -> i `mod` 3 == a) v
    mn = U.minimum . axis
    mx = U.maximum . axis
