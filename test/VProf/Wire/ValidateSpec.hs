{-# LANGUAGE OverloadedStrings #-}
module VProf.Wire.ValidateSpec (spec) where

import qualified Data.ByteString as B
import Test.Hspec

import Support.TestHandler (pingMsg, profileMsg, simpleProfileRequest)
import VProf.Wire.Messages (encodeBare)
import VProf.Wire.Validate

ok, bad :: MsgType -> B.ByteString -> Expectation
ok t b = validateWire t b `shouldBe` Right ()
bad t b = validateWire t b `shouldSatisfy` either (const True) (const False)

one :: B.ByteString
one = B.pack [0, 0, 0, 0, 0, 0, 0xf0, 0x3f]  -- 1.0 as fixed64

spec :: Spec
spec = describe "validateWire" $ do
  it "accepts what the Haskell encoder writes" $ do
    ok TRequest (encodeBare (pingMsg 3 "ü"))
    ok TRequest (encodeBare (profileMsg 4 (simpleProfileRequest 4)))
    ok TRequest B.empty
  it "skips unknown fields of every wire type" $
    ok TRequest (B.pack [0xf8, 0x06, 0x2a, 0xf9, 0x06] <> one <> B.pack [0xfd, 0x06, 1, 2, 3, 4, 0xfa, 0x06, 1, 9])
  it "rejects a length past the end, also nested" $ do
    bad TRequest (B.pack [0x12, 0x50, 0x01])
    bad TRequest (B.pack [0x22, 0x02, 0x0a, 0x05])          -- ping.payload runs past ping
  it "rejects invalid UTF-8 in a string field" $
    bad TRequest (B.pack [0x22, 0x03, 0x0a, 0x01, 0xff])
  it "rejects group wire types and field number 0" $ do
    bad TRequest (B.pack [0x0b])
    bad TRequest (B.pack [0x00, 0x01])
  it "rejects a known field with the wrong wire type, naming it by its path of field names and what the schema has" $ do
    bad TRequest (B.pack [0x10, 0x05])                      -- profile as a varint
    bad TRequest (B.pack [0x09] <> one)                     -- request_id as fixed64
    validateWire TRequest (B.pack [0x12, 0x02, 0x10, 0x05])  -- profile.route_length as a varint
      `shouldBe` Left "field profile.route_length: wire type 0 where the schema has a double (wire type 1)"
    validateWire TRequest (B.pack [0x12, 0x04, 0x1a, 0x02, 0x08, 0x01])  -- profile.speed_limits[0].start_distance as a varint
      `shouldBe` Left "field profile.speed_limits.start_distance: wire type 0 where the schema has a double (wire type 1)"
  it "rejects truncated varints and fixed64s" $ do
    bad TRequest (B.pack [0x08, 0x80])
    bad TRequest (B.pack [0x12, 0x03, 0x11, 0, 0])          -- profile.route_length cut short
  it "accepts repeated doubles unpacked as well as packed (legal protobuf; they are packed before decoding: VProf.Wire.PackingSpec)" $ do
    ok TResponse (B.pack [0x12, 0x12, 0x21] <> one <> B.pack [0x21] <> one)
    ok TResponse (B.pack [0x12, 0x12, 0x22, 0x10] <> one <> one)
  it "rejects packed doubles whose length is not a multiple of 8" $
    bad TResponse (B.pack [0x12, 0x09, 0x22, 0x07] <> B.take 7 one)
