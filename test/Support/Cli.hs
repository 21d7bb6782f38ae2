-- | Running a subcommand's parser on arguments in-process, as the executable would, and
-- reading the comma-separated lines it writes.
module Support.Cli
  ( runCommand
  , parserRefused
  , splitComma
  ) where

import Options.Applicative
import System.Exit (ExitCode (..))

-- | The exit code of a command run on these arguments; 'parserRefused' when the option
-- parser refuses them (the vprof executable exits 2 then).
runCommand :: Parser (IO ExitCode) -> [String] -> IO ExitCode
runCommand cmd args = case execParserPure defaultPrefs (info cmd forwardOptions) args of
  Success act -> act
  _ -> pure parserRefused

parserRefused :: ExitCode
parserRefused = ExitFailure 99

-- | A line's comma-separated fields, as written (no quoting).
splitComma :: String -> [String]
splitComma r = case break (== ',') r of
  (a, _ : b) -> a : splitComma b
  (a, []) -> [a]
