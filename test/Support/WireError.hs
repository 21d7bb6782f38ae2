-- | What a test expects of an Error message on the wire: its code, the field it names and a
-- part of its text.
module Support.WireError (errorShouldBe) where

import Data.ProtocolBuffers (getField)
import qualified Data.Text as T
import Test.Hspec

import VProf.Wire.Messages

errorShouldBe :: Maybe ErrorMsg -> ErrorCodeEnum -> String -> String -> Expectation
errorShouldBe me code field part = case me of
  Nothing -> expectationFailure ("no error; expected " ++ show code ++ " naming " ++ field)
  Just e -> do
    getEnum (getField (errCode e)) `shouldBe` code
    getField (errField e) `shouldBe` Just (T.pack field)
    fmap (T.isInfixOf (T.pack part)) (getField (errMessage e)) `shouldBe` Just True
