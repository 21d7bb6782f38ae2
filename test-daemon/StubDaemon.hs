-- | @vprof-stub-daemon serve ...@: the real @vprof serve@ server code with the TEST
-- handler of "Support.TestHandler" (ping -> pong, profile -> an empty ProfileResponse
-- echoing request_id). For the client, interop, fuzz and load tools before the generator
-- is merged; after the merge use @vprof serve@ itself.
module Main (main) where

import Options.Applicative
import System.Exit (exitWith)

import VProf.Cli.Serve (serveCommand)
import Support.TestHandler (testHandler)

main :: IO ()
main = do
  act <- execParser $ info (hsubparser (command "serve" (info (serveCommand testHandler <**> helper)
                                          (progDesc "serve with the test handler"))) <**> helper)
                           (progDesc "vprof serve with a stub handler, for tests")
  act >>= exitWith
