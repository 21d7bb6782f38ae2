-- | Small helpers shared by the recording formats: data lines, numeric fields, the
-- track they make, and one-pose-a-line output.
module VProf.Compress.Format.Common
  ( readDouble
  , trackFromRows
  , everyPose
  , dataLines
  , numberField
  , numberFields
  , poseFields
  , splitCells
  , textCells
  , filledLines
  , cellAt
  , poseColumns
  , missingToken
  , shownField
  , renderPoseLines
  , unquote
  , chooseBody
  ) where

import qualified Data.ByteString.Builder as BB
import qualified Data.ByteString.Char8 as B
import qualified Data.ByteString.Lazy as BL
import Data.Char (isSpace, toLower)
import Data.List (intercalate)
import Data.Maybe (fromMaybe)
import Numeric (showFFloat)
import qualified Data.Vector as V
import qualified Data.Vector.Unboxed as U

import VProf.Compress.Clean (Sample (..))
import qualified VProf.Format.Number as N
import VProf.Compress.Types
import VProf.Geometry.Vec

-- | The strictly valid track made of parsed data lines, for reading back a path: a pose
-- value missing ('missingToken', read as NaN) is an error naming the format and the line;
-- any other problem names the format and counts samples by data line.
trackFromRows :: String -> [Sample] -> Either String Track
trackFromRows format rows = do
  everyPose format rows
  case recordingFromArrays (U.fromList (map smTime rows)) (pfromList (map smPos rows)) (pfromList (map smRot rows)) of
    Left e -> Left (format ++ ": " ++ e ++ " (sample k is the k-th data line, counting from 0)")
    Right (Recording tr) -> Right tr

-- | An error naming the format and the line of the first sample with a missing pose value
-- (read as NaN): a path or a list of targets, unlike a recording, needs every pose.
everyPose :: String -> [Sample] -> Either String ()
everyPose format rows = case filter lacksPose rows of
  Sample l _ _ _ : _ -> Left (format ++ " line " ++ show l ++ ": a position or orientation value is missing (empty or nan); every pose of a path must be given")
  [] -> Right ()
  where
    lacksPose (Sample _ _ (P3 x y z) (Q4 w a b c)) = any isNaN [x, y, z, w, a, b, c]

-- | A decimal number (optional sign, fraction, exponent) filling the whole string (spaces
-- around it aside), rounded to the nearest double ("VProf.Format.Number"'s reader; Data.Text's
-- was off by an ulp in a tenth of the shortest-form doubles: 3.4985479464439885e-06 read as
-- 3.498547946443988e-06, 1e300 as 1.0000000000000006e300). Nothing for anything else, and for
-- nan, inf and a number beyond a double.
readDouble :: B.ByteString -> Maybe Double
readDouble s0
  -- no number is written with more digits than this (and parsing millions of them took
  -- minutes: the time grows with the square of the length)
  | B.length s0 > maxNumberLength = Nothing
  | otherwise = case N.readDouble (B.strip s0) of
      Just d | not (isNaN d || isInfinite d) -> Just d
      _ -> Nothing

maxNumberLength :: Int
maxNumberLength = 100

-- | A field as an error message shows it: at most 40 characters, then how long it was.
shownField :: B.ByteString -> String
shownField w
  | B.length w <= 40 = show (B.unpack w)
  | otherwise = show (B.unpack (B.take 40 w)) ++ "... (" ++ show (B.length w) ++ " characters)"

-- | The data lines of a file with their numbers (from 1): each line stripped and cut of
-- the leading characters @skip@ accepts; blank lines and lines starting with @#@ left out.
dataLines :: (Char -> Bool) -> B.ByteString -> [(Int, B.ByteString)]
dataLines skip src = [ (i, s) | (i, l) <- zip [1 ..] (B.lines src)
                              , let s = B.dropWhile skip (B.strip l), not (B.null s), B.head s /= '#' ]

-- | Field c of data line i as a number; an error names the format, line and column.
numberField :: String -> Int -> Int -> B.ByteString -> Either String Double
numberField format i c w = case readDouble w of
  Just d -> Right d
  Nothing -> Left (format ++ " line " ++ show i ++ ", column " ++ show c ++ ": not a number: " ++ shownField w)

-- | The fields of data line i as numbers ('numberField', columns from 1).
numberFields :: String -> Int -> [B.ByteString] -> Either String [Double]
numberFields format i = traverse (uncurry (numberField format i)) . zip [1 :: Int ..]

-- | Whether a field marks a value the tracker did not deliver: empty, or @nan@, @na@, @n/a@
-- or @null@ in any case and with any sign (what motion-capture exports, numpy, R and
-- spreadsheets write when the body was lost).
missingToken :: B.ByteString -> Bool
missingToken w =
  map toLower (B.unpack (B.dropWhile (`elem` ("+-" :: String)) (B.strip w))) `elem` ["", "nan", "na", "n/a", "null"]

-- | The pose fields of data line i (position, orientation) as numbers, a missing value
-- ('missingToken') as NaN: a sample without a pose, which "VProf.Compress.Clean" drops with
-- a warning. Anything else that is not a number is an error naming the format, line and
-- column (counted from @col0@).
poseFields :: String -> Int -> Int -> [B.ByteString] -> Either String [Double]
poseFields format i col0 = traverse (uncurry (poseField format i)) . zip [col0 ..]

poseField :: String -> Int -> Int -> B.ByteString -> Either String Double
poseField format i c w
  | missingToken w = Right (0 / 0)
  | otherwise = numberField format i c w

-- | A data row of an export split at @sep@ into cells, each stripped and without the quotes
-- around it ('unquote'), for 'cellAt'.
splitCells :: Char -> B.ByteString -> V.Vector B.ByteString
splitCells sep = V.fromList . map (unquote . B.strip) . B.split sep

-- | A header row of an export split at @sep@ as 'splitCells' does, as strings.
textCells :: Char -> B.ByteString -> [String]
textCells sep = map B.unpack . V.toList . splitCells sep

-- | The lines of a file that are not blank (where an export's first lines tell its kind).
filledLines :: B.ByteString -> [B.ByteString]
filledLines = filter (not . B.all isSpace) . B.lines

-- | Cell c (from 1) of a split row; empty past the row's end.
cellAt :: V.Vector B.ByteString -> Int -> B.ByteString
cellAt cs c = fromMaybe B.empty (cs V.!? (c - 1))

-- | The cells at columns @cols@ (from 1) of split data line i as pose fields ('poseFields':
-- a missing value as NaN, anything else that is not a number an error naming the column).
poseColumns :: String -> Int -> V.Vector B.ByteString -> [Int] -> Either String [Double]
poseColumns format i cs = traverse (\c -> poseField format i c (cellAt cs c))

-- | The body a motion-capture export's reader takes of those the file holds (each with what
-- the reader needs of it, the list not empty): the only one when none is wanted, else the one
-- of the wanted name, else the only one @alias@ matches (Nexus: a segment's name without its
-- subject; @ambiguous@ says what to give where several do). Errors name the format and list
-- the bodies by @noun@ (plural).
chooseBody :: String -> String -> (String -> String -> Bool) -> String -> Maybe String -> [(String, a)] -> Either String (String, a)
chooseBody format noun alias ambiguous want bodies = case want of
  Nothing -> case bodies of
    [b] -> Right b
    _ -> Left (format ++ ": " ++ show (length bodies) ++ " " ++ noun ++ ": " ++ listed ++ "; choose one with --rigid-body NAME")
  Just w -> case ([ b | b@(nm, _) <- bodies, nm == w ], [ b | b@(nm, _) <- bodies, alias w nm ]) of
    (b : _, _) -> Right b
    ([], [b]) -> Right b
    ([], []) -> Left ("--rigid-body " ++ show w ++ ": not in the file; its " ++ noun ++ ": " ++ listed)
    ([], _) -> Left ("--rigid-body " ++ show w ++ ": " ++ ambiguous ++ ", one of " ++ listed)
  where listed = intercalate ", " [ show nm | (nm, _) <- bodies ]

-- | A field without the double quotes a spreadsheet's export puts around it.
unquote :: B.ByteString -> B.ByteString
unquote f
  | B.length f >= 2, B.head f == '"', B.last f == '"' = B.strip (B.init (B.tail f))
  | otherwise = f

-- | Decimals that write every time of a track distinctly: 6 (1 µs), or up to 12 when
-- waypoints are closer than that (times printed alike were read back as duplicates).
timeDecimals :: U.Vector Double -> Int
timeDecimals ts = head ([ d | d <- [6 .. 12], distinct d ] ++ [12])
  where
    shown d = map (\t -> showFFloat (Just d) t "") (U.toList ts)
    distinct d = let xs = shown d in and (zipWith (/=) xs (drop 1 xs))

-- | One pose a line after a header line: the time (6 decimals, more where 'timeDecimals' needs them), then the numbers @cols@
-- makes of the position and orientation (9 decimals), separated by @sep@.
renderPoseLines :: String -> String -> (P3 -> Q4 -> [Double]) -> Track -> BL.ByteString
renderPoseLines header sep cols (Track ts ps qs) = BB.toLazyByteString $
  BB.string7 header <> BB.char7 '\n' <>
  mconcat [ line t p q | (t, p, q) <- zip3 (U.toList ts) (ptoList ps) (ptoList qs) ]
  where
    d = timeDecimals ts
    line t p q = BB.string7 (intercalate sep (showFFloat (Just d) t "" : map num (cols p q))) <> BB.char7 '\n'
    num v = showFFloat (Just 9) v ""
