{-# LANGUAGE OverloadedStrings #-}
-- | Robot files and the built-in library: every library file parses, validates and names its
-- sources; units convert; malformed files, NaN and unknown robots get clear errors.
module VProf.Kinematics.RobotFileSpec (spec) where

import Control.Monad (forM_)
import qualified Data.ByteString.Char8 as B
import Data.Either (isRight)
import Data.List (isInfixOf)
import qualified Data.Vector.Unboxed as U
import Numeric.Units.Dimensional.Prelude (degree, gram, kilo, meter, milli, second, (/~))
import qualified Numeric.Units.Dimensional.Prelude as D
import Test.Hspec

import Support.FkOracle
import VProf.Kinematics
import VProf.Kinematics.Format.RobotFile
import VProf.Kinematics.Library

errsOf :: B.ByteString -> [String]
errsOf = either id (const []) . readRobotYaml

minimal :: String -> B.ByteString
minimal extra = B.pack $ unlines
  [ "name: two-link"
  , "convention: standard-dh"
  , "joints:"
  , "  - {name: J1, limits: [-90, 90], max_velocity: 100}"
  , "  - {name: J2, limits: [-90, 90]}"
  , "links:"
  , "  - {dh: {theta: 0, d: 0, a: 0.5, alpha: 0}}"
  , "  - {dh: {theta: 0, d: 0, a: 0.3, alpha: 0}}"
  , extra ]

spec :: Spec
spec = do
  describe "the built-in library" $ do
    it "has the 18 robots of the issue" $
      length libraryFiles `shouldBe` 18
    forM_ libraryRobots $ \(key, r) -> it (key ++ " parses, validates, names its sources and states payload and reach") $
      case r of
        Left es -> expectationFailure (unlines es)
        Right rb -> do
          validateRobot rb `shouldBe` []
          robotSources rb `shouldSatisfy` (not . null)
          length (robotLinks rb) `shouldSatisfy` (>= dof rb)
          all (not . null . linkCapsules) (robotLinks rb) `shouldBe` True
          if key == "stanford" then pure () else (robotPayload rb, fmap (> 0) (robotReach rb)) `shouldSatisfy` (\(p, q) -> p /= Nothing && q == Just True)
    it "files say their units in the header" $
      forM_ libraryFiles $ \(p, bs) -> (p, "Units" `B.isInfixOf` bs && "units:" `B.isInfixOf` bs) `shouldBe` (p, True)
    it "converts degrees and millimetres to SI" $ do
      let Right ur5 = lookupRobot "ur5"
          Right lite = lookupRobot "Dobot Magician Lite"
      jointLimits (head (robotJoints ur5)) `shouldBe` Limits (-2 * pi) (2 * pi)
      jointMaxVelocity (head (robotJoints ur5)) `shouldBe` Just pi
      robotReach lite `shouldBe` Just 0.34
      map linkGeometry (take 1 (robotLinks lite)) `shouldBe` [DhModified 0 0 0 0.107]
    it "gives limits, speeds, payload and reach as dimensional quantities" $ do
      let Right ur5 = lookupRobot "ur5"
          j1 = head (robotJoints ur5)
      fmap (/~ (degree D./ second)) (angularVelocityLimit j1) `shouldSatisfy` maybe False (\v -> abs (v - 180) < 1e-9)
      fmap (/~ kilo gram) (payloadMass ur5) `shouldBe` Just 5
      fmap (/~ milli meter) (reachLength ur5) `shouldSatisfy` maybe False (\v -> abs (v - 850) < 1e-9)
      either (\(lo, hi) -> (lo /~ degree, hi /~ degree)) (const (0, 0)) (jointLimitsInUnits j1) `shouldSatisfy` (\(lo, hi) -> abs (lo + 360) < 1e-9 && abs (hi - 360) < 1e-9)
    it "unpublished speeds are absent, not guessed" $ do
      let Right puma = lookupRobot "puma560"
          Right lite = lookupRobot "dobot-magician-lite"
      map jointMaxVelocity (robotJoints puma ++ robotJoints lite) `shouldSatisfy` all (== Nothing)
    it "finds a robot by key or by name, ignoring case and punctuation" $ do
      map (fmap robotName . lookupRobot) ["UR5", "ur-5", "abb irb 140", "franka-panda"]
        `shouldSatisfy` all isRight
    it "an unknown robot gets an error listing the library" $
      either id (const "") (lookupRobot "r2d2") `shouldSatisfy` (\e -> "unknown robot" `isInfixOf` e && "ur5e" `isInfixOf` e)
    it "the library UR5 is the reference UR5 but for d1 (0.089159 m, not roboticstoolbox's 0.089459 m)" $ do
      let Right ur5 = lookupRobot "ur5"
          q = [0.3, -1.2, 0.8, 0.1, 1.7, -0.4]
          ch = compile ur5
          o = foldl1 mmul [dhStd th d a al | (th, d, a, al) <- zip4 q [0.089159, 0, 0, 0.10915, 0.09465, 0.0823] [0, -0.425, -0.39225, 0, 0, 0] [pi / 2, 0, 0, pi / 2, -pi / 2, 0]]
      maxDiff o (matFromRows (toRows4 (forward ch (U.fromList q)))) `shouldSatisfy` (< 1e-12)
    it "the library Dobot Magician Lite is at (204.72, 0, 242) mm at q = 0 (robots.md)" $ do
      let Right lite = lookupRobot "dobot-magician-lite"
          V3 x y z = translation (forward (compile lite) (U.replicate 4 0))
      (abs (x - 0.20472), abs y, abs (z - 0.242)) `shouldSatisfy` (\(a, b, c) -> a < 1e-12 && b < 1e-12 && c < 1e-12)

  describe "a minimal robot file" $ do
    it "reads" $ fmap dof (readRobotYaml (minimal "")) `shouldBe` Right 2
    it "JSON is accepted too" $
      fmap dof (readRobotYaml "{\"name\": \"j\", \"convention\": \"modified-dh\", \"joints\": [{\"name\": \"a\", \"limits\": [-1, 1]}], \"links\": [{\"dh\": {\"d\": 0.1}}]}")
        `shouldBe` Right 1

  describe "malformed robot files: every problem, with its path" $ do
    it "not YAML" $ errsOf "name: [unclosed" `shouldSatisfy` any ("not valid YAML" `isInfixOf`)
    it "not a mapping" $ errsOf "- 1\n- 2\n" `shouldSatisfy` any ("expected a mapping" `isInfixOf`)
    it "missing fields are all reported" $
      errsOf "description: x\n" `shouldSatisfy` (\es -> any ("name: missing" `isInfixOf`) es || any (".name" `isInfixOf`) es)
    it "an unknown convention" $
      errsOf (B.pack "name: x\nconvention: euler\njoints: []\nlinks: []\n") `shouldSatisfy` any ("convention" `isInfixOf`)
    it "limits given backwards name the field, value and unit, in the file's units (degrees by default, as typed)" $
      errsOf (B.pack (unlines ["name: x", "convention: standard-dh", "joints:", "  - {name: J1, limits: [90, -90]}", "links:", "  - {dh: {a: 1}}"]))
        `shouldSatisfy` any ("joints[0].limits.max = -90.0 deg: must be above limits.min (90.0)" `isInfixOf`)
    it "every value of an error is in the units the file states (was in SI: 90 deg read as 1.5707963267948966 rad)" $ do
      let file u = B.pack (unlines
            [ "name: x", "convention: standard-dh", "units: " ++ u, "reach: -700"
            , "joints:", "  - {name: J1, limits: [-170, 170], max_velocity: -250}", "  - {name: J2, limits: [0.5, 0.25]}"
            , "links:", "  - {dh: {a: 300}, capsules: [{a: [0, 0, 0], b: [300, 0, 0], radius: -40}]}", "  - {dh: {a: 1}}" ])
          es = errsOf (file "{length: mm, angle: deg}")
      es `shouldSatisfy` any ("joints[0].max_velocity = -250.0 deg/s" `isInfixOf`)
      es `shouldSatisfy` any ("reach = -700.0 mm" `isInfixOf`)
      es `shouldSatisfy` any ("links[0].capsules[0].radius = -40.0 mm" `isInfixOf`)
      es `shouldSatisfy` any ("joints[1].limits.max = 0.25 deg: must be above limits.min (0.5)" `isInfixOf`)
      -- the same file in m and rad: the values as typed, in those units
      let es' = errsOf (file "{length: m, angle: rad}")
      es' `shouldSatisfy` any ("joints[0].max_velocity = -250.0 rad/s" `isInfixOf`)
      es' `shouldSatisfy` any ("reach = -700.0 m" `isInfixOf`)
      es' `shouldSatisfy` any ("joints[1].limits.max = 0.25 rad: must be above limits.min (0.5)" `isInfixOf`)
    it "a wrong-length limits list" $
      errsOf (B.pack (unlines ["name: x", "convention: standard-dh", "joints:", "  - {name: J1, limits: [1]}", "links:", "  - {dh: {a: 1}}"]))
        `shouldSatisfy` any ("joints[0].limits: expected 2 numbers" `isInfixOf`)
    it "a text where a number belongs, and a second error in the same file" $ do
      let es = errsOf (B.pack (unlines ["name: x", "convention: standard-dh", "joints:", "  - {name: J1, limits: [-1, 1], max_velocity: fast}", "  - {name: J2, limits: [-1, oops]}", "links:", "  - {dh: {a: 1}}", "  - {dh: {a: 1}}"]))
      es `shouldSatisfy` any ("joints[0].max_velocity" `isInfixOf`)
      es `shouldSatisfy` any ("joints[1].limits[1]" `isInfixOf`)
    it "NaN (.nan in YAML) is refused with the field" $
      errsOf (minimal "payload: .nan") `shouldSatisfy` any ("payload" `isInfixOf`)
    it "a negative speed" $
      errsOf (B.pack (unlines ["name: x", "convention: standard-dh", "joints:", "  - {name: J1, limits: [-1, 1], max_velocity: -5}", "links:", "  - {dh: {a: 1}}"]))
        `shouldSatisfy` any ("joints[0].max_velocity = -5.0 deg/s" `isInfixOf`)
    it "a joint speed or acceleration no robot has is refused as a wrong unit, in the file's units (1e308 deg/s showed 'speed Infinity' and a cycle of 0 s; 1e-300 gave the planner a TCP acceleration of 1e-303 m/s^2)" $ do
      let file u v a = B.pack (unlines ["name: x", "convention: standard-dh", "units: {length: m, angle: " ++ u ++ "}", "joints:"
                                       , "  - {name: J1, limits: [-1, 1], max_velocity: " ++ v ++ ", max_acceleration: " ++ a ++ "}", "links:", "  - {dh: {a: 1}}"])
          wrong = "(is the unit right?)"
      errsOf (file "deg" "1e308" "100") `shouldSatisfy` any (\e -> "joints[0].max_velocity = 1.0e308 deg/s: must be from 0.001 to 1e6 degrees a second" `isInfixOf` e && wrong `isInfixOf` e)
      errsOf (file "deg" "1e-300" "100") `shouldSatisfy` any ("joints[0].max_velocity = 1.0e-300 deg/s" `isInfixOf`)
      errsOf (file "deg" "180" "1e9") `shouldSatisfy` any ("joints[0].max_acceleration = 1000000000.0 deg/s^2: must be from 0.001 to 1e8 degrees a second squared" `isInfixOf`)
      errsOf (file "rad" "20000" "10") `shouldSatisfy` any ("joints[0].max_velocity = 20000.0 rad/s" `isInfixOf`)
      -- at the bounds and between them: taken
      mapM_ (\(u, v, a) -> errsOf (file u v a) `shouldBe` []) [("deg", "0.001", "1e8"), ("deg", "1e6", "0.001"), ("rad", "3.14", "10"), ("deg", "180", "500")]
    it "a drive naming no joint" $
      errsOf (B.pack (unlines ["name: x", "convention: standard-dh", "joints:", "  - {name: J1, limits: [-1, 1]}", "links:", "  - {dh: {a: 1}, drive: {J9: 1}}"]))
        `shouldSatisfy` any ("links[0].drive.J9" `isInfixOf`)
    it "a joint that drives nothing" $
      errsOf (B.pack (unlines ["name: x", "convention: standard-dh", "joints:", "  - {name: J1, limits: [-1, 1]}", "  - {name: J2, limits: [-1, 1]}", "links:", "  - {dh: {a: 1}, joint: J1}"]))
        `shouldSatisfy` any ("drives no link" `isInfixOf`)
    it "a misspelt or unknown key is an error naming it, at every level (was ignored: limit: left a joint unbounded)" $ do
      let file js ls extra = B.pack (unlines (["name: x", "convention: standard-dh", "joints:"] ++ js ++ ["links:"] ++ ls ++ extra))
          j = "  - {name: J1, limits: [-1, 1]}"
          l = "  - {dh: {a: 1}}"
      errsOf (file ["  - {name: J1, limit: [-10, 10]}"] [l] []) `shouldSatisfy` any ("joints[0].limit: not a known key" `isInfixOf`)
      errsOf (file [j] ["  - {dh: {theta: 0, d: 0, A: -0.39225, alpha: 0}}"] []) `shouldSatisfy` any ("links[0].dh.A: not a known key" `isInfixOf`)
      errsOf (file [j] ["  - {dh: {a: 1}, capsule: []}"] []) `shouldSatisfy` any ("links[0].capsule: not a known key" `isInfixOf`)
      errsOf (file [j] [l] ["paylod: 7"]) `shouldSatisfy` any ("paylod: not a known key" `isInfixOf`)
      errsOf (file [j] [l] ["units: {length: m, angel: deg}"]) `shouldSatisfy` any ("units.angel" `isInfixOf`)
      errsOf (file [j] [l] ["tool: {xyz: [0, 0, 0], rpy: [0, 0, 0], z: 1}"]) `shouldSatisfy` any ("tool.z" `isInfixOf`)
      errsOf (file [j] ["  - {dh: {a: 1}, capsules: [{a: [0, 0, 0], b: [1, 0, 0], r: 0.1}]}"] []) `shouldSatisfy` any ("capsules[0].r: not a known key" `isInfixOf`)
    it "a capsule_radius of 0 or less names capsule_radius (the field written), once" $ do
      let es = errsOf (minimal "capsule_radius: -0.06")
      es `shouldSatisfy` any ("capsule_radius = -6.0e-2" `isInfixOf`)
      length es `shouldBe` 1
    it "a key of the other convention is an error naming it (a dh table under urdf was ignored)" $ do
      let urdfFile = B.pack (unlines ["name: x", "convention: urdf", "joints:", "  - {name: J1, limits: [-1, 1]}", "links:", "  - {origin: {xyz: [0, 0, 0.1]}, axis: [0, 0, 1], dh: {a: 1}}"])
      errsOf urdfFile `shouldSatisfy` any ("links[0].dh: not a key of the urdf convention" `isInfixOf`)
      errsOf (minimal "") `shouldBe` []
      let dhFile = B.pack (unlines ["name: x", "convention: modified-dh", "joints:", "  - {name: J1, limits: [-1, 1]}", "links:", "  - {dh: {a: 1}, axis: [0, 1, 0]}"])
      errsOf dhFile `shouldSatisfy` any ("links[0].axis: not a key of the modified-dh convention" `isInfixOf`)
    it "lengths beyond 1e9 m, angles beyond 1e6 degrees and capsule radii of 0 are refused naming the field (1e200 m gave NaN residuals)" $ do
      let withLink l = B.pack (unlines ["name: x", "convention: standard-dh", "joints:", "  - {name: J1, limits: [-90, 90]}", "links:", l])
      errsOf (withLink "  - {dh: {a: 1e200}}") `shouldSatisfy` any (\e -> "links[0].dh.a" `isInfixOf` e && "is the unit right" `isInfixOf` e)
      errsOf (withLink "  - {dh: {d: -2e9}}") `shouldSatisfy` any ("links[0].dh.d" `isInfixOf`)
      errsOf (withLink "  - {dh: {a: 1, alpha: 1e300}}") `shouldSatisfy` any ("links[0].dh.alpha" `isInfixOf`)
      errsOf (withLink "  - {dh: {a: 1}, capsules: [{a: [0, 0, 0], b: [1, 0, 0], radius: 0}]}") `shouldSatisfy` any ("links[0].capsules[0].radius" `isInfixOf`)
      errsOf (withLink "  - {dh: {a: 1}, capsules: [{a: [0, 0, 0], b: [1e12, 0, 0], radius: 0.1}]}") `shouldSatisfy` any ("links[0].capsules[0]" `isInfixOf`)
      errsOf (B.append (withLink "  - {dh: {a: 1}}") "base: {xyz: [0, 0, 1e10]}\n") `shouldSatisfy` any ("base.xyz" `isInfixOf`)
      -- the largest that pass: a 1e9 m link, no capsules
      errsOf (withLink "  - {dh: {a: 1e9}, capsules: []}") `shouldBe` []
    it "unknown units" $
      errsOf (minimal "units: {length: furlong}") `shouldSatisfy` any ("units.length" `isInfixOf`)
    it "a missing file" $ do
      r <- readRobotFile "/nonexistent/robot.yaml"
      either id (const []) r `shouldSatisfy` any ("cannot read" `isInfixOf`)

  describe "validation of joint vectors" $ do
    let Right ur5 = lookupRobot "ur5"
    it "wrong joint count" $
      map feField (checkJointVector False ur5 (U.fromList [0, 0])) `shouldBe` ["q"]
    it "NaN names the index" $
      map feField (checkJointVector False ur5 (U.fromList [0, 0, 0 / 0, 0, 0, 0])) `shouldBe` ["q[2]"]
    it "out of limits names the joint, value and unit" $
      map renderFieldError (checkJointVector True ur5 (U.fromList [7, 0, 0, 0, 0, 0]))
        `shouldSatisfy` (\es -> length es == 1 && all (\e -> "q[0]" `isInfixOf` e && "rad" `isInfixOf` e && "base" `isInfixOf` e) es)
  where
    zip4 (a : as) (b : bs) (c : cs) (d : ds) = (a, b, c, d) : zip4 as bs cs ds
    zip4 _ _ _ _ = []
