{-# LANGUAGE TypeFamilies #-}
{-# LANGUAGE OverloadedStrings #-}
module VProf.ServerSpec (spec) where

import Control.Concurrent
import Control.Concurrent.Async
import Control.Exception hiding (Handler)
import Control.Monad
import Data.IORef
import qualified Data.ByteString as B
import Data.ProtocolBuffers (getField, putField)
import qualified Data.Text as T
import Data.Word (Word64)
import GHC.Clock (getMonotonicTime)
import System.Timeout (timeout)
import Test.Hspec

import Support.Robustness
import VProf.Server
import Support.TestClient
import Support.TestHandler
import VProf.Wire.Envelope (Incoming (..), pongResponse)
import VProf.Wire.Framing (FrameResult (..), frame)
import VProf.Wire.Messages

-- | A handler that counts how many calls run at once.
countingHandler :: IORef (Int, Int) -> Double -> Handler
countingHandler ref secs = testHandler { handlerAnswer = \rid inc -> do
  atomicModifyIORef' ref (\(cur, hi) -> ((cur + 1, max hi (cur + 1)), ()))
  threadDelay (round (secs * 1e6)) `finally` atomicModifyIORef' ref (\(cur, hi) -> ((cur - 1, hi), ()))
  testAnswer rid inc }

-- | The test handler, but with this answer for profile bodies and the time limit a profile
-- request's own budget gives.
onProfile :: (Word64 -> IO ResponseMsg) -> Handler
onProfile f = Handler answer limit
  where
    answer rid = \case
      InProfile _ -> f rid
      inc -> testAnswer rid inc
    limit = \case
      InProfile p -> orDefault (getField (prqTimeBudget p))
      inc -> handlerTimeLimit testHandler inc

spec :: Spec
spec = do
  describe "robustness (test handler)" $
    robustnessSpec (HandlerUnderTest testHandler False)

  describe "bounded concurrency" $ do
    it "never runs more than --workers handler calls at once" $ do
      ref <- newIORef (0, 0)
      withServer quietConfig { cfgWorkers = 2 } (countingHandler ref 0.1) $ \s -> do
        _ <- forConcurrently [1 .. 8 :: Word64] $ \i -> withClient (serverPort s) $ \c ->
          roundTrip c (profileMsg i (simpleProfileRequest i))
        snd <$> readIORef ref `shouldReturn` 2
    it "answers a ping at once while every worker is busy (a ping takes no worker)" $ do
      let slow = onProfile (\rid -> threadDelay 3000000 >> testAnswer rid (InPing (PingMsg (putField Nothing))))
      withServer quietConfig { cfgWorkers = 1 } slow $ \s ->
        withAsync (withClient (serverPort s) $ \c -> roundTrip c (profileMsg 1 (simpleProfileRequest 1))) $ \_ -> do
          threadDelay 200000
          t0 <- getMonotonicTime
          r <- withClient (serverPort s) $ \c -> roundTrip c (pingMsg 2 "alive?")
          t1 <- getMonotonicTime
          orDefault (getField (rspRequestId r)) `shouldBe` (2 :: Word64)
          (t1 - t0) `shouldSatisfy` (< 1.5)

  describe "hard timeout" $
    it "answers INTERNAL after time_budget + grace and stays usable" $ do
      let stuck = onProfile (\rid -> forever (threadDelay 1000000) >> testAnswer rid (InPing (PingMsg (putField Nothing))))
      withServer quietConfig { cfgGrace = 0.3, cfgWorkers = 1 } stuck $ \s -> withClient (serverPort s) $ \c -> do
        t0 <- getMonotonicTime
        let p = (simpleProfileRequest 3) { prqTimeBudget = putField' 0.2 }
        r <- roundTrip c (profileMsg 3 p)
        t1 <- getMonotonicTime
        fst <$> errorOf r `shouldBe` Just ErrInternal
        (t1 - t0) `shouldSatisfy` (\d -> d >= 0.45 && d < 3)
        -- the stuck worker was killed: its only slot is free again
        r2 <- roundTrip c (pingMsg 4 "after")
        orDefault (getField (rspRequestId r2)) `shouldBe` (4 :: Word64)

  describe "handler failures" $ do
    it "answers INTERNAL when the handler throws, and the connection lives on" $ do
      let bad = onProfile (\_ -> throwIO (userError "boom"))
      withServer quietConfig bad $ \s -> withClient (serverPort s) $ \c -> do
        r <- roundTrip c (profileMsg 8 (simpleProfileRequest 8))
        fst <$> errorOf r `shouldBe` Just ErrInternal
        orDefault (getField (rspRequestId r)) `shouldBe` (8 :: Word64)
        r2 <- roundTrip c (pingMsg 9 "p")
        orDefault (getField (rspRequestId r2)) `shouldBe` (9 :: Word64)
    it "answers INTERNAL when the response hides an exception in a lazy field" $ do
      let lazyBad = testHandler { handlerAnswer = \rid _ -> pure (pongResponse rid (error "lazy bomb") "v") }
      withServer quietConfig lazyBad $ \s -> withClient (serverPort s) $ \c -> do
        r <- roundTrip c (pingMsg 10 "p")
        fst <$> errorOf r `shouldBe` Just ErrInternal
        r2 <- roundTrip c (pingMsg 11 "p")
        fst <$> errorOf r2 `shouldBe` Just ErrInternal  -- same handler, still answered
    it "echoes the envelope's request_id even when the handler does not" $ do
      let forgetful = testHandler { handlerAnswer = \rid inc -> testAnswer rid inc >>= \r -> pure r { rspRequestId = putField' 0 `asTypeOf` rspRequestId r } }
      withServer quietConfig forgetful $ \s -> withClient (serverPort s) $ \c -> do
        r <- roundTrip c (pingMsg 12345678901234 "p")
        orDefault (getField (rspRequestId r)) `shouldBe` (12345678901234 :: Word64)

  describe "drain" $
    it "stops accepting, answers the in-flight request, then returns" $ do
      s <- startServer quietConfig testHandler
      let port = serverPort s
      c <- connectClient port
      sendRequest c (pingMsg 1 "sleep:0.5")
      threadDelay 150000
      t0 <- getMonotonicTime
      stopServer s
      r <- recvResponse c
      orDefault (getField (rspRequestId r)) `shouldBe` (1 :: Word64)
      recvFrame c `shouldReturn` EndOfInput
      waitServer s
      t1 <- getMonotonicTime
      (t1 - t0) `shouldSatisfy` (< 2)
      res <- try (connectClient port)
      case res of
        Left (_ :: IOException) -> pure ()
        Right c2 -> closeClient c2 >> expectationFailure "accepted a connection after stop"
      closeClient c

  describe "drain with pipelined requests" $
    it "answers every request already received before closing" $ do
      s <- startServer quietConfig testHandler
      c <- connectClient (serverPort s)
      sendRaw c (B.concat (frame (encodeBare (pingMsg 1 "sleep:0.4")) : [frame (encodeBare (pingMsg i "p")) | i <- [2 .. 5]]))
      threadDelay 150000
      stopServer s
      ids <- replicateM 5 (orDefault . getField . rspRequestId <$> recvResponse c)
      ids `shouldBe` [1 .. 5 :: Word64]
      recvFrame c `shouldReturn` EndOfInput
      waitServer s
      closeClient c

  describe "drain with a stalled client" $
    it "closes a connection whose frame is still arriving --grace after the drain began, even without an idle timeout (it held the exit for as long as the client stalled)" $ do
      s <- startServer quietConfig { cfgIdleTimeout = 0, cfgGrace = 0.3 } testHandler
      c <- connectClient (serverPort s)
      -- a length prefix of 100 and 3 of its bytes
      sendRaw c (B.pack [100, 97, 98, 99])
      threadDelay 150000
      stopServer s
      done <- timeout 30000000 (waitServer s)
      done `shouldBe` Just ()
      recvFrame c `shouldReturn` EndOfInput
      closeClient c

  describe "connection limit" $ do
    it "at --max-connections the connection idle longest makes room for a new client, even without an idle timeout (a new client waited until one closed)" $ do
      s <- startServer quietConfig { cfgIdleTimeout = 0, cfgMaxConnections = 2 } testHandler
      c1 <- connectClient (serverPort s)
      _ <- roundTrip c1 (pingMsg 1 "a")
      threadDelay 50000
      c2 <- connectClient (serverPort s)
      _ <- roundTrip c2 (pingMsg 2 "b")
      c3 <- connectClient (serverPort s)
      r <- timeout 20000000 (roundTrip c3 (pingMsg 3 "c"))
      fmap (orDefault . getField . rspRequestId) r `shouldBe` Just (3 :: Word64)
      -- the first, idle longest, was closed; the second is served still
      recvFrame c1 `shouldReturn` EndOfInput
      r2 <- roundTrip c2 (pingMsg 4 "d")
      orDefault (getField (rspRequestId r2)) `shouldBe` (4 :: Word64)
      mapM_ closeClient [c1, c2, c3]
      stopServer s >> waitServer s
    it "a connection with a request in hand is not closed for a new client; the new one waits for it" $ do
      s <- startServer quietConfig { cfgIdleTimeout = 0, cfgMaxConnections = 1 } testHandler
      c1 <- connectClient (serverPort s)
      sendRequest c1 (pingMsg 1 "sleep:0.6")
      threadDelay 100000
      c3 <- connectClient (serverPort s)
      sendRequest c3 (pingMsg 3 "c")
      -- the first is answered in full, then closed to make room (it waits for its next request)
      r1 <- recvResponse c1
      orDefault (getField (rspRequestId r1)) `shouldBe` (1 :: Word64)
      r3 <- timeout 20000000 (recvResponse c3)
      fmap (orDefault . getField . rspRequestId) r3 `shouldBe` Just (3 :: Word64)
      recvFrame c1 `shouldReturn` EndOfInput
      mapM_ closeClient [c1, c3]
      stopServer s >> waitServer s

  describe "idle timeout" $
    it "closes an idle connection" $
      withServer quietConfig { cfgIdleTimeout = 0.3 } testHandler $ \s -> withClient (serverPort s) $ \c -> do
        r <- roundTrip c (pingMsg 1 "a")
        orDefault (getField (rspRequestId r)) `shouldBe` (1 :: Word64)
        threadDelay 700000
        recvFrame c `shouldReturn` EndOfInput

  describe "log lines" $
    it "renders one logfmt line with the required keys" $
      renderLogLine (LogLine 7 "profile" "ok" 3.14 (Just 12) (Just True) (Just True) 120 8000)
        `shouldBe` T.pack "vprof request_id=7 kind=profile outcome=ok ms=3.1 iterations=12 converged=true legal=true bytes_in=120 bytes_out=8000"
  where
    putField' x = putField (Just x)
