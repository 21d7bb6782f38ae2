-- | A scene from several OBJ files, each with a uniform scale and a pose, composed into one
-- triangle set ('VProf.Geometry.Mesh.composeScene': triangle indices run through the files in
-- order). The first file that fails gives the error, prefixed with its path.
module VProf.Geometry.Format.Scene
  ( SceneFile (..)
  , loadScene
  ) where

import qualified Data.Vector.Unboxed as U

import VProf.Geometry.Format.Obj (readObj)
import VProf.Geometry.Mesh
import VProf.Kinematics.Transform (Tf, isRigid)
import VProf.Validation (finite, maxCoordinate, showNumber, tooFarRule)

-- | One mesh of a scene: its OBJ file, the scale (e.g. 0.001 for a file in mm) and its pose in
-- the world (m).
data SceneFile = SceneFile {sfPath :: FilePath, sfScale :: Double, sfPose :: Tf}

loadScene :: [SceneFile] -> IO (Either String Mesh)
loadScene files = go [] files
  where
    go acc [] = pure (Right (composeScene (reverse acc)))
    go acc (SceneFile p s t : rest)
      | not (finite s) || s <= 0 = pure (Left (p ++ ": scale = " ++ show s ++ ": must be a finite number > 0"))
      | not (isRigid 1e-6 t) = pure (Left (p ++ ": pose: the rotation is not orthonormal with determinant 1"))
      | otherwise = readObj p >>= \case
          Left e -> pure (Left e)
          Right m
            -- a scale that puts the scene beyond any cell (1e160 overflowed the clearance to
            -- nothing, 1e100 printed 100-digit distances)
            | far * s > maxCoordinate ->
                pure (Left (p ++ ": scale = " ++ show s ++ ": puts its farthest coordinate, " ++ showNumber far ++ ", at "
                            ++ showNumber (far * s) ++ " m: " ++ tooFarRule))
            | otherwise -> go (ScenePart m s t : acc) rest
            where far = U.foldl' (\a x -> max a (abs x)) 0 (meshCoords m)
