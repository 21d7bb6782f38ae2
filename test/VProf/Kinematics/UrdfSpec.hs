{-# LANGUAGE OverloadedStrings, ScopedTypeVariables #-}
-- | The URDF reader: every shared file loads; UR5 from DH and from its URDF agree; malformed files
-- get errors naming the element; mimic joints couple.
module VProf.Kinematics.UrdfSpec (spec) where

import Control.Exception (IOException, try)
import Control.Monad (forM_)
import qualified Data.ByteString.Lazy.Char8 as BL
import Data.List (isInfixOf)
import qualified Data.Vector.Unboxed as U
import System.FilePath ((</>))
import Test.Hspec
import Test.QuickCheck

import Support.FkOracle
import Support.Gen
import Support.Reference
import VProf.Kinematics
import VProf.Kinematics.Format.Urdf
import VProf.Kinematics.Library

urdfTips :: [(FilePath, String, Int)]
urdfTips =
  [ ("irb140.urdf", "tool0", 6), ("kinova.urdf", "j2s6s200_end_effector", 6), ("kr210l150.urdf", "tool0", 6)
  , ("kuka_iiwa_model.urdf", "lbr_iiwa_link_7", 7), ("panda.urdf", "panda_link8", 7), ("ur10_robot.urdf", "tool0", 6)
  , ("ur5_robot.urdf", "tool0", 6), ("xarm7.urdf", "link_eef", 7) ]

wrap :: String -> BL.ByteString
wrap body = BL.pack ("<robot name=\"t\"><link name=\"a\"/><link name=\"b\"/><link name=\"c\"/>" ++ body ++ "</robot>")

errs :: BL.ByteString -> [String]
errs = either id (const []) . readUrdf defaultUrdfOptions {urdfBase = Just "a", urdfTip = Just "c"}

-- | The URDF UR5 is the library's DH UR5 with the base turned π about z.
ur5Agree :: Robot -> Property
ur5Agree u =
  let Right d = lookupRobot "ur5"
      cu = compile u
      cd = compile d
  in forAllQ cu $ \q ->
       let a = forward cu q
           b = compose (rotZ pi) (forward cd q)
       in counterexample (show (toRows a, toRows b)) $ maximum (zipWith (\x y -> abs (x - y)) (toRows a) (toRows b)) < 1e-9

spec :: Spec
spec = do
  describe "shared URDF files" $
    forM_ urdfTips $ \(file, tip, n) -> it (file ++ " loads with " ++ show n ++ " joints to " ++ tip) $ do
      dir <- sharedDir
      r <- readUrdfFile defaultUrdfOptions {urdfTip = Just tip} (dir </> "data" </> "urdf" </> file)
      either (expectationFailure . unlines) (\rb -> (dof rb, null (validateRobot rb)) `shouldBe` (n, True)) r

  describe "UR5: DH (library) and ur5_robot.urdf" $ do
    eu <- runIO (try (sharedDir >>= \dir -> readUrdfFile defaultUrdfOptions {urdfTip = Just "tool0"} (dir </> "data" </> "urdf" </> "ur5_robot.urdf")))
    it "agree after the base frame (the URDF base_link is turned π about z)" $
      case eu of
        Left (e :: IOException) -> property (counterexample (show e) False)
        Right (Left es) -> property (counterexample (unlines es) False)
        Right (Right u) -> ur5Agree u

  describe "URDF semantics" $ do
    it "origin rpy is Rz(y)·Ry(p)·Rx(r), the axis is normalised, fixed joints fold, against the oracle" $ do
      let doc = wrap $ concat
            [ "<joint name=\"j1\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>"
            , "<origin xyz=\"0.1 -0.2 0.3\" rpy=\"0.3 -0.7 1.1\"/><axis xyz=\"0 2 2\"/><limit lower=\"-3\" upper=\"3\"/></joint>"
            , "<joint name=\"f\" type=\"fixed\"><parent link=\"b\"/><child link=\"c\"/><origin xyz=\".5 0 0\" rpy=\"0 0 1.57\"/></joint>" ]
          Right r = readUrdf defaultUrdfOptions {urdfTip = Just "c"} doc
          ch = compile r
      property $ forAll (choose (-3, 3)) $ \q ->
        let o = urdfJoint (0.1, -0.2, 0.3) (0.3, -0.7, 1.1) (0, 2, 2) (Just False) q `mmul` urdfJoint (0.5, 0, 0) (0, 0, 1.57) (1, 0, 0) Nothing 0
        in maxDiff o (matFromRows (toRows4 (forward ch (U.fromList [q])))) < 1e-12
    it "a mimic joint follows its master (multiplier and offset)" $ do
      let doc = wrap $ concat
            [ "<joint name=\"m\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\"/></joint>"
            , "<joint name=\"s\" type=\"prismatic\"><parent link=\"b\"/><child link=\"c\"/><origin xyz=\"1 0 0\"/><axis xyz=\"1 0 0\"/>"
            , "<limit lower=\"0\" upper=\"1\"/><mimic joint=\"m\" multiplier=\"0.5\" offset=\"0.25\"/></joint>" ]
          Right r = readUrdf defaultUrdfOptions {urdfTip = Just "c"} doc
          ch = compile r
          t = forward ch (U.fromList [0.4])
      dof r `shouldBe` 1
      -- prismatic along x by 0.5·0.4 + 0.25 = 0.45, after a turn of 0.4 about z
      (abs (tx t - 1.45 * cos 0.4) < 1e-12, abs (ty t - 1.45 * sin 0.4) < 1e-12) `shouldBe` (True, True)
    it "a mimic joint's limits bound its master: the master's limits are the intersection, and a value inside keeps the mimic inside its own" $
      property $ forAll ((,,,) <$> elements [-2, -0.5, 0.5, 1, 2] <*> choose (-0.5, 0.5) <*> choose (-1.5, 0) <*> choose (0.1, 1.5)) $ \(k, o, ml, w) ->
        let mh = ml + w
            doc = wrap $ concat
              [ "<joint name=\"m\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\"/></joint>"
              , "<joint name=\"s\" type=\"revolute\"><parent link=\"b\"/><child link=\"c\"/><origin xyz=\"1 0 0\"/><axis xyz=\"0 1 0\"/>"
              , "<limit lower=\"", show ml, "\" upper=\"", show mh, "\"/><mimic joint=\"m\" multiplier=\"", show k, "\" offset=\"", show o, "\"/></joint>" ]
            inside q = q >= -1 && q <= 1 && k * q + o >= ml - 1e-12 && k * q + o <= mh + 1e-12
        in case readUrdf defaultUrdfOptions {urdfTip = Just "c"} doc of
             Left e -> counterexample (unlines e) $
                       -- refused only when no master value keeps both within limits
                       all (not . inside) [ -1 + 2 * fromIntegral i / 1000 | i <- [0 .. 1000 :: Int] ]
                       .&&. any ("no value within its limits" `isInfixOf`) e
             Right r -> case map jointLimits (robotJoints r) of
               [Limits lo hi] -> counterexample (show (lo, hi)) $
                 inside lo .&&. inside hi .&&. inside ((lo + hi) / 2)
                 .&&. not (inside (lo - 1e-6)) .&&. not (inside (hi + 1e-6))
               other -> counterexample (show other) False
    it "IK on a URDF with a limited mimic joint never returns a solution that breaks the mimic's limit (was: j3 at 1 rad against +-0.1)" $ do
      let doc = BL.pack $ concat
            [ "<robot name=\"m\"><link name=\"b\"/><link name=\"l1\"/><link name=\"l2\"/><link name=\"l3\"/>"
            , "<joint name=\"j1\" type=\"revolute\"><parent link=\"b\"/><child link=\"l1\"/><origin xyz=\"0 0 0.1\"/><axis xyz=\"0 0 1\"/><limit lower=\"-3\" upper=\"3\"/></joint>"
            , "<joint name=\"j2\" type=\"revolute\"><parent link=\"l1\"/><child link=\"l2\"/><origin xyz=\"0 0 0.3\"/><axis xyz=\"0 1 0\"/><limit lower=\"-3\" upper=\"3\"/></joint>"
            , "<joint name=\"j3\" type=\"revolute\"><parent link=\"l2\"/><child link=\"l3\"/><origin xyz=\"0.3 0 0\"/><axis xyz=\"0 1 0\"/><limit lower=\"-0.1\" upper=\"0.1\"/><mimic joint=\"j2\"/></joint></robot>" ]
          Right r = readUrdf defaultUrdfOptions doc
      map jointLimits (robotJoints r) `shouldBe` [Limits (-3) 3, Limits (-0.1) 0.1]
    it "a chain of 10,000 joints (a daemon's request of 1.4 MB) is read, its tool turned by the sum of the angles; and a mimic chain through it resolves (the reader's lookups were by lists: 15 s and the daemon's guard)" $ do
      let n = 10000 :: Int
          joint i extra = "<joint name=\"j" ++ show i ++ "\" type=\"continuous\"><parent link=\"l" ++ show i ++ "\"/><child link=\"l" ++ show (i + 1)
                          ++ "\"/><axis xyz=\"0 0 1\"/>" ++ extra ++ "</joint>"
          doc = BL.pack ("<robot name=\"s\">" ++ concat [ "<link name=\"l" ++ show i ++ "\"/>" | i <- [0 .. n] ]
                         ++ concatMap (\i -> joint i (if i == n - 1 then "<mimic joint=\"j0\" multiplier=\"2\"/>" else "")) [0 .. n - 1] ++ "</robot>")
          Right r = readUrdf defaultUrdfOptions doc
          qs = U.generate (n - 1) (\i -> 1e-4 * fromIntegral (i `mod` 7))
          Pose _ (Quat w _ _ z) = forwardPose (compile r) qs
          -- the last joint mimics the first at twice its angle
          total = U.sum qs + 2 * U.head qs
      length (robotJoints r) `shouldBe` n - 1
      abs (2 * atan2 z w - total) `shouldSatisfy` (< 1e-9)
    it "a continuous joint has no limits" $ do
      let Right r = readUrdf defaultUrdfOptions {urdfBase = Just "a", urdfTip = Just "b"} (wrap "<joint name=\"c\" type=\"continuous\"><parent link=\"a\"/><child link=\"b\"/></joint>")
      map jointLimits (robotJoints r) `shouldBe` [Limits (-1 / 0) (1 / 0)]

  describe "malformed URDF: clear errors, nothing thrown" $ do
    it "not XML, in words: the line and column or the tags, no Haskell records (were ParseError {errorContexts = …} and Name {nameLocalName = …})" $ do
      errs "<robot><link" `shouldSatisfy` any ("not well-formed XML" `isInfixOf`)
      -- bytes that are not UTF-8 (a binary file): said so with the offset, not in the decoder library's words
      errs "<robot>\231'#\212</robot>" `shouldSatisfy` (\es -> any ("not UTF-8 text (a byte that is not UTF-8 at offset " `isInfixOf`) es
                                                          && not (any ("Data.Conduit" `isInfixOf`) es))
      let bad = [ "<robot name=\"x\"><link name=\"a\"></robot>", "<robot name=\"x\"><link name=\"a\"/>\n<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"</joint></robot>" ]
      mapM_ (\src -> errs src `shouldSatisfy` all (\e -> not ("Name {" `isInfixOf` e) && not ("ParseError" `isInfixOf` e) && not ("errorContexts" `isInfixOf` e))) bad
      errs (bad !! 0) `shouldSatisfy` any ("<link>" `isInfixOf`)
      errs (bad !! 1) `shouldSatisfy` any ("line 2, column 66" `isInfixOf`)
    it "wrong root" $ errs "<model/>" `shouldSatisfy` any ("expected <robot>" `isInfixOf`)
    it "bad origin numbers name the joint and the attribute" $
      errs (wrap "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"c\"/><origin xyz=\"1 x 2\"/><limit lower=\"0\" upper=\"1\"/></joint>")
        `shouldSatisfy` any (\e -> "joint \"j\"" `isInfixOf` e && "origin xyz" `isInfixOf` e)
    it "a zero axis" $
      errs (wrap "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"c\"/><axis xyz=\"0 0 0\"/><limit lower=\"0\" upper=\"1\"/></joint>")
        `shouldSatisfy` any ("zero vector" `isInfixOf`)
    it "a revolute joint without limits" $
      errs (wrap "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"c\"/></joint>")
        `shouldSatisfy` any ("needs a <limit>" `isInfixOf`)
    it "lower above upper" $
      errs (wrap "<joint name=\"j\" type=\"prismatic\"><parent link=\"a\"/><child link=\"c\"/><limit lower=\"2\" upper=\"1\"/></joint>")
        `shouldSatisfy` any ("above upper" `isInfixOf`)
    it "equal lower and upper limits fail validation, naming the joint and its <limit> as the URDF does (was the robot file's joints[0].limits.max)" $
      errs (wrap "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"c\"/><limit lower=\"1\" upper=\"1\"/></joint>")
        `shouldSatisfy` any (\e -> "joint \"j\" <limit upper>" `isInfixOf` e && "<limit lower>" `isInfixOf` e)
    it "an unsupported joint type in the chain" $
      errs (wrap "<joint name=\"j\" type=\"floating\"><parent link=\"a\"/><child link=\"c\"/></joint>")
        `shouldSatisfy` any ("not supported" `isInfixOf`)
    it "a missing parent" $
      errs (wrap "<joint name=\"j\" type=\"fixed\"><child link=\"c\"/></joint>") `shouldSatisfy` any ("no <parent" `isInfixOf`)
    it "an unknown tip link" $
      either id (const []) (readUrdf defaultUrdfOptions {urdfBase = Just "a", urdfTip = Just "nope"} (wrap ""))
        `shouldSatisfy` any ("tip link \"nope\"" `isInfixOf`)
    it "a tip not below the base" $
      either id (const []) (readUrdf defaultUrdfOptions {urdfTip = Just "a", urdfBase = Just "c"} (wrap "<joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"c\"/></joint>"))
        `shouldSatisfy` any ("not below" `isInfixOf`)
    it "a link with two parent joints, an undeclared link and a joint from a link to itself are refused, naming them (were dropped silently)" $ do
      errs (wrap "<joint name=\"j1\" type=\"revolute\"><parent link=\"a\"/><child link=\"c\"/><limit lower=\"0\" upper=\"1\"/></joint><joint name=\"j2\" type=\"revolute\"><parent link=\"b\"/><child link=\"c\"/><limit lower=\"0\" upper=\"1\"/></joint>")
        `shouldSatisfy` any (\e -> "link \"c\" is the child of 2 joints" `isInfixOf` e && "\"j2\"" `isInfixOf` e)
      errs (wrap "<joint name=\"j\" type=\"revolute\"><parent link=\"nosuch\"/><child link=\"c\"/><limit lower=\"0\" upper=\"1\"/></joint>")
        `shouldSatisfy` any (\e -> "parent link \"nosuch\"" `isInfixOf` e)
      errs (wrap "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"ghost\"/><limit lower=\"0\" upper=\"1\"/></joint>")
        `shouldSatisfy` any (\e -> "child link \"ghost\"" `isInfixOf` e)
      errs (wrap "<joint name=\"j\" type=\"revolute\"><parent link=\"b\"/><child link=\"b\"/><limit lower=\"0\" upper=\"1\"/></joint>")
        `shouldSatisfy` any ("the same link" `isInfixOf`)
    it "joints that form a loop say so (was 'no joint has a child link')" $
      either id (const []) (readUrdf defaultUrdfOptions
          (wrap ("<joint name=\"j1\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><limit lower=\"-1\" upper=\"1\"/></joint>"
                 ++ "<joint name=\"j2\" type=\"revolute\"><parent link=\"b\"/><child link=\"a\"/><limit lower=\"-1\" upper=\"1\"/></joint>")))
        `shouldSatisfy` any ("form a loop" `isInfixOf`)
    it "a mimic of an unknown joint" $
      errs (wrap "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"c\"/><limit lower=\"0\" upper=\"1\"/><mimic joint=\"ghost\"/></joint>")
        `shouldSatisfy` any ("ghost" `isInfixOf`)
    it "model errors speak of the URDF's elements, not the robot file's links[i] (a 0 multiplier said links[1].drive[0].coefficient); a multiplier of 1e300 is refused" $ do
      let two extra = wrap ("<joint name=\"j1\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\"/></joint>"
                            ++ "<joint name=\"j2\" type=\"revolute\"><parent link=\"b\"/><child link=\"c\"/>" ++ extra ++ "</joint>")
          says frags = (`shouldSatisfy` (\es -> any (\e -> all (`isInfixOf` e) frags) es))
      says ["the joint into link \"c\" <mimic multiplier> = 0.0", "non-zero"] (errs (two "<limit lower=\"-1\" upper=\"1\"/><mimic joint=\"j1\" multiplier=\"0\"/>"))
      says ["the joint into link \"c\" <mimic multiplier> = 1.0e300", "at most 1e6"] (errs (two "<limit lower=\"-1\" upper=\"1\"/><mimic joint=\"j1\" multiplier=\"1e300\"/>"))
      says ["the joint into link \"c\" <origin xyz> = 1.0e12", "1e9 m"] (errs (two "<origin xyz=\"1e12 0 0\"/><limit lower=\"-1\" upper=\"1\"/>"))
      -- a ratio of a few couples as before
      fmap (length . robotJoints) (readUrdf defaultUrdfOptions (two "<limit lower=\"-1\" upper=\"1\"/><mimic joint=\"j1\" multiplier=\"-3\"/>")) `shouldBe` Right 1
    it "the base is the root of the tip's tree: a link no joint touches and a second tree do not stop it" $ do
      let arm = "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"c\"/><axis xyz=\"0 0 1\"/><limit lower=\"0\" upper=\"1\"/></joint>"
          other = "<link name=\"d\"/><link name=\"e\"/><joint name=\"k\" type=\"revolute\"><parent link=\"d\"/><child link=\"e\"/><axis xyz=\"0 0 1\"/><limit lower=\"0\" upper=\"1\"/></joint>"
      -- link b of 'wrap' is touched by no joint
      fmap (map jointName . robotJoints) (readUrdf defaultUrdfOptions (wrap arm)) `shouldBe` Right ["j"]
      fmap (map jointName . robotJoints) (readUrdf defaultUrdfOptions {urdfTip = Just "e"} (wrap (arm ++ other))) `shouldBe` Right ["k"]
      either id (const []) (readUrdf defaultUrdfOptions (wrap (arm ++ other)))
        `shouldSatisfy` any (\e -> "2 leaf links (c e)" `isInfixOf` e && "--tip" `isInfixOf` e)
      either id (const []) (readUrdf defaultUrdfOptions (wrap ""))
        `shouldSatisfy` any ("no <joint>" `isInfixOf`)
    it "a missing file" $ do
      r <- readUrdfFile defaultUrdfOptions "/nonexistent/robot.urdf"
      either id (const []) r `shouldSatisfy` any ("cannot read" `isInfixOf`)
