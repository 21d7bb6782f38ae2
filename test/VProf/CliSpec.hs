-- | The whole command line: a mistake inside a command (an option it does not know, two options
-- that exclude each other) is reported with that command's usage, where the options it takes are
-- listed, not with the top level's, which named no command.
module VProf.CliSpec (spec) where

import Data.List (isInfixOf)
import Options.Applicative
import Test.Hspec

import VProf.Cli (cliParser, cliPrefs)

failureText :: [String] -> Maybe String
failureText args = case execParserPure cliPrefs cliParser args of
  Failure f -> Just (fst (renderFailure f "vprof"))
  _ -> Nothing

spec :: Spec
spec = describe "vprof's command line" $ do
  it "reports an unknown option with its command's usage, for every command" $
    mapM_ (\(cmd, args) -> failureText ([cmd] ++ args ++ ["--bogus"]) `shouldSatisfy`
              maybe False (\t -> "Invalid option `--bogus'" `isInfixOf` t && ("Usage: vprof " ++ cmd) `isInfixOf` t))
      [ ("generate", ["r.json"]), ("check", ["r.json", "p.csv"]), ("encode", ["r.json"])
      , ("compress", ["rec.txt"]), ("robots", []), ("ik", ["ur5"]), ("select", ["task.yaml"])
      , ("plan", ["path.csv", "--robot", "ur5"]), ("serve", []) ]
  it "reports --points with --tolerance under compress's usage, which shows they exclude each other" $
    failureText ["compress", "rec.txt", "--points", "3", "--tolerance", "5"] `shouldSatisfy`
      maybe False (\t -> "Invalid option `--tolerance'" `isInfixOf` t
                         && "[--points K | --margin M | --tolerance MM]" `isInfixOf` t)
  it "still takes a bare request as generate's, and --version at the top" $ do
    failureText ["r.json"] `shouldBe` Nothing
    failureText ["--version"] `shouldSatisfy` maybe False ("0." `isInfixOf`)
