{-# LANGUAGE OverloadedStrings #-}
-- | The edges of @vprof plan@: RAPID speed and zone data as options, the CSV path reader
-- reading back what @vprof compress@ writes, the time budget, a URDF robot's tip and the bodies
-- left out of the scene check.
module VProf.Cli.PlanSpec (spec) where

import qualified Data.Aeson as A
import qualified Data.Aeson.KeyMap as KM
import qualified Data.ByteString.Lazy as BL
import Data.Scientific (toRealFloat)
import qualified Data.Vector as V
import Data.List (isInfixOf, isPrefixOf)
import qualified Data.Vector.Unboxed as U
import System.Directory (doesFileExist)
import System.Exit (ExitCode (..))
import System.FilePath ((</>))
import System.IO.Temp (withSystemTempDirectory)
import Test.Hspec
import Test.QuickCheck

import Support.Arbitrary (shared)
import Support.Cli (captureStderr, parserMessage, parserRefused, runCommand)
import VProf.Cli.Plan (parseSpeedData, parseZoneData, planCommand)
import VProf.Compress.Format.Csv (parseCsv, renderCsv)
import VProf.Compress.Types (Track (..), recordingFromArrays, Recording (..))
import VProf.Geometry.Vec (P3 (..), Q4 (..), pfromList, ptoList)
import VProf.Plan (Zone (..), zoneRadius)

spec :: Spec
spec = do
  dir <- runIO shared
  let run = runCommand planCommand
      urdf f = dir </> "data" </> "urdf" </> f
      cell = dir </> "data" </> "cell" </> "cell.obj"
  describe "vprof plan end to end" $ do
    it "a plan not done within --time-budget is exit 1 (the square at dt 0.25 ms takes about 45 s); a budget <= 0 or above an hour is refused" $ do
      run ["examples/plan-square.csv", "--robot", "ur5", "--dt", "0.00025", "--time-budget", "0.3"] `shouldReturn` ExitFailure 1
      mapM_ (\b -> run ["examples/plan-square.csv", "--robot", "ur5", "--time-budget", b] `shouldReturn` parserRefused) ["0", "-1", "3601", "nan"]
    it "a URDF with several leaves needs --tip (exit 2); with it the real UR5 URDF plans the square (exit 0); --tip needs a URDF" $ do
      run ["examples/plan-square.csv", "--robot", urdf "ur5_robot.urdf"] `shouldReturn` ExitFailure 2
      run ["examples/plan-square.csv", "--robot", urdf "ur5_robot.urdf", "--tip", "tool0"] `shouldReturn` ExitSuccess
      run ["examples/plan-square.csv", "--robot", urdf "ur5_robot.urdf", "--tip", "no_such_link"] `shouldReturn` ExitFailure 2
      run ["examples/plan-square.csv", "--robot", "ur5", "--tip", "tool0"] `shouldReturn` ExitFailure 2
    it "--ignore-body must name one of the robot's bodies (exit 2)" $ do
      run ["examples/plan-square.csv", "--robot", "ur5", "--environment", cell, "--ignore-body", "7"] `shouldReturn` ExitFailure 2
      run ["examples/plan-square.csv", "--robot", "ur5", "--environment", cell, "--ignore-body", "99"] `shouldReturn` ExitFailure 2
      run ["examples/plan-square.csv", "--robot", "ur5", "--ignore-body", "99"] `shouldReturn` ExitFailure 2
    it "--clearance or --ignore-body without an environment (no --environment, no task cell) is exit 2 (each went unused)" $ do
      run ["examples/plan-square.csv", "--robot", "ur5", "--clearance", "0.05"] `shouldReturn` ExitFailure 2
      run ["examples/plan-square.csv", "--robot", "ur5", "--ignore-body", "1"] `shouldReturn` ExitFailure 2
    it "an output (-o, --plot) that is the path itself is refused (exit 2) and the path left as it was; a path with a missing pose value is exit 2" $
      withSystemTempDirectory "vprof-plan" $ \tmp -> do
        src <- BL.readFile "examples/plan-square.csv"
        let p = tmp </> "square.csv"
        BL.writeFile p src
        run [p, "--robot", "ur5", "-o", p] `shouldReturn` ExitFailure 2
        run [p, "--robot", "ur5", "-o", tmp </> "." </> "square.csv"] `shouldReturn` ExitFailure 2
        BL.readFile p `shouldReturn` src
        run [p, "--robot", "ur5", "-o", tmp </> "traj.csv"] `shouldReturn` ExitSuccess
        let holed = tmp </> "holed.csv"
            ls = BL.split 10 src
        BL.writeFile holed (BL.intercalate "\n" (take 2 ls ++ ["1,nan,-0.10,0.30,0,1,0,0"] ++ drop 3 ls))
        run [holed, "--robot", "ur5"] `shouldReturn` ExitFailure 2
    it "an -o onto a file the task names (its path file) is refused (exit 2) and the file left as it was" $
      withSystemTempDirectory "vprof-plan" $ \tmp -> do
        task <- readFile "examples/freiburg-task.yaml"
        path <- BL.readFile "examples/freiburg-40.csv"
        let t = tmp </> "task.yaml"; p = tmp </> "freiburg-40.csv"
        -- the cell by its place from the temporary directory: left out, the path file is what matters
        writeFile t (unlines [ l | l <- lines task, not (any (`isPrefixOf` l) ["environment:", "  - file:", "    scale:", "    pose:", "ignore_bodies:"]) ])
        BL.writeFile p path
        run [t, "--robot", "ur10", "-o", p] `shouldReturn` ExitFailure 2
        BL.readFile p `shouldReturn` path
        run [t, "--robot", "ur10", "--format", "csv", "-o", tmp </> "traj.svg", "--plot", tmp </> "traj.svg"] `shouldReturn` ExitFailure 2
    it "a zone between 0 and 0.1 mm is refused (z0.0001 planned for 12 s, z1e-9 ran out of time); a speed too slow for the sample cap names --speed (exit 2)" $ do
      mapM_ (\z -> run ["examples/plan-square.csv", "--robot", "ur5", "--zone", z] `shouldReturn` parserRefused) ["z0.0001", "z1e-9", "z0.09"]
      run ["examples/plan-square.csv", "--robot", "ur5", "--speed", "v0.001"] `shouldReturn` ExitFailure 2
    it "--base and --tool beyond 1e9 m or a million degrees are refused (1e300 degrees was taken)" $
      mapM_ (\(o, v) -> run ["examples/plan-square.csv", "--robot", "ur5", o, v] `shouldReturn` parserRefused)
            [("--base", "0 0 0 1e300 0 0"), ("--tool", "0 0 2e9"), ("--base", "0 0 0 0 -1e7 0")]
    it "--scale without --environment is exit 2 (it went unused); a --start beyond a million degrees with --deg is named in degrees as typed (1e308 was named 'Infinity rad'); a --clearance beyond 1e9 m is refused naming its unit" $
      withSystemTempDirectory "vprof-plan" $ \tmp -> do
        run ["examples/plan-square.csv", "--robot", "ur5", "--scale", "0.001"] `shouldReturn` ExitFailure 2
        (c, e) <- captureStderr (tmp </> "e.txt") (run ["examples/plan-square.csv", "--robot", "ur5", "--deg", "--start", "0 0 0 0 0 1e308"])
        c `shouldBe` ExitFailure 2
        e `shouldSatisfy` isInfixOf "--start[5] = 1.0e308 deg: is more than 1e6 degrees (is the unit right?)"
        parserMessage planCommand ["examples/plan-square.csv", "--robot", "ur5", "--environment", cell, "--clearance", "1e308"]
          `shouldSatisfy` maybe False (isInfixOf "--clearance 1e308 m: is more than 1e9 m (is the unit right?)")
    it "--deg without --start is exit 2 naming what it needs (it was taken and went unused)" $
      withSystemTempDirectory "vprof-plan" $ \tmp -> do
        (c, e) <- captureStderr (tmp </> "e.txt") (run ["examples/plan-square.csv", "--robot", "ur5", "--deg"])
        c `shouldBe` ExitFailure 2
        e `shouldSatisfy` isInfixOf "--deg: needs --start"
    it "a path too long for the sample cap because a waypoint lies far beyond the arm's reach names that waypoint (a waypoint 1000 km away was blamed on --speed alone)" $
      withSystemTempDirectory "vprof-plan" $ \tmp -> do
        let far = tmp </> "far.csv"
        writeFile far "time,x,y,z,qw,qx,qy,qz\n0,0.4,0.1,0.3,0,1,0,0\n1,1000000,0.1,0.3,0,1,0,0\n"
        (c, e) <- captureStderr (tmp </> "e.txt") (run [far, "--robot", "ur5"])
        c `shouldBe` ExitFailure 2
        e `shouldSatisfy` (\w -> "--speed" `isInfixOf` w && "waypoint 1 is 1000000.0 m from the robot's shoulder, beyond its reach" `isInfixOf` w)
    it "--start outside a joint's limits is exit 2 (degrees typed without --deg were taken as radians, silently another branch); inside them exit 0" $ do
      run ["examples/plan-square.csv", "--robot", "ur5", "--start", "0 -90 90 -90 -90 0"] `shouldReturn` ExitFailure 2
      run ["examples/plan-square.csv", "--robot", "ur5", "--start", "100 0 0 0 0 0"] `shouldReturn` ExitFailure 2
      run ["examples/plan-square.csv", "--robot", "ur5", "--start", "0 -90 90 -90 -90 0", "--deg"] `shouldReturn` ExitSuccess
    it "--start of the wrong length is exit 2, named as typed (was in radians with --deg)" $
      run ["examples/plan-square.csv", "--robot", "ur5", "--start", "0 -90 -90 -90 90", "--deg"] `shouldReturn` ExitFailure 2
    it "examples/plan-turn.csv (two turns in place) plans from rest to rest, 0.1 m of s per rad, stopping before and after each turn; a repeated pose is exit 2" $
      withSystemTempDirectory "vprof-plan" $ \tmp -> do
        let out = tmp </> "turn.json"; p = tmp </> "repeat.csv"
        run ["examples/plan-turn.csv", "--robot", "ur5", "--format", "json", "-o", out] `shouldReturn` ExitSuccess
        Just o <- A.decode <$> BL.readFile out
        let num k = case KM.lookup k o of { Just (A.Number x) -> toRealFloat x; _ -> 0 / 0 } :: Double
            turn = 0.1 * pi / 2
        num "route_length_m" `shouldSatisfy` (\l -> abs (l - (0.4 + 2 * turn)) < 1e-9)
        case KM.lookup "stops_m" o of
          Just (A.Array xs) -> [ toRealFloat x | A.Number x <- V.toList xs ] `shouldSatisfy`
                                 (\ss -> length ss == 4 && and (zipWith (\a b -> abs (a - b) < 1e-9) ss [0.1, 0.1 + turn, 0.3 + turn, 0.3 + 2 * turn :: Double]))
          other -> expectationFailure ("stops_m: " ++ show other)
        writeFile p (unlines [ "time,x,y,z,qw,qx,qy,qz", "0,0.40,-0.10,0.30,0,1,0,0", "1,0.50,-0.10,0.30,0,1,0,0", "2,0.50,-0.10,0.30,0,1,0,0" ])
        run [p, "--robot", "ur5"] `shouldReturn` ExitFailure 2
    it "a task's path file is read as the path itself is: a zero quaternion or times that go back are exit 2 either way (through a task they went on, as NaN or unnoticed)" $
      withSystemTempDirectory "vprof-plan" $ \tmp -> do
        let task = tmp </> "task.yaml"; p = tmp </> "path.csv"
            paths = [ ["0,0.40,-0.10,0.30,0,0,0,0", "1,0.50,-0.10,0.30,0,1,0,0"]
                    , ["1,0.40,-0.10,0.30,0,1,0,0", "0,0.50,-0.10,0.30,0,1,0,0"] ]
        writeFile task (unlines ["payload: 1", "clearance: 0.01", "path:", "  file: path.csv"])
        mapM_ (\rows -> do
                writeFile p (unlines ("time,x,y,z,qw,qx,qy,qz" : rows))
                run [p, "--robot", "ur5"] `shouldReturn` ExitFailure 2
                run [task, "--robot", "ur5"] `shouldReturn` ExitFailure 2) paths
        writeFile p (unlines ["time,x,y,z,qw,qx,qy,qz", "0,0.40,-0.10,0.30,0,1,0,0", "1,0.50,-0.10,0.30,0,1,0,0"])
        run [task, "--robot", "ur5"] `shouldReturn` ExitSuccess
    it "a task's payload above the robot's rating is exit 1 (it was planned: 10000 kg on a UR5); at the rating exit 0" $
      withSystemTempDirectory "vprof-plan" $ \tmp -> do
        let task = tmp </> "task.yaml"; p = tmp </> "path.csv"
        writeFile p (unlines ["time,x,y,z,qw,qx,qy,qz", "0,0.40,-0.10,0.30,0,1,0,0", "1,0.50,-0.10,0.30,0,1,0,0"])
        writeFile task (unlines ["payload: 10000", "clearance: 0.01", "path:", "  file: path.csv"])
        run [task, "--robot", "ur5"] `shouldReturn` ExitFailure 1
        writeFile task (unlines ["payload: 5", "clearance: 0.01", "path:", "  file: path.csv"])
        run [task, "--robot", "ur5"] `shouldReturn` ExitSuccess
    it "--acceleration or --jerk too weak for --dt is exit 2 naming the option (was exit 1, 'no legal profile', under the generator's field names); just above the least, exit 0" $ do
      run ["examples/plan-square.csv", "--robot", "ur5", "--jerk", "1e-6"] `shouldReturn` ExitFailure 2
      run ["examples/plan-square.csv", "--robot", "ur5", "--acceleration", "1e-12"] `shouldReturn` ExitFailure 2
      run ["examples/plan-square.csv", "--robot", "ur5", "--jerk", "7e-4", "--dt", "0.004"] `shouldReturn` ExitSuccess
    it "an -o that cannot be written (/dev/full) is exit 2, not an exception" $ do
      full <- doesFileExist "/dev/full"
      if not full then pendingWith "no /dev/full here" else
        run ["examples/plan-square.csv", "--robot", "ur5", "-o", "/dev/full"] `shouldReturn` ExitFailure 2
  it "reads RAPID speed data vN as N mm/s and refuses anything else" $ do
    parseSpeedData "v500" `shouldBe` Right 0.5
    parseSpeedData "V7000" `shouldBe` Right 7
    mapM_ (\s -> parseSpeedData s `shouldSatisfy` either (const True) (const False)) ["500", "v0", "v-5", "vx", "z10"]
  it "reads RAPID zone data zN as N mm and fine as a stop" $ do
    fmap zoneRadius (parseZoneData "z10") `shouldBe` Right 0.01
    parseZoneData "fine" `shouldBe` Right Fine
    parseZoneData "z0" `shouldBe` Right Fine
    mapM_ (\s -> fmap zoneRadius (parseZoneData s) `shouldSatisfy` either (const True) (const False)) ["10", "z-1", "zq", "v500"]
  it "reads back the CSV it writes (times to 1 µs, positions and quaternions to 1e-9)" $
    property $ forAll (choose (2, 30)) $ \n -> forAll (vectorOf n row) $ \rows ->
      let ts = U.fromList (scanl1 (+) [ dt | (dt, _, _) <- rows ])
          Right (Recording tr) = recordingFromArrays ts (pfromList [ p | (_, p, _) <- rows ]) (pfromList [ q | (_, _, q) <- rows ])
      in case parseCsv (BL.toStrict (renderCsv tr)) of
           Left e -> counterexample e False
           Right tr' -> conjoin
             [ U.maximum (U.zipWith (\a b -> abs (a - b)) (tTime tr) (tTime tr')) <= 1e-6
             , and [ abs (a - x) <= 1e-9 && abs (b - y) <= 1e-9 && abs (c - z) <= 1e-9
                   | (P3 a b c, P3 x y z) <- zip (ptoList (tPos tr)) (ptoList (tPos tr')) ]
             , and [ maximum (zipWith (\u v -> abs (u - v)) [a, b, c, d] [w, x, y, z]) <= 1e-8
                   | (Q4 a b c d, Q4 w x y z) <- zip (ptoList (tRot tr)) (ptoList (tRot tr')) ] ]
  it "names the line and column of a bad number" $
    parseCsv (BL.toStrict "time,x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n1,0,abc,0,1,0,0,0\n")
      `shouldSatisfy` either (\e -> "line 3" `elem` [take 6 (drop i e) | i <- [0 .. length e]] ) (const False)
  where
    row = do
      dt <- choose (0.01, 2)
      p <- P3 <$> choose (-2, 2) <*> choose (-2, 2) <*> choose (-2, 2)
      (w, x, y, z) <- (,,,) <$> choose (-1, 1) <*> choose (-1, 1) <*> choose (-1, 1) <*> choose (-1, 1)
      let k = sqrt (w * w + x * x + y * y + z * z)
      pure (dt, p, if k < 0.1 then Q4 1 0 0 0 else Q4 (w / k) (x / k) (y / k) (z / k))
