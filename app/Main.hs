module Main where

import Options.Applicative
import System.Exit (exitWith)

import VProf.Cli.Compress (compressCommand)

-- Temporary entry point of the compress branch; the lead reconciles Main.hs.
main :: IO ()
main = do
  act <- execParser (info (commands <**> helper) (fullDesc <> progDesc "vprof: velocity profiles and path compression" <> failureCode 2))
  act >>= exitWith
  where
    commands = subparser (command "compress" (info (compressCommand <**> helper)
                 (progDesc "compress a recorded 6-DOF motion into few linear moves")))
