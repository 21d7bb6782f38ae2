{-# LANGUAGE OverloadedStrings #-}
module VProf.Wire.EnvelopeSpec (spec) where

import Data.ProtocolBuffers (getField, putField)
import qualified Data.Text as T
import Test.Hspec

import Support.TestHandler
import VProf.Wire.Envelope
import VProf.Wire.Messages

spec :: Spec
spec = describe "classify" $ do
  let ping = PingMsg (putField (Just "p"))
      prof = simpleProfileRequest 1
  it "accepts exactly one body" $ do
    classify (requestWith 1 Nothing Nothing (Just ping)) `shouldBe` Right (InPing ping)
    classify (requestWith 1 (Just prof) Nothing Nothing) `shouldBe` Right (InProfile prof)
  it "rejects an empty envelope naming body" $
    case classify (requestWith 1 Nothing Nothing Nothing) of
      Left e -> do
        getEnum (getField (errCode e)) `shouldBe` ErrInvalidArgument
        getField (errField e) `shouldBe` Just "body"
        orDefault (getField (errMessage e)) `shouldSatisfy` T.isInfixOf "exactly one"
      Right b -> expectationFailure (show b)
  it "rejects two bodies naming them" $
    case classify (requestWith 1 (Just prof) Nothing (Just ping)) of
      Left e -> do
        getField (errField e) `shouldBe` Just "body"
        orDefault (getField (errMessage e)) `shouldSatisfy` T.isInfixOf "profile, ping"
      Right b -> expectationFailure (show b)
