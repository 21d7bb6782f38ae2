-- | Stand-alone driver for the closed-form IK spec (the project's suite finds the spec
-- through hspec-discover). A module of its own name, so that hpack can list it:
--
-- > ghc -O1 -main-is CfMain -isrc/core -itest -outputdir /tmp/cf-build -o /tmp/cf-test test/CfMain.hs
module CfMain (main) where

import Test.Hspec (hspec)
import qualified VProf.Kinematics.ClosedFormSpec as ClosedForm

main :: IO ()
main = hspec ClosedForm.spec
