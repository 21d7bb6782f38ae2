{-# LANGUAGE FlexibleContexts #-}
{-# LANGUAGE DeriveGeneric #-}
-- | The thesis's measures of a path's quality (section 2.5, table 1, @finnFeil.m@) plus
-- the root-mean-square errors and the geometric distance of each sample to the polyline.
-- All in SI (m, rad, m/s, ratios as fractions); "VProf.Compress.Format.Report" prints mm/deg/%.
module VProf.Compress.Metrics
  ( Metrics (..)
  , computeMetrics
  , geometricDistances
  ) where

import Control.DeepSeq (NFData)
import qualified Data.Vector.Unboxed as U
import GHC.Generics (Generic)


import VProf.Geometry.NearestSegment (buildSegIndex, nearestSegmentDistance)
import VProf.Geometry.Quaternion
import VProf.Compress.Objective
import VProf.Geometry.Vec

data Metrics = Metrics
  { mPositionSse      :: !Double  -- ^ m², time-synchronous
  , mPositionRmse     :: !Double  -- ^ m
  , mPositionMean     :: !Double
  , mPositionMax      :: !Double
  , mOrientationSse   :: !Double  -- ^ rad²
  , mOrientationRmse  :: !Double  -- ^ rad
  , mOrientationMean  :: !Double
  , mOrientationMax   :: !Double
  , mVelocitySse      :: !Double  -- ^ (m/s)²
  , mVelocityRmse     :: !Double  -- ^ m/s
  , mVelocityMean     :: !Double
  , mVelocityMax      :: !Double
  , mGeometricRmse    :: !Double  -- ^ m, distance of each sample to the polyline
  , mGeometricMean    :: !Double
  , mGeometricMax     :: !Double
  , mLengthRatio      :: !Double  -- ^ path length / recording length
  , mOrientationRatio :: !Double  -- ^ total rotation of path / of recording
  , mPoints           :: !Int
  , mSamples          :: !Int
  , mReduction        :: !Double  -- ^ 1 − points/samples
  } deriving (Show, Eq, Generic)

-- | JSON with the proto's field names (position_rmse, ...), SI units.
instance NFData Metrics

-- | Distance of every sample to the nearest segment of the polyline, regardless of time
-- (a bounding-volume hierarchy over the segments, "VProf.Geometry.NearestSegment": about
-- O(samples · log points) instead of O(samples · points)).
geometricDistances :: Prepared -> PathA -> U.Vector Double
geometricDistances pr (PathA _ ps _) = U.generate (plength (rcP pr)) (nearestSegmentDistance idx (1 / 0) . pindex (rcP pr))
  where
    idx = buildSegIndex ps

computeMetrics :: Prepared -> PathA -> Metrics
computeMetrics pr pa@(PathA _ ps qs) = Metrics
  { mPositionSse = sse ep, mPositionRmse = rms ep, mPositionMean = mean ep, mPositionMax = mx ep
  , mOrientationSse = sse eo, mOrientationRmse = rms eo, mOrientationMean = mean eo, mOrientationMax = mx eo
  , mVelocitySse = sse ev, mVelocityRmse = rms ev, mVelocityMean = mean ev, mVelocityMax = mx ev
  , mGeometricRmse = rms eg, mGeometricMean = mean eg, mGeometricMax = mx eg
  , mLengthRatio = ratio (len ps) (len (rcP pr))
  , mOrientationRatio = ratio (rot qs) (rot (rcQ pr))
  , mPoints = k, mSamples = n
  , mReduction = 1 - fromIntegral k / fromIntegral n
  }
  where
    (ep, eo, ev) = pointErrors pr pa
    eg = geometricDistances pr pa
    n = U.length (rcT pr)
    k = plength ps
    sse v = U.sum (U.map (\x -> x * x) v)
    rms v = if U.null v then 0 else sqrt (sse v / fromIntegral (U.length v))
    mean v = if U.null v then 0 else U.sum v / fromIntegral (U.length v)
    mx v = if U.null v then 0 else U.maximum v
    len :: V3s -> Double
    len v = sum [ distance (pindex v i) (pindex v (i + 1)) | i <- [0 .. plength v - 2] ]
    rot :: Qs -> Double
    rot v = sum [ qangle (pindex v i) (pindex v (i + 1)) | i <- [0 .. plength v - 2] ]
    ratio a b = if b == 0 then (if a == 0 then 1 else 0) else a / b
