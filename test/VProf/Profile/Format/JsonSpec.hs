{-# LANGUAGE OverloadedStrings #-}
-- | Requests in proto3 JSON: numbers may also be written as strings, including "NaN",
-- "Infinity" and "-Infinity"; those parse, and validation then rejects the non-finite ones
-- by field name and value.
module VProf.Profile.Format.JsonSpec (spec) where

import qualified Data.ByteString.Lazy.Char8 as BLC
import Data.List (intercalate, isInfixOf)
import Test.Hspec
import Test.QuickCheck

import qualified Data.Aeson as A
import Data.Scientific (fromFloatDigits, toRealFloat)
import VProf.Profile.Format.Json (profileJson, profileToJson, requestFromJson)
import VProf.Profile.Generate (generatePure)

import Support.Arbitrary (RandomRequest (..))
import VProf.Profile.Request
import VProf.Units

-- | A valid request with one field set to the given JSON text (replacing its default).
withField :: String -> String -> BLC.ByteString
withField name value = BLC.pack $
  "{" ++ intercalate ", " [ show k ++ ": " ++ v | (k, v) <- (name, value) : filter ((/= name) . fst) base ] ++ "}"
  where
    base = [ ("route_length", "10"), ("speed_limits", "[{\"start_distance\": 0, \"velocity\": 2}]")
           , ("min_acceleration", "-1"), ("max_acceleration", "1"), ("min_jerk", "-1"), ("max_jerk", "1") ]

routeLength :: BLC.ByteString -> Either String Double
routeLength bs = si . rqRouteLength <$> requestFromJson bs

errorsOf :: BLC.ByteString -> [String]
errorsOf bs = case requestFromJson bs of
  Left e -> ["parse: " ++ e]
  Right rq -> either (map renderFieldError) (const []) (validate rq)

spec :: Spec
spec = do
  it "a double written as a string reads as the number" $ property $ \x ->
    routeLength (withField "route_length" (show (show (x :: Double)))) === Right x
  it "refuses a key a letter or two from a field's name, naming the field meant (time_stpe and end_velocty were passed over: the run took the default time step and end velocity); other unknown keys (an example's name and note) are passed over" $ do
    requestFromJson (withField "time_stpe" "0.01") `shouldBe` Left "time_stpe: unknown field; did you mean time_step?"
    requestFromJson (withField "EndVelocity" "1") `shouldBe` Left "EndVelocity: unknown field; did you mean end_velocity?"
    requestFromJson (withField "end-tolerance" "0.001") `shouldBe` Left "end-tolerance: unknown field; did you mean end_tolerance?"
    requestFromJson (BLC.pack "{\"route_length\": 10, \"speed_limits\": [{\"start_distance\": 0, \"velocty\": 2}]}")
      `shouldBe` Left "speed_limits[0].velocty: unknown field; did you mean velocity?"
    fmap (si . rqRouteLength) (requestFromJson (withField "name" "\"a case\"")) `shouldBe` Right 10
    fmap (si . rqRouteLength) (requestFromJson (withField "note" "\"a note\"")) `shouldBe` Right 10
    fmap (fmap si . rqTimeStep) (requestFromJson (withField "timeStep" "0.01")) `shouldBe` Right (Just 0.01)
  it "a file that is not JSON is said so with at most 20 characters of where the parser stopped, the bytes that are not printable escaped (a binary file's bytes went to the terminal)" $
    property $ \bytes -> not (null bytes) ==>
      let src = BLC.pack (map (toEnum . (`mod` 256)) (0xff : bytes :: [Int]))
      in case requestFromJson src of
           Left e -> counterexample e (all (\c -> c >= ' ' && c <= '~') e .&&. length e < 200)
           Right _ -> property False
  it "accepts the lowerCamelCase name and an integer as a string" $ do
    fmap rqMaxIterations (requestFromJson (withField "maxIterations" "\"50\"")) `shouldBe` Right (Just 50)
  it "\"NaN\", \"Infinity\" and \"-Infinity\" parse; validation names the field and the value" $ do
    errorsOf (withField "route_length" "\"NaN\"") `shouldBe` ["route_length = NaN m: must be a finite number"]
    errorsOf (withField "max_jerk" "\"Infinity\"") `shouldBe` ["max_jerk = Infinity m/s³: must be a finite number"]
    errorsOf (withField "time_step" "\"-Infinity\"") `shouldBe` ["time_step = -Infinity s: must be a finite number"]
  it "a string that is not a number is a parse error naming the field" $
    case requestFromJson (withField "end_tolerance" "\"ten\"") of
      Left e -> e `shouldSatisfy` ("end_tolerance" `isInfixOf`)
      Right rq -> expectationFailure (show rq)
  it "a parse error names the field as the request does, a zone by its place, without the parser's \"Error in $\" notation, and shows the value as JSON writes it" $ do
    either id (const "parsed") (requestFromJson (withField "route_length" "true")) `shouldBe` "route_length: expected a number, got true"
    case requestFromJson (BLC.pack "{\"route_length\": 10, \"speed_limits\": [{\"velocity\": 1}, {\"start_distance\": \"q\", \"velocity\": 2}]}") of
      Left e -> do
        e `shouldSatisfy` ("speed_limits[1].start_distance: " `isInfixOf`)
        e `shouldNotSatisfy` ("Error in" `isInfixOf`)
      Right rq -> expectationFailure (show rq)
  it "a UTF-8 byte-order mark before the request is passed over (it was 'not a valid json value')" $
    fmap (si . rqRouteLength) (requestFromJson (BLC.pack "\xEF\xBB\xBF" <> withField "route_length" "12.5")) `shouldBe` Right 12.5
  it "the CLI's fast JSON of a profile reads back as the same value as the aeson rendering (every number the same double)" $
    withMaxSuccess 100 $ property $ \(RandomRequest rq) ->
      let r = generatePure rq in fmap asDoubles (A.decode (profileJson r)) === Just (asDoubles (profileToJson r))

-- | Numbers as the doubles they read back to: two shortest digit strings of one double are
-- different decimals but the same number to a reader.
asDoubles :: A.Value -> A.Value
asDoubles = \case
  A.Number n -> A.Number (fromFloatDigits (toRealFloat n :: Double))
  A.Array xs -> A.Array (fmap asDoubles xs)
  A.Object o -> A.Object (fmap asDoubles o)
  v -> v
