-- | Plots of a profile like the thesis's figures: velocity with the speed limit as the
-- robot sees it at s(t), acceleration, jerk and distance over time, stacked; PNG, SVG
-- or PDF by the file's extension. This is an edge module: it writes files.
module VProf.Plot.Profile
  ( plotProfile
  ) where

import Control.Lens ((.~), (&))
import Data.Colour (opaque)
import Data.Colour.Names (red, black, blue, darkgreen, purple)
import Data.Default.Class (def)
import qualified Data.Vector.Unboxed as U
import Graphics.Rendering.Chart
import Graphics.Rendering.Chart.Backend.Cairo

import VProf.Plot.Decimate (decimate, plotRuns)
import VProf.Plot.File (fileFormatOf)
import VProf.Profile.Sampled
import VProf.Profile.Request (Problem (..))
import VProf.Profile.SpeedLimit (limitAt)

plotProfile :: FilePath -> String -> Problem -> Profile -> IO ()
plotProfile path title pb p = do
  let fmt = fileFormatOf path
  let Columns{..} = columns p
      t = U.toList colTime
      s = U.toList colDistance
      v = U.toList colVelocity
      a = U.toList colAcceleration
      j = U.toList colJerk
      lim = [ limitAt pb x | x <- s ]
      line name colour ys = toPlot $ def
        & plot_lines_title .~ name
        & plot_lines_style .~ (solidLine 1.5 (opaque colour))
        & plot_lines_values .~ [decimate plotRuns (zip t ys)]
      stepLine name colour ys = toPlot $ def
        & plot_lines_title .~ name
        & plot_lines_style .~ (dashedLine 1.2 [5, 3] (opaque colour))
        & plot_lines_values .~ [decimate plotRuns (zip t ys)]
      layout ttl ylabel plots = def
        & layout_title .~ ttl
        & layout_y_axis . laxis_title .~ ylabel
        & layout_x_axis . laxis_title .~ "t [s]"
        & layout_plots .~ plots
      stacked = def
        & slayouts_layouts .~
            [ StackedLayout (layout title "v [m/s]" [line "velocity" blue v, stepLine "speed limit at s(t)" red lim])
            , StackedLayout (layout "" "a [m/s²]" [line "acceleration" darkgreen a])
            , StackedLayout (layout "" "j [m/s³]" [line "jerk" purple j])
            , StackedLayout (layout "" "s [m]" [line "distance" black s])
            ]
        & slayouts_compress_legend .~ False
  _ <- renderableToFile (def & fo_size .~ (900, 1100) & fo_format .~ fmt) path (renderStackedLayouts stacked)
  pure ()
