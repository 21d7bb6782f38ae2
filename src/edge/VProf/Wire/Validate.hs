-- | A strict structural check of protobuf wire bytes against @vprof.proto@.
--
-- Debian's @protobuf@ package decodes leniently: a field whose length runs past the end
-- of the message, or a string that is not UTF-8, is silently dropped, so truncated or
-- corrupted bytes would decode to a "valid" request with missing fields. This walker
-- rejects what protoc's parsers reject (bad tags, wire types 3/4/6/7, varints over 10
-- bytes, lengths past the end, invalid UTF-8 in string fields, packed doubles whose
-- length is not a multiple of 8) and, more strictly than protoc, a known field sent with
-- the wrong wire type (which the Haskell decoder would misread) and repeated doubles in the
-- unpacked encoding (legal protobuf, but the Haskell decoder silently drops them; every
-- proto3 encoder writes them packed). Unknown fields are walked and skipped, as protoc
-- does.
module VProf.Wire.Validate
  ( validateWire
  , MsgType (..)
  ) where

import Data.Bits ((.&.), shiftR)
import qualified Data.ByteString as B
import qualified Data.Text.Encoding as TE
import Data.Word (Word64)

import VProf.Wire.Varint (VarintResult (..), decodeVarint)

data MsgType
  = TRequest | TResponse | TProfileRequest | TSpeedLimit | TProfileResponse | TViolation
  | TError | TPoses | TCompressRequest | TCompressMetrics | TCompressedPath | TPing | TPong
  | TRobot | TPose | TFkRequest | TFkResponse | TMesh | TIkRequest | TIkSolution | TIkResponse
  | TCapsule | TSelectRequest | TSelectTarget | TSelectSegment | TSelectRobotResult | TSelectResponse
  | TPlanZone | TPlanRequest | TPlanResponse
  deriving (Eq, Show, Enum, Bounded)

data Kind = KVarint | KF64 | KStr | KMsg MsgType | KPackedF64 | KPackedVarint

fields :: MsgType -> Word64 -> Maybe Kind
fields t n = case t of
  TRequest -> lookup n [ (1, KVarint), (2, KMsg TProfileRequest), (3, KMsg TCompressRequest), (4, KMsg TPing)
                       , (5, KMsg TFkRequest), (6, KMsg TIkRequest), (7, KMsg TSelectRequest), (8, KMsg TPlanRequest) ]
  TResponse -> lookup n [ (1, KVarint), (2, KMsg TProfileResponse), (3, KMsg TCompressedPath), (4, KMsg TPong), (5, KMsg TError)
                        , (6, KMsg TFkResponse), (7, KMsg TIkResponse), (8, KMsg TSelectResponse), (9, KMsg TPlanResponse) ]
  TProfileRequest
    | n == 1 || n == 14 || n == 17 -> Just KVarint
    | n == 3 -> Just (KMsg TSpeedLimit)
    | n >= 2 && n <= 16 -> Just KF64
    | otherwise -> Nothing
  TSpeedLimit -> if n == 1 || n == 2 then Just KF64 else Nothing
  TProfileResponse
    | n `elem` [1, 9, 10, 11, 17] -> Just KVarint
    | n `elem` [2, 3, 12, 16] -> Just KF64
    | n >= 4 && n <= 8 -> Just KPackedF64
    | n == 13 -> Just (KMsg TViolation)
    | n == 14 || n == 15 -> Just (KMsg TError)
    | otherwise -> Nothing
  TViolation -> lookup n [(1, KStr), (2, KVarint), (3, KF64), (4, KF64), (5, KStr)]
  TError -> lookup n [(1, KVarint), (2, KStr), (3, KStr)]
  TPoses -> if n >= 1 && n <= 8 then Just KPackedF64 else Nothing
  TCompressRequest
    | n `elem` [1, 3, 4, 10] -> Just KVarint
    | n == 2 -> Just (KMsg TPoses)
    | n >= 5 && n <= 9 -> Just KF64
    | otherwise -> Nothing
  TCompressMetrics
    | n == 15 || n == 16 -> Just KVarint
    | n >= 1 && n <= 17 -> Just KF64
    | otherwise -> Nothing
  TCompressedPath -> lookup n [(1, KVarint), (2, KMsg TPoses), (3, KMsg TCompressMetrics), (4, KF64), (5, KMsg TError), (6, KStr)]
  TPing -> lookup n [(1, KStr)]
  TPong -> lookup n [(1, KStr), (2, KStr)]
  TRobot -> if n >= 1 && n <= 5 then Just KStr else Nothing
  TPose -> if n >= 1 && n <= 7 then Just KF64 else Nothing
  TFkRequest -> lookup n [(1, KVarint), (2, KMsg TRobot), (3, KPackedF64), (4, KVarint)]
  TFkResponse -> lookup n [ (1, KVarint), (2, KMsg TPose), (3, KMsg TPose), (4, KPackedF64), (5, KF64), (6, KF64)
                          , (7, KF64), (8, KMsg TError), (9, KVarint) ]
  TMesh -> lookup n [(1, KPackedF64), (2, KPackedVarint), (3, KF64), (4, KMsg TPose)]
  TIkRequest -> lookup n [ (1, KVarint), (2, KMsg TRobot), (3, KMsg TPose), (4, KPackedF64), (5, KVarint), (6, KF64)
                         , (7, KF64), (8, KF64), (9, KMsg TMesh), (10, KF64), (11, KPackedVarint) ]
  TIkSolution -> lookup n [(1, KPackedF64), (2, KF64), (3, KF64), (4, KStr), (5, KF64), (6, KF64), (7, KF64)]
  TIkResponse -> lookup n [(1, KVarint), (2, KMsg TIkSolution), (3, KStr), (4, KF64), (5, KMsg TError), (6, KVarint)]
  TCapsule -> if n >= 1 && n <= 7 then Just KF64 else Nothing
  TSelectRequest -> lookup n [ (1, KVarint), (2, KMsg TMesh), (3, KMsg TPose), (4, KMsg TPose), (5, KMsg TCapsule), (6, KF64)
                             , (7, KF64), (8, KMsg TPose), (9, KVarint), (10, KF64), (11, KMsg TRobot), (12, KPackedVarint) ]
  TSelectTarget -> lookup n [ (1, KStr), (2, KVarint), (3, KPackedF64), (4, KStr), (5, KF64), (6, KStr), (7, KF64)
                            , (8, KStr), (9, KVarint) ]
  TSelectSegment -> lookup n [(1, KVarint), (2, KVarint), (3, KVarint), (4, KStr)]
  TSelectRobotResult -> lookup n [ (1, KStr), (2, KStr), (3, KVarint), (4, KStr), (5, KMsg TSelectTarget)
                                 , (6, KMsg TSelectSegment), (7, KVarint), (8, KVarint), (9, KVarint), (10, KF64)
                                 , (11, KStr), (12, KF64), (13, KF64), (14, KStr), (15, KF64), (16, KVarint) ]
  TSelectResponse -> lookup n [(1, KVarint), (2, KMsg TSelectRobotResult), (3, KF64), (4, KMsg TError), (5, KMsg TError)]
  TPlanZone -> lookup n [(1, KF64), (2, KF64), (3, KF64), (4, KStr)]
  TPlanRequest -> lookup n [ (1, KVarint), (2, KMsg TPoses), (3, KMsg TRobot), (4, KMsg TPose), (5, KMsg TPose), (6, KMsg TMesh)
                           , (7, KF64), (8, KPackedVarint), (9, KF64), (10, KF64), (11, KF64), (12, KF64), (13, KF64)
                           , (14, KPackedF64), (15, KF64) ]
  TPlanResponse
    | n == 1 || n == 2 || n == 3 -> Just KVarint
    | n == 4 || n == 12 || n == 13 || n == 16 || n == 20 || n == 21 -> Just KF64
    | (n >= 5 && n <= 11) || n == 14 -> Just KPackedF64
    | n == 15 -> Just (KMsg TPlanZone)
    | n == 17 -> Just (KMsg TPose)
    | n == 18 || n == 19 -> Just KStr
    | n == 22 || n == 23 -> Just (KMsg TError)
    | otherwise -> Nothing

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
              here = path ++ "/" ++ show num
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
            (Just KPackedF64, 1) ->
              Left ("field " ++ here ++ ": unpacked repeated double (wire type 1); this server reads "
                    ++ "only the packed encoding proto3 writes (the Haskell decoder would drop it)")
            (Just KPackedF64, 2)
              | B.length payload `mod` 8 == 0 -> Right ()
              | otherwise -> Left ("field " ++ here ++ ": packed doubles of " ++ show (B.length payload) ++ " bytes")
            (Just KPackedVarint, 0) ->
              Left ("field " ++ here ++ ": unpacked repeated integer (wire type 0); this server reads "
                    ++ "only the packed encoding proto3 writes (the Haskell decoder would drop it)")
            (Just KPackedVarint, 2) -> varints here payload
            (Just KStr, 2) -> either (const (Left ("field " ++ here ++ ": string is not valid UTF-8"))) (const (Right ()))
                                     (TE.decodeUtf8' payload)
            (Just (KMsg sub), 2) -> go (depth + 1) here sub payload
            (Just _, _) -> Left ("field " ++ here ++ " of " ++ show t ++ ": wrong wire type " ++ show wt)
          go depth path t rest'
    varints path bs
      | B.null bs = Right ()
      | otherwise = varint path bs >>= \(_, u) -> varints path (B.drop u bs)
    varint path bs = case decodeVarint bs of
      VarintOk v u -> Right (v, u)
      VarintIncomplete -> Left ("truncated varint at " ++ place path)
      VarintMalformed -> Left ("varint longer than 10 bytes at " ++ place path)
    place path = if null path then "the message's top level (a field tag)" else "field " ++ path
    fixed path n bs
      | B.length bs < n = Left ("field " ++ path ++ ": truncated fixed" ++ show (n * 8))
      | otherwise = Right (B.empty, B.drop n bs)
