-- | The compression tests' measure of a path against a recording, independent of vprof's
-- own measures ("VProf.Compress.Metrics"): the path interpolated at every sample's time.
module Support.PathError
  ( worstPositionError
  , positionErrorsOf
  ) where

import qualified Data.Vector.Unboxed as U

import VProf.Compress.Types
import VProf.Geometry.Polyline (polylineAt)
import VProf.Geometry.Vec

-- | The largest time-synchronous position error (m) of a path's track against a
-- recording's: the distance from each sample to the path's position at the sample's time.
worstPositionError :: Track -> Track -> Double
worstPositionError path rec = maximum (positionErrorsOf path rec)

-- | Every sample's time-synchronous position error (m), in the recording's order.
positionErrorsOf :: Track -> Track -> [Double]
positionErrorsOf path rec =
  [ distance (fst (polylineAt (tTime path) (tPos path) (tRot path) t)) x
  | (t, x) <- zip (U.toList (tTime rec)) (ptoList (tPos rec)) ]
