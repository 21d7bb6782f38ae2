-- | Round trips and error messages of the recording/path formats.
module VProf.Compress.FormatSpec (spec) where

import Control.Monad (forM_)
import qualified Data.ByteString.Char8 as B
import qualified Data.ByteString.Lazy.Char8 as BL
import Data.Char (isSpace)
import Data.List (dropWhileEnd, intercalate, isInfixOf)
import Numeric (showFFloat)
import GHC.Float (castWord64ToDouble)
import Text.Printf (printf)
import VProf.Compress.Format.Common (readDouble)
import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import VProf.Compress
import VProf.Compress.Clean (Sample (..))
import VProf.Compress.Format.Csv
import VProf.Compress.Format.Kitti
import VProf.Compress.Format.Log
import VProf.Compress.Format.Motive
import VProf.Compress.Format.Qualisys
import VProf.Compress.Format.Vicon
import VProf.Compress.Format.Rapid
import VProf.Compress.Format.Tum
import VProf.Geometry.Quaternion (qangle, qnormalize)
import qualified VProf.Kinematics.Transform as T
import Support.Mocap
import Support.Recordings
import VProf.Geometry.Vec

genTrack :: Gen Track
genTrack = do
  n <- choose (2, 40)
  t0 <- choose (0, 2e9)
  dts <- vectorOf (n - 1) (choose (0.01, 1))
  ps <- vectorOf n (P3 <$> choose (-3, 3) <*> choose (-3, 3) <*> choose (-3, 3))
  qs <- vectorOf n (qnormalize <$> (Q4 <$> choose (0.1, 1) <*> choose (-1, 1) <*> choose (-1, 1) <*> choose (-1, 1)))
  let ts = scanl (+) t0 dts
  pure (Track (U.fromList ts) (pfromList ps) (pfromList qs))

-- | Same poses within the given tolerances (s, m, rad).
closeTo :: (Double, Double, Double) -> Track -> Track -> Property
closeTo (et, ep, eo) a b =
  counterexample (show (a, b)) $
    trackLength a === trackLength b .&&.
    conjoin [ counterexample ("pose " ++ show i) $
                abs (tTime a U.! i - tTime b U.! i) <= et
                .&&. distance (pindex (tPos a) i) (pindex (tPos b) i) <= ep
                .&&. qangle (pindex (tRot a) i) (pindex (tRot b) i) <= eo
            | i <- [0 .. trackLength a - 1] ]

-- | A Motive export of a track as the body "Tool", beside a body "Cup" and a marker, in one of
-- the two header layouts (labelled rows, as Motive 1.2x and later write them, or unlabelled),
-- positions in a random length unit, the columns of the two bodies in a random order.
data Motive = Motive Track (String, Double) Bool Bool

instance Show Motive where show = renderMotive

genMotive :: Gen Motive
genMotive = Motive <$> genTrack <*> elements [("Meters", 1), ("Centimeters", 100), ("Millimeters", 1000)] <*> arbitrary <*> arbitrary

-- | Lines before the first frame.
mHeaderLines :: Motive -> Int
mHeaderLines _ = 7

renderMotive :: Motive -> String
renderMotive (Motive (Track ts ps qs) (unit, k) labelled toolFirst) = unlines (header ++ frames)
  where
    bodies = if toolFirst then ["Tool", "Cup"] else ["Cup", "Tool"]
    label l = if labelled then l else ""
    group f = concatMap f bodies
    header =
      [ "Format Version,1.23,Take Name,Take 2026-11-30 10.00.00 AM,Capture Frame Rate,120.000000,Export Frame Rate,120.000000,Total Exported Frames,"
          ++ show (U.length ts) ++ ",Rotation Type,Quaternion,Length Units," ++ unit ++ ",Coordinate Space,Global"
      , ""
      , "," ++ label "Type" ++ "," ++ intercalate "," (group (replicate 8 . const "Rigid Body") ++ replicate 3 "Marker")
      , "," ++ label "Name" ++ "," ++ intercalate "," (group (replicate 8) ++ replicate 3 "Tool:Marker1")
      , "," ++ label "ID" ++ "," ++ intercalate "," (group (\b -> replicate 8 (if b == "Tool" then "1" else "2")) ++ replicate 3 "3")
      , ",," ++ intercalate "," (group (const (replicate 4 "Rotation" ++ replicate 3 "Position" ++ ["Mean Marker Error"])) ++ replicate 3 "Position")
      , "Frame,Time (Seconds)," ++ intercalate "," (group (const ["X", "Y", "Z", "W", "X", "Y", "Z", ""]) ++ ["X", "Y", "Z"]) ]
    frames = [ intercalate "," ([show i, num t] ++ group (pose i) ++ ["0.1", "0.2", "0.3"]) | (i, t) <- zip [0 :: Int ..] (U.toList ts) ]
    pose i b
      | b == "Tool" = let P3 x y z = pindex ps i; Q4 w a bq c = pindex qs i in map num [a, bq, c, w, x * k, y * k, z * k] ++ ["0.000120"]
      | otherwise = ["0.5", "0.5", "0.5", "0.5", "9", "9", "9", "0.000200"]
    num v = showFFloat (Just 12) v ""

-- | A Motive export with the given rigid bodies (8 columns each: rotation x y z w, position x y
-- z, marker error) and frames.
motiveText :: [String] -> String -> String -> [String] -> String
motiveText bodies unit rot frames = unlines $
  [ "Format Version,1.23,Take Name,Take 1,Rotation Type," ++ rot ++ ",Length Units," ++ unit ++ ",Coordinate Space,Global"
  , ""
  , ",Type," ++ intercalate "," (concatMap (const (replicate 8 "Rigid Body")) bodies)
  , ",Name," ++ intercalate "," (concatMap (replicate 8) bodies)
  , ",ID," ++ intercalate "," (concatMap (const (replicate 8 "1")) bodies)
  , ",," ++ intercalate "," (concatMap (const (replicate 4 "Rotation" ++ replicate 3 "Position" ++ ["Mean Marker Error"])) bodies)
  , "Frame,Time (Seconds)," ++ intercalate "," (concatMap (const ["X", "Y", "Z", "W", "X", "Y", "Z", ""]) bodies) ]
  ++ frames

-- | Samples read from an export of a track's poses at 100 frames a second: frame i at i/100 s
-- (within the given tolerance) with the track's pose i, but the lost frames', which have none.
framesRead :: Double -> Track -> [Int] -> [Sample] -> Property
framesRead et (Track _ ps qs) lost ss =
  counterexample "a lost frame read as a pose" (and [ isNaN x | (i, Sample _ _ (P3 x _ _) _) <- zip [0 ..] ss, i `elem` lost ])
  .&&. conjoin [ abs (smTime sm - fromIntegral i / 100) <= et
                 .&&. distance (smPos sm) (pindex ps i) <= 1e-8
                 .&&. qangle (smRot sm) (pindex qs i) <= 1e-7
               | (i, sm) <- zip [0 ..] ss, i `notElem` lost ]

-- | Another body or two beside "Tool" and where the tool's columns go, the header, CRLF and
-- trailing-tab choices, and the tool's lost frames with how each is written.
qtmCase :: Track -> Gen ([String], Int, Bool, Bool, Bool, [(Int, QtmFrame)])
qtmCase tr = do
  others <- elements [[], ["Cup"], ["Cup", "Lid"]]
  toolAt <- choose (0, length others)
  losses <- sublistOf [0 .. trackLength tr - 1] >>= mapM (\i -> (,) i <$> elements [LostNaN, LostEmpty, LostZeros]) . take 3
  (,,,,,) others toolAt <$> arbitrary <*> arbitrary <*> arbitrary <*> pure losses

-- | Other subjects' segments beside "Rig:Tool" and where it goes, the units, the frames whose
-- helical axis is a whole turn longer, and the tool's lost frames.
nexusCase :: Track -> Gen ([String], Int, (String, String), [Int], [Int])
nexusCase tr = do
  others <- elements [[], ["Rig:Cup"], ["Rig:Cup", "Other:Tool"]]
  toolAt <- choose (0, length others)
  units <- elements [("deg", "mm"), ("rad", "m"), ("deg", "m"), ("rad", "mm")]
  turns <- sublistOf [0 .. trackLength tr - 1]
  lostAt <- take 3 <$> sublistOf [0 .. trackLength tr - 1]
  pure (others, toolAt, units, turns, lostAt)

spec :: Spec
spec = do
  describe "TUM" $ do
    it "round trips (write then read gives the same poses)" $ property $ forAll genTrack $ \tr ->
      case parseTum (BL.toStrict (renderTum tr)) of
        Left e -> counterexample e False
        Right tr' -> closeTo (1e-6, 1e-8, 1e-8) tr tr'
    it "reads the freiburg recording (3000 samples, strictly increasing times)" $ do
      Recording tr <- loadTum "freiburg1_xyz-groundtruth.txt"
      trackLength tr `shouldBe` 3000
    it "names the line and the bad value" $ do
      let Left e = parseTum (B.pack "# c\n1 2 3 4 0 0 0 1\n2 2 3 x 0 0 0 1\n")
      e `shouldSatisfy` ("line 3" `isInfixOf`)
      e `shouldSatisfy` ("\"x\"" `isInfixOf`)
    it "rejects times that do not increase, naming the sample" $ do
      let Left e = parseTum (B.pack "1 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n")
      e `shouldSatisfy` ("sample 1" `isInfixOf`)
    it "reads samples as written with their line numbers: CRLF, comments, blank lines, tabs; duplicates and order left to the cleaning" $ do
      let Right ss = readTum (B.pack "# header\r\n\r\n2.0\t1 2 3 0 0 0 1\r\n  1.0  4 5 6   0 0 0 1 \r\n1.0 4 5 6 0 0 0 1\r\n")
      map smLoc ss `shouldBe` [3, 4, 5]
      map smTime ss `shouldBe` [2, 1, 1]
      map smPos ss `shouldBe` [P3 1 2 3, P3 4 5 6, P3 4 5 6]
      map smRot ss `shouldBe` replicate 3 (Q4 1 0 0 0)
    it "names the line of an inf or text field, and of a time that is not a number" $ do
      mapM_ (\v -> case readTum (B.pack ("1 0 0 0 0 0 0 1\n2 0 " ++ v ++ " 0 0 0 0 1\n")) of
                     Left e -> e `shouldSatisfy` ("line 2, column 3" `isInfixOf`)
                     Right _ -> expectationFailure v) ["inf", "-Infinity", "x", "1,5"]
      mapM_ (\v -> case readTum (B.pack ("1 0 0 0 0 0 0 1\n" ++ v ++ " 0 0 0 0 0 0 1\n")) of
                     Left e -> e `shouldSatisfy` ("line 2, column 1" `isInfixOf`)
                     Right _ -> expectationFailure v) ["nan", "inf", "null"]
    it "reads a pose value written nan (any case or sign), na, n/a or null as NaN: a sample the cleaning drops" $
      forM_ ["nan", "NaN", "-nan", "NA", "n/a", "null"] $ \v -> do
        let Right ss = readTum (B.pack ("1 0 0 0 0 0 0 1\n2 0 " ++ v ++ " 0 0 0 0 1\n3 1 1 1 0 0 0 " ++ v ++ "\n"))
        map smTime ss `shouldBe` [1, 2, 3]
        let P3 _ y _ = smPos (ss !! 1); Q4 w _ _ _ = smRot (ss !! 2)
        (isNaN y, isNaN w) `shouldBe` (True, True)
  describe "CSV with a header" $ do
    it "round trips vprof's own CSV (time,x,y,z,qw,qx,qy,qz in SI)" $ property $ forAll genTrack $ \tr ->
      case parseCsv (BL.toStrict (renderCsv tr)) of
        Left e -> counterexample e False
        Right tr' -> closeTo (1e-6, 1e-8, 1e-8) tr tr'
    it "reads a spreadsheet's quoted header and fields; refuses two columns for one part of the pose and a quaternion with a unit, naming the columns" $ do
      let rows = ["0,0.1,0.2,0.3,1,0,0,0", "0.01,0.11,0.2,0.3,1,0,0,0"]
          quoted = B.pack (unlines ("\"time\",\"x\",\"y\",\"z\",\"qw\",\"qx\",\"qy\",\"qz\"" : [ intercalate "," [ "\"" ++ f ++ "\"" | f <- splitC r ] | r <- rows ]))
          splitC r = case break (== ',') r of (a, _ : b) -> a : splitC b; (a, []) -> [a]
      fmap (map smPos . snd) (readCsv quoted) `shouldBe` Right [P3 0.1 0.2 0.3, P3 0.11 0.2 0.3]
      case readCsv (B.pack (unlines ("time,x,y,z,qw,qx,qy,qz,x" : map (++ ",5") rows))) of
        Left e -> e `shouldSatisfy` (\m -> "columns 2 \"x\" and 9 \"x\" both name x" `isInfixOf` m)
        Right _ -> expectationFailure "two x columns were taken"
      case readCsv (B.pack (unlines ("time,time,x,y,z,qw,qx,qy,qz" : map ("0," ++) rows))) of
        Left e -> e `shouldSatisfy` ("both name time" `isInfixOf`)
        Right _ -> expectationFailure "two time columns were taken"
      case readCsv (B.pack (unlines ("time,x,y,z,qw [deg],qx [deg],qy [deg],qz [deg]" : rows))) of
        Left e -> e `shouldSatisfy` (\m -> "column 5" `isInfixOf` m && "has no unit" `isInfixOf` m)
        Right _ -> expectationFailure "a quaternion in degrees was taken"
    it "finds the columns by name in any order, with units in brackets, and ignores other columns" $
      property $ forAll genTrack $ \tr -> forAll (shuffle [0 .. 8 :: Int]) $ \perm ->
        forAll (elements [("s", 1), ("ms", 1e3), ("us", 1e6)]) $ \(tu, tk) ->
        forAll (elements [("m", 1), ("cm", 1e2), ("mm", 1e3)]) $ \(pu, pk) ->
          let names = ["time [" ++ tu ++ "]", "x [" ++ pu ++ "]", "y [" ++ pu ++ "]", "z [" ++ pu ++ "]", "qw", "qx", "qy", "qz", "temperature [C]"]
              vals t (P3 x y z) (Q4 w a b c) = [t * tk, x * pk, y * pk, z * pk, w, a, b, c, 21.5]
              line vs = intercalate "," [ showFFloat (Just 12) (vs !! j) "" | j <- perm ]
              src = unlines (intercalate "," [names !! j | j <- perm]
                             : [ line (vals t p q) | (t, p, q) <- zip3 (U.toList (tTime tr)) (ptoList (tPos tr)) (ptoList (tRot tr)) ])
          in case readCsv (B.pack src) of
               Left e -> counterexample e False
               Right (lay, ss) ->
                 clTimeUnit lay === (1 / tk, tu, False) .&&. fst (clPosUnit lay) * pk === 1
                 .&&. closeTo (1e-6, 1e-8, 1e-8) tr (Track (U.fromList (map smTime ss)) (pfromList (map smPos ss)) (pfromList (map smRot ss)))
    it "reads the same recording with its columns separated by tabs, semicolons (decimal commas) or blanks (units apart in brackets)" $
      property $ forAll genTrack $ \tr -> forAll (shuffle [0 .. 8 :: Int]) $ \perm ->
        forAll (elements [(Comma, ","), (Tab, "\t"), (Semicolon, ";"), (Blanks, " "), (Blanks, "   "), (Tab, " \t  ")]) $ \(sep, gap) ->
          let names = ["time [ms]", "x [mm]", "y [mm]", "z [mm]", "qw", "qx", "qy", "qz", "temperature [C]"]
              vals t (P3 x y z) (Q4 w a b c) = [t * 1e3, x * 1e3, y * 1e3, z * 1e3, w, a, b, c, 21.5]
              num v = let str = showFFloat (Just 12) v "" in if sep == Semicolon then map (\ch -> if ch == '.' then ',' else ch) str else str
              line vs = intercalate gap [ num (vs !! j) | j <- perm ]
              samples = zip3 (U.toList (tTime tr)) (ptoList (tPos tr)) (ptoList (tRot tr))
              src = unlines ("# a comment line of more than four words before the header"
                             : intercalate gap [names !! j | j <- perm] : [ line (vals t p q) | (t, p, q) <- samples ])
          in counterexample src $ case readCsv (B.pack src) of
               Left e -> counterexample e False
               Right (lay, ss) ->
                 clSeparator lay === sep .&&. clHeaderLine lay === 2 .&&. hasNamedHeader (B.pack src) === True
                 .&&. closeTo (1e-6, 1e-8, 1e-8) tr (Track (U.fromList (map smTime ss)) (pfromList (map smPos ss)) (pfromList (map smRot ss)))
    it "takes TUM's own comment line (# timestamp tx ty tz qx qy qz qw) for a comment, not a header" $ do
      forM_ ["freiburg1_xyz-groundtruth.txt", "V101_gt.txt"] $ \f -> do
        src <- B.readFile ("../shared/data/" ++ f)
        hasNamedHeader src `shouldBe` False
      hasNamedHeader (B.pack "# timestamp tx ty tz qx qy qz qw\n1 0 0 0 0 0 0 1\n") `shouldBe` False
      hasNamedHeader (B.pack "timestamp tx ty tz qx qy qz qw\n1 0 0 0 0 0 0 1\n") `shouldBe` True
    it "reads the EuRoC ground truth layout (#timestamp in ns without a unit, q_RS_w first, 17 columns) as the same recording as its TUM copy" $ do
      Recording tr <- loadTum "V101_gt.txt"
      let hdr = "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z [], \
                \v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], \
                \b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]"
          row t (P3 x y z) (Q4 w a b c) = intercalate "," (show (round (t * 1e9) :: Integer) : map (\v -> showFFloat (Just 6) v "") ([x, y, z, w, a, b, c] ++ replicate 9 0.25))
          src = unlines (hdr : [ row t p q | (t, p, q) <- zip3 (U.toList (tTime tr)) (ptoList (tPos tr)) (ptoList (tRot tr)) ])
      hasCsvHeader (B.pack src) `shouldBe` True
      case readCsv (B.pack src) of
        Left e -> expectationFailure e
        Right (lay, ss) -> do
          clTimeUnit lay `shouldBe` (1e-9, "ns", True)
          (clTime lay, clPos lay, clQuat lay) `shouldBe` ((1, "timestamp"), (2, 3, 4), (5, 6, 7, 8))
          describeLayout lay `shouldSatisfy` ("9 further columns ignored" `isInfixOf`)
          map smLoc ss `shouldBe` [2 .. trackLength tr + 1]
          -- ns in a double: 1.4e18 is exact to 256 ns
          maximum (zipWith (\t s' -> abs (t - smTime s')) (U.toList (tTime tr)) ss) `shouldSatisfy` (< 1e-6)
          maximum (zipWith (\p s' -> distance p (smPos s')) (ptoList (tPos tr)) ss) `shouldSatisfy` (< 1e-6)
          maximum (zipWith (\q s' -> qangle q (smRot s')) (ptoList (tRot tr)) ss) `shouldSatisfy` (< 1e-5)
    it "reads a ROS rostopic echo -p pose export, taking the sensor's stamp over the receive time" $ do
      let src = "%time,field.header.seq,field.header.stamp,field.header.frame_id,field.pose.position.x,field.pose.position.y,\
                \field.pose.position.z,field.pose.orientation.x,field.pose.orientation.y,field.pose.orientation.z,field.pose.orientation.w\n\
                \1700000000120000000,1,1700000000100000000,world,1.5,2.5,3.5,0,0,0.6,0.8\n\
                \1700000000130000000,2,1700000000110000000,world,1.6,2.5,3.5,0,0,0.6,0.8\n"
      case readCsv (B.pack src) of
        Left e -> expectationFailure e
        Right (lay, ss) -> do
          fst (clTime lay) `shouldBe` 3
          clQuat lay `shouldBe` (11, 8, 9, 10)
          map smTime ss `shouldSatisfy` (\[a, b] -> abs (a - 1700000000.1) < 1e-6 && abs (b - a - 0.01) < 1e-6)
          map smRot ss `shouldBe` replicate 2 (Q4 0.8 0 0 0.6)
          map smPos ss `shouldBe` [P3 1.5 2.5 3.5, P3 1.6 2.5 3.5]
    it "names what the header lacks, an unknown unit, a short row and a bad number" $ do
      let err src = either id (const "no error") (readCsv (B.pack src))
      err "time,x,y,z,qx,qy,qz\n0,0,0,0,0,0,0\n" `shouldSatisfy` (\e -> "names no column for qw" `isInfixOf` e && "\"qz\"" `isInfixOf` e)
      err "time [h],x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n" `shouldSatisfy` (\e -> "column 1" `isInfixOf` e && "[h]" `isInfixOf` e)
      err "time,x [ft],y [ft],z [ft],qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n" `shouldSatisfy` ("[ft]" `isInfixOf`)
      err "time,x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n1,0,0\n" `shouldSatisfy` ("line 3" `isInfixOf`)
      err "time,x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n1,0,abc,0,1,0,0,0\n" `shouldSatisfy` (\e -> "line 3, column 3" `isInfixOf` e && "abc" `isInfixOf` e)
    it "reads empty pose fields (an OptiTrack or Vicon export while the body was lost) as NaN; an empty time is an error naming it" $ do
      let src = "time,x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n0.01,,,,,,,\n0.02,1,NaN,1,1,0,0,0\n0.03,1,1,1,1,0,0,0\n"
      case readCsv (B.pack src) of
        Left e -> expectationFailure e
        Right (_, ss) -> do
          map smLoc ss `shouldBe` [2, 3, 4, 5]
          map (\(Sample _ _ (P3 x y z) (Q4 w a b c)) -> any isNaN [x, y, z, w, a, b, c]) ss `shouldBe` [False, True, True, False]
      either id (const "no error") (readCsv (B.pack "time,x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n,1,1,1,1,0,0,0\n"))
        `shouldSatisfy` ("line 3, column 1" `isInfixOf`)
      -- a log line with a lost pose is not mistaken for a header
      hasCsvHeader (B.pack "1000,nan,nan,nan,nan,nan,nan,nan\n1010,1,2,3,1,0,0,0\n") `shouldBe` False
      hasCsvHeader (B.pack "1000,,,,,,,\n1010,1,2,3,1,0,0,0\n") `shouldBe` False
      let Right ls = readLog (B.pack "1000,,,,,,,\n1010,1,2,3,1,0,0,0\n")
      map (isNaN . (\(P3 x _ _) -> x) . smPos) ls `shouldBe` [True, False]
    it "tells a header from a Polhemus log line or a comment" $ do
      hasCsvHeader (B.pack "time,x,y,z,qw,qx,qy,qz\n") `shouldBe` True
      hasCsvHeader (B.pack "\n# time [ms], x [mm], y [mm], z [mm], qw, qx, qy, qz\n") `shouldBe` True
      hasCsvHeader (B.pack "1540012, 719.7, -97.2, -480.8, -0.61, 0.12, -0.75, 0.22, 0, 0\n") `shouldBe` False
      hasCsvHeader (B.pack "# a comment\n1540012, 719.7, -97.2, -480.8, -0.61, 0.12, -0.75, 0.22\n") `shouldBe` False
      -- a comment before the header (was read as a log: "not a number: time"); a header in
      -- other separators is taken as one, so that the CSV reader says what it lacks
      hasCsvHeader (B.pack "# exported by a tracker\ntime,x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n") `shouldBe` True
      hasCsvHeader (B.pack "time;x;y;z;qw;qx;qy;qz\n0;0;0;0;1;0;0;0\n") `shouldBe` True
      hasCsvHeader (B.pack "1540012, 1e-3, -97.2, -480.8, -0.61, 0.12, -0.75, 0.22\n") `shouldBe` False
  describe "OptiTrack Motive CSV export" $ do
    it "reads the named rigid body's poses (quaternion x y z w, the file's length unit) among other bodies and markers, in either header layout" $
      property $ forAll genMotive $ \m ->
        case readMotive (Just "Tool") (B.pack (renderMotive m)) of
          Left e -> counterexample e False
          Right (lay, ss) ->
            let Motive (Track ts ps qs) _ _ _ = m
                got = Track (U.fromList (map smTime ss)) (pfromList (map smPos ss)) (pfromList (map smRot ss))
            in counterexample (renderMotive m) $
                 mlBody lay === "Tool" .&&. mlOthers lay === ["Cup"]
                 .&&. map smLoc ss === [mHeaderLines m + 1 .. mHeaderLines m + U.length ts]
                 .&&. closeTo (1e-6, 1e-8, 1e-8) (Track ts ps qs) got
    it "takes the only rigid body without a name; with several, names them and asks for one; an unknown name lists them" $ do
      let one = motiveText ["Tool"] "Meters" "Quaternion" ["0,0.0,0,0,0,1,1,2,3,0.0001", "1,0.01,0,0,0,1,1.1,2,3,0.0001"]
          two = motiveText ["Tool", "Cup"] "Meters" "Quaternion" ["0,0.0,0,0,0,1,1,2,3,0.0001,0,0,0,1,4,5,6,0.0002"]
      fmap (map smPos . snd) (readMotive Nothing (B.pack one)) `shouldBe` Right [P3 1 2 3, P3 1.1 2 3]
      either id (const "no error") (readMotive Nothing (B.pack two))
        `shouldSatisfy` (\e -> "2 rigid bodies" `isInfixOf` e && "\"Tool\", \"Cup\"" `isInfixOf` e && "--rigid-body" `isInfixOf` e)
      fmap (map smPos . snd) (readMotive (Just "Cup") (B.pack two)) `shouldBe` Right [P3 4 5 6]
      either id (const "no error") (readMotive (Just "Duck") (B.pack two))
        `shouldSatisfy` (\e -> "\"Duck\"" `isInfixOf` e && "\"Cup\"" `isInfixOf` e)
    it "reads a frame where the body was lost (empty cells) as NaN, for the cleaning to drop; a bad number names its line and column" $ do
      let src = motiveText ["Tool"] "Millimeters" "Quaternion" ["0,0.0,0,0,0,1,1000,2000,3000,0.1", "1,0.01,,,,,,,,", "2,0.02,0,0,0,1,1000,2000,abc,0.1"]
      either id (const "no error") (readMotive Nothing (B.pack src))
        `shouldSatisfy` (\e -> "line 10, column 9" `isInfixOf` e && "abc" `isInfixOf` e)
      let Right (_, ss) = readMotive Nothing (B.pack (motiveText ["Tool"] "Millimeters" "Quaternion" ["0,0.0,0,0,0,1,1000,2000,3000,0.1", "1,0.01,,,,,,,,"]))
      map smLoc ss `shouldBe` [8, 9]
      smPos (head ss) `shouldBe` P3 1 2 3
      (\(P3 x _ _) -> isNaN x) (smPos (ss !! 1)) `shouldBe` True
    it "refuses a row that ends before the body's columns, naming the line (a cut file's last row was taken for a lost frame)" $ do
      let src = motiveText ["Tool"] "Millimeters" "Quaternion" ["0,0.0,0,0,0,1,1000,2000,3000,0.1", "1,0.01,0,0,0,1,1000,20"]
      either id (const "no error") (readMotive Nothing (B.pack src))
        `shouldBe` "Motive CSV line 9: the row ends after 8 columns, but Tool's run to column 9: is the file cut short? (a frame where the body was lost keeps its commas, with empty cells)"
      -- the second body's columns are cut, the first one's are whole: only a read of the second fails
      let two = motiveText ["Tool", "Cup"] "Meters" "Quaternion" ["0,0.0,0,0,0,1,1,2,3,0.0001,0,0,0,1,4,5,6,0.0002", "1,0.01,0,0,0,1,1,2,3,0.0001,0,0"]
      fmap (length . snd) (readMotive (Just "Tool") (B.pack two)) `shouldBe` Right 2
      either id (const "no error") (readMotive (Just "Cup") (B.pack two)) `shouldSatisfy` isInfixOf "line 9: the row ends after 12 columns, but Cup's run to column 17"
    it "refuses Euler angles and an unknown length unit, naming the setting and its value" $ do
      either id (const "no error") (readMotive Nothing (B.pack (motiveText ["Tool"] "Meters" "XYZ" ["0,0.0,0,0,0,1,1,2,3,0"])))
        `shouldSatisfy` (\e -> "Rotation Type is \"XYZ\"" `isInfixOf` e && "Quaternion" `isInfixOf` e)
      either id (const "no error") (readMotive Nothing (B.pack (motiveText ["Tool"] "Inches" "Quaternion" ["0,0.0,0,0,0,1,1,2,3,0"])))
        `shouldSatisfy` (\e -> "Length Units \"Inches\"" `isInfixOf` e && "line 1" `isInfixOf` e)
    it "is told from other CSV by its settings line" $ do
      isMotiveCsv (B.pack (motiveText ["Tool"] "Meters" "Quaternion" [])) `shouldBe` True
      isMotiveCsv (B.pack "time,x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n") `shouldBe` False
      hasCsvHeader (B.pack (motiveText ["Tool"] "Meters" "Quaternion" [])) `shouldBe` True

  describe "Qualisys 6D TSV export" $ do
    it "reads the named body's poses (mm, Rot[0..8] column by column) among other bodies, with or without the header, CRLF and trailing tabs; lost frames (NaN, empty, a matrix of zeros) as lost samples on their lines" $
      property $ forAll genTrack $ \tr -> forAll (qtmCase tr) $ \(others, toolAt, hdr, crlf, tt, losses) ->
        let Track ts ps qs = tr
            n = U.length ts
            tool = [ if i `elem` map fst losses then maybe LostNaN id (lookup i losses) else Tracked (pindex ps i) (pindex qs i) | i <- [0 .. n - 1] ]
            other k = (k, [ Tracked (P3 1 2 3) (Q4 1 0 0 0) | _ <- [1 .. n] ])
            bodies = take toolAt (map other others) ++ [("Tool", tool)] ++ drop toolAt (map other others)
            txt = qtmText 100 hdr crlf tt bodies
            firstRow = (if hdr then 10 else 0) + 2
        in counterexample txt $ case readQualisys (Just "Tool") (B.pack txt) of
             Left e -> counterexample e False
             Right (lay, ss) ->
               qlBody lay === "Tool" .&&. qlOthers lay === others
               .&&. qlUntracked lay === length [ () | (_, LostZeros) <- losses ]
               .&&. map smLoc ss === [firstRow .. firstRow + n - 1]
               .&&. framesRead 1e-5 tr (map fst losses) ss
    it "reads a real QTM export (an excerpt of a ship-model test, 4 frames) so that each rotation is the file's own roll, pitch and yaw as Rx·Ry·Rz, which the rows of Rot[] would not give" $ do
      src <- B.readFile "test/data/qualisys-6d-excerpt.tsv"
      isQualisysTsv src `shouldBe` True
      let Right (lay, ss) = readQualisys Nothing src
          rows = [ map (read . B.unpack) (B.split '\t' (B.strip l)) :: [Double] | l <- drop 11 (B.lines src) ]
      qlBody lay `shouldBe` "PSVH"
      map smLoc ss `shouldBe` [12, 13, 14, 15]
      map smTime ss `shouldBe` [0, 0.01, 210.52, 210.53]
      forM_ (zip ss rows) $ \(sm, r) -> do
        let euler = eulerXyzMatrix (r !! 5) (r !! 6) (r !! 7)
            got = rotationMatrix (smRot sm)
            off a b = maximum (zipWith (\x y -> abs (x - y)) (concat a) (concat b))
            P3 x y z = smPos sm
        off got euler `shouldSatisfy` (< 1e-4)
        maximum (zipWith (\a b -> abs (a - b / 1000)) [x, y, z] (take 3 (drop 2 r))) `shouldSatisfy` (< 1e-9)
        -- the rows of Rot[] would be the transposed matrix: far off where the yaw is 92 degrees
        if abs (r !! 7) > 45 then off (transpose3 got) euler `shouldSatisfy` (> 0.5) else pure ()
    it "takes the only body without a name; with several, names them and asks for one; an unknown name lists them" $ do
      let frames = [Tracked (P3 0.1 0.2 0.3) (Q4 1 0 0 0)]
          two = qtmText 100 True False True [("Tool", frames), ("Cup", frames)]
      fmap (map smPos . snd) (readQualisys Nothing (B.pack (qtmText 100 True False True [("Tool", frames)]))) `shouldBe` Right [P3 0.1 0.2 0.3]
      either id (const "no error") (readQualisys Nothing (B.pack two))
        `shouldSatisfy` (\e -> "2 bodies" `isInfixOf` e && "\"Tool\", \"Cup\"" `isInfixOf` e && "--rigid-body" `isInfixOf` e)
      fmap (length . snd) (readQualisys (Just "Cup") (B.pack two)) `shouldBe` Right 1
      either id (const "no error") (readQualisys (Just "Duck") (B.pack two))
        `shouldSatisfy` (\e -> "\"Duck\"" `isInfixOf` e && "\"Cup\"" `isInfixOf` e)
    it "reads a column row that names the body in every column (Tool X, Tool Y, …, Tool Rot[8])" $ do
      let cols = "Frame\tTime\t" ++ intercalate "\t" (map ("Tool " ++) (["X", "Y", "Z", "Roll", "Pitch", "Yaw", "Residual"] ++ [ "Rot[" ++ show j ++ "]" | j <- [0 .. 8 :: Int] ]))
          src = B.pack (unlines ["NO_OF_FRAMES\t1", "DATA_INCLUDED\t6D", cols, "1\t0.00\t100\t200\t300\t0\t0\t90\t0.5\t0\t1\t0\t-1\t0\t0\t0\t0\t1"])
      fmap (\(l, ss) -> (qlBody l, map smPos ss)) (readQualisys Nothing src) `shouldBe` Right ("Tool", [P3 0.1 0.2 0.3])
      -- Rot[] column by column: x to y, y to -x, a quarter turn about z
      fmap (map (\sm -> qangle (smRot sm) (Q4 (sqrt 0.5) 0 0 (sqrt 0.5))) . snd) (readQualisys Nothing src) `shouldSatisfy` either (const False) (all (< 1e-9))
    it "refuses a matrix that is no rotation, a cut row, a bad number and a 3D export, naming the line and the value" $ do
      let good = "1\t0.00\t100\t200\t300\t0\t0\t0\t0.5\t1\t0\t0\t0\t1\t0\t0\t0\t1"
          cols = "Frame\tTime\tTool X\tY\tZ\tRoll\tPitch\tYaw\tResidual\t" ++ intercalate "\t" [ "Rot[" ++ show j ++ "]" | j <- [0 .. 8 :: Int] ]
          file rows = B.pack (unlines (["NO_OF_FRAMES\t2", "FREQUENCY\t100", "DATA_INCLUDED\t6D", "BODY_NAMES\tTool", cols, good] ++ rows))
      either id (const "no error") (readQualisys Nothing (file ["2\t0.01\t100\t200\t300\t0\t0\t0\t0.5\t1\t0\t0\t0\t2\t0\t0\t0\t1"]))
        `shouldSatisfy` (\e -> "line 7, columns 10-18" `isInfixOf` e && "not a rotation" `isInfixOf` e && "\"2\"" `isInfixOf` e)
      either id (const "no error") (readQualisys Nothing (file ["2\t0.01\t100\t200\t300\t0\t0"]))
        `shouldSatisfy` (\e -> "line 7" `isInfixOf` e && "cut short" `isInfixOf` e)
      either id (const "no error") (readQualisys Nothing (file ["2\t0.01\t100\tabc\t300\t0\t0\t0\t0.5\t1\t0\t0\t0\t1\t0\t0\t0\t1"]))
        `shouldSatisfy` (\e -> "line 7, column 4" `isInfixOf` e && "abc" `isInfixOf` e)
      either id (const "no error") (readQualisys Nothing (B.pack "NO_OF_FRAMES\t1\nDATA_INCLUDED\t3D\nFrame\tTime\tM1 X\tM1 Y\tM1 Z\n1\t0\t1\t2\t3\n"))
        `shouldSatisfy` (\e -> "line 2" `isInfixOf` e && "DATA_INCLUDED is \"3D\"" `isInfixOf` e)
    it "is told from other files by its header keys or its column row" $ do
      isQualisysTsv (B.pack (qtmText 100 True False False [("Tool", [])])) `shouldBe` True
      isQualisysTsv (B.pack (qtmText 100 False True True [("Tool", [])])) `shouldBe` True
      isQualisysTsv (B.pack "time\tx\ty\tz\tqw\tqx\tqy\tqz\n0\t0\t0\t0\t1\t0\t0\t0\n") `shouldBe` False
      isQualisysTsv (B.pack "1305031102.175304 1.2334 -0.0113 1.6941 0.7907 0.4393 -0.1770 -0.3879\n") `shouldBe` False

  describe "Vicon Nexus CSV export" $ do
    it "reads the named segment's poses (helical axis in deg or rad, a whole turn longer or not; translation in mm or m) among other subjects' segments; a lost frame (empty cells, or its frame number alone) as a lost sample on its line" $
      property $ forAll genTrack $ \tr -> forAll (nexusCase tr) $ \(others, toolAt, units, turns, lostAt) ->
        let Track ts ps qs = tr
            n = U.length ts
            tool = [ if i `elem` lostAt then NexusLost else NexusTracked (i `elem` turns) (pindex ps i) (pindex qs i) | i <- [0 .. n - 1] ]
            -- the others are lost where the tool is on odd frames: the row is then the frame number alone
            other k = (k, [ if i `elem` lostAt && odd i then NexusLost else NexusTracked False (P3 1 2 3) (Q4 1 0 0 0) | i <- [0 .. n - 1] ])
            segs = take toolAt (map other others) ++ [("Rig:Tool", tool)] ++ drop toolAt (map other others)
            txt = nexusSegmentsText 100 units segs
            -- the segment's name alone where no other subject has a Tool
            want = if "Other:Tool" `elem` others then "Rig:Tool" else "Tool"
        in counterexample txt $ case readVicon (Just want) (B.pack txt) of
             Left e -> counterexample e False
             Right (lay, ss) ->
               vlSegment lay === "Rig:Tool" .&&. vlOthers lay === others .&&. vlSections lay === ["Segments", "Trajectories"]
               .&&. map smLoc ss === [6 .. 5 + n]
               .&&. framesRead 1e-12 tr lostAt ss
    it "reads real Nexus rows (a gripper in three poses, then lost) so that its five markers keep their place on the segment: the helical axis is the rotation, its transpose would move them" $ do
      src <- B.readFile "test/data/vicon-nexus-excerpt.csv"
      isViconCsv src `shouldBe` True
      let Right (lay, ss) = readVicon Nothing src
          markers = [ map (read . B.unpack) (drop 2 (B.split ',' (B.strip l))) :: [Double] | l <- take 3 (drop 15 (B.lines src)) ]
          inSegment rot sm m = let P3 x y z = smPos sm in apply3 (rot (rotationMatrix (smRot sm))) (zipWith (-) m [x * 1000, y * 1000, z * 1000])
          spread rot = maximum [ maximum [ maximum (map abs (zipWith (-) a b)) | a <- ls, b <- ls ]
                               | k <- [0 .. 4], let ls = [ inSegment rot sm (take 3 (drop (3 * k) m)) | (sm, m) <- zip ss markers ] ]
      vlSegment lay `shouldBe` "New Subject:gripper"
      map smLoc ss `shouldBe` [6, 7, 8, 9]
      map smTime ss `shouldBe` [0, 0.01, 0.02, 0.03]
      (\(P3 x _ _) -> isNaN x) (smPos (ss !! 3)) `shouldBe` True
      spread transpose3 `shouldSatisfy` (< 2)     -- mm: R^T (p - T) is the same for each pose
      spread id `shouldSatisfy` (> 20)           -- 32 mm with the matrix transposed
    it "takes the only segment without a name, or a segment by its name alone; with several, names them; refuses a file without a Segments section and an unknown unit" $ do
      let frames = [NexusTracked False (P3 0.1 0.2 0.3) (Q4 1 0 0 0)]
          two = nexusSegmentsText 100 ("deg", "mm") [("A:Tool", frames), ("A:Cup", frames)]
      fmap (map smPos . snd) (readVicon Nothing (B.pack (nexusSegmentsText 100 ("deg", "mm") [("A:Tool", frames)]))) `shouldBe` Right [P3 0.1 0.2 0.3]
      either id (const "no error") (readVicon Nothing (B.pack two))
        `shouldSatisfy` (\e -> "2 segments" `isInfixOf` e && "\"A:Tool\", \"A:Cup\"" `isInfixOf` e && "--rigid-body" `isInfixOf` e)
      fmap (length . snd) (readVicon (Just "A:Cup") (B.pack two)) `shouldBe` Right 1
      either id (const "no error") (readVicon (Just "Duck") (B.pack two)) `shouldSatisfy` (\e -> "\"Duck\"" `isInfixOf` e && "\"A:Cup\"" `isInfixOf` e)
      let traj = "Trajectories\n100\n,,S:M1,,\nFrame,Sub Frame,X,Y,Z\n,,mm,mm,mm\n1,0,1,2,3\n"
      isViconCsv (B.pack traj) `shouldBe` True
      either id (const "no error") (readVicon Nothing (B.pack traj))
        `shouldSatisfy` (\e -> "no Segments section" `isInfixOf` e && "Trajectories" `isInfixOf` e)
      either id (const "no error") (readVicon Nothing (B.pack (nexusSegmentsText 100 ("grad", "mm") [("A:Tool", frames)])))
        `shouldSatisfy` (\e -> "line 5, column 3" `isInfixOf` e && "\"grad\"" `isInfixOf` e)
      isViconCsv (B.pack "time,x,y,z,qw,qx,qy,qz\n0,0,0,0,1,0,0,0\n") `shouldBe` False

  describe "KITTI poses with a times file" $ do
    it "reads [R | t] rows (9 significant digits, as KITTI writes them) as the same poses, the times from the times file" $
      property $ forAll genTrack $ \tr ->
        let row p (Q4 w a b c) = let P3 x y z = p
                                     tf = T.fromQuat (T.V3 x y z) (T.Quat w a b c)
                                 in unwords [ showEFloat' v | v <- T.toRows tf ]
            showEFloat' v = showFFloat (Just 9) v ""
            poses = unlines [ row p q | (p, q) <- zip (ptoList (tPos tr)) (ptoList (tRot tr)) ]
            times = unlines [ showFFloat (Just 9) t "" | t <- U.toList (tTime tr) ]
        in looksLikeKitti (B.pack poses) .&&.
           case readKitti (B.pack poses) (B.pack times) of
             Left e -> counterexample e False
             Right ss -> map smLoc ss === [1 .. trackLength tr]
                         .&&. closeTo (1e-6, 1e-8, 1e-7) tr (Track (U.fromList (map smTime ss)) (pfromList (map smPos ss)) (pfromList (map smRot ss)))
    it "reads KITTI 00 as the same recording the benchmark converts (first pose the identity at t = 0)" $ do
      pf <- dataFile "KITTI_00_gt.txt"
      tf <- dataFile "KITTI_00_gt_times.txt"
      ps <- B.readFile pf
      ts <- B.readFile tf
      case readKitti ps ts of
        Left e -> expectationFailure e
        Right ss -> do
          length ss `shouldBe` 4541
          qangle (smRot (head ss)) (Q4 1 0 0 0) `shouldSatisfy` (< 1e-6)
          smTime (ss !! 1) `shouldSatisfy` (\t -> abs (t - 0.1037359) < 1e-9)
          -- line 2: t = (-4.690294e-02, -2.839928e-02, 8.586941e-01)
          distance (smPos (ss !! 1)) (P3 (-4.690294e-2) (-2.839928e-2) 0.8586941) `shouldSatisfy` (< 1e-12)
    it "names the line of a matrix that is not a rotation, a short line and a count mismatch" $ do
      let idLine = "1 0 0 0 0 1 0 0 0 0 1 0\n"
          err ps ts = either id (const "no error") (readKitti (B.pack ps) (B.pack ts))
      err (idLine ++ "2 0 0 0 0 1 0 0 0 0 1 0\n") "0\n1\n" `shouldSatisfy` (\e -> "line 2" `isInfixOf` e && "not a rotation" `isInfixOf` e)
      err (idLine ++ "-1 0 0 0 0 1 0 0 0 0 1 0\n") "0\n1\n" `shouldSatisfy` ("line 2" `isInfixOf`)
      err (idLine ++ "1 0 0 0 0 1 0 0 0 0 1\n") "0\n1\n" `shouldSatisfy` (\e -> "line 2" `isInfixOf` e && "got 11" `isInfixOf` e)
      err (idLine ++ idLine) "0\n" `shouldSatisfy` ("2 poses but 1 times" `isInfixOf`)
      err idLine "zero\n" `shouldSatisfy` (\e -> "KITTI times line 1" `isInfixOf` e && "zero" `isInfixOf` e)
      looksLikeKitti (B.pack "# c\n1 0 0 0 0 0 0 1\n") `shouldBe` False
  describe "Polhemus log (thesis figure 33)" $ do
    it "reads samples with their line numbers (CRLF accepted)" $ do
      let Right ss = readLog (B.pack "# c\r\n1000, 1, 2, 3, 1, 0, 0, 0\r\n1000, 1, 2, 3, 1, 0, 0, 0, 7\r\n")
      map smLoc ss `shouldBe` [2, 3]
      map smTime ss `shouldBe` [1, 1]
    it "reads time (ms), position (mm) and quaternion w x y z, ignoring further columns" $ do
      let src = B.pack "1540012, 719.734558105469, -97.2053146362305, -480.808166503906, -0.610407650470734, 0.124314948916435, -0.749075055122375, 0.225465580821037, 0, 0\n\
                       \1540062, 720.0, -97.0, -480.0, -0.61, 0.124, -0.749, 0.225, 0, 0\n"
      case parseLog src of
        Left e -> expectationFailure e
        Right tr -> do
          tTime tr U.! 0 `shouldSatisfy` (\t -> abs (t - 1540.012) < 1e-9)
          let P3 x y z = phead (tPos tr)
          (x, y, z) `shouldSatisfy` (\(a, b, c) -> abs (a - 0.719734558105469) < 1e-12 && abs (b + 0.0972053146362305) < 1e-12 && abs (c + 0.480808166503906) < 1e-12)
          let Q4 w _ _ _ = phead (tRot tr)
          w `shouldSatisfy` (< 0)
    it "names the line of a short row" $ do
      let Left e = parseLog (B.pack "1, 2, 3\n")
      e `shouldSatisfy` ("line 1" `isInfixOf`)
  describe "times closer than a microsecond" $
    it "are written distinctly and read back as the same count of waypoints, in TUM, CSV and RAPID (6 decimals wrote them alike)" $
      property $ forAll (choose (2, 20)) $ \n -> forAll (elements [1e-9, 3e-8, 4e-7, 2e-6]) $ \dt -> forAll (choose (0, 100)) $ \t0 ->
        let tr = Track (U.fromList [ t0 + fromIntegral i * dt | i <- [0 .. n - 1] ])
                       (pfromList [ P3 (fromIntegral i) 0 0 | i <- [0 .. n - 1] ]) (pfromList (replicate n (Q4 1 0 0 0)))
            back f = either (const 0) trackLength f
        in back (parseTum (BL.toStrict (renderTum tr))) === n .&&. back (parseCsv (BL.toStrict (renderCsv tr))) === n
           .&&. back (parseRapid (B.pack (renderRapid defaultRapidOptions tr))) === n
  describe "fields" $ do
    it "a number reads as the nearest double: any finite double (all bit patterns) in its shortest form and in 17 digits (Data.Text's reader was an ulp off in a tenth of them)" $
      property $ \w -> let x = castWord64ToDouble w in not (isNaN x || isInfinite x) ==>
        readDouble (B.pack (show x)) === Just x .&&. readDouble (B.pack (printf "%.16e" x)) === Just x
    it "reads spaces around a number, subnormals and near neighbours apart; not nan, inf, beyond a double or a decimal comma" $ do
      map (readDouble . B.pack) ["3.4985479464439885e-06", "1e300", "5e-324", " -0.25 ", "+.5", "1.000000000000001e+16", "1.0000000000000012e+16"]
        `shouldBe` map Just [3.4985479464439885e-06, 1e300, 5e-324, -0.25, 0.5, 1.000000000000001e+16, 1.0000000000000012e+16]
      map (readDouble . B.pack) ["nan", "inf", "-Infinity", "1e309", "1.5e", "1,5", "0x10", ""] `shouldSatisfy` all (== Nothing)
    it "a field of millions of digits is refused at once, and the message shows its start and its length" $ do
      let big = replicate 2000000 '1'
          Left e = readTum (B.pack ("0 0 0 0 0 0 0 1\n1 " ++ big ++ " 0 0 0 0 0 1\n"))
      e `shouldSatisfy` ("line 2, column 2" `isInfixOf`)
      e `shouldSatisfy` ("(2000000 characters)" `isInfixOf`)
      length e `shouldSatisfy` (< 300)
  describe "RAPID" $ do
    it "round trips a path (robtargets in mm and \\T:= segment times)" $ property $ forAll genTrack $ \tr ->
      case parseRapid (B.pack (renderRapid defaultRapidOptions tr)) of
        Left e -> counterexample e False
        Right tr' -> closeTo (1e-5 * fromIntegral (trackLength tr), 2e-7, 1e-8) tr tr'
    it "a compressed path written as RAPID and read back is the same path" $ do
      rec <- loadTum "freiburg1_xyz-groundtruth.txt"
      let Right out = compress defaultSettings { sPoints = Just 40 } rec
          Path p = oPath out
      case parseRapid (B.pack (renderRapid defaultRapidOptions p)) of
        Left e -> expectationFailure e
        Right p' -> do
          trackLength p' `shouldBe` trackLength p
          maximum [ abs (tTime p U.! i - tTime p' U.! i) | i <- [0 .. trackLength p - 1] ] `shouldSatisfy` (< 1e-4)
          maximum [ distance (pindex (tPos p) i) (pindex (tPos p') i) | i <- [0 .. trackLength p - 1] ] `shouldSatisfy` (< 2e-7)
          maximum [ qangle (pindex (tRot p) i) (pindex (tRot p') i) | i <- [0 .. trackLength p - 1] ] `shouldSatisfy` (< 1e-8)
    it "reads the thesis's ABB excerpt (figures 34-35): PaintL with \\T:=, quaternion split over lines" $ do
      let src = unlines
            [ "module M1", "!", "! Sensor WObj Frame : [ 1124.06 160.87 -199.9 ]"
            , "Local Const robtarget p0 :="
            , "[[349.5059, 924.2835, 425.4585], [0.195888182433874, 0.69373051780106"
            , "0.673120452632127, -0.165150051563343], [0, 0, 0], [0, 0, 0, 0]];"
            , "Local Const robtarget p200 :="
            , "[[359.5059, 914.2835, 425.4585], [0.195888182433874, 0.69373051780106, 0.673120452632127, -0.165150051563343], [0, 0, 0], [0, 0, 0, 0]];"
            , "proc mainM1()", "MoveAbsJ jReadyPos, v500, z50, toolSRP \\WObj:=wobjSRP;", "SetBrush 1;"
            , "PaintL p0, v500, z50, toolSRP \\WObj:=wobjSRP;"
            , "PaintL p200, v500\\T:=0.20, z50, toolSRP \\WObj:=wobjSRP;", "endproc", "endmodule" ]
      case parseRapid (B.pack src) of
        Left e -> expectationFailure e
        Right tr -> do
          U.toList (tTime tr) `shouldBe` [0, 0.2]
          distance (phead (tPos tr)) (P3 0.3495059 0.9242835 0.4254585) `shouldSatisfy` (< 1e-12)
          distance (plast (tPos tr)) (P3 0.3595059 0.9142835 0.4254585) `shouldSatisfy` (< 1e-12)
    it "refuses a circular or searching move, naming its line (MoveC used to be dropped without a word)" $
      forM_ ["MoveC p1, p2, v500\\T:=1, z10, tool0;", "SearchL \\Stop, di1, sp, p1, v100, tool0;", "PaintC p1, p2, v500, z10, tool0;"] $ \instr -> do
        let src = unlines [ "MODULE m"
                          , "  CONST robtarget p0 := [[400,-100,300],[0,1,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];"
                          , "  CONST robtarget p1 := [[500,-100,300],[0,1,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];"
                          , "  CONST robtarget p2 := [[500,100,300],[0,1,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];"
                          , "  PROC main()", "    MoveL p0, v500, z10, tool0;", "    " ++ instr
                          , "    MoveL p2, v500\\T:=1, fine, tool0;", "  ENDPROC", "ENDMODULE" ]
        case parseRapid (B.pack src) of
          Left e -> e `shouldSatisfy` (\m -> "line 7" `isInfixOf` m && "not supported" `isInfixOf` m)
          Right _ -> expectationFailure ("accepted: " ++ instr)
    it "refuses a robtarget whose position or orientation has the wrong count (a short position used to borrow the quaternion's first number)" $
      forM_ [("[[500,-100],[250,1,0,0],[0,0,0,0]]", "2 numbers in the position"), ("[[400,-100,300,7],[0,1,0,0]]", "4 numbers in the position")
            , ("[[400,-100,300],[0,1,0]]", "3 in the orientation")] $ \(val, what) -> do
        let src = "MODULE m\n  CONST robtarget p0 := " ++ val ++ ";\n  PROC main()\n    MoveL p0, v500, z10, tool0;\n  ENDPROC\nENDMODULE\n"
        case parseRapid (B.pack src) of
          Left e -> e `shouldSatisfy` (\m -> "line 2" `isInfixOf` m && what `isInfixOf` m)
          Right _ -> expectationFailure ("accepted: " ++ val)
    it "takes names in any case, as RAPID does, and refuses a robtarget declared twice (the last one won), naming both lines" $ do
      let target n x = "  CONST robtarget " ++ n ++ " := [[" ++ show (x :: Int) ++ ",0,300],[0,1,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];"
          modl ts = unlines (["MODULE m"] ++ ts ++ ["  PROC main()", "    MoveL P0, v500, z10, tool0;", "    MoveL p1, v500\\T:=1, fine, tool0;", "  ENDPROC", "ENDMODULE"])
      fmap (map (\(P3 x _ _) -> x) . ptoList . tPos) (parseRapid (B.pack (modl [target "p0" 400, target "P1" 500]))) `shouldBe` Right [0.4, 0.5]
      case parseRapid (B.pack (modl [target "p0" 400, target "p1" 500, target "P1" 600])) of
        Left e -> e `shouldSatisfy` (\m -> "lines 3 and 4" `isInfixOf` m && "declared 2 times" `isInfixOf` m)
        Right _ -> expectationFailure "a robtarget declared twice was accepted"
    it "refuses loops, branches and jumps, and moves in two procedures, naming them (a FOR loop was read once, a PROC never called was appended)" $ do
      let targets = [ "  CONST robtarget p" ++ show i ++ " := [[" ++ show (400 + 100 * i) ++ ",0,300],[0,1,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];" | i <- [0, 1 :: Int] ]
          modl body = unlines (["MODULE m"] ++ targets ++ body ++ ["ENDMODULE"])
          moves = ["    MoveL p0, v500, z10, tool0;", "    MoveL p1, v500\\T:=1, fine, tool0;"]
      forM_ [ (["  PROC main()", "    FOR i FROM 1 TO 3 DO"] ++ moves ++ ["    ENDFOR", "  ENDPROC"], "line 5", "FOR")
            , (["  PROC main()", "    WHILE TRUE DO"] ++ moves ++ ["    ENDWHILE", "  ENDPROC"], "line 5", "WHILE")
            , (["  PROC main()", "    IF di1 = 1 THEN"] ++ moves ++ ["    ENDIF", "  ENDPROC"], "line 5", "IF")
            , (["  PROC main()"] ++ moves ++ ["  ENDPROC", "  PROC spare()", "    MoveL p0, v500\\T:=1, fine, tool0;", "  ENDPROC"], "main from line 5", "spare from line 9") ] $ \(body, where_, what) ->
        case parseRapid (B.pack (modl body)) of
          Left e -> e `shouldSatisfy` (\m -> where_ `isInfixOf` m && what `isInfixOf` m)
          Right _ -> expectationFailure ("accepted: " ++ unlines body)
      -- moves in one procedure that main calls are fine
      fmap trackLength (parseRapid (B.pack (modl (["  PROC main()", "    path1;", "  ENDPROC", "  PROC path1()"] ++ moves ++ ["  ENDPROC"])))) `shouldBe` Right 2
    it "refuses a module cut short anywhere (the moves after the cut were lost without a word), naming the line" $
      property $ forAll genTrack $ \tr -> do
        let txt = renderRapid defaultRapidOptions tr
            complete = length (dropWhileEnd isSpace txt)
        forAll (choose (0, complete - 1)) $ \c ->
          case parseRapid (B.pack (take c txt)) of
            Left e -> counterexample e (c == 0 || "line" `isInfixOf` e || "no MoveL" `isInfixOf` e)
            Right tr' -> counterexample ("accepted a module cut after " ++ show c ++ " of " ++ show complete ++ " characters, "
                                          ++ show (trackLength tr') ++ " of " ++ show (trackLength tr) ++ " waypoints") False
    it "a cut module's message says which part is missing" $ do
      let modl = [ "MODULE m"
                 , "  CONST robtarget p0 := [[400,0,300],[0,1,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];"
                 , "  CONST robtarget p1 := [[500,0,300],[0,1,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];"
                 , "  PROC main()", "    MoveL p0, v500, z10, tool0;", "    MoveL p1, v500\\T:=1, fine, tool0;", "  ENDPROC", "ENDMODULE" ]
          err n = either id (const "accepted") (parseRapid (B.pack (unlines (take n modl))))
      fmap trackLength (parseRapid (B.pack (unlines modl))) `shouldBe` Right 2
      err 7 `shouldBe` "RAPID line 1: MODULE m has no ENDMODULE: is the file cut short?"
      err 6 `shouldBe` "RAPID line 4: PROC main has no ENDPROC: is the file cut short?"
      either id (const "accepted") (parseRapid (B.pack (unlines (take 5 modl) ++ "    MoveL p1, v500\\T:=1, fi")))
        `shouldBe` "RAPID line 6: the statement is not ended by ';': is the file cut short?"
      -- a procedure alone, without a module, is taken
      fmap trackLength (parseRapid (B.pack (unlines (take 6 (drop 1 modl))))) `shouldBe` Right 2
    it "names the line of a move to an undeclared target" $ do
      let Left e = parseRapid (B.pack "MODULE m\nPROC main()\n  MoveL nowhere, v500, z10, tool0;\nENDPROC\nENDMODULE\n")
      e `shouldSatisfy` ("line 3" `isInfixOf`)
      e `shouldSatisfy` ("nowhere" `isInfixOf`)
