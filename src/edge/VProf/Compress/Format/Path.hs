-- | A path file as @vprof plan@ and a selection task's @path.file@ read it: RAPID (@.mod@), a
-- headed CSV (@.csv@, e.g. @time,x,y,z,qw,qx,qy,qz@) or else TUM, by its extension. Its
-- waypoints are checked as a recording's samples are (every pose given, times strictly
-- increasing, quaternions of about unit length), so that a file gets the same answer whichever
-- command reads it.
module VProf.Compress.Format.Path
  ( PathFile (..)
  , readPathFile
  , readWaypoints
  ) where

import qualified Data.ByteString.Char8 as B
import Data.Char (toLower)
import System.FilePath (takeExtension)

import VProf.Compress.Clean (Sample (..))
import VProf.Compress.Format.Common (trackFromRows)
import VProf.Compress.Format.Csv (readCsv)
import VProf.Compress.Format.Rapid (rapidTrack, readRapid)
import VProf.Compress.Format.Tum (readTum)
import VProf.Compress.Types (Track)
import VProf.Format.Text (dropBom)

-- | The waypoints as written, each with its line (for messages), and the track they make.
data PathFile = PathFile
  { pfSamples :: [Sample]
  , pfTrack :: Track
  }

-- | A path of at least two waypoints: @vprof plan@'s. An error names the file, the format and
-- the line or waypoint.
readPathFile :: FilePath -> B.ByteString -> Either String PathFile
readPathFile f bytes = prefixed f $ do
  (ss, toTrack) <- reader f bytes
  PathFile ss <$> toTrack ss

-- | The waypoints of a path file, any number of them (targets: a task may have one), each
-- checked as in 'readPathFile': a lone waypoint has no time to compare, its pose is checked
-- as any other's.
readWaypoints :: FilePath -> B.ByteString -> Either String [Sample]
readWaypoints f bytes = prefixed f $ do
  (ss, toTrack) <- reader f bytes
  ss <$ case ss of
    [] -> Right ()
    [s] -> () <$ toTrack [s, s { smTime = smTime s + 1 }]
    _ -> () <$ toTrack ss

-- | The samples of a file by its extension, and how they are checked into a track.
reader :: FilePath -> B.ByteString -> Either String ([Sample], [Sample] -> Either String Track)
reader f bytes = case map toLower (takeExtension f) of
  ".mod" -> (, rapidTrack) <$> readRapid src
  ".csv" -> (\(_, ss) -> (ss, trackFromRows "CSV")) <$> readCsv src
  _ -> (, trackFromRows "TUM") <$> readTum src
  where src = dropBom bytes

prefixed :: FilePath -> Either String a -> Either String a
prefixed f = either (Left . ((f ++ ": ") ++)) Right
