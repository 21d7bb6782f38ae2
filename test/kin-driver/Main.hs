-- | A stand-alone driver running only the kinematics specs (the project's Spec.hs discovers them
-- too). Kept out of the module tree (the directory name is not a module name) so that the test
-- suite does not pick it up:
--   ghc -O1 -isrc/core -isrc/edge -itest -outputdir /tmp/kin-build -o /tmp/kin-test test/kin-driver/Main.hs
module Main (main) where

import Test.Hspec

import qualified VProf.Kinematics.IkSpec
import qualified VProf.Kinematics.JacobianSpec
import qualified VProf.Kinematics.ReferenceSpec
import qualified VProf.Kinematics.RobotFileSpec
import qualified VProf.Kinematics.UrdfSpec

main :: IO ()
main = hspec $ do
  describe "Reference" VProf.Kinematics.ReferenceSpec.spec
  describe "Urdf" VProf.Kinematics.UrdfSpec.spec
  describe "RobotFile" VProf.Kinematics.RobotFileSpec.spec
  describe "Jacobian" VProf.Kinematics.JacobianSpec.spec
  describe "Ik" VProf.Kinematics.IkSpec.spec
