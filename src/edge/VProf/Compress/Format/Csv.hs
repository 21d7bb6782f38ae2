-- | Recordings and paths as CSV with a header that names the columns. vprof writes
-- @time,x,y,z,qw,qx,qy,qz@ in SI units; it reads that, the EuRoC / ASL ground truth
-- (@#timestamp, p_RS_R_x [m], …, q_RS_w [], …@, times in ns, further columns ignored), a
-- ROS @rostopic echo -p@ pose export (@field.header.stamp@, @….position.x@,
-- @….orientation.w@) and any header naming a time, x, y, z and the four quaternion parts,
-- in any order, with units in brackets. The columns may be separated by commas, tabs, semicolons
-- (then a decimal comma is read as a point, as spreadsheets in much of Europe write it) or
-- blanks; the header's line decides. The layout it found is reported, so a file read with the
-- wrong unit does not pass unnoticed.
module VProf.Compress.Format.Csv
  ( renderCsv
  , parseCsv
  , readCsv
  , hasCsvHeader
  , hasNamedHeader
  , CsvLayout (..)
  , Separator (..)
  , describeLayout
  ) where

import qualified Data.ByteString.Char8 as B
import qualified Data.ByteString.Lazy as BL
import Data.Char (isAlpha, isSpace, toLower)
import Data.List (elemIndex, intercalate, sort)
import Data.Maybe (isJust, isNothing)

import VProf.Compress.Clean (Sample (..))
import VProf.Compress.Format.Common (missingToken, numberField, poseFields, readDouble, renderPoseLines, trackFromRows, unquote)
import VProf.Compress.Types
import VProf.Geometry.Vec

renderCsv :: Track -> BL.ByteString
renderCsv = renderPoseLines "time,x,y,z,qw,qx,qy,qz" "," (\(P3 x y z) (Q4 w a b c) -> [x, y, z, w, a, b, c])

-- | A strictly valid track (increasing times, no duplicates) from a headed CSV; for
-- reading back paths vprof wrote. Real recordings go through 'readCsv' and
-- "VProf.Compress.Clean".
parseCsv :: B.ByteString -> Either String Track
parseCsv src = readCsv src >>= trackFromRows "CSV" . snd

-- | Where the pose is in a headed CSV and in which units (columns counted from 1).
data CsvLayout = CsvLayout
  { clHeaderLine :: !Int
  , clTime       :: !(Int, String)           -- ^ column and its header name
  , clTimeUnit   :: !(Double, String, Bool)  -- ^ seconds per unit, unit, whether inferred from the values
  , clPos        :: !(Int, Int, Int)
  , clPosUnit    :: !(Double, String)
  , clQuat       :: !(Int, Int, Int, Int)    -- ^ w, x, y, z
  , clColumns    :: !Int
  , clSeparator  :: !Separator
  } deriving (Show, Eq)

-- | What separates the columns, as the header's line shows it: a comma if it has one, else a
-- tab, else a semicolon, else blanks.
data Separator = Comma | Tab | Semicolon | Blanks deriving (Show, Eq)

separatorOf :: B.ByteString -> Separator
separatorOf l
  | B.elem ',' l = Comma
  | B.elem '\t' l = Tab
  | B.elem ';' l = Semicolon
  | otherwise = Blanks

separatorName :: Separator -> String
separatorName = \case
  Comma -> "comma"
  Tab -> "tab"
  Semicolon -> "semicolon"
  Blanks -> "blank"

-- | A line's fields. After semicolons a decimal comma is a point; between blanks a unit in
-- brackets written apart ("x [mm]") stays with its name.
splitFields :: Separator -> B.ByteString -> [B.ByteString]
splitFields sep l = case sep of
  Comma -> B.split ',' l
  Tab -> B.split '\t' l
  Semicolon -> map (B.map (\c -> if c == ',' then '.' else c)) (B.split ';' l)
  Blanks -> glue (B.words l)
  where
    glue (a : b : rest) | B.isPrefixOf (B.pack "[") b = glue (B.concat [a, B.pack " ", b] : rest)
    glue (a : rest) = a : glue rest
    glue [] = []

-- | One sentence on how the file was read: which columns, which units.
describeLayout :: CsvLayout -> String
describeLayout l =
  "read as CSV" ++ (if clSeparator l == Comma then "" else " (" ++ separatorName (clSeparator l) ++ "-separated)")
    ++ " with the header of line " ++ show (clHeaderLine l) ++ ": time column "
    ++ show (fst (clTime l)) ++ " (" ++ show (snd (clTime l)) ++ ") in " ++ unitT
    ++ ", position columns " ++ cols3 (clPos l) ++ " in " ++ snd (clPosUnit l)
    ++ ", quaternion w x y z columns " ++ cols4 (clQuat l)
    ++ (if clColumns l > 8 then ", " ++ show (clColumns l - 8) ++ " further columns ignored" else "")
  where
    (_, u, inferred) = clTimeUnit l
    unitT = u ++ (if inferred then " (no unit in the header; the time steps are too large for seconds)" else "")
    cols3 (a, b, c) = intercalate ", " (map show [a, b, c])
    cols4 (a, b, c, d) = intercalate ", " (map show [a, b, c, d])

-- | Whether the first line that is neither blank nor a @#@ comment is a CSV header (at least
-- four fields by 'separatorOf', not all numbers; a leading @#@ allowed before commas, as EuRoC
-- writes it), or an attempt at one (words where numbers would be, which 'readCsv' then
-- explains). A file without one is the thesis's Polhemus log ("VProf.Compress.Format.Log").
hasCsvHeader :: B.ByteString -> Bool
hasCsvHeader src = go (filter (not . B.all isSpace) (B.lines src))
  where
    go (l : ls)
      | isJust (headerFields l) = True
      | B.isPrefixOf (B.pack "#") (B.strip l) = go ls      -- a comment before the header
      | any word (B.split ',' l) = True   -- words where numbers would be: a header 'readCsv' explains
      | otherwise = False
    go [] = False
    -- a field that is no number and holds letters, other than the words of non-finite numbers
    word f = let g = B.strip f
             in isNothing (readDouble g) && B.any isAlpha g
                && not (missingToken g) && map toLower (B.unpack (B.dropWhile (`elem` ("+-" :: String)) g)) `notElem` ["inf", "infinity"]

-- | Whether the first line that is neither blank nor a @#@ comment is a header naming the columns
-- (at least four fields, not all numbers, by 'separatorOf'): a whitespace- or tab-separated
-- file with such a header is read as a headed CSV, not as TUM.
hasNamedHeader :: B.ByteString -> Bool
hasNamedHeader src = case [ l | l <- B.lines src, let s = B.strip l, not (B.null s), B.head s /= '#' ] of
  l : _ -> isJust (headerFields l)
  [] -> False

-- | A header line's separator and names. A line after @#@ is a header only with commas (as EuRoC
-- writes it): a blank-separated comment ("# timestamp tx ty tz qx qy qz qw", TUM's) is a comment.
headerFields :: B.ByteString -> Maybe (Separator, [String])
headerFields l0 =
  let s0 = B.strip l0
      l = B.dropWhile (== '#') s0
      sep = separatorOf l
      fs = map (B.unpack . unquote . B.strip) (splitFields sep l)
      commented = B.isPrefixOf (B.pack "#") s0 && sep /= Comma
  in if not commented && length fs >= 4 && any (\f -> isNothing (readDouble (B.pack f)) && not (missingToken (B.pack f))) fs
       then Just (sep, fs) else Nothing

-- | The samples of a headed CSV (SI units), each with its line number (from 1), and the
-- layout found. Lines before the header, blank lines and later lines starting with @#@
-- are skipped; an empty or @nan@ pose value (what motion-capture exports write when the
-- body was lost) is read as NaN, for the cleaning to drop. Errors name the line and column, or the columns the header lacks.
readCsv :: B.ByteString -> Either String (CsvLayout, [Sample])
readCsv src = do
  (hi, (sep, names)) <- case [ (i, h) | (i, l) <- numbered, Just h <- [headerFields l] ] of
    h : _ -> Right h
    [] -> Left "CSV: no header line naming the columns (e.g. time,x,y,z,qw,qx,qy,qz; separated by commas, tabs, semicolons or blanks)"
  lay0 <- layoutOf hi sep names
  let body = [ (i, s) | (i, l) <- numbered, i > hi, let s = B.strip l, not (B.null s), B.head s /= '#' ]
      (a, b, c) = clPos lay0
      (w, x, y, z) = clQuat lay0
      used = [fst (clTime lay0), a, b, c, w, x, y, z]
      need = maximum used
      row (i, l) =
        let cols = map (unquote . B.strip) (splitFields sep l)
        in if length cols < need
             then Left ("CSV line " ++ show i ++ ": expected at least " ++ show need
                        ++ " " ++ separatorName sep ++ "-separated fields (the header's columns up to the quaternion), got "
                        ++ show (length cols))
             else do
               vs <- (:) <$> field i cols (head used) <*> traverse (poseField i cols) (drop 1 used)
               case vs of
                 [t, px, py, pz, qw, qx, qy, qz] -> Right (i, t, P3 px py pz, Q4 qw qx qy qz)
                 _ -> Left "impossible"
  rows <- traverse row body
  let lay = inferTimeUnit lay0 [ t | (_, t, _, _) <- rows ]
      (ts, _, _) = clTimeUnit lay
      sp = fst (clPosUnit lay)
  pure (lay, [ Sample i (t * ts) (P3 (px * sp) (py * sp) (pz * sp)) q | (i, t, P3 px py pz, q) <- rows ])
  where
    numbered = zip [1 ..] (B.lines src)
    field i cols c = numberField "CSV" i c (cols !! (c - 1))
    poseField i cols c = head <$> poseFields "CSV" i c [cols !! (c - 1)]

-- | What a header names: the time, a position axis (0–2) or a quaternion part (w x y z: 0–3).
data Role = RTime | RPos Int | RQuat Int deriving (Eq)

-- | A header name's base (lower case, without @#@, @%@ and the unit) and its unit.
splitName :: String -> (String, String)
splitName n0 =
  let n = dropWhile (`elem` "#% ") (trim n0)
      (base, rest) = break (== '[') n
      unit = takeWhile (/= ']') (drop 1 rest)
  in (map toLower (trim base), map toLower (trim unit))
  where trim = reverse . dropWhile isSpace . reverse . dropWhile isSpace

roleOf :: String -> Maybe Role
roleOf base
  | base `elem` ["time", "timestamp", "t", "stamp", "times"] = Just RTime
  | Just k <- elemIndex base ["qw", "qx", "qy", "qz"] = Just (RQuat k)
  | Just k <- elemIndex base ["x", "y", "z"] = Just (RPos k)
  | Just k <- elemIndex base ["tx", "ty", "tz"] = Just (RPos k)
  | Just k <- elemIndex base ["px", "py", "pz"] = Just (RPos k)
  | null toks = Nothing
  | lastTok `elem` ["time", "timestamp", "stamp"] = Just RTime
  | Just k <- elemIndex lastTok ["w", "x", "y", "z"], any quatTok (init toks) = Just (RQuat k)
  | Just k <- elemIndex lastTok ["x", "y", "z"], any (`elem` ["p", "pos", "position", "t", "trans", "translation"]) (init toks) = Just (RPos k)
  | otherwise = Nothing
  where
    toks = words (map (\c -> if c `elem` "._-/ " then ' ' else c) base)
    lastTok = last toks
    quatTok t = take 1 t == "q" || t `elem` ["orientation", "rotation", "rot", "quaternion", "quat", "attitude"]

layoutOf :: Int -> Separator -> [String] -> Either String CsvLayout
layoutOf hi sep names = do
  let named = [ (c, n, base, unit, roleOf base) | (c, n) <- zip [1 :: Int ..] names, let (base, unit) = splitName n ]
      firstOf r = [ (c, n, unit) | (c, n, _, unit, Just r') <- named, r' == r ]
      -- a sensor's stamp before a receive time (ROS exports both)
      timeCols = stamps ++ firstOf RTime
      stamps = [ t | t@(_, n, _) <- firstOf RTime, "stamp" `elem` words (map (\ch -> if ch `elem` "._-/ " then ' ' else toLower ch) n) ]
      pick r = case firstOf r of (c, n, u) : _ -> Just (c, n, u); [] -> Nothing
      slots = [ ("time", case timeCols of t : _ -> Just t; [] -> Nothing) ]
              ++ [ (nm, pick (RPos k)) | (k, nm) <- zip [0 ..] ["x", "y", "z"] ]
              ++ [ (nm, pick (RQuat k)) | (k, nm) <- zip [0 ..] ["qw", "qx", "qy", "qz"] ]
      missing = [ nm | (nm, Nothing) <- slots ]
      -- two columns for one part of the pose: which one is meant cannot be guessed
      twice = [ (nm, cs) | (nm, cs) <- ("time", timeTies) : [ (nm, firstOf r) | (nm, r) <- poseRoles ], length cs > 1 ]
      timeTies = if null stamps then firstOf RTime else stamps
      poseRoles = zip ["x", "y", "z"] (map RPos [0 ..]) ++ zip ["qw", "qx", "qy", "qz"] (map RQuat [0 ..])
      quatUnits = [ (c, n, u) | (_, r) <- drop 3 poseRoles, (c, n, u) : _ <- [firstOf r], not (null u) ]
  case twice of
    (nm, cs) : _ -> Left ("CSV header (line " ++ show hi ++ "): columns " ++ intercalate " and " [ show c ++ " " ++ show n | (c, n, _) <- cs ]
                          ++ " both name " ++ nm ++ "; which one is meant? (rename or remove one)")
    [] -> Right ()
  case quatUnits of
    (c, n, u) : _ -> Left ("CSV header (line " ++ show hi ++ "), column " ++ show c ++ " " ++ show n ++ ": a quaternion part has no unit, got ["
                           ++ u ++ "] (orientation in degrees would be Euler angles, which vprof does not read)")
    [] -> Right ()
  if not (null missing)
    then Left ("CSV header (line " ++ show hi ++ ") names no column for " ++ intercalate ", " missing
               ++ "; its columns: " ++ intercalate ", " (map show names)
               ++ " (expected names such as time,x,y,z,qw,qx,qy,qz or the EuRoC #timestamp, p_RS_R_x [m], ..., q_RS_w [], ...)")
    else do
      let get nm = case lookup nm slots of Just (Just v) -> v; _ -> error "layoutOf: checked above"
          (tc, tn, tu) = get "time"
          [(xc, xn, xu), (yc, _, yu), (zc, _, zu)] = map get ["x", "y", "z"]
          [wq, xq, yq, zq] = map (\nm -> let (c, _, _) = get nm in c) ["qw", "qx", "qy", "qz"]
      tUnit <- case tu of
        "" -> Right (1, "s", False)
        u | u `elem` ["s", "sec"] -> Right (1, "s", False)
          | u == "ms" -> Right (1e-3, "ms", False)
          | u `elem` ["us", "\181s", "\956s"] -> Right (1e-6, "us", False)
          | u == "ns" -> Right (1e-9, "ns", False)
          | otherwise -> Left ("CSV header (line " ++ show hi ++ "), column " ++ show tc ++ " " ++ show tn
                               ++ ": unknown time unit [" ++ u ++ "]; expected s, ms, us or ns")
      pUnit <- if xu /= yu || xu /= zu
        then Left ("CSV header (line " ++ show hi ++ "): the position columns have different units: ["
                   ++ xu ++ "], [" ++ yu ++ "], [" ++ zu ++ "]")
        else case xu of
          u | u `elem` ["", "m"] -> Right (1, "m")
            | u == "mm" -> Right (1e-3, "mm")
            | u == "cm" -> Right (1e-2, "cm")
            | otherwise -> Left ("CSV header (line " ++ show hi ++ "), column " ++ show xc ++ " " ++ show xn
                                 ++ ": unknown position unit [" ++ u ++ "]; expected m, cm or mm")
      Right (CsvLayout hi (tc, tn) tUnit (xc, yc, zc) pUnit (wq, xq, yq, zq) (length names) sep)

-- | A time column without a unit is read in seconds, unless its median step is at least
-- 1e5 (a day between samples in seconds, 0.1 ms in nanoseconds): then in nanoseconds, as
-- EuRoC and ROS write them.
inferTimeUnit :: CsvLayout -> [Double] -> CsvLayout
inferTimeUnit l ts
  | (_, _, False) <- clTimeUnit l, unitless, not (null steps), median >= 1e5 = l { clTimeUnit = (1e-9, "ns", True) }
  | otherwise = l
  where
    unitless = null (snd (splitName (snd (clTime l))))
    steps = sort [ b - a | (a, b) <- zip ts (drop 1 ts), b > a ]
    median = steps !! (length steps `div` 2)
