-- | A strict structural check of protobuf wire bytes against @vprof.proto@.
--
-- Debian's @protobuf@ package decodes leniently: a field whose length runs past the end
-- of the message, or a string that is not UTF-8, is silently dropped, so truncated or
-- corrupted bytes would decode to a "valid" request with missing fields. This walker
-- rejects what protoc's parsers reject (bad tags, wire types 3/4/6/7, varints over 10
-- bytes, lengths past the end, invalid UTF-8 in string fields, packed doubles whose
-- length is not a multiple of 8) and, more strictly than protoc, a known field sent with
-- the wrong wire type (which the Haskell decoder would misread). Repeated numbers in the
-- unpacked encoding are legal protobuf and taken (proto3 encoders write them packed, others
-- may not); the Haskell decoder drops them, so a message is packed ("VProf.Wire.Packing")
-- before it is decoded. Unknown fields are walked and skipped, as protoc does.
module VProf.Wire.Validate
  ( validateWire
  , MsgType (..)
  ) where

import Data.Bits ((.&.), shiftR)
import qualified Data.ByteString as B
import qualified Data.Text.Encoding as TE

import VProf.Wire.Schema
import VProf.Wire.Varint (VarintResult (..), decodeVarint)

-- | @Right ()@ when the bytes are a well-formed encoding of the message type; otherwise a
-- message saying where (byte offset, field path) and what is wrong.
validateWire :: MsgType -> B.ByteString -> Either String ()
validateWire = go (0 :: Int) ""
  where
    go depth path t bs
      | depth > 32 = Left ("nesting deeper than 32 at " ++ place path)
      | B.null bs = Right ()
      | otherwise = do
          (tag, used) <- varint path bs
          let num = tag `shiftR` 3
              wt = tag .&. 7
              rest = B.drop used bs
              -- the field by its name, as a path from the top message (request.profile.route_length);
              -- an unknown one by its number
              here = (if null path then "" else path ++ ".") ++ maybe ("#" ++ show num) id (fieldName t num)
          if num == 0 || num > 536870911 then Left ("bad field number " ++ show num ++ " at " ++ place path) else Right ()
          (payload, rest') <- case wt of
            0 -> (\(_, u) -> (B.empty, B.drop u rest)) <$> varint here rest
            1 -> fixed here 8 rest
            5 -> fixed here 4 rest
            2 -> do
              (len, u) <- varint here rest
              let body = B.drop u rest
              if len > fromIntegral (B.length body)
                then Left ("field " ++ here ++ ": length " ++ show len ++ " runs past the end ("
                           ++ show (B.length body) ++ " bytes left)")
                else Right (B.splitAt (fromIntegral len) body)
            _ -> Left ("field " ++ here ++ ": wire type " ++ show wt ++ " is not supported")
          case (fields t num, wt) of
            (Nothing, _) -> Right ()
            (Just KVarint, 0) -> Right ()
            (Just KF64, 1) -> Right ()
            (Just KPackedF64, 1) -> Right ()
            (Just KPackedF64, 2)
              | B.length payload `mod` 8 == 0 -> Right ()
              | otherwise -> Left ("field " ++ here ++ ": packed doubles of " ++ show (B.length payload) ++ " bytes")
            (Just KPackedVarint, 0) -> Right ()
            (Just KPackedVarint, 2) -> varints here payload
            (Just KStr, 2) -> either (const (Left ("field " ++ here ++ ": string is not valid UTF-8"))) (const (Right ()))
                                     (TE.decodeUtf8' payload)
            (Just (KMsg sub), 2) -> go (depth + 1) here sub payload
            (Just k, _) -> Left ("field " ++ here ++ ": wire type " ++ show wt ++ " where the schema has " ++ kindWords k)
          go depth path t rest'
    kindWords = \case
      KVarint -> "a varint (wire type 0)"
      KF64 -> "a double (wire type 1)"
      KStr -> "a string (wire type 2)"
      KMsg sub -> "a " ++ messageName sub ++ " message (wire type 2)"
      KPackedF64 -> "repeated doubles (wire type 2, or 1 each)"
      KPackedVarint -> "repeated integers (wire type 2, or 0 each)"
    varints path bs
      | B.null bs = Right ()
      | otherwise = varint path bs >>= \(_, u) -> varints path (B.drop u bs)
    varint path bs = case decodeVarint bs of
      VarintOk v u -> Right (v, u)
      VarintIncomplete -> Left ("truncated varint at " ++ place path)
      VarintMalformed -> Left ("varint of more than 10 bytes or beyond 64 bits at " ++ place path)
    place path = if null path then "the message's top level (a field tag)" else "field " ++ path
    fixed path n bs
      | B.length bs < n = Left ("field " ++ path ++ ": truncated fixed" ++ show (n * 8))
      | otherwise = Right (B.empty, B.drop n bs)
