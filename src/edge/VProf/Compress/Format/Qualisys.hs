-- | Rigid-body recordings exported by Qualisys Track Manager as a 6D TSV (@…_6D.tsv@): tab
-- separated, a header of @KEY<TAB>value@ lines (@NO_OF_FRAMES@, @FREQUENCY@, @DATA_INCLUDED@
-- @6D@, @BODY_NAMES@, …; QTM can leave them out), then the column row
-- @Frame  Time  <body> X  Y  Z  Roll  Pitch  Yaw  Residual  Rot[0] … Rot[8]@ with those 16
-- columns for each body, and one frame a line. The pose of one body is read: its position
-- (QTM writes mm) and its rotation matrix, @Rot[0..8]@ column by column (the matrix maps the
-- body's coordinates to the reference frame's); the Euler angles are not used, their
-- definition being a QTM setting. A frame where the body was not tracked has NaN or empty
-- cells, or (older QTM) a rotation matrix of zeros: read as a lost sample, which the cleaning
-- drops with a warning. A matrix that is no rotation is an error naming its line.
module VProf.Compress.Format.Qualisys
  ( isQualisysTsv
  , readQualisys
  , QualisysLayout (..)
  , describeQualisys
  ) where

import qualified Data.ByteString.Char8 as B
import Data.Char (isSpace, toLower, toUpper)
import Data.List (intercalate, isSuffixOf)
import Data.Maybe (listToMaybe)
import qualified Data.Vector as V

import VProf.Compress.Clean (Sample (..))
import VProf.Compress.Format.Common (cellAt, chooseBody, filledLines, numberField, poseColumns, readDouble, shownField, splitCells, textCells)
import VProf.Geometry.Vec (P3 (..), Q4 (..))
import VProf.Kinematics.Transform (Quat (..), fromRows, isRigid, toQuat)

-- | How a 6D TSV was read (columns counted from 1).
data QualisysLayout = QualisysLayout
  { qlBody     :: !String     -- ^ the body read
  , qlOthers   :: ![String]   -- ^ the other bodies in the file
  , qlColumns  :: !Int        -- ^ line of the column row
  , qlTime     :: !(Either Double Int)  -- ^ the Time column, or the frame rate the frames are timed by
  , qlPos      :: !Int        -- ^ the body's X column (Y, Z follow)
  , qlRot      :: !Int        -- ^ the body's Rot[0] column (Rot[1..8] follow)
  , qlUntracked :: !Int       -- ^ frames with a rotation matrix of zeros, read as lost
  } deriving (Show, Eq)

-- | The header keys QTM writes first (any of them on the first line that is not blank), or a
-- header-less export's column row.
isQualisysTsv :: B.ByteString -> Bool
isQualisysTsv src = case filledLines src of
  l : _ -> let cs = tabCells l in case cs of
    c : _ | map toUpper c `elem` qtmKeys -> True
    c : t : _ -> map toLower c == "frame" && map toLower t == "time" && any (labelled "rot[0]") cs
    _ -> False
  [] -> False
  where
    qtmKeys = ["NO_OF_FRAMES", "FILE_VERSION", "NO_OF_CAMERAS", "NO_OF_BODIES"]

-- | Whether a column's label is this axis, alone or after the body's name ("Y" or "Tool Y"),
-- in any case.
labelled :: String -> String -> Bool
labelled axis l = let l' = map toLower l in l' == axis || (' ' : axis) `isSuffixOf` l'

tabCells :: B.ByteString -> [String]
tabCells = textCells '\t'

-- | One sentence on what was read.
describeQualisys :: QualisysLayout -> String
describeQualisys l =
  "read as a Qualisys 6D TSV export: body " ++ show (qlBody l)
    ++ (case qlOthers l of
          [] -> ""
          os -> " (the file also holds " ++ intercalate ", " (map show os) ++ "; choose with --rigid-body)")
    ++ (case qlTime l of
          Right c -> ", time column " ++ show c ++ " in s"
          Left f -> ", no Time column: frame k at (k - 1) / " ++ show f ++ " s (FREQUENCY)")
    ++ ", position columns " ++ show (qlPos l) ++ "-" ++ show (qlPos l + 2) ++ " in mm"
    ++ ", rotation matrix Rot[0..8] columns " ++ show (qlRot l) ++ "-" ++ show (qlRot l + 8) ++ " (column by column)"
    ++ (if qlUntracked l > 0 then "; " ++ show (qlUntracked l) ++ " frames with a rotation matrix of zeros (not tracked) read as lost" else "")

-- | The samples of one body of a 6D TSV (SI units), each with its line number, and how they
-- were read. @Nothing@ takes the only body of the file; a file with several needs a name.
-- Errors name the line, the column or the header key, and the value.
readQualisys :: Maybe String -> B.ByteString -> Either String (QualisysLayout, [Sample])
readQualisys want src = do
  let numbered = zip [1 :: Int ..] (B.lines src)
      isColumnRow cs = case cs of
        f : _ -> map toLower f == "frame"
        _ -> False
  (colLine, cols0) <- case [ (i, cs) | (i, l) <- numbered, let cs = tabCells l, isColumnRow cs ] of
    a : _ -> Right a
    [] -> Left "Qualisys TSV: no column row (Frame, Time, <body> X, Y, Z, …, Rot[0] … Rot[8]); export it with the data header on"
  let header = [ (i, map toUpper k, vs) | (i, l) <- numbered, i < colLine, k : vs <- [tabCells l], not (null k) ]
      key k = listToMaybe [ (i, vs) | (i, k', vs) <- header, k' == k ]
      -- QTM ends each row with a tab: the empty cells after the last column are not columns
      cols = reverse (dropWhile null (reverse cols0))
      n = length cols
      label c = map toLower (cols !! (c - 1))
  case key "DATA_INCLUDED" of
    Just (i, v : _) | map toUpper v /= "6D" ->
      Left ("Qualisys TSV line " ++ show i ++ ": DATA_INCLUDED is " ++ show v
            ++ ": this export holds no rigid-body poses (a 3D export has marker positions only, no orientation); export the 6D data")
    _ -> Right ()
  let rot0s = [ c | c <- [1 .. n], labelled "rot[0]" (cols !! (c - 1)) ]
      names = maybe [] (filter (not . null) . snd) (key "BODY_NAMES")
  blocks <- traverse (block cols names colLine) (zip [0 ..] rot0s)
  if null blocks
    then Left ("Qualisys TSV line " ++ show colLine ++ ": no Rot[0] column: the export holds no rigid-body rotation (a 3D export has marker positions only); export the 6D data")
    else Right ()
  (body, (x0, r0)) <- chooseBody "Qualisys TSV" "bodies" (\_ _ -> False) "" want [ (b, (x, r)) | (b, x, r) <- blocks ]
  timing <- case [ c | c <- [1 .. n], label c == "time" ] of
    c : _ -> Right (Right c)
    [] -> case key "FREQUENCY" of
      Just (i, v : _) -> case readDouble (B.pack v) of
        Just f | f > 0 -> Right (Left f)
        _ -> Left ("Qualisys TSV line " ++ show i ++ ": FREQUENCY " ++ show v ++ ": expected a frame rate > 0 in Hz")
      _ -> Left ("Qualisys TSV line " ++ show colLine ++ ": no Time column and no FREQUENCY in the header to time the frames by")
  let needed = r0 + 8
      rows = [ (i, l) | (i, l) <- numbered, i > colLine, not (B.all isSpace l) ]
      row (i, l) = do
        let cs = splitCells '\t' l
            cell = cellAt cs
        if V.length cs < needed
          then Left ("Qualisys TSV line " ++ show i ++ ": the row ends after " ++ show (V.length cs) ++ " columns, but " ++ body
                     ++ "'s run to column " ++ show needed ++ ": is the file cut short?")
          else Right ()
        t <- case timing of
          Right c -> numberField "Qualisys TSV" i c (cell c)
          Left f -> (\k -> (k - 1) / f) <$> numberField "Qualisys TSV" i 1 (cell 1)
        vs <- poseColumns "Qualisys TSV" i cs ([x0 .. x0 + 2] ++ [r0 .. r0 + 8])
        case vs of
          [x, y, z, a0, a1, a2, a3, a4, a5, a6, a7, a8]
            | any isNaN vs -> Right (lost i t, False)
            | all (== 0) [a0, a1, a2, a3, a4, a5, a6, a7, a8] -> Right (lost i t, True)
            -- Rot[] runs down the columns: the matrix's rows are Rot[0,3,6], Rot[1,4,7], Rot[2,5,8]
            | Just tf <- fromRows [a0, a3, a6, x, a1, a4, a7, y, a2, a5, a8, z], isRigid 1e-3 tf ->
                let Quat qw' qx' qy' qz' = toQuat tf
                in Right (Sample i t (P3 (x * 1e-3) (y * 1e-3) (z * 1e-3)) (Q4 qw' qx' qy' qz'), False)
            | otherwise ->
                Left ("Qualisys TSV line " ++ show i ++ ", columns " ++ show r0 ++ "-" ++ show (r0 + 8) ++ ": Rot[0..8] of "
                      ++ body ++ " is not a rotation (orthonormal to 1e-3, determinant +1): "
                      ++ intercalate ", " [ shownField (cell c) | c <- [r0 .. r0 + 8] ])
          _ -> Left ("Qualisys TSV line " ++ show i ++ ": " ++ shownField l)
      lost i t = Sample i t (P3 nan nan nan) (Q4 nan nan nan nan)
      nan = 0 / 0
  samples <- traverse row rows
  pure ( QualisysLayout body [ b | (b, _, _) <- blocks, b /= body ] colLine timing x0 r0 (length (filter snd samples))
       , map fst samples )
  where
    -- a body's columns: X, Y, Z seven before its Rot[0], Rot[1..8] after it; its name from
    -- the X column's label (QTM writes "<body> X"), else BODY_NAMES in order
    block cols names colLine (k, r0) = do
      let at c = if c >= 1 && c <= length cols then cols !! (c - 1) else ""
          x0 = r0 - 7
          xLabel = at x0
          fromLabel = if map toLower xLabel == "x" then "" else take (length xLabel - 2) xLabel
          name
            | " x" `isSuffixOf` map toLower xLabel, not (null fromLabel) = fromLabel
            | k < length names = names !! k
            | otherwise = "body " ++ show (k + 1 :: Int)
      if x0 >= 1 && labelled "x" xLabel && labelled "y" (at (x0 + 1)) && labelled "z" (at (x0 + 2))
           && and [ labelled ("rot[" ++ show j ++ "]") (at (r0 + j)) | j <- [0 .. 8 :: Int] ]
        then Right (name, x0, r0)
        else Left ("Qualisys TSV line " ++ show colLine ++ ", column " ++ show r0 ++ ": expected a body's columns X, Y, Z, three angles, Residual, then Rot[0] … Rot[8]; found "
                   ++ intercalate ", " (map show ([at c | c <- [max 1 x0 .. x0 + 2]] ++ [at (r0 + j) | j <- [0 .. 8]])))
