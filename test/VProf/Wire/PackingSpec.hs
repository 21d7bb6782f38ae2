-- | Repeated numbers sent unpacked, in several runs or both, read as the one packed run
-- protoc writes ("VProf.Wire.Packing"): the oracle is the Haskell encoder's own packed bytes.
module VProf.Wire.PackingSpec (spec) where

import Data.Bits ((.|.), shiftL)
import qualified Data.ByteString as B
import qualified Data.ByteString.Lazy as BL
import qualified Data.ByteString.Builder as BB
import Data.ProtocolBuffers (getField, putField)
import Data.Word (Word32, Word64)
import Test.Hspec
import Test.QuickCheck

import VProf.Wire.Messages
import VProf.Wire.Packing (packRepeated)
import VProf.Wire.Validate (MsgType (..), validateWire)
import VProf.Wire.Varint (encodeVarint)

tagged :: Word64 -> Word64 -> B.ByteString
tagged num wt = encodeVarint ((num `shiftL` 3) .|. wt)

delimited :: Word64 -> B.ByteString -> B.ByteString
delimited num body = tagged num 2 <> encodeVarint (fromIntegral (B.length body)) <> body

double :: Double -> B.ByteString
double = BL.toStrict . BB.toLazyByteString . BB.doubleLE

-- | Elements cut into consecutive pieces, each written packed (one run) or unpacked (one tag
-- an element), as an encoder may.
data Piece = PackedRun | Unpacked deriving (Show, Eq)

encodePieces :: Word64 -> (a -> B.ByteString) -> Word64 -> [(Piece, [a])] -> B.ByteString
encodePieces num enc unpackedWt = B.concat . map piece
  where
    piece (PackedRun, xs) = delimited num (B.concat (map enc xs))
    piece (Unpacked, xs) = B.concat [ tagged num unpackedWt <> enc x | x <- xs ]

genPieces :: Gen a -> Gen [(Piece, [a])]
genPieces g = listOf ((,) <$> elements [PackedRun, Unpacked] <*> listOf1 g)

spec :: Spec
spec = describe "packRepeated" $ do
  it "an FK request's joints and an IK request's ignored bodies, sent in any mix of packed runs and unpacked elements, decode to every element in order (unpacked ones were refused as MALFORMED)" $
    property $ forAll (genPieces (arbitrary :: Gen Double)) $ \jointPieces ->
      forAll (genPieces (arbitrary :: Gen Word32)) $ \bodyPieces ->
        let joints = concatMap snd jointPieces
            bodies = concatMap snd bodyPieces
            fk = delimited 5 (tagged 4 0 <> encodeVarint 1 <> encodePieces 3 double 1 jointPieces)
            ik = delimited 6 (encodePieces 11 (encodeVarint . fromIntegral) 0 bodyPieces <> tagged 5 0 <> encodeVarint 1)
            readFk = do
              r <- decodeBare (packRepeated TRequest fk) :: Either String RequestMsg
              pure (fmap (getField . fkqJoints) (getField (reqFk r)))
            readIk = do
              r <- decodeBare (packRepeated TRequest ik) :: Either String RequestMsg
              pure (fmap (getField . ikqIgnoreBodies) (getField (reqIk r)))
        in validateWire TRequest fk === Right () .&&. validateWire TRequest ik === Right ()
             .&&. readFk === Right (Just joints) .&&. readIk === Right (Just bodies)
  it "leaves the encoder's own bytes (one packed run a field) as they are" $
    property $ \xs ys ->
      let Right fk = decodeBare (runOf 3 (map double xs)) :: Either String FkRequestMsg
          Right ik = decodeBare (runOf 11 (map (encodeVarint . fromIntegral) (ys :: [Word32]))) :: Either String IkRequestMsg
          Right r0 = decodeBare B.empty :: Either String RequestMsg
          msg = encodeBare r0 { reqFk = putField (Just fk), reqIk = putField (Just ik) }
      in packRepeated TRequest msg === msg
  where
    runOf num elems = if null elems then B.empty else delimited num (B.concat elems)
