-- | Repeated keys in YAML and JSON documents: random nested documents, written as JSON and as
-- block YAML, have none; the same document with one key of one mapping written twice has exactly
-- that one, named by its path; and the readers that use it refuse such files, naming the key.
module VProf.Format.DuplicateKeysSpec (spec) where

import qualified Data.ByteString.Char8 as B
import qualified Data.ByteString.Lazy.Char8 as BL
import Data.List (intercalate, isInfixOf, nub)
import System.FilePath ((</>))
import System.IO.Temp (withSystemTempDirectory)
import Test.Hspec
import Test.QuickCheck

import VProf.Format.DuplicateKeys (duplicateJsonKeyErrors, duplicateKeyErrors, duplicateKeys)
import VProf.Kinematics.Format.RobotFile (readRobotYaml)
import VProf.Profile.Format.Json (requestFromJson)
import VProf.Select.Format.Task (readTaskFile)

-- | A document: a number, a list or a mapping (keys as given, in order).
data Doc = Num Int | List [Doc] | Map [(String, Doc)]
  deriving (Show)

-- | Mappings with distinct keys, nested up to the size.
genDoc :: Int -> Gen Doc
genDoc n
  | n <= 0 = Num <$> arbitrary
  | otherwise = frequency
      [ (1, Num <$> arbitrary)
      , (2, List <$> (choose (0, 4) >>= \k -> vectorOf k (genDoc (n `div` 2))))
      , (4, do ks <- nub <$> listOf1 key
               Map <$> mapM (\k -> (,) k <$> genDoc (n `div` 2)) (take 6 ks)) ]
  where key = elements ["a", "b", "speed", "clearance", "x_1", "joint name", "q"]

json :: Doc -> String
json (Num k) = show k
json (List ds) = "[" ++ intercalate ", " (map json ds) ++ "]"
json (Map kvs) = "{" ++ intercalate ", " [ show k ++ ": " ++ json v | (k, v) <- kvs ] ++ "}"

-- | Block YAML at an indentation (lists and mappings that are empty in flow style).
yaml :: Int -> Doc -> String
yaml _ (Num k) = " " ++ show k ++ "\n"
yaml _ (List []) = " []\n"
yaml _ (Map []) = " {}\n"
yaml i (List ds) = "\n" ++ concat [ replicate i ' ' ++ "-" ++ yaml (i + 2) d | d <- ds ]
yaml i (Map kvs) = "\n" ++ concat [ replicate i ' ' ++ show k ++ ":" ++ yaml (i + 2) v | (k, v) <- kvs ]

-- | Every mapping with at least one key, by its path, with a way to write its first key twice.
mappings :: String -> Doc -> [(String, Doc -> Doc)]
mappings _ (Num _) = []
mappings p (List ds) =
  [ (q, \d -> case d of List es -> List [ if j == i then f e else e | (j, e) <- zip [0 ..] es ]; _ -> d)
  | (i, e) <- zip [0 :: Int ..] ds, (q, f) <- mappings (p ++ "[" ++ show i ++ "]") e ]
mappings p (Map kvs) =
  [ (at (fst (head kvs)), \d -> case d of Map ((k, v) : rest) -> Map ((k, v) : (k, Num 7) : rest); _ -> d) | not (null kvs) ]
  ++ [ (q, \d -> case d of Map es -> Map [ if j == i then (k', f v') else (k', v') | (j, (k', v')) <- zip [0 ..] es ]; _ -> d)
     | (i, (k, v)) <- zip [0 :: Int ..] kvs, (q, f) <- mappings (at k) v ]
  where at k = if null p then k else p ++ "." ++ k

spec :: Spec
spec = do
  describe "duplicateKeys" $ do
    it "a document with distinct keys in every mapping has none, as JSON and as YAML" $
      property $ forAll (sized (genDoc . min 12)) $ \d ->
        duplicateKeys (B.pack (json d)) === [] .&&. duplicateKeys (B.pack ("top:" ++ yaml 2 d)) === []
    it "one key written twice in one mapping is found, named by its path, as JSON and as YAML" $
      property $ forAll (sized (genDoc . min 12) `suchThat` (not . null . mappings "")) $ \d ->
        let ms = mappings "" d in
        forAll (choose (0, length ms - 1)) $ \i ->
          let (path, twice) = ms !! i
              d' = twice d
          in counterexample (json d') $ duplicateKeys (B.pack (json d')) === [path] .&&. duplicateKeys (B.pack ("top:" ++ yaml 2 d')) === [(if take 1 path == "[" then "top" else "top.") ++ path]
    it "JSON: the fast check agrees with the walk, with and without a repeated key" $
      property $ forAll (sized (genDoc . min 12)) $ \d ->
        let ms = mappings "" d
            docs = B.pack (json d) : [ B.pack (json (twice d)) | (_, twice) <- take 3 ms ]
        in conjoin [ duplicateJsonKeyErrors b === duplicateKeyErrors b | b <- docs ]
    it "a document libyaml cannot parse has none (the decoder says what is wrong)" $
      duplicateKeys (B.pack "{\"a\": [1, 2") `shouldBe` []
  describe "the readers refuse a repeated key, naming it (one of the values was kept silently)" $ do
    it "a profile request as JSON" $
      requestFromJson (BL.pack "{\"route_length\": 10, \"route_length\": 20, \"speed_limits\": [{\"start_distance\": 0, \"velocity\": 1}], \"max_acceleration\": 1, \"min_acceleration\": -1, \"max_jerk\": 1, \"min_jerk\": -1, \"time_step\": 0.01}")
        `shouldSatisfy` either ("route_length: the key appears more than once" `isInfixOf`) (const False)
    it "a profile request with one field in both spellings (snake_case and lowerCamelCase)" $
      requestFromJson (BL.pack "{\"route_length\": 10, \"routeLength\": 20, \"speed_limits\": [{\"start_distance\": 0, \"velocity\": 1}], \"max_acceleration\": 1, \"min_acceleration\": -1, \"max_jerk\": 1, \"min_jerk\": -1, \"time_step\": 0.01}")
        `shouldSatisfy` either ("route_length and routeLength" `isInfixOf`) (const False)
    it "a robot file" $
      readRobotYaml (B.pack "name: r\nname: s\n") `shouldSatisfy` either (any ("name: the key appears more than once" `isInfixOf`)) (const False)
    it "a task file" $
      withSystemTempDirectory "vprof-dup" $ \dir -> do
        let f = dir </> "task.yaml"
        writeFile f "payload: 1\nclearance: 0.01\nclearance: 0.5\ntargets:\n  - {position: [0.5, 0, 0.3]}\n"
        r <- readTaskFile f
        r `shouldSatisfy` either (any ("clearance: the key appears more than once" `isInfixOf`)) (const False)
    it "a task file's misspelt keys in nested mappings (path, environment, tool_capsule) and a path step below 0.1 mm (ran for minutes)" $
      withSystemTempDirectory "vprof-dup" $ \dir -> do
        let f = dir </> "task.yaml"
            errsOf body = do
              writeFile f ("payload: 1\nclearance: 0.01\n" ++ body)
              either id (const []) <$> readTaskFile f
        errsOf "path: {file: /dev/null, folow: true}\n" >>= (`shouldSatisfy` any ("path.folow: unknown field" `isInfixOf`))
        errsOf "environment: [{file: /dev/null, scael: 0.001}]\ntargets:\n  - {position: [0.5, 0, 0.3]}\n" >>= (`shouldSatisfy` any ("environment[0].scael: unknown field" `isInfixOf`))
        errsOf "tool_capsule: {a: [0, 0, 0], b: [0, 0, 0.1], radus: 0.02}\ntargets:\n  - {position: [0.5, 0, 0.3]}\n" >>= (`shouldSatisfy` any ("tool_capsule.radus: unknown field" `isInfixOf`))
        errsOf "path: {file: /dev/null, follow: true, step: 1.0e-7}\n" >>= (`shouldSatisfy` any ("path.step = 0.0000001 m: must be at least 0.0001 m" `isInfixOf`))
