-- | The @vprof serve@ subcommand, over any 'Handler' (the executable passes
-- "VProf.Service"'s 'VProf.Service.service'; the test daemon its stub).
module VProf.Cli.Serve
  ( serveCommand
  , serveOptions
  , ServeOptions (..)
  , runServe
  ) where

import Options.Applicative
import System.Exit (ExitCode (..))

import VProf.Server


data ServeOptions = ServeOptions
  { soConfig :: ServerConfig
  , soStdio  :: Bool
  , soIdleGiven :: Maybe Double
  }

serveOptions :: Parser ServeOptions
serveOptions = mk
  <$> strOption (long "host" <> metavar "HOST" <> value (cfgHost d) <> showDefault
                 <> help "address to listen on")
  <*> option (eitherReader (whole "--port" 0 65535 "a TCP port from 0 to 65535 (0 picks a free one)"))
        (long "port" <> metavar "PORT" <> value (cfgPort d) <> showDefault
         <> help "TCP port, 0 to 65535; 0 picks a free one (printed as 'listening on HOST:PORT workers=N' on stderr)")
  <*> switch (long "stdio" <> help "serve one client on stdin/stdout (same framing) instead of TCP")
  <*> option (eitherReader (whole "--workers" 0 maxWorkers ("0 (the number of cores) or a count up to " ++ show maxWorkers)))
        (long "workers" <> metavar "N" <> value 0
         <> help "handler calls run at once (default 0: the number of cores)")
  <*> option (eitherReader (whole "--max-frame-bytes" minFrameBytes maxFrameBytes
                              ("a whole number of bytes from " ++ show minFrameBytes ++ " to " ++ show maxFrameBytes)))
        (long "max-frame-bytes" <> metavar "BYTES" <> value (cfgMaxFrameBytes d) <> showDefault
         <> help ("largest request frame (" ++ show minFrameBytes ++ " to " ++ show maxFrameBytes
                  ++ "); larger ones get FRAME_TOO_LARGE and the connection is closed"))
  <*> optional (option (eitherReader (seconds "--idle-timeout" maxIdleSeconds))
        (long "idle-timeout" <> metavar "SECONDS"
         <> help ("close connections idle this long (default 60 on TCP, none with --stdio; 0 = never; at most "
                  ++ show (round maxIdleSeconds :: Int) ++ ")")))
  <*> option (eitherReader (seconds "--grace" maxGraceSeconds))
        (long "grace" <> metavar "SECONDS" <> value (cfgGrace d) <> showDefault
         <> help ("hard timeout of a request = its time_budget + this (at most "
                  ++ show (round maxGraceSeconds :: Int) ++ "); then Error INTERNAL"))
  <*> option (eitherReader (whole "--max-connections" 1 maxConnections ("a count from 1 to " ++ show maxConnections)))
        (long "max-connections" <> metavar "N" <> value (cfgMaxConnections d) <> showDefault
         <> help "connections served at once; at the limit the one idle longest is closed for a new client, and while every one has a request in hand the new client waits")
  <*> switch (long "quiet" <> help "no per-request log lines on stderr")
  where
    d = defaultServerConfig
    mk host port stdio workers maxFrame idleT grace maxConn quiet = ServeOptions
      { soConfig = d { cfgHost = host, cfgPort = port, cfgWorkers = workers
                     , cfgMaxFrameBytes = maxFrame
                     , cfgIdleTimeout = maybe (if stdio then 0 else cfgIdleTimeout d) id idleT
                     , cfgGrace = grace, cfgMaxConnections = maxConn, cfgQuiet = quiet }
      , soStdio = stdio
      , soIdleGiven = idleT
      }
    -- read as an Integer, so that a number beyond Int is refused, not wrapped around (a
    -- --port of 70000 served on 4464)
    whole :: String -> Integer -> Integer -> String -> String -> Either String Int
    whole opt lo hi expected str = case reads str of
      [(x, "")] | x >= lo && x <= hi -> Right (fromInteger x)
      _ -> Left (opt ++ " " ++ str ++ ": expected " ++ expected)
    seconds :: String -> Double -> String -> Either String Double
    seconds opt hi str = case reads str of
      [(x, "")] | not (isNaN x || isInfinite x) && x >= 0 && x <= hi -> Right x
      _ -> Left (opt ++ " " ++ str ++ " s: expected a number of seconds from 0 to " ++ show (round hi :: Int))

-- | Bounds of the options: beyond them a value is a typing error, not a configuration.
maxWorkers, minFrameBytes, maxFrameBytes, maxConnections :: Integer
maxWorkers = 1024
minFrameBytes = 64            -- a ping's frame is a few bytes; a profile request a few dozen
maxFrameBytes = 1024 * 1024 * 1024
maxConnections = 65536
maxIdleSeconds, maxGraceSeconds :: Double
maxIdleSeconds = 1e6
maxGraceSeconds = 3600

runServe :: Handler -> ServeOptions -> IO ExitCode
runServe handler o = do
  if soStdio o then serveStdio (soConfig o) handler else serve (soConfig o) handler
  pure ExitSuccess

-- | The parser of @vprof serve@'s options, returning the action that runs the daemon
-- and exits 0 after a drain.
serveCommand :: Handler -> Parser (IO ExitCode)
serveCommand handler = runServe handler <$> serveOptions
