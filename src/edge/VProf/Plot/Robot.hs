-- | A drawing of a robot arm at one joint vector, for a user to see a pose: a side view (x–z) and
-- a top view (x–y) of the base frame, each with the link frames' origins joined as a polyline,
-- the joints as dots, the base as a square and the tool frame's axes (x red, y green, z blue).
-- Both views share one scale on both axes, so the arm is not distorted. PNG or SVG by the
-- file's extension (Chart + Chart-cairo).
module VProf.Plot.Robot
  ( plotRobot
  , armPoints
  ) where

import Control.Lens ((.~), (&))
import Control.Monad (void)
import Data.Colour (opaque)
import Data.Colour.Names (black, blue, gray, green, red)
import Data.Default.Class (def)
import qualified Data.Vector.Unboxed as U
import Graphics.Rendering.Chart
import VProf.Plot.File (fileFormatOf)
import Graphics.Rendering.Chart.Backend.Cairo (FileOptions (..), renderableToFile)
import Graphics.Rendering.Chart.Grid (besideN, gridToRenderable, tval, weights)

import VProf.Kinematics

-- | The origins of the base frame, of every moving link's frame and of the tool frame, in order;
-- and the tool frame itself.
armPoints :: Chain -> U.Vector Double -> ([V3], Tf)
armPoints ch q = (map translation frames, last frames)
  where frames = linkFrames ch q

-- | Write the drawing of the arm at q (rad, m) to a .png or .svg file.
plotRobot :: FilePath -> String -> Chain -> U.Vector Double -> IO ()
plotRobot file title ch q = void (renderableToFile opts file (gridToRenderable grid))
  where
    fmt = fileFormatOf file
    opts = FileOptions (1200, 640) fmt
    (pts, tool) = armPoints ch q
    reach = maximum (1e-3 : [ v3Norm (v3Sub a b) | (a, b) <- zip (tail pts) pts ]) -- the longest link
    axisLen = max 0.05 (0.25 * reach)
    V3 ox oy oz = translation tool
    axisEnd k = let V3 ax ay az = column k in V3 (ox + axisLen * ax) (oy + axisLen * ay) (oz + axisLen * az)
    column k = let [r0, r1, r2] = [ take 3 (drop (4 * i) (toRows tool)) | i <- [0 .. 2] ] in V3 (r0 !! k) (r1 !! k) (r2 !! k)
    toolAxes = [ (axisEnd 0, red, "tool x"), (axisEnd 1, green, "tool y"), (axisEnd 2, blue, "tool z") ]
    everything = pts ++ [ p | (p, _, _) <- toolAxes ]
    -- one square range for every view: the arm's bounding box, its largest side, 10 % margin
    lo f = minimum (map f everything)
    hi f = maximum (map f everything)
    span' = maximum (1e-3 : [ hi f - lo f | f <- [vx, vy, vz] ]) * 1.2
    range f = let c = 0.5 * (lo f + hi f) in (c - span' / 2, c + span' / 2)
    vx (V3 x _ _) = x
    vy (V3 _ y _) = y
    vz (V3 _ _ z) = z
    view ttl (fa, la) (fb, lb) =
      let proj p = (fa p, fb p)
          joints = init (tail pts)
      in layoutToRenderable $ def
           & layout_title .~ ttl
           & layout_x_axis . laxis_title .~ la ++ " [m]"
           & layout_y_axis . laxis_title .~ lb ++ " [m]"
           & layout_x_axis . laxis_generate .~ scaledAxis def (range fa)
           & layout_y_axis . laxis_generate .~ scaledAxis def (range fb)
           & layout_plots .~
               ( [ toPlot (def & plot_lines_title .~ "links"
                               & plot_lines_style .~ solidLine 3 (opaque gray)
                               & plot_lines_values .~ [map proj pts]) ]
                 ++ [ toPlot (def & plot_lines_title .~ name
                                  & plot_lines_style .~ solidLine 2 (opaque c)
                                  & plot_lines_values .~ [[proj (translation tool), proj e]])
                    | (e, c, name) <- toolAxes ]
                 ++ [ toPlot (def & plot_points_title .~ "joints"
                                  & plot_points_style .~ filledCircles 5 (opaque black)
                                  & plot_points_values .~ map proj joints)
                    , toPlot (def & plot_points_title .~ "base"
                                  & plot_points_style .~ filledPolygon 7 4 False (opaque black)
                                  & plot_points_values .~ [proj (head pts)])
                    , toPlot (def & plot_points_title .~ "tool"
                                  & plot_points_style .~ filledCircles 5 (opaque red)
                                  & plot_points_values .~ [proj (translation tool)]) ] )
    grid = besideN [ weights (1, 1) (tval (view (title ++ ": side view (x-z)") (vx, "x") (vz, "z")))
                   , weights (1, 1) (tval (view (title ++ ": top view (x-y)") (vx, "x") (vy, "y"))) ]
