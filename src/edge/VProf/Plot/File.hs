-- | Which image format a plot's file name asks for, checked before any work is done: an
-- unknown extension is a bad option (exit 2), not a PNG written under another name.
module VProf.Plot.File
  ( plotPath
  , fileFormatOf
  ) where

import Data.Char (toLower)
import Data.List (intercalate)
import Graphics.Rendering.Chart.Backend.Cairo (FileFormat (..))
import System.FilePath (takeExtension)

-- | The path when its extension is one of the given ones (".png", ".svg", ".pdf"), else the
-- message for the user.
plotPath :: [String] -> FilePath -> Either String FilePath
plotPath exts path
  | map toLower (takeExtension path) `elem` exts = Right path
  | otherwise = Left ("--plot " ++ path ++ ": unknown file type " ++ show (takeExtension path)
                      ++ " (use " ++ intercalate ", " exts ++ ")")

-- | The Cairo format of a checked path: .svg, .pdf, else PNG.
fileFormatOf :: FilePath -> FileFormat
fileFormatOf path = case map toLower (takeExtension path) of
  ".svg" -> SVG
  ".pdf" -> PDF
  _ -> PNG
