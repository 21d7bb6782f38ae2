{-# LANGUAGE TypeApplications #-}
{-# LANGUAGE OverloadedStrings #-}
-- | @vprof serve@: the Protobuf daemon the automation stack talks to (thesis 4.2.2, 4.6.1).
--
-- Every message on the stream is a length-delimited @vprof.v1.Request@ (see
-- "VProf.Wire.Framing"); every request is answered by one @vprof.v1.Response@, in order,
-- echoing its @request_id@. The server knows nothing about what the bodies ask: it
-- decodes and classifies each request ("VProf.Wire.Envelope") and hands the one body to a
-- 'Handler' (the real one is "VProf.Service"'s), which also says how long that body may
-- take.
--
-- What the server guarantees whatever the handler or the clients do:
--
-- * at most 'cfgWorkers' handler calls run at once (a semaphore), so generation never takes
--   every CPU of the robot computer; a ping takes no slot, so a busy daemon still answers it;
-- * every handler call is guarded by a hard timeout (the handler's 'handlerTimeLimit' for
--   the body, plus 'cfgGrace'); past it the client gets Error INTERNAL instead of a hang;
-- * a handler exception (or a response that cannot be encoded) is answered with
--   Error INTERNAL; the connection and the daemon live on;
-- * a length prefix above 'cfgMaxFrameBytes' is answered with FRAME_TOO_LARGE and the
--   connection is closed without decoding the body (the body is read and dropped for up to
--   'cfgGrace' seconds, at most 5, so that a client that writes the whole frame before it
--   reads gets the answer, not a reset connection); a prefix longer than 10 bytes is
--   MALFORMED and closes too; at most 'cfgMaxConnections' connections are served at once,
--   so memory stays bounded by about connections x max frame;
-- * undecodable bodies are answered with MALFORMED and the connection stays usable;
-- * idle connections are closed after 'cfgIdleTimeout' seconds, and at the limit of
--   'cfgMaxConnections' the one that has waited longest for a request makes room for a new
--   client (a connection with a request in hand is never closed for it);
-- * 'stopServer' (SIGTERM / SIGINT in 'serve') stops accepting, lets every request whose
--   bytes have started to arrive finish and be answered, then returns; a frame still arriving
--   or an answer the client does not read 'cfgGrace' seconds after the drain began closes
--   its connection, so that no client holds the exit.
module VProf.Server
  ( Handler (..)
  , ServerConfig (..)
  , defaultServerConfig
  , resolveWorkers
    -- * Running
  , serve
  , serveStdio
  , Server
  , startServer
  , serverPort
  , stopServer
  , waitServer
  , withServer
    -- * Internals exposed for tests

  , LogLine (..)
  , renderLogLine
  ) where

import Control.Concurrent
import Control.Concurrent.Async
import Control.Concurrent.STM
import Control.Exception hiding (Handler)
import Control.Monad
import qualified Data.ByteString as B
import Data.IORef (atomicModifyIORef', newIORef)
import Data.List (sortOn)
import qualified Data.Map.Strict as M
import Data.ProtocolBuffers (getField, putField)
import Data.Text (Text)
import qualified Data.Text as T
import qualified Data.Text.IO as T
import Data.Word (Word32, Word64)
import GHC.Clock (getMonotonicTime)
import GHC.Conc (getNumProcessors)
import Network.Socket
import qualified Network.Socket.ByteString as NSB
import Numeric (showFFloat)
import System.IO
import qualified System.Posix.Signals as Sig
import System.Timeout (timeout)

import VProf.Wire.Envelope
import VProf.Wire.Framing
import VProf.Wire.Messages
import VProf.Version (versionString)
import VProf.Wire.Packing (packRepeated)
import VProf.Wire.Validate (MsgType (TRequest), validateWire)

-- | What the server runs for one classified request body.
data Handler = Handler
  { handlerAnswer    :: Word64 -> Incoming -> IO ResponseMsg
    -- ^ the envelope's request_id and its one body
  , handlerTimeLimit :: Incoming -> Double
    -- ^ seconds the body may take; the hard timeout adds 'cfgGrace'
  }

data ServerConfig = ServerConfig
  { cfgHost           :: String  -- ^ default 127.0.0.1
  , cfgPort           :: Int     -- ^ default 7450; 0 picks a free port
  , cfgWorkers        :: Int     -- ^ concurrent handler calls; 0 means the number of cores
  , cfgMaxFrameBytes  :: Int     -- ^ default 4 MiB
  , cfgIdleTimeout    :: Double  -- ^ s; 0 or less means never
  , cfgQuiet          :: Bool    -- ^ no per-request log lines
  , cfgGrace          :: Double  -- ^ s added to the handler's time limit for the hard timeout
  , cfgMaxConnections :: Int     -- ^ connections served at once; at the limit the one idle longest makes room, else a new one waits
  , cfgVersion        :: Text    -- ^ for logs
  } deriving (Show)

defaultServerConfig :: ServerConfig
defaultServerConfig = ServerConfig
  { cfgHost = "127.0.0.1"
  , cfgPort = 7450
  , cfgWorkers = 0
  , cfgMaxFrameBytes = 4 * 1024 * 1024
  , cfgIdleTimeout = 60
  , cfgQuiet = False
  , cfgGrace = 5
  , cfgMaxConnections = 256
  , cfgVersion = T.pack versionString
  }

resolveWorkers :: ServerConfig -> IO Int
resolveWorkers cfg
  | cfgWorkers cfg > 0 = pure (cfgWorkers cfg)
  | otherwise = max 1 <$> getNumProcessors

----------------------------------------------------------------------------- environment

data ServerEnv = ServerEnv
  { envCfg      :: ServerConfig
  , envHandler  :: Handler
  , envSem      :: QSem
  , envLog      :: Text -> IO ()
  , envDraining :: TVar Bool
  }

newEnv :: ServerConfig -> Handler -> IO ServerEnv
newEnv cfg h = do
  n <- resolveWorkers cfg
  sem <- newQSem n
  lock <- newMVar ()
  draining <- newTVarIO False
  let logger line
        | cfgQuiet cfg = pure ()
        | otherwise = withMVar lock $ \_ -> T.hPutStrLn stderr line >> hFlush stderr
  pure (ServerEnv cfg h sem logger draining)

----------------------------------------------------------------------------- logging

-- | One structured (logfmt) line per request.
data LogLine = LogLine
  { llRequestId :: Word64
  , llKind      :: Text
  , llOutcome   :: Text
  , llMillis    :: Double
  , llIterations :: Maybe Word64
  , llConverged :: Maybe Bool
  , llLegal     :: Maybe Bool
  , llBytesIn   :: Int
  , llBytesOut  :: Int
  } deriving (Eq, Show)

renderLogLine :: LogLine -> Text
renderLogLine LogLine{..} = T.unwords $
  [ "vprof"
  , "request_id=" <> tshow llRequestId
  , "kind=" <> llKind
  , "outcome=" <> llOutcome
  , "ms=" <> T.pack (showFFloat (Just 1) llMillis "")
  ] ++
  maybe [] (\i -> ["iterations=" <> tshow i]) llIterations ++
  maybe [] (\c -> ["converged=" <> bool c]) llConverged ++
  maybe [] (\l -> ["legal=" <> bool l]) llLegal ++
  [ "bytes_in=" <> tshow llBytesIn
  , "bytes_out=" <> tshow llBytesOut
  ]
  where bool b = if b then "true" else "false"

tshow :: Show a => a -> Text
tshow = T.pack . show

-- | The outcome of a response as logged: @ok@ or the lower-case error code.
outcomeOf :: ResponseMsg -> (Text, Maybe Word64, Maybe Bool, Maybe Bool)
outcomeOf r
  | Just p <- getField (rspProfile r) =
      ( maybe "ok" codeOf (getField (prsError p))
      , Just (fromIntegral (orDefault (getField (prsIterations p)) :: Word32))
      , Just (orDefault (getField (prsConverged p)))
      , Just (orDefault (getField (prsLegal p))) )
  | Just c <- getField (rspCompressed r) = (maybe "ok" codeOf (getField (cpError c)), Nothing, Nothing, Nothing)
  | Just e <- getField (rspError r) = (codeOf e, Nothing, Nothing, Nothing)
  | Just _ <- getField (rspPong r) = ("ok", Nothing, Nothing, Nothing)
  | Just f <- getField (rspFk r) = (maybe "ok" codeOf (getField (fksError f)), Nothing, Nothing, Nothing)
  | Just k <- getField (rspIk r) = (maybe "ok" codeOf (getField (ikrError k)), Nothing, Nothing, Nothing)
  | Just s <- getField (rspSelect r) = (maybe "ok" codeOf (getField (slrError s)), Nothing, Nothing, Nothing)
  | Just p <- getField (rspPlan r) = (maybe "ok" codeOf (getField (plrError p)), Nothing, Nothing, Nothing)
  | otherwise = ("empty", Nothing, Nothing, Nothing)
  where codeOf e = errorCodeName (getEnum (getField (errCode e)))

----------------------------------------------------------------------------- one frame

-- | Answer one frame body: decode, classify, run the handler under the semaphore and the
-- hard timeout, encode. Never throws (save asynchronous exceptions). Returns the encoded
-- response body (without length prefix).
processFrame :: ServerEnv -> B.ByteString -> Int -> IO B.ByteString
processFrame env body bytesIn = do
  t0 <- getMonotonicTime
  decoded <- safeDecode body
  (rid, kind, resp) <- case decoded of
    Left err -> pure (0, "unknown", errorResponse 0 ErrMalformed ""
                        ("bytes do not decode as vprof.v1.Request: " <> T.pack err))
    Right req -> do
      let rid = requestIdOf req
      case classify req of
        Left e -> pure (rid, "invalid", errorResponse rid (getEnum (getField (errCode e)))
                                   (orDefault (getField (errField e)))
                                   (orDefault (getField (errMessage e))))
        Right inc -> (rid, incomingKind inc,) <$> guarded env rid inc
  out <- encodeOrInternal rid resp
  t1 <- getMonotonicTime
  let (outcome, iters, conv, legal) = outcomeOf resp
  envLog env $ renderLogLine LogLine
    { llRequestId = rid, llKind = kind, llOutcome = outcome, llMillis = (t1 - t0) * 1000
    , llIterations = iters, llConverged = conv, llLegal = legal
    , llBytesIn = bytesIn, llBytesOut = B.length out }
  pure out

-- | Decode and force every field (by re-encoding), so that no exception hides in a thunk.
safeDecode :: B.ByteString -> IO (Either String RequestMsg)
safeDecode body = do
  r <- try $ case validateWire TRequest body >> decodeBare (packRepeated TRequest body) of
    Left e -> pure (Left e)
    Right req -> do
      _ <- evaluate (B.length (encodeBare req))
      pure (Right req)
  pure $ case r of
    Left (e :: SomeException) -> Left (show e)
    Right x -> x

encodeOrInternal :: Word64 -> ResponseMsg -> IO B.ByteString
encodeOrInternal rid resp = do
  r <- try (evaluate (encodeBare resp))
  case r of
    Right bs -> B.length bs `seq` pure bs
    Left (e :: SomeException) ->
      pure (encodeBare (errorResponse rid ErrInternal "" ("response could not be encoded: " <> tshow e)))

-- | Run the handler in a worker thread holding a semaphore slot; answer INTERNAL on an
-- exception or when the hard timeout passes (the worker is then killed in the background
-- and gives its slot back only when it has really stopped).
guarded :: ServerEnv -> Word64 -> Incoming -> IO ResponseMsg
guarded env rid inc = do
  result <- newEmptyMVar
  tid <- mask_ $ do
    when holdsSlot (waitQSem (envSem env))
    forkIOWithUnmask $ \unmask ->
      (unmask (try work) >>= putMVar result) `finally` when holdsSlot (signalQSem (envSem env))
  r <- timeout (round (limitS * 1e6)) (readMVar result)
  case r of
    Nothing -> do
      _ <- forkIO (killThread tid)
      pure (errorResponse rid ErrInternal ""
             ("the handler did not answer within " <> T.pack (showFFloat (Just 1) limitS "")
              <> " s (its time limit + grace)"))
    Just (Left (e :: SomeException)) ->
      pure (errorResponse rid ErrInternal "" ("the handler failed: " <> tshow e))
    Just (Right resp) -> pure resp
  where
    -- a ping takes no worker slot: a daemon whose workers are all busy with long requests
    -- still answers at once that it is alive (six thesis requests kept a ping waiting 6 s)
    holdsSlot = case inc of
      InPing _ -> False
      _ -> True
    limitS = handlerTimeLimit (envHandler env) inc + cfgGrace (envCfg env)
    work = do
      resp <- handlerAnswer (envHandler env) rid inc
      let resp' = resp { rspRequestId = putField (nonDefault rid) }
      _ <- evaluate (B.length (encodeBare resp'))  -- force it here, inside the guard
      pure resp'

----------------------------------------------------------------------------- connections

data Wake = Drain | Evicted | Idle | Ready Bool

-- | What a connection tells the server while it waits for a request, and how it hears that it
-- is to make room for a new one (TCP; nothing on stdin/stdout).
data Gate = Gate
  { gateIdle    :: IO ()   -- ^ waiting for the next request
  , gateBusy    :: IO ()   -- ^ a request is arriving or in hand
  , gateEvicted :: STM ()  -- ^ returns once the connection is asked to close
  }

noGate :: Gate
noGate = Gate (pure ()) (pure ()) retry

-- | What a connection left behind when it ended.
data Ending = Done | InputUnread  -- ^ a frame's body (or more) was refused without being read

-- | Serve one connection (or stdin/stdout) until end of input, idle timeout, a broken
-- frame, a drain, or a request to make room for a new connection while it waits.
connectionLoop :: ServerEnv -> Gate -> Double -> Source -> (B.ByteString -> IO ()) -> IO Ending
connectionLoop env gate idleS src send = loop
  where
    cfg = envCfg env
    idle :: IO a -> IO (Maybe a)
    idle act | idleS > 0 = timeout (round (idleS * 1e6)) act
             | otherwise = Just <$> act
    connLog msg = envLog env ("vprof event=" <> msg)
    -- after a drain began, a frame still arriving or an answer the client does not read gets
    -- 'cfgGrace' more seconds, then the connection is closed (a client that stalled inside a
    -- frame, or stopped reading, held the daemon's exit for as long as it liked; the handler's
    -- work on a frame received whole is never cut)
    bounded :: IO a -> IO (Maybe a)
    bounded act = either (const Nothing) Just <$> race drainDeadline act
    drainDeadline = do
      atomically (readTVar (envDraining env) >>= check)
      threadDelay (round (max 0 (cfgGrace cfg) * 1e6))
    reply rid code msg = void . try @SomeException . idle . send . frame . encodeBare $
                           errorResponse rid code "" msg
    loop = do
      -- bytes already received (pipelined requests) are in flight: answer them even
      -- when draining; otherwise wait for data, a drain or the idle timeout
      buffered <- hasBuffered src
      w <- if buffered then pure (Ready True) else do
             gateIdle gate
             r <- race (atomically ((Drain <$ (readTVar (envDraining env) >>= check)) `orElse` (Evicted <$ gateEvicted gate)))
                       (idle (awaitData src))
             gateBusy gate
             pure (either id (maybe Idle Ready) r)
      case w of
        Drain -> pure Done
        Evicted -> Done <$ connLog "closed_for_a_new_connection"
        Idle -> Done <$ connLog "idle_timeout"
        Ready False -> pure Done
        Ready True -> do
          fr <- bounded (idle (readFrame (cfgMaxFrameBytes cfg) src))
          case join fr of
            Nothing -> Done <$ connLog (maybe "drain_deadline_in_frame" (const "idle_timeout_in_frame") fr)
            Just EndOfInput -> pure Done
            Just (Truncated n) -> do
              connLog ("truncated_frame bytes=" <> tshow n)
              Done <$ reply 0 ErrMalformed ("input ended inside a frame after " <> tshow n <> " bytes")
            Just BadVarint -> do
              connLog "bad_length_prefix"
              InputUnread <$ reply 0 ErrMalformed "length prefix is not a varint of at most 10 bytes; closing"
            Just (TooLarge n) -> do
              connLog ("frame_too_large bytes=" <> tshow n)
              InputUnread <$ reply 0 ErrFrameTooLarge
                ("frame of " <> tshow n <> " bytes is above --max-frame-bytes "
                 <> tshow (cfgMaxFrameBytes cfg) <> "; closing")
            Just (Frame body n) -> do
              out <- processFrame env body n
              sent <- bounded (idle (send (frame out)))
              case join sent of
                Nothing -> Done <$ connLog (maybe "drain_deadline_in_send" (const "send_timeout") sent)
                Just () -> loop

----------------------------------------------------------------------------- TCP

data Server = Server
  { srvPort    :: PortNumber
  , srvSocket  :: Socket
  , srvAccept  :: Async ()
  , srvEnv     :: ServerEnv
  , srvActive  :: TVar Int
  }

serverPort :: Server -> Int
serverPort = fromIntegral . srvPort

-- | Bind, listen and start accepting in the background.
startServer :: ServerConfig -> Handler -> IO Server
startServer cfg handler = do
  env <- newEnv cfg handler
  let hints = defaultHints { addrSocketType = Stream, addrFlags = [AI_NUMERICSERV] }
  addr : _ <- getAddrInfo (Just hints) (Just (cfgHost cfg)) (Just (show (cfgPort cfg)))
  sock <- socket (addrFamily addr) Stream defaultProtocol
  setSocketOption sock ReuseAddr 1
  bind sock (addrAddress addr)
  listen sock 128
  port <- socketPort sock
  active <- newTVarIO 0
  -- every connection served: since when it waits for a request (Nothing while one is in
  -- hand) and whether it was asked to make room
  registry <- newTVarIO (M.empty :: M.Map Int (TVar (Maybe Double), TVar Bool))
  ids <- newIORef (0 :: Int)
  let maxConns = max 1 (cfgMaxConnections cfg)
      -- at the limit of connections, the one that has waited longest for a request is asked
      -- to close (at once, as it waits), so that a new client is served; while one asked is
      -- still open, or every connection has a request in hand, the new client waits (held
      -- connections kept every new client waiting until one idled out: 58.6 s with 256 idle
      -- sockets, never with a ping now and then)
      makeRoom = do
        done <- atomically $ do
          n <- readTVar active
          if n < maxConns then pure True else do
            states <- mapM (\(iv, ev) -> (,,) <$> readTVar iv <*> readTVar ev <*> pure ev) . M.elems =<< readTVar registry
            if or [ asked | (_, asked, _) <- states ] then retry
            else case sortOn fst [ (t, ev) | (Just t, False, ev) <- states ] of
              (_, ev) : _ -> writeTVar ev True >> pure False
              [] -> retry
        unless done makeRoom
      acceptLoop = forever $ do
        (conn, _peer) <- accept sock
        makeRoom `onException` close conn
        mask_ $ do
          cid <- atomicModifyIORef' ids (\i -> (i + 1, i))
          idleV <- newTVarIO Nothing
          evictV <- newTVarIO False
          atomically $ do
            modifyTVar' active (+ 1)
            modifyTVar' registry (M.insert cid (idleV, evictV))
          let gate = Gate { gateIdle = getMonotonicTime >>= atomically . writeTVar idleV . Just
                          , gateBusy = atomically (writeTVar idleV Nothing)
                          , gateEvicted = readTVar evictV >>= check }
          void $ forkIOWithUnmask $ \unmask -> do
            _ <- try @SomeException (unmask (serveConn env gate conn))
            close conn
            atomically $ do
              modifyTVar' registry (M.delete cid)
              modifyTVar' active (subtract 1)
  acc <- async acceptLoop
  pure (Server port sock acc env active)

serveConn :: ServerEnv -> Gate -> Socket -> IO ()
serveConn env gate conn = do
  setSocketOption conn NoDelay 1
  src <- newSource (NSB.recv conn 65536)
  ending <- connectionLoop env gate (cfgIdleTimeout (envCfg env)) src (NSB.sendAll conn)
  case ending of
    Done -> pure ()
    InputUnread -> lingeringClose (lingerSeconds (envCfg env)) conn

-- | How long a refused frame's body is read and dropped before its connection closes: the
-- grace, at most 5 s.
lingerSeconds :: ServerConfig -> Double
lingerSeconds cfg = min 5 (max 0 (cfgGrace cfg))

-- | Before closing a connection whose client may still be sending (a frame refused unread),
-- send end-of-stream after the answer and read and drop what arrives, until the client closes
-- or the time is up. Closing with unread bytes in the socket makes the kernel reset the
-- connection, and a client still writing the frame got ECONNRESET from its write instead of
-- the answer (the Python client's @sendall@ of a 5 MB request, every time here).
lingeringClose :: Double -> Socket -> IO ()
lingeringClose seconds conn = void . try @SomeException $ do
  shutdown conn ShutdownSend
  let dropAll = do
        chunk <- NSB.recv conn 65536
        unless (B.null chunk) dropAll
  void (timeout (round (seconds * 1e6)) dropAll)

-- | Stop accepting and ask every connection to finish after its in-flight request.
stopServer :: Server -> IO ()
stopServer s = do
  atomically (writeTVar (envDraining (srvEnv s)) True)
  cancel (srvAccept s)
  close (srvSocket s)

-- | Wait until the server has been stopped and every connection has finished.
waitServer :: Server -> IO ()
waitServer s = atomically $ do
  d <- readTVar (envDraining (srvEnv s))
  n <- readTVar (srvActive s)
  check (d && n == 0)

-- | Run an action with a server on the configured port; stop and drain after.
withServer :: ServerConfig -> Handler -> (Server -> IO a) -> IO a
withServer cfg h act = bracket (startServer cfg h) (\s -> stopServer s >> waitServer s) act

-- | @vprof serve@ on TCP: print @listening on HOST:PORT@ on stderr, serve until SIGTERM or
-- SIGINT, then drain and return.
serve :: ServerConfig -> Handler -> IO ()
serve cfg handler = do
  hSetBuffering stderr LineBuffering
  s <- startServer cfg handler
  n <- resolveWorkers cfg
  hPutStrLn stderr ("listening on " <> cfgHost cfg <> ":" <> show (serverPort s)
                    <> " workers=" <> show n)
  hFlush stderr
  let onSignal = Sig.Catch (stopServer s)
  _ <- Sig.installHandler Sig.sigTERM onSignal Nothing
  _ <- Sig.installHandler Sig.sigINT onSignal Nothing
  waitServer s
  unless (cfgQuiet cfg) $ hPutStrLn stderr "vprof event=drained"

-- | @vprof serve --stdio@: the same framing on stdin/stdout, for running as a subprocess.
-- Ends at end of input or, after the in-flight request, on SIGTERM / SIGINT. No idle
-- timeout unless one is configured explicitly by the caller (pass it in 'cfgIdleTimeout').
serveStdio :: ServerConfig -> Handler -> IO ()
serveStdio cfg handler = do
  hSetBuffering stderr LineBuffering
  hSetBinaryMode stdin True
  hSetBinaryMode stdout True
  hSetBuffering stdout (BlockBuffering Nothing)
  env <- newEnv cfg handler
  let onSignal = Sig.Catch (atomically (writeTVar (envDraining env) True))
  _ <- Sig.installHandler Sig.sigTERM onSignal Nothing
  _ <- Sig.installHandler Sig.sigINT onSignal Nothing
  src <- newSource (B.hGetSome stdin 65536)
  void (connectionLoop env noGate (cfgIdleTimeout cfg) src (\bs -> B.hPut stdout bs >> hFlush stdout))
