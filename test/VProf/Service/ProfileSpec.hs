-- | The daemon's profile handler on what only the wire can send: an algorithm number this
-- version does not know.
module VProf.Service.ProfileSpec (spec) where

import qualified Data.ByteString as B
import Data.ProtocolBuffers (getField)
import Data.Word (Word8)
import Test.Hspec

import Support.TestHandler (simpleProfileRequest)
import Support.WireError (errorShouldBe)
import VProf.Service.Profile (serveProfile)
import VProf.Wire.Messages

-- | The request with field 17 (algorithm, varint: tag 0x88 0x01) appended as sent.
withAlgorithm :: [Word8] -> ProfileRequestMsg
withAlgorithm bytes = either error id (decodeBare (encodeBare (simpleProfileRequest 5) <> B.pack (0x88 : 0x01 : bytes)))

spec :: Spec
spec = describe "serveProfile" $ do
  it "refuses an algorithm number it does not know (99, -1 as sent) naming algorithm, instead of running the default" $
    mapM_ (\(bytes, shown) -> do
             rsp <- serveProfile (withAlgorithm bytes)
             errorShouldBe (getField (prsError rsp)) ErrInvalidArgument "algorithm" shown
             getField (prsVelocity rsp) `shouldBe` [])
          [([99], "99"), (replicate 9 0xff ++ [0x01], "-1")]
  it "runs a known one (2: thesis) and says so" $ do
    rsp <- serveProfile (withAlgorithm [2])
    getField (prsError rsp) `shouldBe` Nothing
    getEnum (getField (prsAlgorithm rsp)) `shouldBe` AlgorithmThesis
