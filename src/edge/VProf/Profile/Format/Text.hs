-- | Text renderings of a generated profile: the summary a person reads, CSV (columns
-- exactly @t,s,v,a,j@, SI units, full precision) and an aligned table.
module VProf.Profile.Format.Text
  ( summary
  , csv
  , table
  ) where

import qualified Data.ByteString.Builder as BB
import qualified Data.ByteString.Lazy as BL
import qualified Data.Vector.Unboxed as U
import Numeric (showFFloat)
import Text.Printf (printf)

import VProf.Format.Chunked (chunkRanges, renderChunked)
import VProf.Format.Number (doubleBuilder)
import VProf.Profile.Generate
import VProf.Profile.Legality
import VProf.Profile.Sampled
import VProf.Profile.Request (Algorithm (..))

f3 :: Double -> String
f3 x = showFFloat (Just 3) x ""

summary :: Result -> String
summary r = unlines $
  [ "algorithm:     " ++ (case resAlgorithm r of Band -> "band"; Thesis -> "thesis") ]
  ++ (case resProfile r of
        Nothing -> []
        Just p ->
          [ "duration:      " ++ f3 (duration p) ++ " s"
          , "distance:      " ++ showFFloat (Just 4) (finalDistance p) "" ++ " m"
          , "samples:       " ++ show (sampleCount p) ++ " (dt " ++ show (prDt p) ++ " s, dv " ++ show (resVelStep r) ++ " m/s)"
          , "peak speed:    " ++ f3 (peakVelocity p) ++ " m/s" ])
  ++
  [ "iterations:    " ++ show (resIterations r)
  , "converged:     " ++ yn (resConverged r)
  , "legal:         " ++ yn (resultLegal r)
  , "compute time:  " ++ showFFloat (Just 2) (resSeconds r * 1000) "" ++ " ms"
  ]
  ++ [ "violations:    " ++ show (length (resViolations r)) | not (null (resViolations r)) ]
  ++ map (("  " ++) . renderViolation) (take 10 (resViolations r))
  ++ (case resOutcome r of
        Generated -> []
        Failed f -> ["error:         " ++ renderFailure f])
  where yn b = if b then "yes" else "no"

rows :: Profile -> [(Double, Double, Double, Double, Double)]
rows p = U.toList (U.zip5 colTime colDistance colVelocity colAcceleration colJerk)
  where Columns{..} = columns p

-- | CSV with a header @t,s,v,a,j@; doubles printed as 'show' prints them, so that they
-- read back exactly ("VProf.Format.Number"). Rendered 8192 rows a piece on every core
-- ("VProf.Format.Chunked").
csv :: Profile -> BL.ByteString
csv p = renderChunked (BB.string7 "t,s,v,a,j\n" : [ foldMap row [i .. i + m - 1] | (i, m) <- chunkRanges 8192 (U.length colTime) ])
  where
    Columns{..} = columns p
    row k = num colTime k <> comma <> num colDistance k <> comma <> num colVelocity k <> comma
            <> num colAcceleration k <> comma <> num colJerk k <> BB.char7 '\n'
    num c k = doubleBuilder (U.unsafeIndex c k)
    comma = BB.char7 ','

-- | The aligned table: the time with as many decimals as the time step needs (at least 3, at
-- most 9), so that no two samples show the same time.
table :: Profile -> String
table p = unlines $
  printf "%*s %12s %10s %10s %10s" wt ("t [s]" :: String) ("s [m]" :: String) ("v [m/s]" :: String) ("a [m/s2]" :: String) ("j [m/s3]" :: String)
  : [ printf "%*.*f %12.4f %10.5f %10.5f %10.5f" wt dt t s v a j | (t, s, v, a, j) <- rows p ]
  where
    dt = timeDecimals (prDt p)
    wt = max 10 (dt + 7)

-- | The fewest decimals (3 to 9) that write the time step h exactly to a part in 10⁶.
timeDecimals :: Double -> Int
timeDecimals h = head ([ d | d <- [3 .. 8], let k = h * 10 ^^ d, abs (k - fromIntegral (round k :: Integer)) <= 1e-6 * k ] ++ [9])
