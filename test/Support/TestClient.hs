-- | A minimal framed client for the server tests.
module Support.TestClient
  ( Client
  , connectClient
  , closeClient
  , withClient
  , sendRaw
  , sendRequest
  , recvFrame
  , recvResponse
  , shutdownSend
  , roundTrip
  ) where

import Control.Exception (bracket)
import qualified Data.ByteString as B
import Network.Socket
import qualified Network.Socket.ByteString as NSB
import System.Timeout (timeout)

import VProf.Wire.Framing
import VProf.Wire.Messages

data Client = Client { clSock :: Socket, clSrc :: Source }

connectClient :: Int -> IO Client
connectClient port = do
  let hints = defaultHints { addrSocketType = Stream, addrFlags = [AI_NUMERICSERV] }
  addr : _ <- getAddrInfo (Just hints) (Just "127.0.0.1") (Just (show port))
  s <- socket (addrFamily addr) Stream defaultProtocol
  connect s (addrAddress addr)
  Client s <$> newSource (NSB.recv s 65536)

closeClient :: Client -> IO ()
closeClient = close . clSock

withClient :: Int -> (Client -> IO a) -> IO a
withClient port = bracket (connectClient port) closeClient

sendRaw :: Client -> B.ByteString -> IO ()
sendRaw c = NSB.sendAll (clSock c)

sendRequest :: Client -> RequestMsg -> IO ()
sendRequest c = sendRaw c . frame . encodeBare

shutdownSend :: Client -> IO ()
shutdownSend c = shutdown (clSock c) ShutdownSend

-- | The next frame (10 s timeout, then an error).
recvFrame :: Client -> IO FrameResult
recvFrame c = timeout 10000000 (readFrame (64 * 1024 * 1024) (clSrc c))
  >>= maybe (fail "no answer within 10 s") pure

recvResponse :: Client -> IO ResponseMsg
recvResponse c = recvFrame c >>= \case
  Frame b _ -> either (fail . ("undecodable response: " ++)) pure (decodeBare b)
  other -> fail ("expected a response frame, got " ++ show other)

roundTrip :: Client -> RequestMsg -> IO ResponseMsg
roundTrip c r = sendRequest c r >> recvResponse c
