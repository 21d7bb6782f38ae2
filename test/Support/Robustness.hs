{-# LANGUAGE OverloadedStrings #-}
-- | Robustness of the daemon, parameterised by the request handler so that the same tests
-- run against the test handler ("Support.TestHandler") and against the real one
-- ("VProf.Service"'s 'VProf.Service.service').
--
-- Every test abuses an in-process server on a free loopback port and then checks that it
-- still answers a valid ping and a valid profile request correctly.
module Support.Robustness
  ( HandlerUnderTest (..)
  , robustnessSpec
  , assertAlive
  , quietConfig
  , errorOf
  ) where

import Control.Concurrent.Async (forConcurrently)
import Control.Monad
import Data.Bits (shiftR, xor, shiftL)
import qualified Data.ByteString as B
import Data.ProtocolBuffers (getField, putField)
import Data.Text (Text)
import qualified Data.Text as T
import Data.Word (Word64, Word8)
import Test.Hspec

import VProf.Server
import Support.TestClient
import Support.TestHandler (pingMsg, profileMsg, requestWith, simpleProfileRequest)
import VProf.Wire.Framing
import VProf.Wire.Messages

data HandlerUnderTest = HandlerUnderTest
  { hutHandler :: Handler
  , hutReal    :: Bool  -- ^ the real generator: also check what only it can answer
  }

quietConfig :: ServerConfig
quietConfig = defaultServerConfig { cfgPort = 0, cfgQuiet = True, cfgWorkers = 2 }

errorOf :: ResponseMsg -> Maybe (ErrorCodeEnum, Text)
errorOf r = (\e -> (getEnum (getField (errCode e)), orDefault (getField (errField e))))
  <$> getField (rspError r)

-- | A fresh connection answers a ping (payload echoed) and the "simple" profile request
-- (a profile body echoing request_id; with the real generator: legal and converged).
assertAlive :: HandlerUnderTest -> Int -> IO ()
assertAlive hut port = withClient port $ \c -> do
  r <- roundTrip c (pingMsg 77 "still there?")
  orDefault (getField (rspRequestId r)) `shouldBe` (77 :: Word64)
  (orDefault . getField . pongPayload <$> getField (rspPong r)) `shouldBe` Just ("still there?" :: Text)
  p <- roundTrip c (profileMsg 78 (simpleProfileRequest 78))
  orDefault (getField (rspRequestId p)) `shouldBe` (78 :: Word64)
  case getField (rspProfile p) of
    Nothing -> expectationFailure ("no profile body: " ++ show p)
    Just pr -> do
      orDefault (getField (prsRequestId pr)) `shouldBe` (78 :: Word64)
      when (hutReal hut) $ do  -- needs the real generator
        orDefault (getField (prsLegal pr)) `shouldBe` True
        orDefault (getField (prsConverged pr)) `shouldBe` True
        length (getField (prsVelocity pr)) `shouldSatisfy` (> 2)

-- | A deterministic byte stream (xorshift), so failures reproduce.
pseudoRandomBytes :: Word64 -> Int -> B.ByteString
pseudoRandomBytes seed n = fst (B.unfoldrN n step (seed * 2654435761 + 1))
  where
    step s = let a = s `xor` (s `shiftL` 13); b = a `xor` (a `shiftR` 7); c = b `xor` (b `shiftL` 17)
             in Just (fromIntegral (c `shiftR` 24) :: Word8, c)

robustnessSpec :: HandlerUnderTest -> Spec
robustnessSpec hut = around (withServer quietConfig (hutHandler hut) . (. serverPort)) $ do
  let alive = assertAlive hut

  it "answers a valid ping and profile" alive

  it "answers pipelined requests in order on one connection" $ \port -> do
    withClient port $ \c -> do
      sendRaw c (B.concat [ frame (encodeBare (pingMsg i (T.pack (show i)))) | i <- [1 .. 50] ])
      forM_ [1 .. 50 :: Word64] $ \i -> do
        r <- recvResponse c
        orDefault (getField (rspRequestId r)) `shouldBe` i
    alive port

  it "answers a zero-length frame with INVALID_ARGUMENT naming body, and stays usable" $ \port -> do
    withClient port $ \c -> do
      sendRaw c (B.singleton 0)
      r <- recvResponse c
      errorOf r `shouldBe` Just (ErrInvalidArgument, "body")
      r2 <- roundTrip c (pingMsg 5 "x")
      orDefault (getField (rspRequestId r2)) `shouldBe` (5 :: Word64)
    alive port

  it "rejects an envelope with two bodies naming body" $ \port -> do
    withClient port $ \c -> do
      r <- roundTrip c (requestWith 9 (Just (simpleProfileRequest 9)) Nothing
                                  (Just (PingMsg (putField Nothing))))
      errorOf r `shouldBe` Just (ErrInvalidArgument, "body")
      orDefault (getField (rspRequestId r)) `shouldBe` (9 :: Word64)
    alive port

  it "answers a truncated frame (then end of input) without dying" $ \port -> do
    withClient port $ \c -> do
      sendRaw c (B.pack [100] <> B.replicate 10 7)
      shutdownSend c
      f <- recvFrame c
      case f of
        Frame b _ -> fmap errorOf (either fail pure (decodeBare b))
                       `shouldReturn` Just (ErrMalformed, "")
        other -> expectationFailure (show other)
      recvFrame c `shouldReturn` EndOfInput
    alive port

  it "answers an oversized length prefix with FRAME_TOO_LARGE and closes" $ \port -> do
    withClient port $ \c -> do
      sendRaw c (encodeVarint (5 * 1024 * 1024))
      r <- recvResponse c
      fst <$> errorOf r `shouldBe` Just ErrFrameTooLarge
      recvFrame c `shouldReturn` EndOfInput
    withClient port $ \c -> do  -- a 2^63 prefix too
      sendRaw c (encodeVarint (2 ^ (63 :: Int)) <> "garbage")
      fmap (fmap fst . errorOf) (recvResponse c) `shouldReturn` Just ErrFrameTooLarge
    alive port

  it "answers FRAME_TOO_LARGE to a client that writes the whole oversized frame before it reads" $ \port -> do
    -- the server reads and drops the refused body before it closes: the client's write
    -- succeeds (closing with it unread reset the connection, and the write failed with
    -- ECONNRESET), then it reads the answer and the end of the stream
    withClient port $ \c -> do
      let n = 5 * 1024 * 1024
      sendRaw c (encodeVarint (fromIntegral n) <> B.replicate n 7)
      r <- recvResponse c
      fst <$> errorOf r `shouldBe` Just ErrFrameTooLarge
      recvFrame c `shouldReturn` EndOfInput
    alive port

  it "answers a length prefix of 11 varint bytes with MALFORMED and closes" $ \port -> do
    withClient port $ \c -> do
      sendRaw c (B.replicate 11 0xff)
      fmap (fmap fst . errorOf) (recvResponse c) `shouldReturn` Just ErrMalformed
      recvFrame c `shouldReturn` EndOfInput
    alive port

  it "answers 300 frames of random bytes, one answer each, on one connection" $ \port -> do
    withClient port $ \c -> do
      forM_ [1 .. 300 :: Word64] $ \i -> do
        let body = pseudoRandomBytes i (fromIntegral (i `mod` 97))
        sendRaw c (frame body)
        _ <- recvResponse c
        pure ()
      r <- roundTrip c (pingMsg 301 "after random")
      orDefault (getField (rspRequestId r)) `shouldBe` (301 :: Word64)
    alive port

  it "answers undecodable bytes with MALFORMED and stays usable" $ \port -> do
    withClient port $ \c -> do
      -- field 2 (profile) declared length-delimited with a length past the end
      r <- roundTrip' c (B.pack [0x12, 0x50, 0x01])
      fst <$> errorOf r `shouldBe` Just ErrMalformed
      r2 <- roundTrip c (pingMsg 6 "y")
      orDefault (getField (rspRequestId r2)) `shouldBe` (6 :: Word64)
    alive port

  it "tolerates valid frames with garbage fields (unknown numbers, wrong wire types)" $ \port -> do
    withClient port $ \c -> do
      let ping = encodeBare (pingMsg 11 "g")
          unknown = B.pack [0xf8, 0x06, 0x2a]            -- field 111, varint 42
          unknownLen = B.pack [0xfa, 0x06, 0x03, 1, 2, 3] -- field 111, 3 bytes
      r <- roundTrip' c (ping <> unknown <> unknownLen)
      orDefault (getField (rspRequestId r)) `shouldBe` (11 :: Word64)
      (orDefault . getField . pongPayload <$> getField (rspPong r)) `shouldBe` Just ("g" :: Text)
      -- request_id (a varint field) sent as a fixed64: must be answered, whatever it is
      _ <- roundTrip' c (B.pack [0x09, 1, 2, 3, 4, 5, 6, 7, 8])
      -- profile (a message field) sent as a varint
      _ <- roundTrip' c (B.pack [0x10, 0x05])
      r2 <- roundTrip c (pingMsg 12 "z")
      orDefault (getField (rspRequestId r2)) `shouldBe` (12 :: Word64)
    alive port

  it "answers NaN and infinite field values (the real generator: INVALID_ARGUMENT)" $ \port -> do
    withClient port $ \c -> do
      let base = simpleProfileRequest 21
          cases = [ base { prqRouteLength = putField (Just (0 / 0)) }
                  , base { prqMaxAcceleration = putField (Just (1 / 0)) }
                  , base { prqMinJerk = putField (Just (-1 / 0)) }
                  , base { prqTimeBudget = putField (Just (0 / 0)) }
                  , base { prqSpeedLimits = putField [SpeedLimitMsg (putField Nothing) (putField (Just (0 / 0)))] } ]
      forM_ (zip [21 ..] cases) $ \(i, p) -> do
        r <- roundTrip c (profileMsg i p)
        orDefault (getField (rspRequestId r)) `shouldBe` i
        when (hutReal hut) $  -- needs the real handler's validation
          (getEnum . getField . errCode <$> (getField (rspProfile r) >>= getField . prsError))
            `shouldBe` Just ErrInvalidArgument
    alive port

  it "serves 64 concurrent clients, each answered in order" $ \port -> do
    oks <- forConcurrently [1 .. 64 :: Word64] $ \k -> withClient port $ \c -> do
      let ids = [k * 1000 + j | j <- [1 .. 5]]
      sendRaw c (B.concat (map (\i -> frame (encodeBare (pingMsg i (T.pack (show i))))) ids
                           ++ [frame (encodeBare (profileMsg (k * 1000 + 6) (simpleProfileRequest k)))]))
      got <- replicateM 6 (orDefault . getField . rspRequestId <$> recvResponse c)
      pure (got == ids ++ [k * 1000 + 6])
    oks `shouldBe` replicate 64 True
    alive port

  it "survives clients that connect and vanish mid-frame" $ \port -> do
    forM_ [1 .. 20 :: Int] $ \i -> withClient port $ \c ->
      sendRaw c (B.pack [0x80, 0x80] <> B.take (i `mod` 3) "ab")
    alive port
  where
    roundTrip' c b = sendRaw c (frame b) >> recvResponse c
