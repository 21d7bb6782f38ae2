-- | The daemon's robustness tests against the real generator (see "VProf.Robustness").
module VProf.ServiceServerSpec (spec) where

import Test.Hspec

import VProf.Robustness
import VProf.Service (service)

spec :: Spec
spec = robustnessSpec (HandlerUnderTest service True)
