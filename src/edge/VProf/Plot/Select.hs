-- | The picture of a selection: the cell's triangles (their edges, thinned to a few thousand
-- triangles) seen from the top (x–y) and from the side (x–z), the chosen robot's capsule axes at
-- each target it reaches, and the targets. PNG or SVG by the file's extension (Chart-cairo).
module VProf.Plot.Select
  ( plotSelection
  ) where

import Control.Lens ((.~), (&))
import Control.Monad (void)
import Data.Colour (opaque, withOpacity)
import Data.Colour.Names (black, blue, gray, red)
import Data.Default.Class (def)
import Graphics.Rendering.Chart
import VProf.Plot.File (fileFormatOf)
import Graphics.Rendering.Chart.Backend.Cairo (FileOptions (..), renderableToFile)
import Graphics.Rendering.Chart.Grid (aboveN, gridToRenderable, tval, weights)

import VProf.Geometry.Mesh (Mesh, triangle, triangleCount)
import VProf.Kinematics.Collision
import VProf.Kinematics.Model (Capsule (..), Robot (..))
import VProf.Kinematics.Transform (V3 (..), translation)
import VProf.Select.Selection
import VProf.Select.Task

-- | At most this many triangles are drawn (every k-th one).
maxTriangles :: Int
maxTriangles = 4000

plotSelection :: FilePath -> Task -> Mesh -> Robot -> RobotResult -> IO ()
plotSelection file task mesh robot result = void (renderableToFile opts file (gridToRenderable grid))
  where
    fmt = fileFormatOf file
    opts = FileOptions (900, 1200) fmt
    n = triangleCount mesh
    stride = max 1 ((n + maxTriangles - 1) `div` maxTriangles)
    tris = [triangle mesh k | k <- [0, stride .. n - 1]]
    cm = collisionModel defaultCollisionOptions {coTool = taskToolCapsule task} robot
    poses = [q | t <- rrTargets result, Just q <- [trJoints t]]
    caps = [wcCapsule w | q <- poses, w <- robotCapsules cm q]
    targets = map (translation . tgPose) (taskTargets task)
    view name (px, py) (lx, ly) =
      let edges = concat [[[p a, p b, p c, p a]] | (a, b, c) <- tris]
          p v = (px v, py v)
          cell = toPlot (def & plot_lines_title .~ "cell (" ++ show (length tris) ++ " of " ++ show n ++ " triangles)"
                             & plot_lines_style .~ solidLine 0.3 (gray `withOpacity` 0.6)
                             & plot_lines_values .~ edges)
          arm = toPlot (def & plot_lines_title .~ rrKey result ++ " capsule axes at its targets"
                            & plot_lines_style .~ solidLine 2.5 (blue `withOpacity` 0.7)
                            & plot_lines_values .~ [[p a, p b] | Capsule a b _ <- caps])
          pts = toPlot (def & plot_points_title .~ "targets"
                            & plot_points_style .~ filledCircles 3 (opaque red)
                            & plot_points_values .~ map p targets)
      in def & layout_title .~ name
             & layout_x_axis . laxis_title .~ lx
             & layout_y_axis . laxis_title .~ ly
             & layout_plots .~ [cell, arm, pts]
             & layout_legend .~ Just (def & legend_label_style .~ (def & font_color .~ opaque black))
    xOf (V3 x _ _) = x
    yOf (V3 _ y _) = y
    zOf (V3 _ _ z) = z
    grid = aboveN [ weights (1, 1) (tval (layoutToRenderable (view ("top view: " ++ rrKey result) (xOf, yOf) ("x [m]", "y [m]"))))
                  , weights (1, 1) (tval (layoutToRenderable (view ("side view: " ++ rrKey result) (xOf, zOf) ("x [m]", "z [m]")))) ]
