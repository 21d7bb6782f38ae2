-- | The @vprof@ command line: the subcommands of every capability under one parser.
-- Exit codes: 0 ok, 1 illegal, infeasible or not converged, 2 invalid input.
module VProf.Cli
  ( main
  , cliPrefs
  , cliParser
  ) where

import Control.Exception (IOException, try)
import Options.Applicative
import System.Exit
import System.IO (hFlush, hPutStrLn, stderr, stdout)
import System.IO.Error (ioeGetFileName)

import VProf.Format.IOError (ioWriteReason)

import VProf.Cli.Compress (compressCommand)
import VProf.Cli.Kinematics (fkCommand, ikCommand, robotsCommand)
import VProf.Cli.Plan (planCommand)
import VProf.Cli.Profile (checkCommand, encodeCommand, generateOptions)
import VProf.Cli.Select (selectCommand)
import VProf.Cli.Serve (serveCommand)
import VProf.Service (service)
import VProf.Version (versionString)

main :: IO ()
main = do
  action <- customExecParser cliPrefs cliParser
  -- the commands say what they could not read or write; an output that fails where a
  -- command does not look (standard output full or closed, most often) is said here, exit
  -- 2 as a bad output, never a raw exception or a silent exit 0 (the buffer flushed at exit).
  -- A command that said so itself (exit 2) is not said again for what its buffer still holds.
  r <- try action
  case r of
    Left e -> cannotWrite e
    Right code -> try (hFlush stdout) >>= \case
      Left e | code /= ExitFailure 2 -> cannotWrite e
      _ -> exitWith code
  where
    cannotWrite (e :: IOException) = do
      let what = case ioeGetFileName e of
            Just "<stdout>" -> "standard output"
            Just f -> f
            Nothing -> "the output"
      hPutStrLn stderr ("vprof: cannot write " ++ what ++ ": " ++ ioWriteReason e)
      exitWith (ExitFailure 2)

-- | The parser's preferences. noBacktrack: an option a command does not know is reported with
-- that command's usage, not handed back to the top level, whose usage named no command.
cliPrefs :: ParserPrefs
cliPrefs = prefs (showHelpOnEmpty <> noBacktrack)

-- | Every command under one parser; a bare REQUEST is @generate@'s.
cliParser :: ParserInfo (IO ExitCode)
cliParser = info (commands <**> helper <**> versionFlag) desc
  where
    versionFlag = infoOption versionString (long "version" <> help "print the version")
    desc = fullDesc
      <> failureCode 2
      <> header "vprof - jerk-limited velocity profiles, path compression and robot kinematics for robot automation stacks"
      <> progDesc "vprof REQUEST generates a velocity profile from a ProfileRequest (.pb or .json). \
                  \Exit codes: 0 ok, 1 illegal/infeasible/not converged, 2 invalid input."
    commands = hsubparser
      ( command "generate" (info generateOptions (progDesc "Generate a velocity profile (the default command)"))
     <> command "check" (info checkCommand (progDesc "Check a profile (CSV, JSON or pb) against a request; exit 1 on any violation"))
     <> command "encode" (info encodeCommand (progDesc "Write the binary protobuf form of a (JSON) ProfileRequest"))
     <> command "compress" (info compressCommand (progDesc "Compress a recorded 6-DOF motion into a few timed straight moves"))
     <> command "robots" (info robotsCommand (progDesc "List the built-in robot library, or show one robot (library name, robot file or URDF)"))
     <> command "fk" (info fkCommand (forwardOptions <> progDesc "Forward kinematics: the tool pose, manipulability and condition number for joint values (negative values need no quoting)"))
     <> command "ik" (info ikCommand (progDesc "Inverse kinematics: joint values within the limits that reach a pose, nearest the seed first"))
     <> command "select" (info selectCommand (progDesc "Robot selection: which robots reach every target of a task in its cell, ranked, with the reason for every failure"))
     <> command "plan" (info planCommand (failureCode 2 <> progDesc "Plan a path (RAPID .mod, CSV or TUM) for a robot: a timed, checked joint trajectory; exit 1 when the plan stops"))
     <> command "serve" (info (serveCommand service) (progDesc "Serve length-delimited Request/Response messages over TCP or --stdio"))
      ) <|> generateOptions
