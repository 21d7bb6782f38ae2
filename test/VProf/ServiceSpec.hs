-- | The daemon's robustness tests against the real generator (see "Support.Robustness").
module VProf.ServiceSpec (spec) where

import Test.Hspec

import Support.Robustness
import VProf.Service (service)

spec :: Spec
spec = robustnessSpec (HandlerUnderTest service True)
