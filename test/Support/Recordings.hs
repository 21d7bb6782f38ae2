-- | Where the shared recordings are: $VPROF_SHARED (the shared directory, or its data
-- directory), then ../shared/data from the project root.
module Support.Recordings
  ( dataFile
  , loadTum
  ) where

import qualified Data.ByteString.Char8 as B
import System.Directory (doesFileExist)
import System.Environment (lookupEnv)
import System.FilePath ((</>))

import VProf.Compress.Format.Tum (parseTum)
import VProf.Compress.Types

dataFile :: FilePath -> IO FilePath
dataFile name = do
  env <- lookupEnv "VPROF_SHARED"
  let candidates = maybe [] (\d -> [d </> "data" </> name, d </> name]) env
                   ++ ["../shared/data" </> name]
  found <- filterM' doesFileExist candidates
  case found of
    (f : _) -> pure f
    [] -> fail ("test data " ++ name ++ " not found; tried " ++ show candidates
                ++ " (set VPROF_SHARED to the shared directory)")
  where
    filterM' p = fmap concat . mapM (\x -> (\ok -> [x | ok]) <$> p x)

loadTum :: FilePath -> IO Recording
loadTum name = do
  f <- dataFile name
  src <- B.readFile f
  either (fail . ((f ++ ": ") ++)) (pure . Recording) (parseTum src)
