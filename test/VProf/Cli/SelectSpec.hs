-- | The task file and @vprof select@ end to end (in process): the example task ranks the library
-- with exit 0; a task nobody can do is exit 1; a missing field, a bad number, a bad quaternion,
-- a missing mesh or path file are exit 2 with a message naming the field and the value; a path
-- written as TUM or as vprof compress's CSV becomes one target a waypoint, placed by its frame.
module VProf.Cli.SelectSpec (spec) where

import Data.List (isInfixOf)
import System.Directory (createDirectory, doesFileExist, makeAbsolute)
import System.Exit (ExitCode (..))
import System.FilePath ((</>))
import System.IO.Temp (withSystemTempDirectory)
import Test.Hspec

import Support.Cli (runCommand)

import Support.Arbitrary (shared)
import VProf.Cli.Select (selectCommand)
import VProf.Kinematics.Transform
import VProf.Select.Format.Task
import VProf.Select.Task

run :: [String] -> IO ExitCode
run = runCommand selectCommand

-- | A task file in dir with the cell given by its absolute-or-relative path and the rest as text.
writeTask :: FilePath -> String -> String -> IO FilePath
writeTask dir cell rest = do
  let f = dir </> "task.yaml"
  writeFile f ("environment:\n  - {file: " ++ show cell ++ ", scale: 1}\n" ++ rest)
  pure f

errorsOf :: FilePath -> IO [String]
errorsOf f = either id (const []) <$> readTaskFile f

spec :: Spec
spec = do
  dir <- runIO shared
  -- the task files are written in a temporary directory: the cell by its absolute path
  cell <- runIO (makeAbsolute (dir </> "data" </> "cell" </> "cell.obj"))
  describe "vprof select" $ do
    it "ranks the named robots for the example task in the cell (exit 0), JSON too, and draws the plot" $
      withSystemTempDirectory "vprof-select" $ \tmp -> do
        run ["examples/cell-task.yaml", "--robots", "ur10,ur3,dobot-magician"] `shouldReturn` ExitSuccess
        run ["examples/cell-task.yaml", "--robots", "ur10", "--format", "json", "--plot", tmp </> "s.png"] `shouldReturn` ExitSuccess
        doesFileExist (tmp </> "s.png") `shouldReturn` True
        -- a plot in a directory that does not exist: exit 2 before the selection (was a raw
        -- 'user error' after it, exit 1: "no robot reaches every target")
        run ["examples/cell-task.yaml", "--robots", "ur10", "--plot", tmp </> "nodir" </> "s.png"] `shouldReturn` ExitFailure 2
    it "is exit 1 when no robot reaches every target (a target 3 m away)" $
      withSystemTempDirectory "vprof-select" $ \tmp -> do
        f <- writeTask tmp cell "payload: 1\nclearance: 0.01\ntargets:\n  - {position: [3, 0, 0.3], rpy_deg: [180, 0, 0]}\n"
        run [f, "--robots", "ur5,abb-irb140"] `shouldReturn` ExitFailure 1
    it "is exit 2 for an unknown robot" $
      run ["examples/cell-task.yaml", "--robots", "no-such-robot"] `shouldReturn` ExitFailure 2
    it "takes a real URDF with several leaves by --tip (without it exit 2); --tip without a URDF is exit 2" $ do
      let panda = dir </> "data" </> "urdf" </> "panda.urdf"
      run ["examples/cell-task.yaml", "--robots", panda] `shouldReturn` ExitFailure 2
      run ["examples/cell-task.yaml", "--robots", "ur10," ++ panda, "--tip", "panda_hand_tcp"] `shouldReturn` ExitSuccess
      run ["examples/cell-task.yaml", "--robots", panda, "--tip", "no_such_link"] `shouldReturn` ExitFailure 2
      run ["examples/cell-task.yaml", "--robots", "ur10", "--tip", "tool0"] `shouldReturn` ExitFailure 2
  describe "bad task files: exit 2, the message names the field and the value" $ do
    let cases =
          [ ("a missing payload", "clearance: 0.01\ntargets:\n  - {position: [0.5, 0, 0.3]}\n", ["payload", "missing"])
          , ("a bad number", "payload: 1\nclearance: ten\ntargets:\n  - {position: [0.5, 0, 0.3]}\n", ["clearance", "\"ten\""])
          , ("a negative clearance", "payload: 1\nclearance: -0.02\ntargets:\n  - {position: [0.5, 0, 0.3]}\n", ["clearance", "0.02"])
          , ("a short position", "payload: 1\nclearance: 0.01\ntargets:\n  - {position: [0.5, 0]}\n", ["targets[0].position", "3 numbers"])
          , ("a quaternion that is not a unit", "payload: 1\nclearance: 0.01\ntargets:\n  - {position: [0.5, 0, 0.3], quaternion: [1, 1, 0, 0]}\n", ["targets[0].quaternion", "unit"])
          , ("no targets", "payload: 1\nclearance: 0.01\n", ["targets", "missing"])
          , ("an unknown field", "payload: 1\nclearance: 0.01\nclearence: 0.02\ntargets:\n  - {position: [0.5, 0, 0.3]}\n", ["clearence"])
          , ("a number beyond a double (read as infinity)", "payload: 1\nclearance: 0.01\ntargets:\n  - {position: [0.5, 0, 1e400]}\n", ["targets[0].position[2]", "1.0e400"])
          , ("a position beyond 1e9 m (the reach message overflowed to Infinity mm)", "payload: 1\nclearance: 0.01\ntargets:\n  - {position: [1e300, 0, 0.3]}\n", ["targets[0].position", "1.0e300", "from the origin"])
          , ("a robot base beyond 1e9 m", "payload: 1\nclearance: 0.01\nbase: {position: [0, -2e9, 0]}\ntargets:\n  - {position: [0.5, 0, 0.3]}\n", ["base.position", "from the origin"])
          , ("a roll angle beyond a million degrees (1e300 was taken: its sine is noise)", "payload: 1\nclearance: 0.01\ntargets:\n  - {position: [0.5, 0, 0.3], rpy_deg: [1e300, 0, 0]}\n", ["targets[0].rpy_deg", "degrees"])
          , ("a tool capsule radius beyond 1e9 m (1e300 read as a self-collision 24.5 mm apart)", "payload: 1\nclearance: 0.01\ntool_capsule: {a: [0, 0, -0.1], b: [0, 0, 0], radius: 1e300}\ntargets:\n  - {position: [0.5, 0, 0.3]}\n", ["tool_capsule.radius"])
          , ("a missing path file", "payload: 1\nclearance: 0.01\npath: {file: nowhere.mod}\n", ["path.file", "nowhere.mod"])
          ]
    mapM_ (\(what, body, needles) -> it what $ withSystemTempDirectory "vprof-select" $ \tmp -> do
             f <- writeTask tmp cell body
             es <- errorsOf f
             es `shouldSatisfy` (\xs -> not (null xs) && all (\n -> any (n `isInfixOf`) xs) needles)
             run [f, "--robots", "ur5"] `shouldReturn` ExitFailure 2) cases
    it "a missing mesh" $ withSystemTempDirectory "vprof-select" $ \tmp -> do
      f <- writeTask tmp (tmp </> "no-cell.obj") "payload: 1\nclearance: 0.01\ntargets:\n  - {position: [0.5, 0, 0.3]}\n"
      es <- errorsOf f
      es `shouldSatisfy` any (\e -> "environment[0].file" `isInfixOf` e && "no-cell.obj" `isInfixOf` e)
      run [f, "--robots", "ur5"] `shouldReturn` ExitFailure 2
    it "a mesh or path file that is a directory is said to be one (it was said not to exist)" $ withSystemTempDirectory "vprof-select" $ \tmp -> do
      createDirectory (tmp </> "adir.obj")
      f <- writeTask tmp (tmp </> "adir.obj") "payload: 1\nclearance: 0.01\ntargets:\n  - {position: [0.5, 0, 0.3]}\n"
      es <- errorsOf f
      es `shouldSatisfy` any (\e -> "environment[0].file" `isInfixOf` e && "is a directory, not a file" `isInfixOf` e)
      run [f, "--robots", "ur5"] `shouldReturn` ExitFailure 2
    it "a malformed path file, or one with a missing pose value, names its line" $
      mapM_ (\bad -> withSystemTempDirectory "vprof-select" $ \tmp -> do
               writeFile (tmp </> "p.txt") ("# t x y z qx qy qz qw\n0 0.5 0 0.3 0 0 0 1\n1 0.5 0.1 " ++ bad ++ " 0 0 0 1\n")
               f <- writeTask tmp cell "payload: 1\nclearance: 0.01\npath: {file: p.txt}\n"
               es <- errorsOf f
               es `shouldSatisfy` any (\e -> "line 3" `isInfixOf` e)
               run [f, "--robots", "ur5"] `shouldReturn` ExitFailure 2) ["zz", "nan"]
    it "a path file whose times go back, or with a zero quaternion, is refused as vprof plan refuses it (went on: unnoticed, or as a NaN target)" $
      mapM_ (\(rows, needle) -> withSystemTempDirectory "vprof-select" $ \tmp -> do
               writeFile (tmp </> "p.csv") (unlines ("time,x,y,z,qw,qx,qy,qz" : rows))
               f <- writeTask tmp cell "payload: 1\nclearance: 0.01\npath: {file: p.csv}\n"
               es <- errorsOf f
               es `shouldSatisfy` any (\e -> "p.csv" `isInfixOf` e && needle `isInfixOf` e)
               run [f, "--robots", "ur5"] `shouldReturn` ExitFailure 2)
            [ (["1,0.5,0,0.3,0,1,0,0", "0,0.5,0.1,0.3,0,1,0,0"], "strictly increasing")
            , (["0,0.5,0,0.3,0,0,0,0", "1,0.5,0.1,0.3,0,1,0,0"], "not a unit quaternion")
            , (["0,0.5,0,0.3,0,0,0,0"], "not a unit quaternion") ]
    it "ignore_bodies naming no body of any robot selected is exit 2 (99 was taken and left out nothing); 7, the Panda's last link, is taken with it and refused without it" $
      withSystemTempDirectory "vprof-select" $ \tmp -> do
        let body b = "payload: 1\nclearance: 0.01\nignore_bodies: [" ++ show (b :: Int) ++ "]\ntargets:\n  - {position: [0.5, 0, 0.3], rpy_deg: [180, 0, 0]}\n"
        f99 <- writeTask tmp cell (body 99)
        run [f99, "--robots", "ur5,franka-panda"] `shouldReturn` ExitFailure 2
        f7 <- writeTask tmp cell (body 7)
        run [f7, "--robots", "ur5"] `shouldReturn` ExitFailure 2
        run [f7, "--robots", "ur5,franka-panda"] `shouldNotReturn` ExitFailure 2
    it "a scene scaled beyond 1e9 m is exit 2 naming the scale (1e160 showed no clearance, 1e100 printed 100-digit distances)" $
      withSystemTempDirectory "vprof-select" $ \tmp -> do
        let f = tmp </> "task.yaml"
        writeFile f ("environment:\n  - {file: " ++ show cell ++ ", scale: 1e100}\npayload: 1\nclearance: 0.01\ntargets:\n  - {position: [0.5, 0, 0.3]}\n")
        run [f, "--robots", "ur5"] `shouldReturn` ExitFailure 2
  describe "path files as targets" $ do
    it "a quaternion off unit length is normalised with a warning naming the file and line, as vprof plan gives it (it was normalised silently)" $
      withSystemTempDirectory "vprof-select" $ \tmp -> do
        writeFile (tmp </> "p.csv") "time,x,y,z,qw,qx,qy,qz\n0,0.5,0,0.3,0,1.1,0,0\n1,0.5,0.1,0.3,0,1,0,0\n"
        f <- writeTask tmp cell "payload: 1\nclearance: 0.01\npath: {file: p.csv}\n"
        r <- readTaskFileWarned f
        case r of
          Right (_, [w]) -> w `shouldSatisfy` (\m -> "p.csv" `isInfixOf` m && "line 2" `isInfixOf` m && "normalised" `isInfixOf` m)
          other -> expectationFailure (show (fmap snd other))
        writeFile (tmp </> "p.csv") "time,x,y,z,qw,qx,qy,qz\n0,0.5,0,0.3,0,1,0,0\n1,0.5,0.1,0.3,0,1,0,0\n"
        fmap snd <$> readTaskFileWarned f `shouldReturn` Right []
    it "TUM and vprof compress's CSV: one target a waypoint, in the path's frame, every field read" $
      withSystemTempDirectory "vprof-select" $ \tmp -> do
        writeFile (tmp </> "p.txt") "# t x y z qx qy qz qw\n0 0.5 0 0.3 1 0 0 0\n1.5 0.5 0.1 0.3 1 0 0 0\n"
        writeFile (tmp </> "p.csv") "time,x,y,z,qw,qx,qy,qz\n0,0.5,0,0.3,0,1,0,0\n1.5,0.5,0.1,0.3,0,1,0,0\n2,0.4,0.1,0.3,0,1,0,0\n"
        f1 <- writeTask tmp cell "payload: 1\nclearance: 0.01\npath: {file: p.txt, follow: true, frame: {position: [0, 0, 0.1]}}\n"
        Right t1 <- readTaskFile f1
        taskPath t1 `shouldBe` True
        map (translation . tgPose) (taskTargets t1) `shouldBe` [V3 0.5 0 0.4, V3 0.5 0.1 0.4]
        map tgLabel (taskTargets t1) `shouldSatisfy` all ("line" `isInfixOf`)
        -- the quaternion (x = 1) is a half turn about x: the tool points down
        rotationAngle (compose (inverse (rotX pi)) (tgPose (head (taskTargets t1)))) `shouldSatisfy` (< 1e-9)
        f2 <- writeTask tmp cell "payload: 1\nclearance: 0.01\npath: {file: p.csv}\n"
        Right t2 <- readTaskFile f2
        length (taskTargets t2) `shouldBe` 3
        taskPath t2 `shouldBe` False
        run [f1, "--robots", "ur5"] `shouldReturn` ExitSuccess
