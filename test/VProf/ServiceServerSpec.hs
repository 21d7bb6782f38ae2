-- | The daemon's robustness tests against the real generator (see "VProf.Robustness").
module VProf.ServiceServerSpec (spec) where

import Test.Hspec

import VProf.Robustness
import VProf.Service (handleRequest, unsupportedCompress)

spec :: Spec
spec = robustnessSpec (HandlerUnderTest (handleRequest unsupportedCompress) True)
