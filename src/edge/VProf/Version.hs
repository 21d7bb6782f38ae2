-- | The version of vprof, from the package description (one place: @package.yaml@).
module VProf.Version
  ( versionString
  ) where

import Data.Version (showVersion)

import qualified Paths_vprof

versionString :: String
versionString = showVersion Paths_vprof.version
