-- | Recordings exported by OptiTrack Motive as CSV: a first line of settings
-- (@Format Version,1.23,…,Rotation Type,Quaternion,Length Units,Meters,…@), rows that name
-- each column's asset type, asset name, and kind (@Rotation@, @Position@), then the axis row
-- @Frame,Time (Seconds),X,Y,Z,W,X,Y,Z,…@ and one frame a line. The pose of one rigid body (or
-- skeleton bone) is read: its quaternion (Motive writes x y z w) and its position in the
-- file's length unit. A frame where the body was lost has empty cells: read as NaN, for the
-- cleaning to drop with a warning; a row that ends before the body's columns is an error (the
-- file was cut short: Motive keeps a lost frame's commas). Euler-angle exports are refused (their convention is the
-- exporter's setting, not written in the file).
module VProf.Compress.Format.Motive
  ( isMotiveCsv
  , readMotive
  , MotiveLayout (..)
  , describeMotive
  ) where

import qualified Data.ByteString.Char8 as B
import Data.Char (isSpace, toLower)
import Data.List (intercalate, nub)
import Data.Maybe (listToMaybe)
import qualified Data.Vector as V

import VProf.Compress.Clean (Sample (..))
import VProf.Compress.Format.Common (cellAt, chooseBody, filledLines, numberField, poseColumns, shownField, splitCells, textCells)
import VProf.Geometry.Vec

-- | How a Motive export was read (columns counted from 1).
data MotiveLayout = MotiveLayout
  { mlVersion   :: !String
  , mlBody      :: !String            -- ^ the body read
  , mlOthers    :: ![String]          -- ^ the other bodies in the file
  , mlAxisLine  :: !Int               -- ^ line of the Frame,Time,X,Y,Z,… row
  , mlTime      :: !Int
  , mlQuat      :: !(Int, Int, Int, Int)  -- ^ x, y, z, w
  , mlPos       :: !(Int, Int, Int)
  , mlUnit      :: !(Double, String)      -- ^ metres per length unit, its name as written
  , mlSpace     :: !String                -- ^ Coordinate Space as written (Global, Local), or ""
  } deriving (Show, Eq)

-- | Whether the first line that is not blank is Motive's settings line.
isMotiveCsv :: B.ByteString -> Bool
isMotiveCsv src = case filledLines src of
  l : _ -> map toLower (B.unpack (B.takeWhile (/= ',') (B.strip l))) == "format version"
  [] -> False

-- | One sentence on what was read.
describeMotive :: MotiveLayout -> String
describeMotive l =
  "read as an OptiTrack Motive export (format version " ++ mlVersion l ++ "): rigid body " ++ show (mlBody l)
    ++ (case mlOthers l of
          [] -> ""
          os -> " (the file also holds " ++ intercalate ", " (map show os) ++ "; choose with --rigid-body)")
    ++ ", time column " ++ show (mlTime l) ++ " in s, quaternion x y z w columns " ++ cols4 (mlQuat l)
    ++ ", position columns " ++ cols3 (mlPos l) ++ " in " ++ snd (mlUnit l)
    ++ (if null (mlSpace l) then "" else ", coordinate space " ++ mlSpace l)
    ++ " (Motive's frame is y-up unless its export was set otherwise)"
  where
    cols3 (a, b, c) = intercalate ", " (map show [a, b, c])
    cols4 (a, b, c, d) = intercalate ", " (map show [a, b, c, d])

-- | The samples of one body of a Motive export (SI units), each with its line number, and how
-- they were read. @Nothing@ takes the only rigid body (or bone) of the file; a file with
-- several needs a name. Errors name the line, the column or the setting, and the value.
readMotive :: Maybe String -> B.ByteString -> Either String (MotiveLayout, [Sample])
readMotive want src = do
  let numbered = zip [1 :: Int ..] (B.lines src)
      cells = textCells ','
  (metaLine, meta) <- case [ (i, cells l) | (i, l) <- numbered, not (B.all isSpace l) ] of
    m : _ -> Right m
    [] -> Left "Motive CSV: empty file"
  let settings = pairs meta
      setting k = lookup k settings
      version = maybe "?" id (setting "format version")
  case setting "rotation type" of
    Just r | map toLower r /= "quaternion" ->
      Left ("Motive CSV line " ++ show metaLine ++ ": Rotation Type is " ++ show r
            ++ " (Euler angles, whose order and frame are the exporter's setting); export again with Rotation Type: Quaternion")
    _ -> Right ()
  unit <- case setting "length units" of
    Nothing -> Right (1, "m (no Length Units setting: metres assumed)")
    Just u -> case map toLower u of
      v | v `elem` ["meters", "metres", "meter", "metre", "m"] -> Right (1, "m")
        | v `elem` ["centimeters", "centimetres", "centimeter", "centimetre", "cm"] -> Right (1e-2, "cm")
        | v `elem` ["millimeters", "millimetres", "millimeter", "millimetre", "mm"] -> Right (1e-3, "mm")
        | otherwise -> Left ("Motive CSV line " ++ show metaLine ++ ": Length Units " ++ show u ++ ": expected Meters, Centimeters or Millimeters")
  let isAxisRow cs = case cs of
        f : t : _ -> map toLower f == "frame" && take 4 (map toLower t) == "time"
        _ -> False
  (axisLine, axes) <- case [ (i, cs) | (i, l) <- numbered, i > metaLine, let cs = cells l, isAxisRow cs ] of
    a : _ -> Right a
    [] -> Left ("Motive CSV: no column header row (Frame,Time (Seconds),X,Y,Z,…) after the settings of line " ++ show metaLine)
  case map toLower (axes !! 1) of
    t | t `elem` ["time (seconds)", "time (s)", "time"] -> Right ()
      | otherwise -> Left ("Motive CSV line " ++ show axisLine ++ ", column 2: unknown time column " ++ show (axes !! 1) ++ "; expected Time (Seconds)")
  let headerRows = [ (i, cells l) | (i, l) <- numbered, i > metaLine, i < axisLine, not (B.all isSpace l) ]
      labelled name = listToMaybe [ cs | (_, cs) <- headerRows, map toLower (filter (/= ':') (at cs 1)) == name ]
      -- older exports leave the label cell empty: the type row is the first header row, the name row the second
      typeRow = maybe (at' 0) id (labelled "type")
      nameRow = maybe (at' 1) id (labelled "name")
      at' k = maybe [] snd (listToMaybe (drop k headerRows))
      kindRow = case reverse headerRows of (_, cs) : _ -> cs; [] -> []
      n = length axes
      cols = [ (c, at typeRow (c - 1), at nameRow (c - 1), map toLower (at kindRow (c - 1)), map toLower (axes !! (c - 1))) | c <- [3 .. n] ]
      bodyType ty = map toLower ty `elem` ["rigid body", "bone"]
      bodies = nub [ nm | (_, ty, nm, _, _) <- cols, bodyType ty ]
      colOf nm kind ax = listToMaybe [ c | (c, ty, nm', k, a) <- cols, bodyType ty, nm' == nm, k == kind, a == ax ]
  body <- case (want, bodies) of
    (_, []) -> Left ("Motive CSV: no rigid body in the file (the type row names "
                     ++ (case nub [ ty | (_, ty, _, _, _) <- cols, not (null ty) ] of
                           [] -> "nothing"
                           ts -> intercalate ", " (map show ts))
                     ++ "); export it with Rigid Bodies on")
    (_, bs) -> fst <$> chooseBody "Motive CSV" "rigid bodies" (\_ _ -> False) "" want [ (b, ()) | b <- bs ]
  let need = [ (kind ++ " " ++ map (\ch -> if ch == 'w' then 'W' else ch) ax, colOf body kind ax)
             | (kind, ax) <- [("rotation", "x"), ("rotation", "y"), ("rotation", "z"), ("rotation", "w"), ("position", "x"), ("position", "y"), ("position", "z")] ]
  found <- case [ what | (what, Nothing) <- need ] of
    [] -> Right [ c | (_, Just c) <- need ]
    miss -> Left ("Motive CSV line " ++ show axisLine ++ ": rigid body " ++ show body ++ " has no column for " ++ intercalate ", " miss)
  (qx, qy, qz, qw, px, py, pz) <- case found of
    [a, b, c, d, e, f, g] -> Right (a, b, c, d, e, f, g)
    _ -> Left "Motive CSV: impossible column count"
  let body' = [ (i, s) | (i, l) <- numbered, i > axisLine, let s = B.strip l, not (B.null s) ]
      sc = fst unit
      row (i, l) = do
        let cs = splitCells ',' l
            cell = cellAt cs
            needed = maximum [qx, qy, qz, qw, px, py, pz]
        -- a lost frame keeps its commas (empty cells); a row that ends before the body's
        -- columns was cut (a copy or an export that stopped), not lost
        if V.length cs < needed
          then Left ("Motive CSV line " ++ show i ++ ": the row ends after " ++ show (V.length cs) ++ " columns, but " ++ body
                     ++ "'s run to column " ++ show needed ++ ": is the file cut short? (a frame where the body was lost keeps its commas, with empty cells)")
          else Right ()
        t <- if B.null (cell 2) then Left ("Motive CSV line " ++ show i ++ ", column 2: no time") else numberField "Motive CSV" i 2 (cell 2)
        vs <- poseColumns "Motive CSV" i cs [qx, qy, qz, qw, px, py, pz]
        case vs of
          [a, b, c, d, x, y, z] -> Right (Sample i t (P3 (x * sc) (y * sc) (z * sc)) (Q4 d a b c))
          _ -> Left ("Motive CSV line " ++ show i ++ ": " ++ shownField l)
  samples <- traverse row body'
  pure ( MotiveLayout version body (filter (/= body) bodies) axisLine 2 (qx, qy, qz, qw) (px, py, pz) unit (maybe "" id (setting "coordinate space"))
       , samples )
  where
    at cs k = if k < length cs then cs !! k else ""
    -- the settings line as key, value pairs, keys in lower case
    pairs (k : v : rest) = (map toLower k, v) : pairs rest
    pairs _ = []

