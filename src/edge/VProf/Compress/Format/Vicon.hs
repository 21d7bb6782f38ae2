-- | Recordings exported by Vicon Nexus as CSV: sections (@Segments@, @Trajectories@, @Model
-- Outputs@, @Joints@, @Devices@) separated by a blank line, each a name line, the frame rate,
-- a row naming each group of columns (@Subject:Segment@ in its first cell), the axis row
-- (@Frame,Sub Frame,RX,RY,RZ,TX,TY,TZ,…@), the units row (@,,deg,deg,deg,mm,mm,mm@) and one
-- frame a line. The pose of one segment is read from the Segments section: its global
-- rotation as a helical axis (RX, RY, RZ: the axis times the angle, in the units row's deg or
-- rad; a length past 180° is the same rotation) and its translation (TX, TY, TZ, mm unless
-- the units row says otherwise). Frame k is at (k - 1) / rate s. A frame where the segment
-- was lost has empty cells, or only its frame number: read as a lost sample, which the
-- cleaning drops with a warning. Marker trajectories hold no orientation and are not read.
module VProf.Compress.Format.Vicon
  ( isViconCsv
  , readVicon
  , ViconLayout (..)
  , describeVicon
  ) where

import qualified Data.ByteString.Char8 as B
import Data.Char (isSpace, toLower)
import Data.List (intercalate)

import VProf.Compress.Clean (Sample (..))
import VProf.Compress.Format.Common (cellAt, chooseBody, filledLines, numberField, poseColumns, readDouble, splitCells, textCells)
import VProf.Geometry.Quaternion (qexp)
import VProf.Geometry.Vec (P3 (..))
import VProf.Validation (showBound)

-- | How a Nexus export was read (columns counted from 1).
data ViconLayout = ViconLayout
  { vlSegment  :: !String            -- ^ the segment read, as the names row writes it
  , vlOthers   :: ![String]          -- ^ the other segments of the section
  , vlSections :: ![String]          -- ^ the file's sections
  , vlAxisLine :: !Int               -- ^ line of the Segments section's axis row
  , vlRate     :: !Double            -- ^ frames per second
  , vlRot      :: !Int               -- ^ RX column (RY, RZ follow)
  , vlPos      :: !Int               -- ^ TX column (TY, TZ follow)
  , vlRotUnit  :: !(Double, String)  -- ^ rad per unit, its name
  , vlPosUnit  :: !(Double, String)  -- ^ m per unit, its name
  } deriving (Show, Eq)

sectionNames :: [String]
sectionNames = ["segments", "trajectories", "model outputs", "joints", "devices"]

cells :: B.ByteString -> [String]
cells = textCells ','

-- | A section line: a section's name in the first cell, the others empty.
sectionOf :: B.ByteString -> Maybe String
sectionOf l = case cells l of
  c : rest | map toLower c `elem` sectionNames, all null rest -> Just c
  _ -> Nothing

-- | Whether the first line that is not blank names a Nexus section and a line follows it (the
-- frame rate: one that is not a rate is the reader's error, naming it).
isViconCsv :: B.ByteString -> Bool
isViconCsv src = case filledLines src of
  l : _ : _ | Just _ <- sectionOf l -> True
  _ -> False

-- | The frame rates taken (Hz): a rate outside them is a wrong number or unit (below a frame in
-- 1000 s the times of a long take run out of digits; above a million frames a second no
-- motion capture records, and 1e308 Hz put every frame at 0 s).
minFrameRate, maxFrameRate :: Double
minFrameRate = 1e-3
maxFrameRate = 1e6

-- | One sentence on what was read.
describeVicon :: ViconLayout -> String
describeVicon l =
  "read as a Vicon Nexus CSV export (sections " ++ intercalate ", " (vlSections l) ++ "): segment " ++ show (vlSegment l)
    ++ (case vlOthers l of
          [] -> ""
          os -> " (the file also holds " ++ intercalate ", " (map show os) ++ "; choose with --rigid-body)")
    ++ ", frame k at (k - 1) / " ++ show (vlRate l) ++ " s"
    ++ ", helical axis columns " ++ show (vlRot l) ++ "-" ++ show (vlRot l + 2) ++ " in " ++ snd (vlRotUnit l)
    ++ ", translation columns " ++ show (vlPos l) ++ "-" ++ show (vlPos l + 2) ++ " in " ++ snd (vlPosUnit l)

-- | The samples of one segment of a Nexus export (SI units), each with its line number, and
-- how they were read. @Nothing@ takes the only segment of the Segments section; a section with
-- several needs a name (@Subject:Segment@, or the segment's name alone where no other subject
-- has one of that name). Errors name the line, the column and the value.
readVicon :: Maybe String -> B.ByteString -> Either String (ViconLayout, [Sample])
readVicon want src = do
  let numbered = zip [1 :: Int ..] (B.lines src)
      -- a section starts at a section line, at the file's start or after a blank line
      starts = [ (i, s) | ((i, l), prevBlank) <- zip numbered (True : map (B.all isSpace . snd) numbered)
                        , prevBlank, Just s <- [sectionOf l] ]
      sections = map snd starts
  segLine <- case [ i | (i, s) <- starts, map toLower s == "segments" ] of
    i : _ -> Right i
    [] -> Left ("Vicon Nexus CSV: no Segments section (the file has " ++ intercalate ", " sections
                ++ "); marker trajectories hold no orientation: export the segments' global poses (Segments) from Nexus")
  let line i = maybe B.empty id (lookup i numbered)
      rateLine = segLine + 1
      namesLine = segLine + 2
      axisLine = segLine + 3
      unitsLine = segLine + 4
  rate <- case cells (line rateLine) of
    c : _ | Just f <- readDouble (B.pack c), f >= minFrameRate, f <= maxFrameRate -> Right f
          | Just f <- readDouble (B.pack c), f > 0 ->
              Left ("Vicon Nexus CSV line " ++ show rateLine ++ ": the Segments section's frame rate " ++ c ++ " Hz is outside "
                    ++ showBound minFrameRate ++ " to " ++ showBound maxFrameRate ++ " Hz (is the number right?)")
          | Just _ <- readDouble (B.pack c) ->
              Left ("Vicon Nexus CSV line " ++ show rateLine ++ ": the Segments section's frame rate " ++ c ++ " Hz is not above 0")
    c : _ -> Left ("Vicon Nexus CSV line " ++ show rateLine ++ ": the Segments section's frame rate " ++ show c ++ " is not a number (Hz)")
    [] -> Left ("Vicon Nexus CSV line " ++ show rateLine ++ ": no frame rate after the Segments line")
  let names = cells (line namesLine)
      axes = map (map toLower) (cells (line axisLine))
      units = map (map toLower) (cells (line unitsLine))
      at xs c = if c >= 1 && c <= length xs then xs !! (c - 1) else ""
  case axes of
    f : _ | f == "frame" -> Right ()
    _ -> Left ("Vicon Nexus CSV line " ++ show axisLine ++ ": expected the axis row Frame,Sub Frame,RX,RY,RZ,TX,TY,TZ; found "
               ++ show (B.unpack (B.take 80 (line axisLine))))
  -- each named group of the names row: its rotation and translation columns
  let groups = [ (c, nm) | (c, nm) <- zip [1 ..] names, c >= 2, not (null nm) ]
      colsOf c = (colIn c "rx", colIn c "tx")
      colIn c ax = case [ c' | c' <- [c .. c + 5], at axes c' == ax ] of
        c' : _ -> Just c'
        [] -> Nothing
      segs = [ (nm, r, p) | (c, nm) <- groups, (Just r, Just p) <- [colsOf c]
                          , at axes (r + 1) == "ry", at axes (r + 2) == "rz", at axes (p + 1) == "ty", at axes (p + 2) == "tz" ]
  if null segs
    then Left ("Vicon Nexus CSV line " ++ show axisLine ++ ": the Segments section names no segment with columns RX, RY, RZ, TX, TY, TZ (names row line "
               ++ show namesLine ++ ": " ++ show (B.unpack (B.take 80 (line namesLine))) ++ ")")
    else Right ()
  let segName nm = reverse (takeWhile (/= ':') (reverse nm))
  (seg, (rc, pc)) <- chooseBody "Vicon Nexus CSV" "segments" (\w nm -> segName nm == w)
                       "several subjects have a segment of that name; give Subject:Segment" want [ (nm, (r, p)) | (nm, r, p) <- segs ]
  rotUnit <- unitOf unitsLine rc [("deg", (pi / 180, "deg")), ("", (pi / 180, "deg (none written: degrees assumed)")), ("rad", (1, "rad"))] (at units rc)
  posUnit <- unitOf unitsLine pc [("mm", (1e-3, "mm")), ("", (1e-3, "mm (none written: millimetres assumed)")), ("cm", (1e-2, "cm")), ("m", (1, "m"))] (at units pc)
  let dataRows = takeWhile (not . B.all isSpace . snd) [ (i, l) | (i, l) <- numbered, i > unitsLine ]
      (ru, _) = rotUnit
      (pu, _) = posUnit
      row (i, l) = do
        let cs = splitCells ',' l
        frame <- numberField "Vicon Nexus CSV" i 1 (cellAt cs 1)
        -- a frame without the segment: empty cells, or (Nexus) its frame number alone
        vs <- poseColumns "Vicon Nexus CSV" i cs ([rc .. rc + 2] ++ [pc .. pc + 2])
        case vs of
          [rx, ry, rz, tx, ty, tz] ->
            Right (Sample i ((frame - 1) / rate) (P3 (tx * pu) (ty * pu) (tz * pu)) (qexp (P3 (rx * ru) (ry * ru) (rz * ru))))
          _ -> Left ("Vicon Nexus CSV line " ++ show i ++ ": " ++ show (B.unpack (B.take 80 l)))
  samples <- traverse row dataRows
  pure ( ViconLayout seg [ nm | (nm, _, _) <- segs, nm /= seg ] sections axisLine rate rc pc rotUnit posUnit
       , samples )
  where
    unitOf li c known u = case lookup u known of
      Just k -> Right k
      Nothing -> Left ("Vicon Nexus CSV line " ++ show li ++ ", column " ++ show c ++ ": unit " ++ show u
                       ++ ": expected " ++ intercalate " or " [ k | (k, _) <- known, not (null k) ])
