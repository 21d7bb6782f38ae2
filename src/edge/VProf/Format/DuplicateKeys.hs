-- | Keys that appear more than once in one mapping of a YAML or JSON document. The YAML and
-- JSON decoders keep one of the values without a word, so a task file with @clearance@ twice
-- would be read with one of its two values; the readers (task files, robot files, profile
-- requests and profiles as JSON) refuse such a file, naming each repeated key by its path, e.g.
-- @targets[2].position@.
module VProf.Format.DuplicateKeys
  ( duplicateKeys
  , duplicateKeyErrors
  , duplicateJsonKeyErrors
  ) where

import Control.Exception (SomeException, evaluate, try)
import Control.Monad.Trans.Resource (runResourceT)
import Data.Aeson.Parser (jsonNoDup)
import Data.Attoparsec.ByteString (parseOnly)
import qualified Data.ByteString as B
import Data.Conduit (runConduit, (.|))
import Data.List (isInfixOf)
import qualified Data.Set as Set
import qualified Data.Text as T
import Data.Yaml.Parser (RawDoc (..), YamlValue (..), sinkRawDoc)
import System.IO.Unsafe (unsafePerformIO)
import qualified Text.Libyaml as L

-- | The path of every key repeated in a mapping, in document order. A document libyaml cannot
-- parse has none here: the decoder's own error says what is wrong with it. (The parse runs in
-- IO through libyaml; it reads nothing but the bytes, as "Data.Yaml"'s own pure decoder.)
duplicateKeys :: B.ByteString -> [String]
duplicateKeys bs = unsafePerformIO $ do
  r <- try (runResourceT (runConduit (L.decode bs .| sinkRawDoc)) >>= \(RawDoc v _) -> evaluate (force' (walk "" v)))
  pure $ case r of
    Left (_ :: SomeException) -> []
    Right ks -> ks
  where
    force' ks = sum (map length ks) `seq` ks

walk :: String -> YamlValue -> [String]
walk p = \case
  Mapping kvs _ -> [ at p k | k <- repeated (map fst kvs) ] ++ concat [ walk (at p k) v | (k, v) <- kvs ]
  Sequence vs _ -> concat [ walk (p ++ "[" ++ show i ++ "]") v | (i, v) <- zip [0 :: Int ..] vs ]
  _ -> []
  where
    at q k = if null q then T.unpack k else q ++ "." ++ T.unpack k

-- | Each key that comes again after its first appearance, once.
repeated :: [T.Text] -> [T.Text]
repeated = go Set.empty Set.empty
  where
    go _ _ [] = []
    go seen told (k : ks)
      | k `Set.member` seen && not (k `Set.member` told) = k : go seen (Set.insert k told) ks
      | otherwise = go (Set.insert k seen) told ks

-- | One message per repeated key.
duplicateKeyErrors :: B.ByteString -> [String]
duplicateKeyErrors bs = [ k ++ ": the key appears more than once (which value was meant?)" | k <- duplicateKeys bs ]

-- | 'duplicateKeyErrors' for a JSON document, as fast as a JSON parse in the common case: aeson's
-- parser tells whether any key repeats (a 4.7 MB request of 100,000 speed zones in 0.2 s, where
-- the walk through libyaml takes 0.8 s), and only then the walk names them by their paths.
duplicateJsonKeyErrors :: B.ByteString -> [String]
duplicateJsonKeyErrors bs = case parseOnly jsonNoDup bs of
  Left e | "duplicate key" `isInfixOf` e -> case duplicateKeyErrors bs of
    [] -> [e]
    es -> es
  _ -> []
