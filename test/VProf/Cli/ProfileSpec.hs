-- | The velocity-profile commands end to end: generate, check and encode on files, with the
-- exit codes and messages the README promises for bad input.
module VProf.Cli.ProfileSpec (spec) where

import Control.Monad (forM_)
import qualified Data.ByteString as B
import Data.ProtocolBuffers (getField)
import Data.List (intercalate, isInfixOf)
import Options.Applicative
import System.Exit (ExitCode (..))
import System.FilePath (takeFileName, (</>))
import System.IO.Temp (withSystemTempDirectory)
import Test.Hspec

import Support.Cli (captureStderr, parserRefused, runCommand, splitComma)

import VProf.Cli.Profile (checkCommand, encodeCommand, generateOptions)
import VProf.Profile.Format.File (readRequest, readRequestWithId)
import VProf.Wire.Messages (ProfileResponseMsg (..), decodeBare)
import VProf.Profile.Format.Text (table)
import VProf.Profile.Request
import VProf.Profile.Sampled (Profile (..))
import VProf.Validation (showNumber)
import qualified Data.Vector.Unboxed as U

run :: Parser (IO ExitCode) -> [String] -> IO ExitCode
run = runCommand

simple :: FilePath
simple = "examples/simple.json"

spec :: Spec
spec = do
  describe "numbers written for people" $ do
    it "the table writes every time distinctly, whatever the time step (was 3 decimals: 0.0005 s steps repeated times)" $
      mapM_ (\h -> do
               let p = Profile h (U.fromList (replicate 40 1)) 0 0
                   ts = map (head . words) (drop 1 (lines (table p)))
               length ts `shouldBe` 40
               and (zipWith (/=) ts (drop 1 ts)) `shouldBe` True
               map read ts `shouldSatisfy` (\xs -> and [ abs (x - fromIntegral k * h) <= 1e-9 | (k, x) <- zip [0 :: Int ..] (xs :: [Double]) ]))
            [0.125, 0.004, 0.001, 0.0005, 0.00025, 1e-5, 3e-7]
    it "huge and tiny numbers in messages take an exponent (1e300 was 301 digits)" $ do
      showNumber 1e300 `shouldBe` "1.0e300"
      showNumber (-2.5e-20) `shouldBe` "-2.5e-20"
      showNumber 0.000000001 `shouldBe` "0.000000001"
      showNumber 123456.5 `shouldBe` "123456.5"
      showNumber 0 `shouldBe` "0.0"
  describe "vprof (generate)" $ do
    it "an output (-o, --plot) that is the request itself is refused (exit 2) and the request left as it was" $
      withSystemTempDirectory "vprof-gen" $ \dir -> do
        src <- B.readFile simple
        let rq = dir </> "rq.json"
        B.writeFile rq src
        run generateOptions [rq, "-o", rq] `shouldReturn` ExitFailure 2
        run generateOptions [rq, "-o", dir </> ".." </> takeFileName dir </> "rq.json"] `shouldReturn` ExitFailure 2
        B.readFile rq `shouldReturn` src
        run generateOptions [rq, "-o", dir </> "profile.csv"] `shouldReturn` ExitSuccess
    it "a request without a profile (invalid, infeasible) leaves an -o CSV or table file as it was (was emptied)" $
      withSystemTempDirectory "vprof-gen" $ \dir -> do
        let keep = dir </> "keep.csv"; bad = dir </> "bad.json"; slow = dir </> "slow.json"; tbl = dir </> "keep.txt"
        writeFile keep "t,s,v,a,j\n0,0,0,0,0\n"
        writeFile tbl "kept\n"
        writeFile bad "{\"route_length\": 0, \"speed_limits\": [{\"start_distance\": 0, \"velocity\": 4}], \"min_acceleration\": -1, \"max_acceleration\": 1, \"min_jerk\": -2, \"max_jerk\": 2}"
        writeFile slow "{\"route_length\": 10, \"speed_limits\": [{\"start_distance\": 0, \"velocity\": 4}, {\"start_distance\": 0.5, \"velocity\": 0.1}], \"min_acceleration\": -1, \"max_acceleration\": 1, \"min_jerk\": -2, \"max_jerk\": 2, \"start_velocity\": 4}"
        run generateOptions [bad, "-o", keep] `shouldReturn` ExitFailure 2
        run generateOptions [bad, "-o", tbl, "-f", "table"] `shouldReturn` ExitFailure 2
        readFile keep `shouldReturn` "t,s,v,a,j\n0,0,0,0,0\n"
        readFile tbl `shouldReturn` "kept\n"
        -- infeasible: exit 1, no profile
        run generateOptions [slow, "-o", keep] `shouldReturn` ExitFailure 1
        readFile keep `shouldReturn` "t,s,v,a,j\n0,0,0,0,0\n"
    it "-o and --plot on one file are refused (exit 2), as are an -o in a directory that does not exist and an empty -o, before any work" $
      withSystemTempDirectory "vprof-gen" $ \dir -> do
        let p = dir </> "p.svg"
        run generateOptions [simple, "-o", p, "-f", "csv", "--plot", p] `shouldReturn` ExitFailure 2
        run generateOptions [simple, "-o", dir </> "no" </> "p.csv"] `shouldReturn` ExitFailure 2
        run generateOptions [simple, "-o", ""] `shouldReturn` ExitFailure 2
        run generateOptions [simple, "-o", dir] `shouldReturn` ExitFailure 2
        run generateOptions [simple, "-o", dir </> "p.csv", "--plot", p] `shouldReturn` ExitSuccess
    it "echoes the request's request_id in a binary and a JSON profile; a request_id that is no uint64 is refused, naming it" $
      withSystemTempDirectory "vprof-gen" $ \dir -> do
        src <- readFile simple
        let rq = dir </> "rq.json"; pbOut = dir </> "p.pb"; jsOut = dir </> "p.json"
            withId v = "{\"request_id\": " ++ v ++ ", " ++ drop 1 (dropWhile (/= '{') src)
        writeFile rq (withId "\"18446744073709551615\"")
        run generateOptions [rq, "-o", pbOut] `shouldReturn` ExitSuccess
        Right m <- decodeBare <$> B.readFile pbOut
        getField (prsRequestId m) `shouldBe` Just 18446744073709551615
        run generateOptions [rq, "-o", jsOut] `shouldReturn` ExitSuccess
        js <- readFile jsOut
        js `shouldSatisfy` ("\"request_id\":\"18446744073709551615\"" `isInfixOf`)
        -- encode keeps the request's own id unless --request-id says otherwise
        run encodeCommand [rq, dir </> "rq.pb"] `shouldReturn` ExitSuccess
        fmap fst <$> readRequestWithId (dir </> "rq.pb") `shouldReturn` Right 18446744073709551615
        run encodeCommand [rq, dir </> "rq.pb", "--request-id", "7"] `shouldReturn` ExitSuccess
        fmap fst <$> readRequestWithId (dir </> "rq.pb") `shouldReturn` Right 7
        forM_ ["1.5", "-1", "{\"a\": 1}", "\"18446744073709551616\"", "1e400", "true"] $ \bad -> do
          writeFile rq (withId bad)
          readRequest rq >>= either (`shouldSatisfy` ("request_id" `isInfixOf`)) (const (expectationFailure ("request_id " ++ bad ++ " accepted")))
          run generateOptions [rq] `shouldReturn` ExitFailure 2
  describe "vprof check" $ do
    it "reads a profile CSV by its header's names; a row with another count of columns is exit 2 (a 3-column row was read), CRLF and blank lines are fine" $
      withSystemTempDirectory "vprof-check" $ \dir -> do
        let good = dir </> "good.csv"; f = dir </> "f.csv"
        run generateOptions [simple, "-o", good] `shouldReturn` ExitSuccess
        rows <- lines <$> readFile good
        writeFile f (concatMap (++ "\r\n") (take 5 rows ++ [""] ++ drop 5 rows))
        run checkCommand [simple, f] `shouldReturn` ExitSuccess
        writeFile f (unlines [ if i == (7 :: Int) then intercalate "," (take 3 (splitComma r)) else r | (i, r) <- zip [1 ..] rows ])
        run checkCommand [simple, f] `shouldReturn` ExitFailure 2
        writeFile f (unlines ("t,s,speed,a,j" : drop 1 rows))
        run checkCommand [simple, f] `shouldReturn` ExitFailure 2
    it "reads a profile CSV or JSON after a UTF-8 byte-order mark (a spreadsheet's CSV was refused, its header read as \"\\239\\187\\191t\"); a second time not after the first names both" $
      withSystemTempDirectory "vprof-check" $ \dir -> do
        let good = dir </> "good.csv"; f = dir </> "bom.csv"; js = dir </> "good.json"; fj = dir </> "bom.json"; back = dir </> "back.csv"
        run generateOptions [simple, "-o", good, "--time-budget", "30"] `shouldReturn` ExitSuccess
        run generateOptions [simple, "-o", js, "--time-budget", "30"] `shouldReturn` ExitSuccess
        B.writeFile f . (B.pack [0xEF, 0xBB, 0xBF] <>) =<< B.readFile good
        B.writeFile fj . (B.pack [0xEF, 0xBB, 0xBF] <>) =<< B.readFile js
        run checkCommand [simple, f] `shouldReturn` ExitSuccess
        run checkCommand [simple, fj] `shouldReturn` ExitSuccess
        writeFile back "t,s,v,a,j\n0,0,0,0,0\n0,0,0,0,0\n0.125,0,0,0,0\n"
        (c, e) <- captureStderr (dir </> "e.txt") (run checkCommand [simple, back])
        c `shouldBe` ExitFailure 2
        e `shouldSatisfy` isInfixOf "sample 1 is at t = 0.0 s, not after sample 0 at 0 s"
    it "a profile whose velocities are NaN is illegal (exit 1), in CSV, JSON and as a NaN time" $
      withSystemTempDirectory "vprof-check" $ \dir -> do
        let csv = dir </> "nan.csv"; js = dir </> "nan.json"; good = dir </> "good.csv"; badT = dir </> "badt.csv"
        writeFile csv "t,s,v,a,j\n0,0,NaN,0,0\n0.125,0,NaN,0,0\n"
        run checkCommand [simple, csv] `shouldReturn` ExitFailure 1
        writeFile js "{\"time\":[0,0.125],\"velocity\":[null,null]}"
        run checkCommand [simple, js] `shouldReturn` ExitFailure 1
        -- the generator's own profile is legal; one NaN time in it is not (a budget of 30 s:
        -- in a full run beside other jobs the default 1 s ran out in the seed, a stall of the
        -- test process, not of the 6 ms this request takes)
        run generateOptions [simple, "-o", good, "--time-budget", "30"] `shouldReturn` ExitSuccess
        run checkCommand [simple, good] `shouldReturn` ExitSuccess
        rows <- lines <$> readFile good
        length rows `shouldSatisfy` (> 25)
        writeFile badT (unlines [ if i == (20 :: Int) then "NaN" ++ dropWhile (/= ',') r else r | (i, r) <- zip [1 ..] rows ])
        run checkCommand [simple, badT] `shouldNotReturn` ExitSuccess
    it "refuses (exit 2) arrays of different lengths, a first time other than 0, and bytes that are no ProfileResponse" $
      withSystemTempDirectory "vprof-check" $ \dir -> do
        let js = dir </> "short.json"; shifted = dir </> "shifted.csv"; garbage = dir </> "garbage.pb"
        writeFile js "{\"time\":[0,0.125,0.25],\"velocity\":[0,0.1]}"
        run checkCommand [simple, js] `shouldReturn` ExitFailure 2
        writeFile shifted "t,s,v,a,j\n5,0,0,0,0\n5.125,0,0,0,0\n"
        run checkCommand [simple, shifted] `shouldReturn` ExitFailure 2
        B.writeFile garbage (B.pack [0xff, 0xff, 0xff])
        run checkCommand [simple, garbage] `shouldReturn` ExitFailure 2
  describe "vprof generate" $ do
    it "an unknown plot type and an output that cannot be written are bad options (exit 2)" $
      withSystemTempDirectory "vprof-gen" $ \dir -> do
        -- refused by the option parser, before any work (the executable exits 2)
        run generateOptions [simple, "--plot", dir </> "p.txt"] `shouldReturn` parserRefused
        run generateOptions [simple, "-o", dir </> "no" </> "such" </> "x.csv"] `shouldReturn` ExitFailure 2
  describe "vprof encode" $ do
    it "refuses a max_iterations beyond a uint32 (it would wrap on the wire) and a request_id beyond a uint64, and keeps one within" $
      withSystemTempDirectory "vprof-enc" $ \dir -> do
        let big = dir </> "big.json"; ok = dir </> "ok.json"; out = dir </> "out.pb"
            req it = "{\"route_length\":10,\"speed_limits\":[{\"start_distance\":0,\"velocity\":4}],\"min_acceleration\":-1,"
                     ++ "\"max_acceleration\":1,\"min_jerk\":-2,\"max_jerk\":2,\"max_iterations\":" ++ it ++ "}"
        writeFile big (req "4294967297")
        readRequest big >>= either (`shouldSatisfy` ("max_iterations" `isInfixOf`)) (const (expectationFailure "accepted"))
        run encodeCommand [big, out] `shouldReturn` ExitFailure 2
        writeFile ok (req "4294967295")
        run encodeCommand [ok, out] `shouldReturn` ExitSuccess
        Right rq <- readRequest out
        rqMaxIterations rq `shouldBe` Just 4294967295
        run encodeCommand [ok, out, "--request-id", "-3"] `shouldReturn` ExitFailure 99
        run encodeCommand [ok, out, "--request-id", "18446744073709551616"] `shouldReturn` ExitFailure 99
        run encodeCommand [ok, out, "--request-id", "18446744073709551615"] `shouldReturn` ExitSuccess
        run encodeCommand [ok, dir </> "no" </> "x.pb"] `shouldReturn` ExitFailure 2
    it "refuses to write the binary over its own JSON input (exit 2, the input unchanged)" $
      withSystemTempDirectory "vprof-enc" $ \dir -> do
        src <- B.readFile simple
        let rq = dir </> "rq.json"
        B.writeFile rq src
        run encodeCommand [rq, rq] `shouldReturn` ExitFailure 2
        run encodeCommand [rq, dir </> "." </> "rq.json"] `shouldReturn` ExitFailure 2
        B.readFile rq `shouldReturn` src
