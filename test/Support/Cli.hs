-- | Running a subcommand's parser on arguments in-process, as the executable would, and
-- reading the comma-separated lines it writes.
module Support.Cli
  ( runCommand
  , parserRefused
  , parserMessage
  , captureStderr
  , captureHandle
  , splitComma
  ) where

import Control.Exception (finally)
import qualified Data.ByteString.Char8 as B
import GHC.IO.Handle (hDuplicate, hDuplicateTo)
import Options.Applicative
import System.Exit (ExitCode (..))
import System.IO (Handle, IOMode (..), hClose, hFlush, openFile, stderr)

-- | The exit code of a command run on these arguments; 'parserRefused' when the option
-- parser refuses them (the vprof executable exits 2 then).
runCommand :: Parser (IO ExitCode) -> [String] -> IO ExitCode
runCommand cmd args = case execParserPure defaultPrefs (info cmd forwardOptions) args of
  Success act -> act
  _ -> pure parserRefused

parserRefused :: ExitCode
parserRefused = ExitFailure 99

-- | What the option parser says when it refuses the arguments (Nothing when it takes them).
parserMessage :: Parser (IO ExitCode) -> [String] -> Maybe String
parserMessage cmd args = case execParserPure defaultPrefs (info cmd forwardOptions) args of
  Failure f -> Just (fst (renderFailure f "vprof"))
  _ -> Nothing

-- | Run an action with stderr going to a file; what it wrote there.
captureStderr :: FilePath -> IO a -> IO (a, String)
captureStderr = captureHandle stderr

-- | Run an action with a handle going to a file; what it wrote there.
captureHandle :: Handle -> FilePath -> IO a -> IO (a, String)
captureHandle hd f act = do
  old <- hDuplicate hd
  h <- openFile f WriteMode
  hDuplicateTo h hd
  r <- act `finally` (hFlush hd >> hDuplicateTo old hd >> hClose h)
  txt <- B.unpack <$> B.readFile f
  pure (r, txt)

-- | A line's comma-separated fields, as written (no quoting).
splitComma :: String -> [String]
splitComma r = case break (== ',') r of
  (a, _ : b) -> a : splitComma b
  (a, []) -> [a]
