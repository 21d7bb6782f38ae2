-- | Writers of motion-capture exports for the readers' tests, from the formats' own
-- conventions and written out here, not from the product's rotation code: the rotation
-- matrix of a unit quaternion, Qualisys's 6D TSV (its @Rot[0..8]@ column by column, roll,
-- pitch and yaw as Rx·Ry·Rz, positions in mm) and Vicon Nexus's Segments section (the helical
-- axis in degrees, translations in mm).
module Support.Mocap
  ( rotationMatrix
  , rotateBy
  , matMul
  , transpose3
  , apply3
  , eulerXyzMatrix
  , helicalDegrees
  , QtmFrame (..)
  , qtmText
  , NexusFrame (..)
  , nexusSegmentsText
  ) where

import Data.List (intercalate)
import Numeric (showFFloat)

import VProf.Geometry.Vec (P3 (..), Q4 (..))

-- | Rows of the rotation matrix of a unit quaternion (w, x, y, z).
rotationMatrix :: Q4 -> [[Double]]
rotationMatrix (Q4 w x y z) =
  [ [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)]
  , [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)]
  , [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)] ]

-- | A vector rotated by a unit quaternion (q v q*).
rotateBy :: Q4 -> [Double] -> [Double]
rotateBy q = apply3 (rotationMatrix q)

matMul :: [[Double]] -> [[Double]] -> [[Double]]
matMul a b = [ [ sum (zipWith (*) r c) | c <- transpose3 b ] | r <- a ]

transpose3 :: [[Double]] -> [[Double]]
transpose3 m = [ map (!! j) m | j <- [0 .. 2] ]

apply3 :: [[Double]] -> [Double] -> [Double]
apply3 m v = [ sum (zipWith (*) r v) | r <- m ]

-- | Rx(roll)·Ry(pitch)·Rz(yaw), angles in degrees: QTM's default rotation angles (roll about
-- x, then pitch about the new y, then yaw about the newest z).
eulerXyzMatrix :: Double -> Double -> Double -> [[Double]]
eulerXyzMatrix r p y = rx `matMul` ry `matMul` rz
  where
    d = pi / 180
    (cr, sr, cp, sp, cy, sy) = (cos (r * d), sin (r * d), cos (p * d), sin (p * d), cos (y * d), sin (y * d))
    rx = [[1, 0, 0], [0, cr, -sr], [0, sr, cr]]
    ry = [[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]]
    rz = [[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]]

-- | The helical axis of a unit quaternion's rotation: the axis times the angle in degrees,
-- the angle in [0, 180] or, with @turn@, a whole turn more (the same rotation).
helicalDegrees :: Bool -> Q4 -> [Double]
helicalDegrees turn (Q4 w0 x0 y0 z0) =
  let s = if w0 < 0 then -1 else 1
      (w, v) = (s * w0, map (* s) [x0, y0, z0])
      n = sqrt (sum (map (^ (2 :: Int)) v))
      ang = 2 * atan2 n w * 180 / pi + (if turn then 360 else 0)
  in if n < 1e-12 then [0, 0, 0] else map (* (ang / n)) v

num :: Double -> String
num v = showFFloat (Just 9) v ""

-- | A frame of one QTM body: tracked at a pose (m), or lost and written as NaN, as empty cells
-- or (older QTM) as zeros.
data QtmFrame = Tracked P3 Q4 | LostNaN | LostEmpty | LostZeros
  deriving (Show)

-- | A QTM 6D TSV of the named bodies, one list of frames each (equally long), at the given
-- frame rate: with its header or without, with CRLF line ends or LF, and with or without the
-- tab QTM writes after each row's last cell.
qtmText :: Double -> Bool -> Bool -> Bool -> [(String, [QtmFrame])] -> String
qtmText rate withHeader crlf trailingTab bodies = concatMap (++ eol) (header ++ [columns] ++ rows)
  where
    eol = if crlf then "\r\n" else "\n"
    tab = intercalate "\t"
    end cs = tab cs ++ (if trailingTab then "\t" else "")
    n = if null bodies then 0 else length (snd (head bodies))
    header
      | withHeader =
          [ tab ["NO_OF_FRAMES", show n], tab ["NO_OF_CAMERAS", "8"], tab ["NO_OF_BODIES", show (length bodies)]
          , tab ["FREQUENCY", show (round rate :: Int)], tab ["NO_OF_ANALOG", "0"], tab ["ANALOG_FREQUENCY", "0"]
          , tab ["DESCRIPTION", "--"], tab ["TIME_STAMP", "2026-11-30, 10:00:00.000", "1234.5"]
          , tab ["DATA_INCLUDED", "6D"], tab ("BODY_NAMES" : map fst bodies) ]
      | otherwise = []
    columns = end (["Frame", "Time"] ++ concat [ (b ++ " X") : ["Y", "Z", "Roll", "Pitch", "Yaw", "Residual"] ++ [ "Rot[" ++ show j ++ "]" | j <- [0 .. 8 :: Int] ]
                                                | (b, _) <- bodies ])
    rows = [ end ([show (k + 1), showFFloat (Just 5) (fromIntegral k / rate) ""] ++ concatMap (cellsOf . (!! k) . snd) bodies) | k <- [0 .. n - 1] ]
    cellsOf f = case f of
      Tracked (P3 x y z) q ->
        let m = rotationMatrix q
            r = map (\(i, j) -> m !! i !! j) [ (i, j) | j <- [0 .. 2], i <- [0 .. 2] ]  -- column by column
            pitch = asin (max (-1) (min 1 (m !! 0 !! 2)))
            roll = atan2 (negate (m !! 1 !! 2)) (m !! 2 !! 2)
            yaw = atan2 (negate (m !! 0 !! 1)) (m !! 0 !! 0)
        in map (num . (* 1000)) [x, y, z] ++ map (num . (* (180 / pi))) [roll, pitch, yaw] ++ ["0.512"] ++ map num r
      LostNaN -> replicate 16 "NaN"
      LostEmpty -> replicate 16 ""
      LostZeros -> replicate 16 "0.000"

-- | A frame of one Nexus segment: tracked at a pose (m) with the helical axis a whole turn
-- longer or not, or lost (empty cells).
data NexusFrame = NexusTracked Bool P3 Q4 | NexusLost
  deriving (Show)

-- | A Nexus CSV with a Segments section of the named segments (Subject:Segment), one list of
-- frames each, at the given rate, the rotation in @deg@ or @rad@ and the translation in @mm@
-- or @m@; a frame lost for every segment is written as its frame number alone, as Nexus does.
-- A Trajectories section of one marker follows.
nexusSegmentsText :: Double -> (String, String) -> [(String, [NexusFrame])] -> String
nexusSegmentsText rate (rotU, posU) segs = unlines (
  [ "Segments", show (round rate :: Int)
  , ",," ++ intercalate "," (concat [ [nm, "", "", "", "", ""] | (nm, _) <- segs ]) ++ ","
  , "Frame,Sub Frame," ++ intercalate "," (concat (replicate (length segs) ["RX", "RY", "RZ", "TX", "TY", "TZ"]))
  , ",," ++ intercalate "," (concat (replicate (length segs) (replicate 3 rotU ++ replicate 3 posU))) ]
  ++ [ row k | k <- [0 .. n - 1] ]
  ++ [ "", "Trajectories", show (round rate :: Int), ",,Subject:M1,,", "Frame,Sub Frame,X,Y,Z", ",,mm,mm,mm" ]
  ++ [ intercalate "," [show (k + 1), "0", "1", "2", "3"] | k <- [0 .. n - 1] ])
  where
    n = if null segs then 0 else length (snd (head segs))
    rs = if rotU == "rad" then pi / 180 else 1
    ps = if posU == "m" then 1 else 1000
    row k =
      let fs = map ((!! k) . snd) segs
      in if all lost fs then show (k + 1)
         else intercalate "," ([show (k + 1), "0"] ++ concatMap cellsOf fs)
    lost NexusLost = True
    lost _ = False
    cellsOf f = case f of
      NexusTracked turn (P3 x y z) q -> map (num . (* rs)) (helicalDegrees turn q) ++ map (num . (* ps)) [x, y, z]
      NexusLost -> replicate 6 ""
