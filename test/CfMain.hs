-- Throwaway driver for the closed-form IK spec (the project's test suite uses hspec-discover).
module Main (main) where

import Test.Hspec (hspec)
import qualified VProf.Kinematics.ClosedFormSpec as ClosedForm

main :: IO ()
main = hspec ClosedForm.spec
