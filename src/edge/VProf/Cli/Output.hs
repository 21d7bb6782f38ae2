-- | Writing a command's output: a file or standard output that cannot be written is a bad
-- option (exit 2), said on stderr with what could not be written, never a raw exception; an
-- output that is one of the command's inputs is refused before anything runs, so that a
-- slip of the command line does not destroy a recording or a request.
module VProf.Cli.Output
  ( writing
  , overwritesInput
  ) where

import Control.Exception (IOException, try)
import Control.Monad (filterM)
import System.Directory (canonicalizePath, doesFileExist)
import System.IO (hFlush, hPutStrLn, stderr, stdout)

import VProf.Format.IOError (ioWriteReason)

-- | Run the writing action (and flush standard output, so that a full disk shows here):
-- True when it worked, else False after a message "PREFIX: cannot write WHAT: why".
writing :: String -> String -> IO () -> IO Bool
writing prefix what act = try (act >> hFlush stdout) >>= \r -> case r of
  Left (e :: IOException) -> hPutStrLn stderr (prefix ++ ": cannot write " ++ what ++ ": " ++ ioWriteReason e) >> pure False
  Right () -> pure True

-- | The first output (option, file) that is an existing input file (what, file) under
-- another or the same name (paths compared after resolving links, @.@ and @..@), as the
-- message "OPTION FILE is WHAT itself: writing there would overwrite it"; Nothing when
-- none is.
overwritesInput :: [(String, FilePath)] -> [(String, FilePath)] -> IO (Maybe String)
overwritesInput inputs outputs = do
  ins <- mapM (\(w, f) -> (,) w <$> canon f) =<< filterM (doesFileExist . snd) inputs
  outs <- mapM (\(o, f) -> (,,) o f <$> canon f) outputs
  pure $ case [ (o, f, w) | (o, f, c) <- outs, (w, ci) <- ins, c == ci ] of
    (o, f, w) : _ -> Just (o ++ " " ++ f ++ " is " ++ w ++ " itself: writing there would overwrite it; choose another file")
    [] -> Nothing
  where
    canon f = either (\(_ :: IOException) -> f) id <$> try (canonicalizePath f)
