-- | The compress subcommand end to end: files in, files out, exit codes.
module VProf.Compress.CliSpec (spec) where

import qualified Data.ByteString.Char8 as B
import Options.Applicative
import System.Exit (ExitCode (..))
import System.FilePath ((</>))
import System.IO.Temp (withSystemTempDirectory)
import Test.Hspec
import qualified Data.Vector.Unboxed as U

import VProf.Cli.Compress (compressCommand)
import VProf.Compress.Format.Rapid (parseRapid)
import VProf.Compress.Format.Tum (parseTum)
import Support.Recordings
import VProf.Compress.Types

runCli :: [String] -> IO ExitCode
runCli args = case execParserPure defaultPrefs (info compressCommand mempty) args of
  Success act -> act
  _ -> pure (ExitFailure 99)

spec :: Spec
spec = describe "vprof compress" $ do
  it "writes a RAPID module with the requested number of moves and exits 0" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      rec <- dataFile "freiburg1_xyz-groundtruth.txt"
      let out = dir </> "path.mod"
      code <- runCli [rec, "--points", "25", "-o", out]
      code `shouldBe` ExitSuccess
      src <- B.readFile out
      case parseRapid src of
        Left e -> expectationFailure e
        Right tr -> trackLength tr `shouldBe` 25
  it "writes TUM that reads back, with the recording's first and last time" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      recF <- dataFile "V101_gt.txt"
      Recording rec <- loadTum "V101_gt.txt"
      let out = dir </> "path.txt"
      runCli [recF, "--method", "rdp", "--points", "30", "-o", out] `shouldReturn` ExitSuccess
      Right tr <- parseTum <$> B.readFile out
      trackLength tr `shouldBe` 30
      abs (U.head (tTime tr) - U.head (tTime rec)) `shouldSatisfy` (< 1e-6)
  it "exits 1 when the tolerance cannot be met (and still writes the best path)" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      rec <- dataFile "freiburg1_xyz-groundtruth.txt"
      let out = dir </> "path.txt"
      runCli [rec, "--tolerance", "0.001", "-o", out] `shouldReturn` ExitFailure 1
      Right tr <- parseTum <$> B.readFile out
      trackLength tr `shouldSatisfy` (> 2)
  it "exits 2 on a file that is not a recording" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      let bad = dir </> "bad.txt"
      writeFile bad "1 2 3\n"
      runCli [bad] `shouldReturn` ExitFailure 2
  it "exits 2 on a missing file and on more points than samples" $ do
    rec <- dataFile "freiburg1_xyz-groundtruth.txt"
    runCli ["/nonexistent/recording.txt"] `shouldReturn` ExitFailure 2
    runCli [rec, "--points", "5000"] `shouldReturn` ExitFailure 2
