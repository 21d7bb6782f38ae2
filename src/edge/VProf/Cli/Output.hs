-- | Writing a command's output: a file or standard output that cannot be written is a bad
-- option (exit 2), said on stderr with what could not be written, never a raw exception.
module VProf.Cli.Output
  ( writing
  ) where

import Control.Exception (IOException, try)
import System.IO (hFlush, hPutStrLn, stderr, stdout)

-- | Run the writing action (and flush standard output, so that a full disk shows here):
-- True when it worked, else False after a message "PREFIX: cannot write WHAT: why".
writing :: String -> String -> IO () -> IO Bool
writing prefix what act = try (act >> hFlush stdout) >>= \r -> case r of
  Left (e :: IOException) -> hPutStrLn stderr (prefix ++ ": cannot write " ++ what ++ ": " ++ show e) >> pure False
  Right () -> pure True
