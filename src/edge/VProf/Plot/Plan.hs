-- | The plot of a plan: the TCP speed over s with the zones' limit and the pointwise limit
-- from the robot and the route; every joint's speed over t as a fraction of its limit (the
-- limit is 1). PNG or SVG by the file's extension (Chart + Chart-cairo).
module VProf.Plot.Plan
  ( plotPlan
  ) where

import Control.Lens ((.~), (&))
import Control.Monad (void)
import Data.Colour (opaque)
import Data.Colour.Names
import Data.Default.Class (def)
import qualified Data.Vector.Unboxed as U
import Graphics.Rendering.Chart
import VProf.Plot.Decimate (decimate, plotRuns)
import VProf.Plot.File (fileFormatOf)
import Graphics.Rendering.Chart.Backend.Cairo (FileOptions (..), renderableToFile)
import Graphics.Rendering.Chart.Grid (aboveN, gridToRenderable, tval, weights)

import VProf.Kinematics.Model
import VProf.Plan

plotPlan :: FilePath -> Robot -> Plan -> IO ()
plotPlan file r p = void (renderableToFile opts file (gridToRenderable grid))
  where
    fmt = fileFormatOf file
    opts = FileOptions (900, 800) fmt
    tr = planTrajectory p
    st = planSteps p
    mm = (* 1000)
    stepLimit = concat [ [(mm a, mm v), (mm b, mm v)]
                       | k <- [0 .. U.length (slLimit st) - 1]
                       , let a = slS st U.! k; b = slS st U.! (k + 1); v = min (slLimit st U.! k) 10 ]
    zoneLimit = concat [ [(mm (lzStart z), mm (lzSpeed z)), (mm (lzEnd z), mm (lzSpeed z))] | z <- planZoneList p ]
    speed = zip (map mm (U.toList (trS tr))) (map mm (U.toList (trV tr)))
    line name c w pts = toPlot (def & plot_lines_title .~ name
                                    & plot_lines_style .~ solidLine w (opaque c)
                                    & plot_lines_values .~ [decimate plotRuns pts])
    tcpPanel = def & layout_title .~ ("TCP speed along the route (" ++ robotName r ++ ")")
                   & layout_x_axis . laxis_title .~ "s [mm]"
                   & layout_y_axis . laxis_title .~ "mm/s"
                   & layout_plots .~ [ line "limit from robot and route" lightgray 1.0 stepLimit
                                     , line "zones of the profile request" red 1.5 zoneLimit
                                     , line "TCP speed" blue 1.5 speed ]
    joints = robotJoints r
    n = trDof tr
    ts = U.toList (trTime tr)
    colours = cycle [blue, green, red, orange, purple, brown, black]
    jointLine i c = case jointMaxVelocity (joints !! i) of
      Just vmax -> [ line (jointName (joints !! i)) c 1.2
                       (zip ts [ abs (trQd tr U.! (k * n + i)) / vmax | k <- [0 .. length ts - 1] ]) ]
      Nothing -> []
    jointPanel = def & layout_title .~ "joint speeds as a fraction of their limits"
                     & layout_x_axis . laxis_title .~ "t [s]"
                     & layout_y_axis . laxis_title .~ "|q̇| / q̇max"
                     & layout_plots .~ (line "limit" gray 1.5 [(0, 1), (if null ts then 0 else last ts, 1)]
                                        : concat (zipWith jointLine [0 .. n - 1] colours))
    grid = aboveN [ weights (1, 1) (tval (layoutToRenderable tcpPanel))
                  , weights (1, 1) (tval (layoutToRenderable jointPanel)) ]
