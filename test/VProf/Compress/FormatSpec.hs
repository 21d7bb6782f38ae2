-- | Round trips and error messages of the recording/path formats.
module VProf.Compress.FormatSpec (spec) where

import qualified Data.ByteString.Char8 as B
import qualified Data.ByteString.Lazy.Char8 as BL
import Data.List (isInfixOf)
import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import VProf.Compress
import VProf.Compress.Clean (Sample (..))
import VProf.Compress.Format.Log
import VProf.Compress.Format.Rapid
import VProf.Compress.Format.Tum
import VProf.Geometry.Quaternion (qangle, qnormalize)
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
    it "names the line of a nan or inf field" $
      mapM_ (\v -> case readTum (B.pack ("1 0 0 0 0 0 0 1\n2 0 " ++ v ++ " 0 0 0 0 1\n")) of
                     Left e -> e `shouldSatisfy` ("line 2, column 3" `isInfixOf`)
                     Right _ -> expectationFailure v) ["nan", "NaN", "inf", "-Infinity"]
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
    it "names the line of a move to an undeclared target" $ do
      let Left e = parseRapid (B.pack "MODULE m\nPROC main()\n  MoveL nowhere, v500, z10, tool0;\nENDPROC\nENDMODULE\n")
      e `shouldSatisfy` ("line 3" `isInfixOf`)
      e `shouldSatisfy` ("nowhere" `isInfixOf`)
