-- | @vprof serve@'s options: every value in its range is taken as typed; one outside (a port
-- above 65535, a negative count or time, a frame limit no request fits in, a number beyond any
-- machine integer) is refused naming the option and the value, never wrapped around or taken
-- as the default.
module VProf.Cli.ServeSpec (spec) where

import Data.List (isInfixOf)
import Options.Applicative
import Test.Hspec
import Test.QuickCheck hiding (Failure, Success)

import VProf.Cli.Serve (ServeOptions (..), serveOptions)
import VProf.Server (ServerConfig (..))

parse :: [String] -> Either String ServeOptions
parse args = case execParserPure defaultPrefs (info serveOptions forwardOptions) args of
  Success o -> Right o
  Failure f -> Left (fst (renderFailure f "vprof serve"))
  CompletionInvoked _ -> Left "completion"

configOf :: [String] -> Either String ServerConfig
configOf = fmap soConfig . parse

refused :: [String] -> String -> Expectation
refused args what = case parse args of
  Left msg -> msg `shouldSatisfy` (what `isInfixOf`)
  Right o -> expectationFailure (show args ++ " taken: port " ++ show (cfgPort (soConfig o)))

spec :: Spec
spec = describe "vprof serve's options" $ do
  it "takes every port from 0 to 65535 as typed" $ property $
    forAll (choose (0, 65535)) $ \p ->
      (cfgPort <$> configOf ["--port", show p]) === Right (p :: Int)

  it "refuses a port outside 0..65535 naming it (70000 served on 4464, 65536 on a free port)" $ property $
    forAll (oneof [choose (65536, 10 ^ (30 :: Int)), choose (-(10 ^ (30 :: Int)), -1)]) $ \p ->
      case configOf ["--port=" ++ show (p :: Integer)] of
        Left msg -> counterexample msg (("--port " ++ show p ++ ": expected a TCP port") `isInfixOf` msg)
        Right c -> counterexample ("taken as " ++ show (cfgPort c)) False

  it "takes counts and times in range, 0 workers meaning the number of cores" $ do
    let Right c = configOf ["--workers", "0", "--max-frame-bytes", "64", "--idle-timeout", "0"
                           , "--grace", "0", "--max-connections", "1"]
    (cfgWorkers c, cfgMaxFrameBytes c, cfgIdleTimeout c, cfgGrace c, cfgMaxConnections c)
      `shouldBe` (0, 64, 0, 0, 1)
    let Right c' = configOf ["--workers", "1024", "--max-frame-bytes", "1073741824"
                            , "--idle-timeout", "1e6", "--grace", "3600", "--max-connections", "65536"]
    (cfgWorkers c', cfgMaxFrameBytes c', cfgIdleTimeout c', cfgGrace c', cfgMaxConnections c')
      `shouldBe` (1024, 1073741824, 1e6, 3600, 65536)

  it "refuses out-of-range counts and times naming the option and the value" $ do
    refused ["--workers=-1"] "--workers -1: expected 0 (the number of cores)"
    refused ["--workers", "1025"] "--workers 1025:"
    refused ["--max-frame-bytes", "0"] "--max-frame-bytes 0: expected a whole number of bytes from 64"
    refused ["--max-frame-bytes", "99999999999999999999999"] "--max-frame-bytes 99999999999999999999999:"
    refused ["--idle-timeout=-1"] "--idle-timeout -1 s: expected a number of seconds from 0"
    refused ["--idle-timeout", "1e300"] "--idle-timeout 1e300 s:"
    refused ["--grace=-1"] "--grace -1 s:"
    refused ["--grace", "NaN"] "--grace NaN s:"
    refused ["--max-connections", "0"] "--max-connections 0: expected a count from 1"
    refused ["--port", "7450.5"] "--port 7450.5:"
