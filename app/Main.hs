-- | The @vprof@ executable: a thin shell over the library's commands.
module Main (main) where

import VProf.Cli (main)
