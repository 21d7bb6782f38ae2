-- | Raw against fitted motion over time, like the thesis's figures 42–45: position
-- (x, y, z), orientation (rotation vector relative to the first sample, degrees) and speed.
-- PNG or SVG by the file's extension (Chart + Chart-cairo).
module VProf.Plot.Compress
  ( plotCompression
  ) where

import Control.Lens ((.~), (&))
import Control.Monad (void)
import Data.Colour (opaque)
import Data.Colour.Names (blue, red, green, black, gray)
import Data.Default.Class (def)
import qualified Data.Vector.Unboxed as U
import Graphics.Rendering.Chart
import VProf.Plot.Decimate (decimate, plotRuns)
import VProf.Plot.File (fileFormatOf)
import Graphics.Rendering.Chart.Backend.Cairo (FileOptions (..), renderableToFile)
import Graphics.Rendering.Chart.Grid (aboveN, gridToRenderable, tval, weights)

import VProf.Geometry.Quaternion
import VProf.Compress.Objective
import VProf.Geometry.Vec

-- | Write the plot of a recording and a path to a .png or .svg file.
plotCompression :: FilePath -> String -> Prepared -> PathA -> IO ()
plotCompression file title pr pa = void (renderableToFile opts file (gridToRenderable grid))
  where
    fmt = fileFormatOf file
    opts = FileOptions (900, 1000) fmt
    t0 = U.head (rcT pr)
    rt = map (subtract t0) (U.toList (rcT pr))
    wt = map (subtract t0) (U.toList (paT pa))
    comps (P3 x y z) = [x, y, z]
    rawP = map comps (ptoList (rcP pr))
    fitP = map comps (ptoList (paP pa))
    q0 = phead (rcQ pr)
    rotv q = let P3 x y z = qlog (qmul (qconj q0) q) in map (* (180 / pi)) [x, y, z]
    rawO = map rotv (ptoList (rcQ pr))
    fitO = map rotv (ptoList (paQ pa))
    rawV = [ norm (pindex (rcV pr) i) | i <- [0 .. plength (rcV pr) - 1] ]
    fitV = concat [ [(a, v), (b, v)] | (j, (a, b)) <- zip [0 ..] (zip wt (drop 1 wt))
                  , let v = distance (pindex (paP pa) (j + 1)) (pindex (paP pa) j) / (b - a) ]
    colours = [red, green, blue]
    lineP name c w pts = toPlot (def & plot_lines_title .~ name
                                     & plot_lines_style .~ (solidLine w (opaque c))
                                     & plot_lines_values .~ [decimate plotRuns pts])
    pointsP name c pts = toPlot (def & plot_points_title .~ name
                                     & plot_points_style .~ filledCircles 2.5 (opaque c)
                                     & plot_points_values .~ pts)
    panel ttl ylab raw fit =
      def & layout_title .~ ttl
          & layout_x_axis . laxis_title .~ "time [s]"
          & layout_y_axis . laxis_title .~ ylab
          & layout_plots .~ ( [ lineP ("raw " ++ n) (gray) 1.0 (zip rt (map (!! k) raw)) | (k, n) <- zip [0 ..] ["x", "y", "z"] ]
                             ++ [ lineP ("path " ++ n) c 1.5 (zip wt (map (!! k) fit)) | (k, n, c) <- zip3 [0 ..] ["x", "y", "z"] colours ]
                             ++ [ pointsP "waypoints" black [ (t, v) | (t, vs) <- zip wt fit, v <- vs ] ] )
    speedPanel =
      def & layout_title .~ "speed"
          & layout_x_axis . laxis_title .~ "time [s]"
          & layout_y_axis . laxis_title .~ "m/s"
          & layout_plots .~ [ lineP "raw" gray 1.0 (zip rt rawV), lineP "path" blue 1.5 fitV ]
    grid = aboveN [ weights (1, 1) (tval (layoutToRenderable (panel (title ++ ": position") "m" rawP fitP)))
                  , weights (1, 1) (tval (layoutToRenderable (panel "orientation (rotation vector from the first sample)" "deg" rawO fitO)))
                  , weights (1, 1) (tval (layoutToRenderable speedPanel)) ]
