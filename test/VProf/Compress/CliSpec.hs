-- | The compress subcommand end to end: files in, files out, exit codes.
module VProf.Compress.CliSpec (spec) where

import qualified Data.ByteString.Char8 as B
import Control.Monad (forM_)
import Data.List (intercalate, isInfixOf, zip4)
import Options.Applicative
import System.Exit (ExitCode (..))
import System.FilePath ((</>))
import System.IO (stdout)
import System.IO.Temp (withSystemTempDirectory)
import Test.Hspec
import qualified Data.Vector.Unboxed as U

import VProf.Cli.Compress (compressCommand)
import VProf.Compress.Format.Rapid (parseRapid)
import VProf.Compress.Format.Tum (parseTum, renderTum)
import qualified Data.ByteString.Lazy as BL
import Support.Mocap (NexusFrame (..), QtmFrame (..), nexusSegmentsText, qtmText)
import Support.PathError (orientationErrorsOf, positionErrorsOf, worstPositionError)
import Support.Cli (captureHandle, captureStderr, parserMessage, splitComma)
import Support.Recordings
import VProf.Compress.Types
import VProf.Geometry.Vec (P3 (..), Q4 (..), norm, phead, ptoList, (^-^))

-- | The first 300 lines of freiburg1_xyz as rec.txt in dir.
shortRecording :: FilePath -> IO FilePath
shortRecording dir = do
  src <- B.readFile =<< dataFile "freiburg1_xyz-groundtruth.txt"
  let f = dir </> "rec.txt"
  B.writeFile f (B.unlines (take 300 (B.lines src)))
  pure f

-- | The data lines of a TUM file with their line numbers (from 1).
numbered :: B.ByteString -> [(Int, B.ByteString)]
numbered src = [ (i, l) | (i, l) <- zip [1 ..] (B.lines src), not (B.null l), B.head l /= '#' ]

runCli :: [String] -> IO ExitCode
runCli args = case execParserPure defaultPrefs (info compressCommand mempty) args of
  Success act -> act
  _ -> pure (ExitFailure 99)

-- | Run the command with @-o FILE@ (a TUM file in dir), expect exit 0, and read FILE back.
writtenTum :: FilePath -> String -> [String] -> IO Track
writtenTum dir name args = do
  let out = dir </> name
  runCli (args ++ ["-o", out]) `shouldReturn` ExitSuccess
  either (\e -> expectationFailure e >> error e) pure . parseTum =<< B.readFile out

-- | The path written as TUM from V1_01 with @--points k@ and the arguments: k waypoints, the
-- first and last at the recording's first and last time. The recording's track and the path.
v101Path :: FilePath -> String -> Int -> [String] -> IO (Track, Track)
v101Path dir name k args = do
  recF <- dataFile "V101_gt.txt"
  Recording rec <- loadTum "V101_gt.txt"
  tr <- writtenTum dir name (recF : "--points" : show k : args)
  trackLength tr `shouldBe` k
  abs (U.head (tTime tr) - U.head (tTime rec)) `shouldSatisfy` (< 1e-6)
  abs (U.last (tTime tr) - U.last (tTime rec)) `shouldSatisfy` (< 1e-6)
  pure (rec, tr)

spec :: Spec
spec = describe "vprof compress" $ do
  it "refuses counts beyond range (were wrapped around: --points 2^64+5 ran as 5; --search 2^64+5 as 5, now past the limit of 1000) and RAPID names that are not identifiers (wrote invalid RAPID)" $ do
    rec <- dataFile "freiburg1_xyz-groundtruth.txt"
    mapM_ (\args -> runCli (rec : args) `shouldReturn` ExitFailure 99)
      [ ["--points", "18446744073709551621"], ["--points", "99999999999999999999"], ["--search", "x"]
      , ["--rapid-module", "my mod"], ["--rapid-module", ""], ["--rapid-module", "A\nENDMODULE"], ["--rapid-speed", ""], ["--rapid-zone", "z 10"]
      , ["--rapid-tool", "9tool"], ["--rapid-wobj", replicate 33 'w'] ]
  it "an output it cannot write is exit 2 (was a raw exception, exit 1); a UTF-8 byte-order mark before the data is skipped (was \"not a number\")" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      rec <- dataFile "freiburg1_xyz-groundtruth.txt"
      runCli [rec, "--points", "10", "-o", dir </> "no" </> "such" </> "x.txt"] `shouldReturn` ExitFailure 2
      -- refused by the option parser (99 here; the executable exits 2)
      runCli [rec, "--points", "10", "--search", "18446744073709551621"] `shouldReturn` ExitFailure 99
      runCli [rec, "--points", "10", "--plot", dir </> "no" </> "such" </> "x.png"] `shouldReturn` ExitFailure 2
      src <- B.readFile rec
      let bom = dir </> "bom.txt"
      B.writeFile bom (B.append (B.pack "\xEF\xBB\xBF") (B.unlines (take 200 (filter (\l -> not (B.null l) && B.head l /= '#') (B.lines src)))))
      tr <- writtenTum dir "bom-out.txt" [bom, "--points", "10"]
      trackLength tr `shouldBe` 10
  it "takes a recording with tracking dropouts (pose fields nan) and says how many samples it dropped and where" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      rec <- dataFile "freiburg1_xyz-groundtruth.txt"
      src <- B.readFile rec
      let ls = take 300 (numbered src)
          lost = [(i, l) | (i, l) <- ls, i >= 104, i < 110]
          blank l = B.unwords (take 1 (B.words l) ++ replicate 7 (B.pack "nan"))
          f = dir </> "dropouts.txt"
      B.writeFile f (B.unlines [ if (i, l) `elem` lost then blank l else l | (i, l) <- ls ])
      (tr, err) <- captureStderr (dir </> "err") (writtenTum dir "out.txt" [f, "--points", "10"])
      trackLength tr `shouldBe` 10
      -- the lines of the new file: the data lines in order from 1
      let lines' = [ n | (n, (i, _)) <- zip [1 :: Int ..] ls, i >= 104, i < 110 ]
      err `shouldSatisfy` ("6 samples without a pose" `isInfixOf`)
      err `shouldSatisfy` (("at line " ++ show (head lines')) `isInfixOf`)
  it "refuses an output (-o, --plot) that is the recording itself, by any name (exit 2, the recording untouched), and --times beside a recording with times" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      f <- shortRecording dir
      before <- B.readFile f
      runCli [f, "--points", "10", "-o", f] `shouldReturn` ExitFailure 2
      runCli [f, "--points", "10", "-o", dir </> "." </> "rec.txt"] `shouldReturn` ExitFailure 2
      B.readFile f `shouldReturn` before
      (code, err) <- captureStderr (dir </> "err") (runCli [f, "--points", "10", "--times", f, "-o", dir </> "out.txt"])
      code `shouldBe` ExitFailure 2
      err `shouldSatisfy` ("only KITTI poses take a times file" `isInfixOf`)
      runCli [f, "--points", "10", "-o", dir </> "out.txt"] `shouldReturn` ExitSuccess
  it "refuses -o and --plot on one file, -o onto a KITTI recording's times file found beside it, and an -o in no directory (exit 2, before the fit)" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      f <- shortRecording dir
      runCli [f, "--points", "10", "-o", dir </> "p.svg", "--output-format", "tum", "--plot", dir </> "p.svg"] `shouldReturn` ExitFailure 2
      runCli [f, "--points", "10", "-o", dir </> "nodir" </> "p.txt"] `shouldReturn` ExitFailure 2
      runCli [f, "--points", "10", "--plot", dir </> "nodir" </> "p.svg"] `shouldReturn` ExitFailure 2
      pf <- dataFile "KITTI_00_gt.txt"
      tf <- dataFile "KITTI_00_gt_times.txt"
      poses <- B.readFile pf
      times <- B.readFile tf
      let k = dir </> "k.txt"; kt = dir </> "k_times.txt"
          kTimes = B.unlines (take 200 (B.lines times))
      B.writeFile k (B.unlines (take 200 (B.lines poses)))
      B.writeFile kt kTimes
      (code, err) <- captureStderr (dir </> "err") (runCli [k, "--points", "10", "-o", kt])
      code `shouldBe` ExitFailure 2
      err `shouldSatisfy` ("the times file itself" `isInfixOf`)
      B.readFile kt `shouldReturn` kTimes
      -- a times line out of order is named with the times file
      B.writeFile kt (B.unlines [ if i == (5 :: Int) then B.pack "0.01" else l | (i, l) <- zip [1 ..] (B.lines kTimes) ])
      (code', err') <- captureStderr (dir </> "err2") (runCli [k, "--points", "10", "-o", dir </> "out.txt"])
      code' `shouldBe` ExitFailure 2
      err' `shouldSatisfy` (("with the times of " ++ kt) `isInfixOf`)
      err' `shouldSatisfy` ("line 5" `isInfixOf`)
  it "says how a CSV without a header is read (a Polhemus log: ms and mm), and reads a tab-separated one with a header, in .csv and in .txt" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      let f = dir </> "nohdr.csv"; t = dir </> "tabs.csv"
      writeFile f (unlines [ intercalate "," (map show [10 * i, i, 0, 0, 1, 0, 0, 0 :: Double]) | i <- [0 .. 20] ])
      (code, err) <- captureStderr (dir </> "err") (runCli [f, "--points", "3", "-o", dir </> "out.txt"])
      code `shouldBe` ExitSuccess
      err `shouldSatisfy` ("no header: read as a Polhemus-style log (time in ms, position in mm" `isInfixOf`)
      -- qw before qx: read as TUM (x y z order, w last) this would be another orientation
      let tabbed = "time\tx\ty\tz\tqw\tqx\tqy\tqz\n0\t0\t0\t0\t0.6\t0.8\t0\t0\n1\t1\t0\t0\t0.6\t0.8\t0\t0\n2\t2\t0\t0\t0.6\t0.8\t0\t0\n"
      forM_ [t, dir </> "tabs.txt"] $ \g -> do
        writeFile g tabbed
        (code', err') <- captureStderr (dir </> "err2") (runCli [g, "-o", dir </> "tabs-out.csv"])
        code' `shouldBe` ExitSuccess
        err' `shouldSatisfy` ("read as CSV (tab-separated) with the header of line 1" `isInfixOf`)
        out <- readFile (dir </> "tabs-out.csv")
        let quats = [ map read (drop 4 (splitComma l)) :: [Double] | l <- drop 1 (lines out) ]
        length quats `shouldSatisfy` (>= 2)
        quats `shouldSatisfy` all (\q -> maximum (zipWith (\a b -> abs (a - b)) q [0.6, 0.8, 0, 0]) < 1e-9)
  it "refuses an --outlier-factor below 1 (it rejected 995 of 997 samples at 1e-9) and --weights beyond 10^6 (the report overflowed)" $ do
    rec <- dataFile "freiburg1_xyz-groundtruth.txt"
    mapM_ (\k -> runCli [rec, "--outlier-factor", k] `shouldReturn` ExitFailure 99) ["0.5", "1e-9", "0", "2e6"]
    mapM_ (\w -> runCli [rec, "--weights", w] `shouldReturn` ExitFailure 99) ["1e308,1,1", "1,1e7,1", "1,1,Infinity"]
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
    withSystemTempDirectory "vprof-cli" $ \dir ->
      () <$ v101Path dir "path.txt" 30 ["--method", "rdp"]
  it "reads a .csv with a header by its column names (EuRoC: ns, w first) and says so; the path is the TUM copy's" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      recF <- dataFile "V101_gt.txt"
      Recording rec <- loadTum "V101_gt.txt"
      let csv = dir </> "data.csv"
          row t (P3 x y z) (Q4 w a b c) = intercalate "," (show (round (t * 1e9) :: Integer) : map show [x, y, z, w, a, b, c])
      writeFile csv (unlines ("#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z []"
                              : [ row t p q | (t, p, q) <- zip3 (U.toList (tTime rec)) (ptoList (tPos rec)) (ptoList (tRot rec)) ]))
      (_, e) <- captureStderr (dir </> "e.txt") (writtenTum dir "fromcsv.txt" [csv, "--points", "40"])
      e `shouldSatisfy` ("note: " `isInfixOf`)
      e `shouldSatisfy` ("in ns (no unit in the header" `isInfixOf`)
      Right viaCsv <- parseTum <$> B.readFile (dir </> "fromcsv.txt")
      viaTum <- writtenTum dir "fromtum.txt" [recF, "--points", "40"]
      trackLength viaCsv `shouldBe` 40
      U.maximum (U.zipWith (\a b -> abs (a - b)) (tTime viaCsv) (tTime viaTum)) `shouldSatisfy` (< 1e-4)
      maximum (zipWith (\a b -> norm (a ^-^ b)) (ptoList (tPos viaCsv)) (ptoList (tPos viaTum))) `shouldSatisfy` (< 1e-3)
  it "reads an OptiTrack Motive export (mm, quaternion x y z w, two rigid bodies) by --rigid-body and says so; the path is the TUM copy's; a lost frame is dropped with a warning" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      recF <- dataFile "V101_gt.txt"
      Recording rec <- loadTum "V101_gt.txt"
      let mot = dir </> "take.csv"
          t0 = U.head (tTime rec)
          cells = intercalate ","
          header = [ "Format Version,1.23,Take Name,Take 1,Export Frame Rate,20,Rotation Type,Quaternion,Length Units,Millimeters,Coordinate Space,Global"
                   , ""
                   , ",Type," ++ cells (replicate 8 "Rigid Body" ++ replicate 8 "Rigid Body")
                   , ",Name," ++ cells (replicate 8 "Cup" ++ replicate 8 "Tool")
                   , ",ID," ++ cells (replicate 8 "1" ++ replicate 8 "2")
                   , ",," ++ cells (concat (replicate 2 (replicate 4 "Rotation" ++ replicate 3 "Position" ++ ["Mean Marker Error"])))
                   , "Frame,Time (Seconds)," ++ cells (concat (replicate 2 ["X", "Y", "Z", "W", "X", "Y", "Z", ""])) ]
          -- the cup is lost every tenth frame; the tool never
          cup i = if i `mod` 10 == (3 :: Int) then replicate 8 "" else ["0", "0", "0", "1", "10", "20", "30", "0.0001"]
          tool (P3 x y z) (Q4 w a b c) = map show [a, b, c, w, x * 1000, y * 1000, z * 1000] ++ ["0.0001"]
          frame i t p q = cells ([show i, show (t - t0)] ++ cup i ++ tool p q)
      writeFile mot (unlines (header ++ [ frame i t p q | (i, t, p, q) <- zip4 [0 ..] (U.toList (tTime rec)) (ptoList (tPos rec)) (ptoList (tRot rec)) ]))
      (code, e0) <- captureStderr (dir </> "e0.txt") (runCli [mot, "--points", "40"])
      code `shouldBe` ExitFailure 2
      e0 `shouldSatisfy` (\e -> "2 rigid bodies" `isInfixOf` e && "--rigid-body" `isInfixOf` e)
      (_, e) <- captureStderr (dir </> "e.txt") (writtenTum dir "frommotive.txt" [mot, "--points", "40", "--rigid-body", "Tool"])
      e `shouldSatisfy` ("note: " `isInfixOf`)
      e `shouldSatisfy` ("OptiTrack Motive export" `isInfixOf`)
      e `shouldSatisfy` ("in mm" `isInfixOf`)
      e `shouldSatisfy` (not . ("warning" `isInfixOf`))
      Right viaMotive <- parseTum <$> B.readFile (dir </> "frommotive.txt")
      viaTum <- writtenTum dir "fromtum.txt" [recF, "--points", "40"]
      trackLength viaMotive `shouldBe` 40
      U.maximum (U.zipWith (\a b -> abs (a - (b - t0))) (tTime viaMotive) (tTime viaTum)) `shouldSatisfy` (< 1e-4)
      maximum (zipWith (\a b -> norm (a ^-^ b)) (ptoList (tPos viaMotive)) (ptoList (tPos viaTum))) `shouldSatisfy` (< 1e-3)
      -- the cup, lost every tenth frame: those frames dropped, with a warning
      (_, ec) <- captureStderr (dir </> "ec.txt") (writtenTum dir "cup.txt" [mot, "--points", "10", "--rigid-body", "Cup"])
      ec `shouldSatisfy` (\w -> "warning" `isInfixOf` w && "dropped" `isInfixOf` w && "line 11" `isInfixOf` w)
  it "reads a Qualisys 6D TSV export (two bodies, CRLF, trailing tabs) and a Vicon Nexus CSV export (helical axis) by --rigid-body and says so; each path is the TUM copy's; a body's untracked frames are dropped with a warning" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      Recording rec <- loadTum "V101_gt.txt"
      let n = trackLength rec
          uniform = Track (U.generate n (\k -> fromIntegral k / 100)) (tPos rec) (tRot rec)
          tracked = zipWith Tracked (ptoList (tPos rec)) (ptoList (tRot rec))
          -- the cup is untracked (a matrix of zeros) every tenth frame
          cup = [ if i `mod` 10 == (3 :: Int) then LostZeros else Tracked (P3 0.1 0.2 0.3) (Q4 1 0 0 0) | i <- [0 .. n - 1] ]
          qtm = dir </> "take_6D.tsv"
          nexus = dir </> "trial.csv"
          tumF = dir </> "copy.txt"
      writeFile qtm (qtmText 100 True True True [("Cup", cup), ("Tool", tracked)])
      writeFile nexus (nexusSegmentsText 100 ("deg", "mm") [("Rig:Tool", zipWith (NexusTracked False) (ptoList (tPos rec)) (ptoList (tRot rec)))])
      BL.writeFile tumF (renderTum uniform)
      viaTum <- writtenTum dir "fromtum.txt" [tumF, "--points", "40"]
      let same via = do
            trackLength via `shouldBe` 40
            U.maximum (U.zipWith (\a b -> abs (a - b)) (tTime via) (tTime viaTum)) `shouldSatisfy` (< 1e-4)
            maximum (zipWith (\a b -> norm (a ^-^ b)) (ptoList (tPos via)) (ptoList (tPos viaTum))) `shouldSatisfy` (< 1e-3)
      (code, e0) <- captureStderr (dir </> "e0.txt") (runCli [qtm, "--points", "40"])
      code `shouldBe` ExitFailure 2
      e0 `shouldSatisfy` (\e -> "2 bodies" `isInfixOf` e && "--rigid-body" `isInfixOf` e)
      (viaQtm, e) <- captureStderr (dir </> "e.txt") (writtenTum dir "fromqtm.txt" [qtm, "--points", "40", "--rigid-body", "Tool"])
      e `shouldSatisfy` (\w -> "note: " `isInfixOf` w && "Qualisys 6D TSV" `isInfixOf` w && "in mm" `isInfixOf` w && not ("warning" `isInfixOf` w))
      same viaQtm
      (viaNexus, en) <- captureStderr (dir </> "en.txt") (writtenTum dir "fromnexus.txt" [nexus, "--points", "40"])
      en `shouldSatisfy` (\w -> "Vicon Nexus CSV" `isInfixOf` w && "\"Rig:Tool\"" `isInfixOf` w && not ("warning" `isInfixOf` w))
      same viaNexus
      -- the cup's untracked frames (the first on line 15): dropped, with a warning
      (_, ec) <- captureStderr (dir </> "ec.txt") (writtenTum dir "cup.txt" [qtm, "--points", "10", "--rigid-body", "Cup"])
      ec `shouldSatisfy` (\w -> "warning" `isInfixOf` w && "dropped" `isInfixOf` w && "line 15" `isInfixOf` w && "not tracked" `isInfixOf` w)
  it "a Vicon Nexus export whose frame rate is not a rate is refused naming its line and value (0, -5 and abc were read as a plain CSV without a time column; 1e308 Hz put every frame at 0 s)" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      src <- lines <$> readFile "test/data/vicon-nexus-excerpt.csv"
      forM_ ["0", "-5", "abc", "1e-308", "1e308"] $ \rate -> do
        let f = dir </> "trial.csv"
        writeFile f (unlines (take 1 src ++ [rate] ++ drop 2 src))
        (code, e) <- captureStderr (dir </> "e.txt") (runCli [f, "--points", "2"])
        code `shouldBe` ExitFailure 2
        e `shouldSatisfy` (\w -> "Vicon Nexus CSV line 2" `isInfixOf` w && ("frame rate " ++ (if rate == "abc" then show rate else rate)) `isInfixOf` w)
  it "reads KITTI poses (12 numbers a line) with the times file beside them or given by --times, and says so" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      pf <- dataFile "KITTI_00_gt.txt"
      tf <- dataFile "KITTI_00_gt_times.txt"
      (tr, e) <- captureStderr (dir </> "e.txt") (writtenTum dir "kitti.txt" [pf, "--points", "50"])
      e `shouldSatisfy` ("read as KITTI poses" `isInfixOf`)
      e `shouldSatisfy` ("KITTI_00_gt_times.txt" `isInfixOf`)
      trackLength tr `shouldBe` 50
      U.last (tTime tr) `shouldSatisfy` (\t -> abs (t - 470.5816) < 1e-6)
      -- elsewhere, without a times file beside it: exit 2 naming --times; with --times, the same path
      let copy = dir </> "00.txt"
      B.readFile pf >>= B.writeFile copy
      (c, e2) <- captureStderr (dir </> "e2.txt") (runCli [copy, "--points", "50"])
      c `shouldBe` ExitFailure 2
      e2 `shouldSatisfy` ("--times" `isInfixOf`)
      tr2 <- writtenTum dir "kitti2.txt" [copy, "--times", tf, "--points", "50"]
      tTime tr2 `shouldBe` tTime tr
  it "to a tolerance (the knot fit): exit 0, and a note when most samples become waypoints (not for a path of two)" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      -- a zigzag of 60 samples, 1 cm apart, every other one 2 mm off the line
      let rec = dir </> "zigzag.txt"
          line i = unwords (map show [fromIntegral i * 0.1 :: Double, fromIntegral i * 0.01, if even i then 0 else 0.002, 0, 0, 0, 0, 1])
      writeFile rec (unlines (map line [0 .. 59 :: Int]))
      (c1, e1) <- captureStderr (dir </> "e1.txt") (runCli [rec, "--tolerance", "0.5", "-o", dir </> "fine.txt"])
      c1 `shouldBe` ExitSuccess
      e1 `shouldSatisfy` ("of the 60 samples are waypoints: the tolerance is near the recording's noise" `isInfixOf`)
      Right fine <- parseTum <$> B.readFile (dir </> "fine.txt")
      trackLength fine `shouldSatisfy` (> 30)
      (c2, e2) <- captureStderr (dir </> "e2.txt") (runCli [rec, "--tolerance", "5", "-o", dir </> "coarse.txt"])
      c2 `shouldBe` ExitSuccess
      e2 `shouldNotSatisfy` ("samples are waypoints" `isInfixOf`)
      Right coarse <- parseTum <$> B.readFile (dir </> "coarse.txt")
      trackLength coarse `shouldBe` 2
  it "exits 1 when the thesis method cannot meet the tolerance (and still writes the best path)" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      rec <- dataFile "freiburg1_xyz-groundtruth.txt"
      let out = dir </> "path.txt"
      (c, e) <- captureStderr (dir </> "e.txt") (runCli [rec, "--method", "thesis", "--tolerance", "0.001", "-o", out])
      c `shouldBe` ExitFailure 1
      -- what was reached and what to do instead
      e `shouldSatisfy` (\m -> all (`isInfixOf` m) ["tolerance not met: largest position error 0.8244 mm with 450 points", "--points N"])
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
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      (c, e) <- captureStderr (dir </> "e.txt") (runCli [rec, "--points", "5000"])
      c `shouldBe` ExitFailure 2
      -- a whole number, as typed
      e `shouldSatisfy` ("--points = 5000: must be between 2 and the number of samples, 3000" `isInfixOf`)
  it "--search: exits 2 naming --search with the thesis method; past 1000 rounds refused naming the value typed" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      rec <- dataFile "freiburg1_xyz-groundtruth.txt"
      (c1, e1) <- captureStderr (dir </> "e1.txt") (runCli [rec, "--points", "25", "--method", "thesis", "--search", "2"])
      c1 `shouldBe` ExitFailure 2
      e1 `shouldSatisfy` ("--search" `isInfixOf`)
      -- refused by the option parser, naming the value as typed (5000 was named 1001)
      forM_ ["1001", "5000", "99999999999999999999"] $ \n ->
        parserMessage compressCommand [rec, "--points", "25", "--search", n]
          `shouldSatisfy` maybe False (isInfixOf ("--search " ++ n ++ ": expected a whole number from 0 to 1000"))
  it "--ends free: the first and last waypoint fitted (not the first and last sample) at their times; refused with rdp and for an unknown word" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      recF <- dataFile "V101_gt.txt"
      (rec, tr) <- v101Path dir "path.txt" 14 ["--ends", "free"]
      -- V1_01's first waypoint moves by centimetres when fitted (it is not the first sample)
      norm (phead (tPos tr) ^-^ phead (tPos rec)) `shouldSatisfy` (> 1e-4)
      -- the thesis method honours it too
      (_, trT) <- v101Path dir "thesis.txt" 20 ["--method", "thesis", "--ends", "free"]
      norm (phead (tPos trT) ^-^ phead (tPos rec)) `shouldSatisfy` (> 1e-4)
      (c1, e1) <- captureStderr (dir </> "e1.txt") (runCli [recF, "--points", "14", "--ends", "free", "--method", "rdp"])
      c1 `shouldBe` ExitFailure 2
      e1 `shouldSatisfy` ("--ends = free" `isInfixOf`)
      case execParserPure defaultPrefs (info compressCommand mempty) [recF, "--ends", "loose"] of
        Failure f -> fst (renderFailure f "vprof") `shouldSatisfy` ("--ends loose: expected pinned or free" `isInfixOf`)
        _ -> expectationFailure "--ends loose was accepted"
  it "--least-squares-only: a larger largest error and a larger orientation error than the default's (measured here), a lower position RMSE, and --report names it" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      (rec, plain) <- v101Path dir "plain.txt" 87 ["--least-squares-only"]
      (_, polished) <- v101Path dir "polished.txt" 87 []
      let rms xs = sqrt (sum (map (^ (2 :: Int)) xs) / fromIntegral (length xs))
      worstPositionError polished rec `shouldSatisfy` (< worstPositionError plain rec)
      rms (orientationErrorsOf polished rec) `shouldSatisfy` (< rms (orientationErrorsOf plain rec))
      rms (positionErrorsOf plain rec) `shouldSatisfy` (< rms (positionErrorsOf polished rec))
      recF <- dataFile "V101_gt.txt"
      (_, out) <- captureHandle stdout (dir </> "stdout.txt") (runCli [recF, "--points", "20", "--least-squares-only", "--report"])
      out `shouldSatisfy` (", least squares only" `isInfixOf`)
  it "--search with --report keeps the comparison column (RDP at the same points) and names the rounds" $
    withSystemTempDirectory "vprof-cli" $ \dir -> do
      rec <- dataFile "freiburg1_xyz-groundtruth.txt"
      (code, out) <- captureHandle stdout (dir </> "stdout.txt") (runCli [rec, "--points", "20", "--search", "1", "--report"])
      code `shouldBe` ExitSuccess
      out `shouldSatisfy` ("search 1 round," `isInfixOf`)
      out `shouldSatisfy` ("rdp (same points)" `isInfixOf`)

  describe "real recordings" $ do
    it "merges a duplicated timestamp with a different pose (as TUM freiburg2_desk has), exits 0 and warns with the time and lines" $
      withSystemTempDirectory "vprof-cli" $ \dir -> do
        src <- B.readFile =<< dataFile "freiburg1_xyz-groundtruth.txt"
        let ls = B.lines src
            (i, l) = numbered src !! 500
            (t : x : rest) = B.words l
            x' = maybe x (\(v, _) -> B.pack (show (fromIntegral v / 1e4 + 0.0123 :: Double))) (B.readInt (B.filter (/= '.') x))
            dupLine = B.unwords (t : x' : rest)
            dup = B.unlines (take i ls ++ [dupLine] ++ drop i ls)
            f = dir </> "dup.txt"
            out = dir </> "path.txt"
        B.writeFile f dup
        (code, err) <- captureStderr (dir </> "stderr.txt") (runCli [f, "--points", "25", "-o", out])
        code `shouldBe` ExitSuccess
        err `shouldSatisfy` ("1 time with more than one sample" `isInfixOf`)
        err `shouldSatisfy` (("t = " ++ B.unpack t ++ " s at line " ++ show i ++ ", line " ++ show (i + 1)) `isInfixOf`)
        err `shouldSatisfy` ("1 sample merged" `isInfixOf`)
        Right tr <- parseTum <$> B.readFile out
        trackLength tr `shouldBe` 25
        (code', js) <- captureHandle stdout (dir </> "stdout.txt") (runCli [f, "--points", "25", "--report-json"])
        code' `shouldBe` ExitSuccess
        js `shouldSatisfy` ("\"warnings\":[" `isInfixOf`)
        js `shouldSatisfy` ("\"kind\":\"duplicate_times\"" `isInfixOf`)
    it "with --duplicates drop also exits 0 and says it dropped" $
      withSystemTempDirectory "vprof-cli" $ \dir -> do
        src <- B.readFile =<< dataFile "freiburg1_xyz-groundtruth.txt"
        let ls = B.lines src
            (i, l) = numbered src !! 10
            f = dir </> "dup.txt"
        B.writeFile f (B.unlines (take i ls ++ [l] ++ drop i ls))
        (code, err) <- captureStderr (dir </> "stderr.txt") (runCli [f, "--points", "25", "--duplicates", "drop", "-o", dir </> "p.txt"])
        code `shouldBe` ExitSuccess
        err `shouldSatisfy` ("1 sample dropped" `isInfixOf`)
    it "refuses an unsorted recording with exit 2, naming the line and the time" $
      withSystemTempDirectory "vprof-cli" $ \dir -> do
        src <- B.readFile =<< dataFile "freiburg1_xyz-groundtruth.txt"
        let ls = B.lines src
            (i, _) = numbered src !! 200
            -- lines i and i+1 swapped: line i+1 holds the earlier sample
            swapped = take (i - 1) ls ++ [ls !! i, ls !! (i - 1)] ++ drop (i + 1) ls
            t = head (B.words (ls !! (i - 1)))
            f = dir </> "unsorted.txt"
        B.writeFile f (B.unlines swapped)
        (code, err) <- captureStderr (dir </> "stderr.txt") (runCli [f, "--points", "25"])
        code `shouldBe` ExitFailure 2
        err `shouldSatisfy` (("at line " ++ show (i + 1) ++ ":") `isInfixOf`)
        err `shouldSatisfy` (B.unpack t `isInfixOf`)
    it "accepts CRLF line ends, comments, blank lines and extra whitespace" $
      withSystemTempDirectory "vprof-cli" $ \dir -> do
        let f = dir </> "crlf.txt"
        B.writeFile f (B.pack "# a comment\r\n\r\n 1.0\t0 0 0  0 0 0 1 \r\n2.0 1 0 0 0 0 0 1\r\n# end\r\n3.0 2 1 0 0 0 0 1\r\n")
        runCli [f, "--points", "3", "-o", dir </> "p.txt"] `shouldReturn` ExitSuccess
    it "refuses an empty file and a single sample with exit 2" $
      withSystemTempDirectory "vprof-cli" $ \dir -> do
        let e = dir </> "empty.txt"
            one = dir </> "one.txt"
        B.writeFile e (B.pack "# only a comment\n")
        B.writeFile one (B.pack "1 0 0 0 0 0 0 1\n")
        (code, err) <- captureStderr (dir </> "stderr.txt") (runCli [e])
        code `shouldBe` ExitFailure 2
        err `shouldSatisfy` ("has no samples" `isInfixOf`)
        runCli [one] `shouldReturn` ExitFailure 2
    it "the thesis method on a recording a few moves fit exactly gives fewer points than asked and says so (was silent, stop ReachedPoints)" $
      withSystemTempDirectory "vprof-cli" $ \dir -> do
        let f = dir </> "still.txt"
        writeFile f (unlines [ show (fromIntegral i * 0.01 :: Double) ++ " 1 2 3 0 0 0 1" | i <- [0 .. 99 :: Int] ])
        (code, err) <- captureStderr (dir </> "stderr.txt") (runCli [f, "--points", "20", "--method", "thesis", "-o", dir </> "p.txt"])
        code `shouldBe` ExitSuccess
        err `shouldSatisfy` ("fewer than the 20 asked" `isInfixOf`)
        err `shouldSatisfy` ("FewerSuffice" `isInfixOf`)
    it "--reject-outliers removes a spike injected into the real recording and says where" $
      withSystemTempDirectory "vprof-cli" $ \dir -> do
        src <- B.readFile =<< dataFile "freiburg1_xyz-groundtruth.txt"
        let ls = B.lines src
            (i, l) = numbered src !! 1500
            (t : _ : rest) = B.words l
            f = dir </> "spike.txt"
        B.writeFile f (B.unlines (take (i - 1) ls ++ [B.unwords (t : B.pack "9.0" : rest)] ++ drop i ls))
        (code, err) <- captureStderr (dir </> "stderr.txt") (runCli [f, "--points", "25", "--reject-outliers", "-o", dir </> "p.txt"])
        code `shouldBe` ExitSuccess
        err `shouldSatisfy` (("1 outlier rejected") `isInfixOf`)
        err `shouldSatisfy` (("at line " ++ show i ++ ")") `isInfixOf`)
