-- | Plain CSV of poses in SI units, with a header: @time,x,y,z,qw,qx,qy,qz@.
module VProf.Compress.Format.Csv
  ( renderCsv
  , parseCsv
  ) where

import qualified Data.ByteString.Char8 as B
import qualified Data.ByteString.Lazy as BL

import VProf.Compress.Format.Common (dataLines, numberFields, renderPoseLines, trackFromRows)
import VProf.Compress.Types
import VProf.Geometry.Vec

renderCsv :: Track -> BL.ByteString
renderCsv = renderPoseLines "time,x,y,z,qw,qx,qy,qz" "," (\(P3 x y z) (Q4 w a b c) -> [x, y, z, w, a, b, c])

-- | Read back what 'renderCsv' writes: a header line starting with @time@ (skipped), then
-- eight numbers a line. Errors name the line and column.
parseCsv :: B.ByteString -> Either String Track
parseCsv src = traverse row rows >>= trackFromRows "CSV"
  where
    rows = [ r | r@(_, l) <- dataLines (const False) src, not (B.pack "time" `B.isPrefixOf` l) ]
    row (i, l) =
      let cols = map B.strip (B.split ',' l)
      in if length cols /= 8
           then Left ("CSV line " ++ show i ++ ": expected 8 comma-separated numbers (time,x,y,z,qw,qx,qy,qz), got "
                      ++ show (length cols))
           else do
             vs <- numberFields "CSV" i cols
             case vs of
               [t, x, y, z, w, a, b, c] -> Right (t, P3 x y z, Q4 w a b c)
               _ -> Left "impossible"
