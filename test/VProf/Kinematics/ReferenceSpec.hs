-- | Every case of ../shared/reference/kinematics reproduced to 1e-9 m and 1e-9 in rotation, each
-- robot built from the file's own table or URDF; the independent oracle agrees too.
module VProf.Kinematics.ReferenceSpec (spec) where

import Control.Monad (forM_)
import qualified Data.Map.Strict as Map
import qualified Data.Vector.Unboxed as U
import System.FilePath ((</>))
import Test.Hspec

import Support.FkOracle
import Support.Reference
import VProf.Kinematics.Format.Urdf
import VProf.Kinematics.Forward
import VProf.Kinematics.Ik.Dobot (dobotModel)
import VProf.Kinematics.Model
import VProf.Kinematics.Transform

dhFiles, urdfFiles :: [String]
dhFiles = ["Puma560", "UR3", "UR5", "UR10", "IRB140", "KR5", "Stanford", "Panda", "LWR4", "Cobra600"]
urdfFiles = ["urdf_iiwa_pybullet", "urdf_irb140", "urdf_kinova_j2s6s200", "urdf_kr210", "urdf_panda", "urdf_ur10", "urdf_ur5", "urdf_xarm7"]

-- | Largest difference between a transform and a row-major 4×4 (rotation and translation apart).
diffs :: Tf -> [Double] -> (Double, Double)
diffs t m =
  let rows = toRows t
      idx = [0 .. 11] :: [Int]
      d = [abs (rows !! i - m !! i) | i <- idx]
      isT i = i `mod` 4 == 3
  in (maximum [x | (i, x) <- zip idx d, isT i], maximum [x | (i, x) <- zip idx d, not (isT i)])

spec :: Spec
spec = do
  describe "DH reference files (roboticstoolbox-python)" $
    forM_ dhFiles $ \name -> it (name ++ ": 40 cases to 1e-9") $ do
      dir <- sharedDir
      f <- loadDh (dir </> "reference" </> "kinematics" </> (name ++ ".json"))
      length (dhCases f) `shouldBe` 40
      let ch = compile (dhRobot f)
      forM_ (dhCases f) $ \(q, t) -> do
        let (dp, dr) = diffs (forward ch (U.fromList q)) t
        (dp <= 1e-9 && dr <= 1e-9, q, dp, dr) `shouldBe` (True, q, dp, dr)
        -- the oracle, from the same table, agrees
        let links = zip3 (dhRows f) q [0 :: Int ..]
            step (r, qi, _) =
              let th = rowTheta r + (if rowType r == "R" then qi + rowOffset r else 0)
                  d = rowD r + (if rowType r == "P" then qi + rowOffset r else 0)
              in if dhConvention f == "standard" then dhStd th d (rowA r) (rowAlpha r) else dhMod (rowAlpha r) (rowA r) th d
            o = foldl mmul (matFromRows (dhBase f)) (map step links) `mmul` matFromRows (dhTool f)
        maxDiff o (matFromRows t) `shouldSatisfy` (<= 1e-9)

  describe "URDF reference files (Pinocchio)" $
    forM_ urdfFiles $ \name -> it (name ++ ": 40 cases to 1e-9") $ do
      dir <- sharedDir
      c <- loadUrdfCase (dir </> "reference" </> "kinematics" </> (name ++ ".json"))
      let file = dir </> "data" </> "urdf" </> reverse (takeWhile (/= '/') (reverse (ucUrdf c)))
      er <- readUrdfFile defaultUrdfOptions{urdfTip = Just (ucTip c)} file
      robot <- either (\e -> fail (unlines e)) pure er
      let ch = compile robot
          names = urdfJointNames robot
      length (ucCases c) `shouldBe` 40
      forM_ (ucCases c) $ \(qAll, t) -> do
        let byName = Map.fromList (zip (ucJoints c) qAll)
            q = U.fromList [Map.findWithDefault (0 / 0) n byName | n <- names]
            (dp, dr) = diffs (forward ch q) t
        (dp <= 1e-9 && dr <= 1e-9, dp, dr) `shouldBe` (True, dp, dr)

  describe "Dobot reference files (RoboDK data)" $
    forM_ ["DobotMagicianLite", "DobotMagician"] $ \name -> it (name ++ ": 40 cases to 1e-9 m") $ do
      dir <- sharedDir
      f <- loadDobot (dir </> "reference" </> "kinematics" </> (name ++ ".json"))
      let rows = [(al, a / 1000, d / 1000, th) | [al, a, d, th] <- dbRows f]
          lims = zip (map (* (pi / 180)) (dbMin f)) (map (* (pi / 180)) (dbMax f))
          ch = compile (dobotModel name rows lims)
      length (dbCases f) `shouldBe` 40
      forM_ (dbCases f) $ \(qDeg, tMm) -> do
        let q = map (* (pi / 180)) qDeg
            t = [if i `mod` 4 == 3 then x / 1000 else x | (i, x) <- zip [0 :: Int ..] tMm]
            (dp, dr) = diffs (forward ch (U.fromList q)) t
        (dp <= 1e-9 && dr <= 1e-9, qDeg, dp, dr) `shouldBe` (True, qDeg, dp, dr)
        -- oracle: θ = offset + [q1, q2, q3 − q2, −q3, q4]
        let [q1, q2, q3, q4] = q
            vs = [q1, q2, q3 - q2, -q3, q4]
            o = foldl1 mmul [dhMod al a (th + v) d | ((al, a, d, th), v) <- zip rows vs]
        maxDiff o (matFromRows t) `shouldSatisfy` (<= 1e-9)
