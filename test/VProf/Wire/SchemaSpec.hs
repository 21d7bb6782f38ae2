-- | The wire walkers' field table ("VProf.Wire.Schema") against the contract itself,
-- @proto/vprof/v1/vprof.proto@, read here by a parser of its own: every message of the file
-- has its type, every field its number, name and encoding, and the table has nothing more.
module VProf.Wire.SchemaSpec (spec) where

import Data.List (isPrefixOf)
import Test.Hspec

import VProf.Wire.Schema

-- | A field of the .proto: repeated or not, its type, name and number.
data ProtoField = ProtoField Bool String String Integer deriving (Show)

-- | The messages of a .proto text (no nested messages, as in ours), each with its fields.
protoMessages :: String -> [(String, [ProtoField])]
protoMessages = go . words . concatMap spaced . unlines . map dropComment . lines
  where
    dropComment l = case breakOn "//" l of (a, _) -> a
    spaced c = if c `elem` "{};=[]" then [' ', c, ' '] else [c]
    go ("message" : name : "{" : rest) = let (body, after) = break (== "}") rest in (name, fieldsOf body) : go (drop 1 after)
    go ("enum" : _ : "{" : rest) = go (drop 1 (dropWhile (/= "}") rest))
    go (_ : rest) = go rest
    go [] = []
    fieldsOf ts = case ts of
      "repeated" : ty : name : "=" : num : rest -> ProtoField True ty name (read num) : fieldsOf (skip rest)
      ty : name : "=" : num : rest -> ProtoField False ty name (read num) : fieldsOf (skip rest)
      _ : rest -> fieldsOf rest
      [] -> []
    skip = drop 1 . dropWhile (/= ";")
    breakOn pat s = case [ i | i <- [0 .. length s - length pat], pat `isPrefixOf` drop i s ] of
      i : _ -> splitAt i s
      [] -> (s, "")

enums :: String -> [String]
enums src = [ name | ("enum" : name : _) <- map words (lines src) ]

-- | The encoding the table should give a field of this type.
expectedKind :: [String] -> Bool -> String -> String
expectedKind enumNames rep ty
  | ty == "double" = if rep then "packed doubles" else "double"
  | ty `elem` ["uint64", "uint32", "int32", "int64", "bool"] || ty `elem` enumNames = if rep then "packed varints" else "varint"
  | ty == "string" = "string"
  | otherwise = "message " ++ ty

kindName :: Kind -> String
kindName = \case
  KVarint -> "varint"
  KF64 -> "double"
  KStr -> "string"
  KMsg t -> "message " ++ messageName t
  KPackedF64 -> "packed doubles"
  KPackedVarint -> "packed varints"

spec :: Spec
spec = describe "the wire schema" $ do
  src <- runIO (readFile "proto/vprof/v1/vprof.proto")
  let msgs = protoMessages src
      types = [minBound .. maxBound] :: [MsgType]
  it "has a message type for every message of proto/vprof/v1/vprof.proto, and none more" $ do
    length msgs `shouldSatisfy` (>= 30)
    map fst msgs `shouldMatchList` map messageName types
  it "gives every field of every message its name and its encoding, and knows no other field number" $
    sequence_
      [ do (fieldName t (fromInteger n), fmap kindName (fields t (fromInteger n)))
             `shouldBe` (Just name, Just (expectedKind (enums src) rep ty))
           -- numbers the message does not have are unknown
           [ k | k <- [1 .. 40], k `notElem` map (\(ProtoField _ _ _ m) -> m) fs, Just _ <- [fields t (fromInteger k)] ] `shouldBe` []
      | (mname, fs) <- msgs, t <- types, messageName t == mname, ProtoField rep ty name n <- fs ]
