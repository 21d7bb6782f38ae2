-- | Writing a command's output: a file or standard output that cannot be written is a bad
-- option (exit 2), said on stderr with what could not be written, never a raw exception; an
-- output that is one of the command's inputs is refused before anything runs, so that a
-- slip of the command line does not destroy a recording or a request. A bad input of any kind
-- is said the same way by every command ('failIn').
module VProf.Cli.Output
  ( writing
  , overwritesInput
  , failIn
  ) where

import Control.Exception (IOException, try)
import Control.Monad (filterM)
import Data.Maybe (catMaybes, listToMaybe)
import System.Directory (canonicalizePath, doesDirectoryExist, doesFileExist)
import System.FilePath (takeDirectory)
import System.Exit (ExitCode (..))
import System.IO (hFlush, hPutStrLn, stderr, stdout)

import VProf.Format.IOError (ioWriteReason)

-- | A bad input to a command: "vprof COMMAND: message" on stderr, exit 2.
failIn :: String -> String -> IO ExitCode
failIn cmd msg = hPutStrLn stderr ("vprof " ++ cmd ++ ": " ++ msg) >> pure (ExitFailure 2)

-- | Run the writing action (and flush standard output, so that a full disk shows here):
-- True when it worked, else False after a message "PREFIX: cannot write WHAT: why".
writing :: String -> String -> IO () -> IO Bool
writing prefix what act = try (act >> hFlush stdout) >>= \r -> case r of
  Left (e :: IOException) -> hPutStrLn stderr (prefix ++ ": cannot write " ++ what ++ ": " ++ ioWriteReason e) >> pure False
  Right () -> pure True

-- | The first output (option, file) that is an existing input file (what, file) under
-- another or the same name (paths compared after resolving links, @.@ and @..@), as the
-- message "OPTION FILE is WHAT itself: writing there would overwrite it", or that is
-- another output's file ("OPTION FILE is also OPTION2's file"); Nothing when none is.
--
-- An output named by an empty string, one in a directory that does not exist and one that is
-- a directory are refused here too, before the work that would have been lost.
overwritesInput :: [(String, FilePath)] -> [(String, FilePath)] -> IO (Maybe String)
overwritesInput inputs outputs = do
  unusable <- catMaybes <$> mapM unwritable outputs
  clash <- clashes inputs outputs
  pure (listToMaybe (unusable ++ maybe [] pure clash))

-- | Why an output file cannot be written, when that is plain before writing.
unwritable :: (String, FilePath) -> IO (Maybe String)
unwritable (o, f)
  | null f = pure (Just (o ++ ": an empty file name"))
  | otherwise = do
      isDir <- doesDirectoryExist f
      let dir = takeDirectory f
      dirOk <- doesDirectoryExist dir
      pure $ if isDir then Just (o ++ " " ++ f ++ ": is a directory; give a file name")
             else if not dirOk then Just (o ++ " " ++ f ++ ": the directory " ++ dir ++ " does not exist")
             else Nothing

clashes :: [(String, FilePath)] -> [(String, FilePath)] -> IO (Maybe String)
clashes inputs outputs = do
  ins <- mapM (\(w, f) -> (,) w <$> canon f) =<< filterM (doesFileExist . snd) inputs
  outs <- mapM (\(o, f) -> (,,) o f <$> canon f) outputs
  let onInput = [ o ++ " " ++ f ++ " is " ++ w ++ " itself: writing there would overwrite it; choose another file"
                | (o, f, c) <- outs, (w, ci) <- ins, c == ci ]
      onOutput = [ o2 ++ " " ++ f2 ++ " is also " ++ o1 ++ "'s file: one would overwrite the other; choose two files"
                 | ((o1, _, c1), i) <- zip outs [0 :: Int ..], ((o2, f2, c2), j) <- zip outs [0 ..], i < j, c1 == c2 ]
  pure $ case onInput ++ onOutput of
    m : _ -> Just m
    [] -> Nothing
  where
    canon f = either (\(_ :: IOException) -> f) id <$> try (canonicalizePath f)
