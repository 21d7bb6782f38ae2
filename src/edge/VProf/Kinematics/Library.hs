{-# LANGUAGE TemplateHaskell #-}
-- | The built-in robot library: the robot files of @src/robots/*.yaml@, embedded in the binary at
-- compile time and read with 'VProf.Kinematics.Format.RobotFile'.
--
-- A robot is found by its file name without @.yaml@ (@ur5@, @dobot-magician-lite@) or by the
-- name inside the file, ignoring case, spaces, dashes and underscores. Invariant: every embedded
-- file parses and validates (the test suite checks all of them); an unknown name gets an error
-- listing the known ones.
module VProf.Kinematics.Library
  ( libraryFiles
  , libraryKeys
  , libraryRobots
  , lookupRobot
  ) where

import qualified Data.ByteString as BS
import Data.Char (isAlphaNum, toLower)
import Data.FileEmbed (embedDir)
import Data.List (find, isSuffixOf, sortOn)

import VProf.Kinematics.Format.RobotFile
import VProf.Kinematics.Model

-- | (file name, contents), sorted by name.
libraryFiles :: [(FilePath, BS.ByteString)]
libraryFiles = sortOn fst [f | f@(p, _) <- $(embedDir "src/robots"), ".yaml" `isSuffixOf` p]

-- | The look-up keys: the file names without .yaml.
libraryKeys :: [String]
libraryKeys = map (stem . fst) libraryFiles

stem :: FilePath -> String
stem = reverse . drop 5 . reverse

-- | Every library robot, parsed (Left with the errors should a file be broken).
libraryRobots :: [(String, Either [String] Robot)]
libraryRobots = [(stem p, readRobotYaml bs) | (p, bs) <- libraryFiles]

norm :: String -> String
norm = map toLower . filter isAlphaNum

lookupRobot :: String -> Either String Robot
lookupRobot name =
  case find (\(k, r) -> norm k == norm name || either (const False) ((== norm name) . norm . robotName) r) libraryRobots of
    Just (k, Left es) -> Left ("library robot " ++ k ++ " is broken: " ++ unlines es)
    Just (_, Right r) -> Right r
    Nothing -> Left ("unknown robot " ++ show name ++ "; the library has: " ++ unwords libraryKeys)
