{-# LANGUAGE OverloadedStrings #-}
-- | The thesis's table 1 (plus RMSE and the geometric distance), as text and as JSON,
-- for one or more compressed paths of the same recording side by side.
module VProf.Compress.Format.Report
  ( ReportColumn (..)
  , renderReport
  , reportJson
  , warningsJson
  , withWarnings
  , thesisObjective
  ) where

import Data.Aeson (Value (Object), camelTo2, defaultOptions, fieldLabelModifier, genericToJSON, object, toJSON, (.=))
import qualified Data.Aeson.Key as K
import qualified Data.Aeson.KeyMap as KM
import Numeric (showFFloat)

import VProf.Compress.Clean
import VProf.Compress.Metrics
import VProf.Compress.Types

data ReportColumn = ReportColumn
  { rcName    :: !String
  , rcMetrics :: !Metrics
  , rcSeconds :: !(Maybe Double)  -- ^ compute time
  }

deg :: Double -> Double
deg r = r * 180 / pi

-- | The thesis's "sum of squared error for all dimensions": the weighted sum of the
-- position (mm²), orientation (deg²) and velocity ((m/s)²) SSE with weights in the
-- thesis's units.
thesisObjective :: (Double, Double, Double) -> Metrics -> Double
thesisObjective (p, o, v) m =
  p * mPositionSse m * 1e6 + o * mOrientationSse m * deg 1 * deg 1 + v * mVelocitySse m

renderReport :: (Double, Double, Double) -> [ReportColumn] -> String
renderReport wts cols = unlines (map fmt (header : sepLine : rows))
  where
    header = "measure" : map rcName cols
    sepLine = "" : map (const "") cols
    row name f = name : map (f . rcMetrics) cols
    num d x = showFFloat (Just d) x ""
    rows =
      [ row "weighted SSE, all dimensions (thesis units)" (num 4 . thesisObjective wts)
      , row "SSE position [mm^2]" (num 4 . (* 1e6) . mPositionSse)
      , row "SSE velocity [(m/s)^2]" (num 4 . mVelocitySse)
      , row "SSE orientation [deg^2]" (num 4 . (\m -> mOrientationSse m * deg 1 * deg 1))
      , row "mean error position [mm]" (num 4 . (* 1e3) . mPositionMean)
      , row "mean error velocity [m/s]" (num 4 . mVelocityMean)
      , row "mean error orientation [deg]" (num 4 . deg . mOrientationMean)
      , row "max error position [mm]" (num 4 . (* 1e3) . mPositionMax)
      , row "max error velocity [m/s]" (num 4 . mVelocityMax)
      , row "max error orientation [deg]" (num 4 . deg . mOrientationMax)
      , row "RMSE position [mm]" (num 4 . (* 1e3) . mPositionRmse)
      , row "RMSE velocity [m/s]" (num 4 . mVelocityRmse)
      , row "RMSE orientation [deg]" (num 4 . deg . mOrientationRmse)
      , row "geometric RMSE (distance to polyline) [mm]" (num 4 . (* 1e3) . mGeometricRmse)
      , row "geometric max [mm]" (num 4 . (* 1e3) . mGeometricMax)
      , row "length ratio [%]" (num 2 . (* 100) . mLengthRatio)
      , row "orientation ratio [%]" (num 2 . (* 100) . mOrientationRatio)
      , row "points" (show . mPoints)
      , row "samples" (show . mSamples)
      , row "reduction [%]" (num 2 . (* 100) . mReduction)
      ] ++
      [ "compute time [s]" : map (maybe "-" (num 3) . rcSeconds) cols | any ((/= Nothing) . rcSeconds) cols ]
    widths = [ maximum (map (length . (!! c)) (header : rows)) | c <- [0 .. length cols] ]
    fmt cells
      | all null (drop 1 cells) && null (head cells) = concatMap (\w -> replicate (w + 2) '-') widths
      | otherwise = concat [ pad c w x | (c, w, x) <- zip3 [0 :: Int ..] widths cells ]
    pad c w x | c == 0 = x ++ replicate (w - length x + 2) ' '
              | otherwise = replicate (w - length x) ' ' ++ x ++ "  "

reportJson :: Weights -> [ReportColumn] -> Value
reportJson w cols = object
  [ "weights_si" .= object [ "position" .= wPosition w, "orientation" .= wOrientation w, "velocity" .= wVelocity w ]
  , "paths" .= object
      [ K.fromString (rcName c) .= object [ "metrics" .= metricsJson (rcMetrics c), "compute_time" .= rcSeconds c ]
      | c <- cols ]
  ]

-- | The measures as JSON, snake_case names of the fields without their prefix.
metricsJson :: Metrics -> Value
metricsJson = genericToJSON defaultOptions { fieldLabelModifier = camelTo2 '_' . drop 1 }

-- | What cleaning the recording changed, as JSON: one object a warning with its kind,
-- how many samples it is about, and the sentence the text report prints.
warningsJson :: Locator -> [CleanWarning] -> Value
warningsJson loc ws = toJSONList
  [ object [ "kind" .= kind w, "count" .= warningCount w, "message" .= renderCleanWarning loc w ] | w <- ws ]
  where
    kind = \case
      MissingPoses {} -> "missing_poses" :: String
      NonUnitQuaternions {} -> "non_unit_quaternions"
      DuplicateTimes {} -> "duplicate_times"
      SignFlips {} -> "sign_flips"
      OutliersRejected {} -> "outliers_rejected"
      OutliersNotJudged {} -> "outliers_not_judged"
      Gaps {} -> "gaps"
      LongMedianStep {} -> "long_median_step"
    toJSONList = toJSON

-- | A report with a @warnings@ member (always present, possibly empty).
withWarnings :: Value -> Value -> Value
withWarnings ws = \case
  Object o -> Object (KM.insert (K.fromString "warnings") ws o)
  v -> v
