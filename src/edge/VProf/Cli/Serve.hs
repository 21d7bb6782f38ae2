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
  <*> option auto (long "port" <> metavar "PORT" <> value (cfgPort d) <> showDefault
                   <> help "TCP port; 0 picks a free one (printed as 'listening on HOST:PORT' on stderr)")
  <*> switch (long "stdio" <> help "serve one client on stdin/stdout (same framing) instead of TCP")
  <*> option auto (long "workers" <> metavar "N" <> value 0
                   <> help "handler calls run at once (default: the number of cores)")
  <*> option auto (long "max-frame-bytes" <> metavar "BYTES" <> value (cfgMaxFrameBytes d)
                   <> showDefault <> help "largest request frame; larger ones get FRAME_TOO_LARGE and the connection is closed")
  <*> optional (option auto (long "idle-timeout" <> metavar "SECONDS"
                   <> help "close connections idle this long (default 60 on TCP, none with --stdio; 0 = never)"))
  <*> option auto (long "grace" <> metavar "SECONDS" <> value (cfgGrace d) <> showDefault
                   <> help "hard timeout of a request = its time_budget + this; then Error INTERNAL")
  <*> option auto (long "max-connections" <> metavar "N" <> value (cfgMaxConnections d)
                   <> showDefault <> help "connections served at once (more wait in the backlog)")
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

runServe :: Handler -> ServeOptions -> IO ExitCode
runServe handler o = do
  if soStdio o then serveStdio (soConfig o) handler else serve (soConfig o) handler
  pure ExitSuccess

-- | The parser of @vprof serve@'s options, returning the action that runs the daemon
-- and exits 0 after a drain.
serveCommand :: Handler -> Parser (IO ExitCode)
serveCommand handler = runServe handler <$> serveOptions
