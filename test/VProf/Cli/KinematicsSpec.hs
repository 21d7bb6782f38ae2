-- | The kinematics subcommands end to end (in process): exit codes for good input, an
-- unreachable target and bad input, for library robots, robot files and URDF; the arm's drawing.
module VProf.Cli.KinematicsSpec (spec) where

import Options.Applicative
import System.Exit (ExitCode (..))
import System.FilePath ((</>))
import System.IO.Temp (withSystemTempDirectory)
import System.IO (stdout)
import Test.Hspec

import Support.Cli (captureHandle, captureStderr, parserMessage, runCommand)

import Support.Arbitrary (shared)
import VProf.Cli.Kinematics (fkCommand, ikCommand, loadRobot, outsideLimits, robotsCommand)
import Data.List (isInfixOf)
import qualified Data.Vector.Unboxed as U
import VProf.Kinematics
import VProf.Kinematics.Library (lookupRobot)
import VProf.Plot.Robot (armPoints)
import Support.Gen (genQ)
import Test.QuickCheck (forAll, property)
import qualified Data.ByteString as B
import qualified Data.ByteString.Char8 as BC
import System.Directory (doesFileExist)

run :: Parser (IO ExitCode) -> [String] -> IO ExitCode
run = runCommand

-- | A command's exit code and what it wrote to standard output.
captured :: Parser (IO ExitCode) -> [String] -> IO (ExitCode, B.ByteString)
captured cmd args = withSystemTempDirectory "vprof-cli" $ \dir ->
  fmap BC.pack <$> captureHandle stdout (dir </> "stdout") (run cmd args)

-- | A command's exit code and what it wrote to standard error.
complaint :: Parser (IO ExitCode) -> [String] -> IO (ExitCode, String)
complaint cmd args = withSystemTempDirectory "vprof-cli" $ \dir -> captureStderr (dir </> "stderr") (run cmd args)

spec :: Spec
spec = describe "vprof robots / fk / ik" $ do
  it "lists the library and shows a robot" $ do
    run robotsCommand [] `shouldReturn` ExitSuccess
    run robotsCommand ["ur5", "--format", "json"] `shouldReturn` ExitSuccess
  it "forward kinematics: 0 for good joint values (negative ones too), 2 for a wrong count or an unknown robot; NaN and a value beyond a double (1e400) refused by the parser" $ do
    run fkCommand ["ur5", "0", "-90", "90", "0", "90", "0", "--deg"] `shouldReturn` ExitSuccess
    run fkCommand ["ur5", "0", "1"] `shouldReturn` ExitFailure 2
    run fkCommand ["no-such-robot", "0"] `shouldReturn` ExitFailure 2
    -- (99: the option parser refused it; the vprof executable exits 2)
    mapM_ (\v -> run fkCommand ["ur5", "0", "0", "0", "0", "0", v] `shouldReturn` ExitFailure 99) ["NaN", "1e400", "-1e400", "x", "0x10", "1_0"]
    -- decimals as the recordings' readers take them (.5 and +1 were refused, Haskell's 0x10 taken)
    mapM_ (\v -> run fkCommand ["ur5", "0", "0", "0", "0", "0", v] `shouldReturn` ExitSuccess) [".5", "+1", "-.5", "1e-3"]
    mapM_ (\p -> run ikCommand ["ur5", "--pose", p] `shouldReturn` ExitFailure 99) ["0.4 0.1 1e400 0 1 0 0", "0.4 0.1 0.3 0 1 0 NaN"]
  it "forward kinematics: one value an argument; an empty one (it crashed: Prelude.head) or one with a comma or several numbers is refused (\"1,5\" was read as 1, \"0.5 9\" as 0.5)" $ do
    mapM_ (\v -> run fkCommand ["ur5", v, "0", "0", "0", "0", "0"] `shouldReturn` ExitFailure 99) ["", " ", ",", "1,5", "0.5 9"]
    run fkCommand ["ur5", "0 0 0 0 0 0"] `shouldReturn` ExitFailure 99
  it "forward kinematics: a prismatic value beyond 1e9 m or a revolute one beyond a million degrees is exit 2 (1e308 m gave a NaN manipulability)" $ do
    run fkCommand ["stanford", "0.1", "0.2", "1e308", "0.3", "0.4", "0.5"] `shouldReturn` ExitFailure 2
    run fkCommand ["stanford", "0.1", "0.2", "2e9", "0.3", "0.4", "0.5"] `shouldReturn` ExitFailure 2
    run fkCommand ["ur5", "2e6", "0", "0", "0", "0", "0", "--deg"] `shouldReturn` ExitFailure 2
    run fkCommand ["stanford", "0.1", "0.2", "0.5", "0.3", "0.4", "0.5"] `shouldReturn` ExitSuccess
  it "inverse kinematics: 0 for a reachable pose, 1 beyond reach or tilted, 2 for a quaternion that is not a unit" $ do
    run ikCommand ["ur5", "--pose", "0.4 0.1 0.3 0 1 0 0"] `shouldReturn` ExitSuccess
    -- the Dobot's flange points down (a half turn about y): a level target is reachable,
    -- the upright orientation is a tilt of 180 degrees
    run ikCommand ["dobot-magician-lite", "--pose", "0.2 0.05 0.1 0 0 1 0", "--all"] `shouldReturn` ExitSuccess
    run ikCommand ["dobot-magician-lite", "--pose", "0.2 0.05 0.1 1 0 0 0"] `shouldReturn` ExitFailure 1
    run ikCommand ["ur5", "--pose", "3 0 0 1 0 0 0"] `shouldReturn` ExitFailure 1
    run ikCommand ["ur5", "--pose", "0.4 0.1 0.3 1 1 0 0"] `shouldReturn` ExitFailure 2
    run ikCommand ["ur5", "--pose", "0.4 0.1 0.3"] `shouldReturn` ExitFailure 99
    -- beyond 1e9 m is a wrong unit (its distance overflowed: "Infinity mm too far")
    mapM_ (\p -> run ikCommand ["ur5", "--pose", p] `shouldReturn` ExitFailure 2) ["1e300 0 0 1 0 0 0", "0 -2e9 0 1 0 0 0"]
  it "forward kinematics outside a joint's limits: computed, with a warning per joint in the units typed (degrees typed without --deg hinted)" $ do
    let Right ur5 = lookupRobot "ur5"
    run fkCommand ["ur5", "90", "0", "0", "0", "0", "0"] `shouldReturn` ExitSuccess
    outsideLimits False ur5 (U.fromList [90, 0, 0, 0, 0, 1e308]) `shouldSatisfy`
      (\ws -> length ws == 2 && all ("degrees need --deg" `isInfixOf`) ws && "90.0000 rad" `isInfixOf` head ws && "1.000e308 rad" `isInfixOf` last ws)
    outsideLimits True ur5 (U.fromList (map (* (pi / 180)) [400, 0, 0, 0, 0, 0])) `shouldSatisfy`
      (\ws -> length ws == 1 && "400.0000°" `isInfixOf` head ws && "360.0000°" `isInfixOf` head ws && not ("--deg" `isInfixOf` head ws))
    outsideLimits False ur5 (U.fromList [6.28, -6.28, 3, 0, 0, 0]) `shouldBe` []
  it "--branch on a robot without a six-axis closed form is a usage error (exit 2); a branch with no solution is exit 1" $ do
    run ikCommand ["franka-panda", "--pose", "0.4 0.1 0.3 0 1 0 0", "--branch", "RUN"] `shouldReturn` ExitFailure 2
    run ikCommand ["abb-irb140", "--pose", "0.515 0 0.712 0.7071068 0 0.7071068 0", "--branch", "RUF", "--format", "json"] `shouldReturn` ExitFailure 1
    run ikCommand ["abb-irb140", "--pose", "0.515 0 0.712 0.7071068 0 0.7071068 0", "--branch", "RUN"] `shouldReturn` ExitSuccess
  it "a negative or NaN clearance and a body number below 1 are refused even without --environment (were accepted)" $ do
    mapM_ (\args -> run ikCommand (["ur5", "--pose", "0.4 0.1 0.3 0 1 0 0"] ++ args) `shouldReturn` ExitFailure 99)
          -- (99: the option parser refused it; the vprof executable exits 2)
          [["--clearance", "-1"], ["--clearance", "NaN"], ["--ignore-body", "0"], ["--ignore-body", "x"]]
  it "--ignore-body must name one of the robot's bodies (the UR5's are 1 to 6): exit 2 for 7 or 99" $ do
    dir <- shared
    let cell = dir </> "data" </> "cell" </> "cell.obj"
    mapM_ (\b -> run ikCommand ["ur5", "--pose", "0.4 0.1 0.3 0 1 0 0", "--environment", cell, "--ignore-body", b] `shouldReturn` ExitFailure 2) ["7", "99"]
    run ikCommand ["ur5", "--pose", "0.4 0.1 0.3 0 1 0 0", "--ignore-body", "99"] `shouldReturn` ExitFailure 2
  it "with --deg, a joint value beyond a million degrees is named in degrees as typed (1e308 was named 'Infinity rad'), in fk, ik's --seed and robots' --q" $ do
    let wide = "1.0e308 deg: is more than 1e6 degrees (is the unit right?)"
    (c1, e1) <- complaint fkCommand ["ur5", "0", "0", "0", "0", "0", "1e308", "--deg"]
    c1 `shouldBe` ExitFailure 2
    e1 `shouldSatisfy` isInfixOf ("q[5] = " ++ wide)
    (c2, e2) <- complaint ikCommand ["ur5", "--pose", "0.4 0.1 0.3 0 1 0 0", "--seed", "0 0 0 1e308 0 0", "--deg"]
    c2 `shouldBe` ExitFailure 2
    e2 `shouldSatisfy` isInfixOf ("--seed[3] = " ++ wide)
    (c3, e3) <- withSystemTempDirectory "vprof-cli" $ \dir ->
      complaint robotsCommand ["ur5", "--plot", dir </> "a.png", "--q", "1e308 0 0 0 0 0", "--deg"]
    c3 `shouldBe` ExitFailure 2
    e3 `shouldSatisfy` isInfixOf ("--q[0] = " ++ wide)
    -- without --deg the value is in radians
    (c4, e4) <- complaint fkCommand ["ur5", "0", "0", "0", "0", "0", "1e308"]
    c4 `shouldBe` ExitFailure 2
    e4 `shouldSatisfy` isInfixOf "q[5] = 1.0e308 rad: is more than 1e6 degrees"
  it "--scale without --environment is exit 2 (it went unused); a --clearance beyond 1e9 m is refused naming its unit (1e308 was taken and printed as Infinity mm)" $ do
    run ikCommand ["ur5", "--pose", "0.4 0.1 0.3 0 1 0 0", "--scale", "0"] `shouldReturn` ExitFailure 2
    parserMessage ikCommand ["ur5", "--pose", "0.4 0.1 0.3 0 1 0 0", "--environment", "cell.obj", "--clearance", "1e308"]
      `shouldSatisfy` maybe False (isInfixOf "--clearance 1e308 m: is more than 1e9 m (is the unit right?)")
  it "--clearance or --ignore-body without --environment is exit 2 (each went unused); with it, exit 0" $ do
    run ikCommand ["ur5", "--pose", "0.4 0.1 0.3 0 1 0 0", "--clearance", "0.05"] `shouldReturn` ExitFailure 2
    run ikCommand ["ur5", "--pose", "0.4 0.1 0.3 0 1 0 0", "--ignore-body", "1"] `shouldReturn` ExitFailure 2
    dir <- shared
    let cell = dir </> "data" </> "cell" </> "cell.obj"
    run ikCommand ["ur5", "--pose", "0.4 0.1 0.3 0 1 0 0", "--environment", cell, "--clearance", "0.005", "--ignore-body", "1"] `shouldReturn` ExitSuccess
  it "--tip with a library robot is exit 2 (was ignored); --time-budget must be > 0 (0 and -5 were taken)" $ do
    run ikCommand ["ur5", "--pose", "0.4 0.1 0.3 0 1 0 0", "--tip", "nosuch"] `shouldReturn` ExitFailure 2
    run fkCommand ["ur5", "0", "0", "0", "0", "0", "0", "--tip", "tool0"] `shouldReturn` ExitFailure 2
    mapM_ (\b -> run ikCommand ["franka-panda", "--pose", "0.5 0 0.3 0 1 0 0", "--time-budget", b] `shouldReturn` ExitFailure 99) ["0", "-5", "nan"]
  it "fk --format json writes null for the condition number at a singularity (JSON has no infinity; it was the string \"+inf\")" $ do
    -- an exact singularity of the UR5 (its condition number is infinite there)
    (code, txt) <- captured fkCommand ["ur5", "0.7374101693382116", "1.450721935564376", "3.141592653589793", "2.654701702662302"
                                      , "1.4393914484395847", "2.533949979992502", "--format", "json"]
    code `shouldBe` ExitSuccess
    B.isInfixOf (BC.pack "\"condition_number\":null") txt `shouldBe` True
    B.isInfixOf (BC.pack "inf") txt `shouldBe` False
  it "ik --deg names the units of its columns: (deg, m) for an arm with a prismatic joint (it said (deg) over the Cobra's quill in m); the residual's angle in degrees" $ do
    (c1, cobra) <- captured ikCommand ["adept-cobra600", "--pose", "0.55822 0.193936 0.287 0 1 0 0", "--deg"]
    c1 `shouldBe` ExitSuccess
    BC.unpack cobra `shouldSatisfy` isInfixOf "first (deg, m)\n"
    (c2, ur5) <- captured ikCommand ["ur5", "--pose", "0.4 0.1 0.3 0 1 0 0", "--deg"]
    c2 `shouldBe` ExitSuccess
    BC.unpack ur5 `shouldSatisfy` isInfixOf " (deg)\n"
    -- the residual's angle too (it was in rad under --deg), and in rad without it
    BC.unpack ur5 `shouldSatisfy` (\t -> " deg\n" `isInfixOf` t && not (" rad\n" `isInfixOf` t))
    (_, ur5r) <- captured ikCommand ["ur5", "--pose", "0.4 0.1 0.3 0 1 0 0"]
    BC.unpack ur5r `shouldSatisfy` isInfixOf " rad\n"
  it "inverse kinematics in the work cell: 0 clear of it, 1 when every solution hits it, 2 for a bad scene or clearance" $ do
    dir <- shared
    let cell = dir </> "data" </> "cell" </> "cell.obj"
        down x = ["--pose", x ++ " 0 1 0 0", "--environment", cell]
    run ikCommand (["ur5"] ++ down "0.5 0.2 0.3") `shouldReturn` ExitSuccess
    -- the base link stands 40 mm from the table's edge: 50 mm cannot be kept unless it is ignored
    run ikCommand (["ur5"] ++ down "0.5 0.2 0.3" ++ ["--clearance", "0.05"]) `shouldReturn` ExitFailure 1
    run ikCommand (["ur5"] ++ down "0.5 0.2 0.3" ++ ["--clearance", "0.05", "--ignore-body", "1"]) `shouldReturn` ExitSuccess
    -- a target 10 cm below the table top
    run ikCommand (["ur5"] ++ down "0.5 0 -0.1") `shouldReturn` ExitFailure 1
    -- refused by the option parser (99 here; the vprof executable exits 2 on a bad option)
    run ikCommand (["ur5"] ++ down "0.5 0.2 0.3" ++ ["--clearance", "-1"]) `shouldReturn` ExitFailure 99
    run ikCommand ["ur5", "--pose", "0.5 0.2 0.3 0 1 0 0", "--environment", dir </> "no-such.obj"] `shouldReturn` ExitFailure 2
  it "reads a URDF with --tip and a robot file; a malformed file is exit code 2" $ do
    dir <- shared
    let urdf = dir </> "data" </> "urdf" </> "panda.urdf"
    Right panda <- loadRobot (Just "panda_link8") urdf
    dof panda `shouldBe` 7
    run fkCommand [urdf, "--tip", "panda_link8", "0", "0", "0", "-1.5", "0", "1.5", "0"] `shouldReturn` ExitSuccess
    run fkCommand ["src/robots/ur5.yaml", "0", "0", "0", "0", "0", "0"] `shouldReturn` ExitSuccess
    withSystemTempDirectory "vprof-kin" $ \tmp -> do
      let bad = tmp </> "bad.yaml"
      writeFile bad "name: broken\njoints: [1, 2\n"
      run fkCommand [bad, "0"] `shouldReturn` ExitFailure 2
  it "robots NAME --plot: writes a non-empty PNG (library robot, --q in degrees, URDF with --tip); refuses a wrong joint count, NaN, a missing NAME" $
    withSystemTempDirectory "vprof-plot" $ \tmp -> do
      dir <- shared
      let png = tmp </> "arm.png"
          isPng f = do
            bs <- B.readFile f
            pure (B.length bs > 1000 && B.take 8 bs == B.pack [137, 80, 78, 71, 13, 10, 26, 10])
      run robotsCommand ["ur5", "--plot", png] `shouldReturn` ExitSuccess
      isPng png `shouldReturn` True
      let png2 = tmp </> "arm-deg.png"
      run robotsCommand ["kuka-lbr-iiwa14", "--plot", png2, "--q", "10 45 0 -60 0 30 0", "--deg"] `shouldReturn` ExitSuccess
      isPng png2 `shouldReturn` True
      let png3 = tmp </> "panda.png"
      run robotsCommand [dir </> "data" </> "urdf" </> "panda.urdf", "--tip", "panda_link8", "--plot", png3] `shouldReturn` ExitSuccess
      isPng png3 `shouldReturn` True
      let bad = tmp </> "bad.png"
      run robotsCommand ["ur5", "--plot", bad, "--q", "0 1"] `shouldReturn` ExitFailure 2
      run robotsCommand ["ur5", "--plot", bad, "--q", "0 0 0 0 0 NaN"] `shouldReturn` ExitFailure 99
      run robotsCommand ["ur5", "--plot", bad, "--q", "0 0 0 0 0 1e999"] `shouldReturn` ExitFailure 99
      run robotsCommand ["no-such-robot", "--plot", bad] `shouldReturn` ExitFailure 2
      run robotsCommand ["--plot", bad] `shouldReturn` ExitFailure 2
      -- a plot in a directory that does not exist: exit 2 before the drawing (was a raw 'user error', exit 1)
      run robotsCommand ["ur5", "--plot", tmp </> "nodir" </> "arm.png"] `shouldReturn` ExitFailure 2
      -- a plot file name the tool cannot write, refused by the option parser (it wrote PNG data under .pdf and .jpg)
      mapM_ (\f -> run robotsCommand ["ur5", "--plot", tmp </> f] `shouldReturn` ExitFailure 99) ["arm.pdf", "arm.jpg", "arm"]
      run robotsCommand ["ur5", "--q", "0 0 0 0 0 0"] `shouldReturn` ExitFailure 2
      doesFileExist bad `shouldReturn` False
  it "the drawn polyline runs from the base frame's origin to the tool's, through every link frame (random q)" $ do
    let Right r = lookupRobot "ur10"
        ch = compile r
    property $ forAll (genQ ch) $ \q ->
      let (pts, tool) = armPoints ch q
          close (V3 a b c) (V3 x y z) = maximum (map abs [a - x, b - y, c - z]) < 1e-12
      in close (last pts) (translation (forward ch q)) && close (head pts) (translation (robotBase r))
           && length pts == length (linkFrames ch q) && maximum (zipWith (\x y -> abs (x - y)) (toRows tool) (toRows (forward ch q))) < 1e-12
