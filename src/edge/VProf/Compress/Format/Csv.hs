-- | Plain CSV of poses in SI units, with a header: @time,x,y,z,qw,qx,qy,qz@.
module VProf.Compress.Format.Csv
  ( renderCsv
  ) where

import qualified Data.ByteString.Lazy as BL

import VProf.Compress.Format.Common (renderPoseLines)
import VProf.Compress.Types
import VProf.Geometry.Vec

renderCsv :: Track -> BL.ByteString
renderCsv = renderPoseLines "time,x,y,z,qw,qx,qy,qz" "," (\(P3 x y z) (Q4 w a b c) -> [x, y, z, w, a, b, c])
