-- | Repeated numbers in the packed encoding, whatever the sender wrote. Protobuf lets an
-- encoder write a repeated number field packed (one length-delimited run) or unpacked (one
-- tag per element), even both and in several runs, which a parser must join in order; proto3
-- encoders write one packed run. Debian's @protobuf@ decoder reads only packed runs and drops
-- unpacked elements, so a message is rewritten here, each such field of every message in it
-- as one packed run where it first occurs, before it is decoded. A message whose repeated
-- numbers are each one packed run already is returned as it is (the usual case: nothing is
-- copied). For bytes 'VProf.Wire.Validate.validateWire' accepted; anything it cannot read is
-- copied as it is.
module VProf.Wire.Packing
  ( packRepeated
  ) where

import Data.Bits ((.&.), (.|.), shiftL, shiftR)
import qualified Data.ByteString as B
import qualified Data.ByteString.Builder as BB
import qualified Data.ByteString.Lazy as BL
import qualified Data.Map.Strict as M
import qualified Data.Set as S
import Data.Word (Word64)

import VProf.Wire.Schema
import VProf.Wire.Varint (VarintResult (..), decodeVarint, encodeVarint)

-- | One field as read: its number, its wire type, the bytes of the whole field (tag
-- included) and the bytes of its value (a varint's or a fixed number's own bytes, a
-- length-delimited field's body). What cannot be read is one field of number 0, copied.
data Field = Field !Word64 !Word64 !B.ByteString !B.ByteString

-- | The message with every repeated number field, in it and in the messages within it, one
-- packed run.
packRepeated :: MsgType -> B.ByteString -> B.ByteString
packRepeated t bs
  | needsPacking 0 t bs = BL.toStrict (BB.toLazyByteString (rewrite 0 t bs))
  | otherwise = bs

-- | Messages nest at most this deep ('VProf.Wire.Validate' refuses deeper ones).
maxDepth :: Int
maxDepth = 32

-- | Whether the message, or one within it, has a repeated number field unpacked or in more
-- than one run.
needsPacking :: Int -> MsgType -> B.ByteString -> Bool
needsPacking depth t bs = depth <= maxDepth && go S.empty (readFields bs)
  where
    go _ [] = False
    go seen (Field num wt _ val : rest)
      | isPackedIn t num = wt /= 2 || S.member num seen || go (S.insert num seen) rest
      | Just (KMsg sub) <- fields t num, wt == 2, needsPacking (depth + 1) sub val = True
      | otherwise = go seen rest

isPackedIn :: MsgType -> Word64 -> Bool
isPackedIn t num = case fields t num of
  Just KPackedF64 -> True
  Just KPackedVarint -> True
  _ -> False

rewrite :: Int -> MsgType -> B.ByteString -> BB.Builder
rewrite depth t bs = mconcat (zipWith emit [0 :: Int ..] fs)
  where
    fs = readFields bs
    -- each repeated number field's elements in order (a packed run's body is its elements'
    -- bytes, an unpacked element's value one element), and where it first occurs
    runs = M.fromListWith (flip (<>)) [ (num, BB.byteString val) | Field num _ _ val <- fs, isPackedIn t num ]
    firsts = M.fromListWith (\_ a -> a) [ (num, i) | (i, Field num _ _ _) <- zip [0 ..] fs, isPackedIn t num ]
    emit i (Field num wt raw val)
      | isPackedIn t num = if M.lookup num firsts == Just i then delimited num (M.findWithDefault mempty num runs) else mempty
      | Just (KMsg sub) <- fields t num, wt == 2, depth < maxDepth = delimited num (rewrite (depth + 1) sub val)
      | otherwise = BB.byteString raw
    delimited num body =
      let b = BL.toStrict (BB.toLazyByteString body)
      in BB.byteString (encodeVarint ((num `shiftL` 3) .|. 2)) <> BB.byteString (encodeVarint (fromIntegral (B.length b))) <> BB.byteString b

-- | The fields of a message in order.
readFields :: B.ByteString -> [Field]
readFields bs
  | B.null bs = []
  | otherwise = case decodeVarint bs of
      VarintOk tag used ->
        let num = tag `shiftR` 3
            wt = tag .&. 7
            rest = B.drop used bs
            field valueStart valueLen =
              let total = used + valueStart + valueLen
              in if total > B.length bs then [unreadable]
                 else Field num wt (B.take total bs) (B.take valueLen (B.drop (used + valueStart) bs)) : readFields (B.drop total bs)
        in case wt of
             0 -> case decodeVarint rest of
                    VarintOk _ u -> field 0 u
                    _ -> [unreadable]
             1 -> field 0 8
             5 -> field 0 4
             2 -> case decodeVarint rest of
                    VarintOk len u | len <= fromIntegral (B.length rest) -> field u (fromIntegral len)
                    _ -> [unreadable]
             _ -> [unreadable]
      _ -> [unreadable]
  where unreadable = Field 0 7 bs bs
