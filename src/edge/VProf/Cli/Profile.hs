{-# LANGUAGE OverloadedStrings #-}
-- | The velocity-profile commands of the @vprof@ executable:
--
-- > vprof REQUEST [--format pb|csv|json|table] [-o FILE] [--plot FILE.png|.svg|.pdf]
-- > vprof check REQUEST PROFILE
--
-- REQUEST is a binary ProfileRequest (@.pb@, or any other extension) or its proto3 JSON
-- form (@.json@). Exit codes: 0 legal and converged, 1 illegal, infeasible or not
-- converged, 2 invalid input.
module VProf.Cli.Profile
  ( generateOptions
  , checkCommand
  , encodeCommand
  ) where

import qualified Data.ByteString as B
import qualified Data.ByteString.Lazy as BL
import qualified Data.ByteString.Lazy.Char8 as BLC
import Data.Char (toLower)
import Data.Word (Word64)
import qualified Data.Vector.Unboxed as U
import Options.Applicative
import VProf.Plot.File (plotPath)
import System.Exit
import System.FilePath (takeExtension)
import System.IO

import qualified VProf.Cli.Output as Out
import VProf.Profile.Generate
import VProf.Profile.Format.File
import VProf.Profile.Format.Json
import VProf.Profile.Legality
import VProf.Profile.Format.Text
import VProf.Plot.Profile
import VProf.Profile.Sampled
import VProf.Profile.Request
import VProf.Units
import VProf.Wire.Profile
import VProf.Wire.Messages

data Format = FPb | FCsv | FJson | FTable deriving (Eq, Show)

data GenOpts = GenOpts
  { goRequest :: FilePath
  , goFormat :: Maybe Format
  , goOutput :: Maybe FilePath
  , goPlot :: Maybe FilePath
  , goAlgorithm :: Maybe Algorithm
  , goBudget :: Maybe Double
  }

formatReader :: ReadM Format
formatReader = eitherReader $ \s -> case map toLower s of
  "pb" -> Right FPb
  "csv" -> Right FCsv
  "json" -> Right FJson
  "table" -> Right FTable
  _ -> Left ("--format: unknown format " ++ show s ++ " (pb, csv, json or table)")

algorithmReader :: ReadM Algorithm
algorithmReader = eitherReader $ \s -> case map toLower s of
  "band" -> Right Band
  "default" -> Right Band
  "thesis" -> Right Thesis
  _ -> Left ("--algorithm: unknown algorithm " ++ show s ++ " (band or thesis)")

-- | The default command: generate a profile.
generateOptions :: Parser (IO ExitCode)
generateOptions = runGenerate <$> (GenOpts
  <$> strArgument (metavar "REQUEST" <> help "a ProfileRequest: binary protobuf (.pb) or proto3 JSON (.json)")
  <*> optional (option formatReader (long "format" <> short 'f' <> metavar "pb|csv|json|table"
        <> help "write the profile in this format (default: from -o's extension, else only the summary)"))
  <*> optional (strOption (long "output" <> short 'o' <> metavar "FILE" <> help "write the profile here instead of standard output"))
  <*> optional (option (eitherReader (plotPath [".png", ".svg", ".pdf"])) (long "plot" <> metavar "FILE.png|.svg|.pdf" <> help "draw v, a, j and s over t with the speed limit"))
  <*> optional (option algorithmReader (long "algorithm" <> metavar "band|thesis" <> help "override the request's algorithm"))
  <*> optional (option auto (long "time-budget" <> metavar "SECONDS" <> help "override the request's time budget")))

runGenerate :: GenOpts -> IO ExitCode
runGenerate o = do
  clash <- Out.overwritesInput [("the request", goRequest o)]
                               ([ ("-o", f) | Just f <- [goOutput o] ] ++ [ ("--plot", f) | Just f <- [goPlot o] ])
  er <- maybe (readRequestWithId (goRequest o)) (pure . Left) clash
  case er of
    Left e -> hPutStrLn stderr ("vprof: " ++ e) >> pure (ExitFailure 2)
    Right (rid, rq0) -> do
      let rq = rq0 { rqAlgorithm = maybe (rqAlgorithm rq0) id (goAlgorithm o)
                   , rqTimeBudget = maybe (rqTimeBudget rq0) (Just . (*~ second)) (goBudget o) }
      res <- generate rq
      let fmt = case (goFormat o, goOutput o) of
            (Just f, _) -> Just f
            (Nothing, Just out) -> Just (formatFromExt out)
            (Nothing, Nothing) -> Nothing
          toStdout = goOutput o == Nothing && fmt /= Nothing
          summaryHandle = if toStdout then stderr else stdout
          -- an output that cannot be written is a bad option: exit 2 naming the file
          writing = Out.writing "vprof"
      okSum <- if toStdout then True <$ hPutStr stderr (summary res)
               else writing "the summary to standard output" (putStr (summary res))
      okOut <- case (fmt, resOutcome res) of
        -- CSV and the table hold only a profile: with none, a file named by -o is left as it
        -- was (an empty one took its place); protobuf and JSON carry the error instead
        (Just f, _) | f `elem` [FCsv, FTable], Nothing <- resProfile res, Just out <- goOutput o -> do
          hPutStrLn stderr ("vprof: no profile to write: " ++ out ++ " left as it was")
          pure True
        (Just f, _) -> writing (maybe "the profile" id (goOutput o)) (writeProfile rid f (goOutput o) res)
        _ -> pure True
      okPlot <- case (goPlot o, resProfile res, validate rq) of
        (Just plotPath, Just p, Right pb) ->
          writing plotPath (plotProfile plotPath "vprof velocity profile" pb p >> hPutStrLn summaryHandle ("plot:          " ++ plotPath))
        _ -> pure True
      pure $ case resOutcome res of
        _ | not (okSum && okOut && okPlot) -> ExitFailure 2
        Generated -> ExitSuccess
        Failed (InvalidRequest _) -> ExitFailure 2
        Failed _ -> ExitFailure 1

formatFromExt :: FilePath -> Format
formatFromExt path = case map toLower (takeExtension path) of
  ".csv" -> FCsv
  ".json" -> FJson
  ".pb" -> FPb
  ".bin" -> FPb
  _ -> FTable

-- | The profile in the format, answering the request with this request_id (echoed in the
-- binary and JSON forms).
writeProfile :: Word64 -> Format -> Maybe FilePath -> Result -> IO ()
writeProfile rid f out res = case f of
  FPb -> let bytes = encodeBare (resultToMsg rid res) in maybe (B.hPut stdout bytes) (`B.writeFile` bytes) out
  FJson -> let bytes = profileJsonFor rid res in maybe (BLC.putStrLn bytes) (`BL.writeFile` bytes) out
  FCsv -> let bytes = maybe BL.empty csv (resProfile res) in maybe (BL.hPut stdout bytes) (`BL.writeFile` bytes) out
  FTable -> text (maybe "" table (resProfile res))
  where text s = maybe (putStr s) (`writeFile` s) out

-- | @vprof check REQUEST PROFILE@
checkCommand :: Parser (IO ExitCode)
checkCommand = runCheck
  <$> strArgument (metavar "REQUEST" <> help "the request the profile answers (.pb or .json)")
  <*> strArgument (metavar "PROFILE" <> help "the profile: CSV (t,s,v,a,j), JSON or binary ProfileResponse")

runCheck :: FilePath -> FilePath -> IO ExitCode
runCheck reqPath profPath = do
  er <- readRequest reqPath
  ep <- readProfile profPath
  case (er, ep) of
    (Left e, _) -> Out.failIn "check" e
    (_, Left e) -> Out.failIn "check" e
    -- the time step is the profile's (from its first two samples); a profile of one sample
    -- has none, and is checked at the request's
    (Right rq, Right (dt0, vs)) -> case validate (if U.length vs < 2 then rq else rq { rqTimeStep = Just (dt0 *~ second) }) of
      Left es -> mapM_ (Out.failIn "check" . renderFieldError) es >> pure (ExitFailure 2)
      Right pb -> do
        let dt = pbDt pb
            p = Profile dt vs (pbA0 pb) (pbAEnd pb)
            vio = check pb p
        putStrLn (show (sampleCount p) ++ " samples, dt " ++ show dt ++ " s, duration " ++ show (duration p)
                  ++ " s, final distance " ++ show (finalDistance p) ++ " m")
        if null vio
          then putStrLn "legal: no violations" >> pure ExitSuccess
          else do
            putStrLn ("illegal: " ++ show (length vio) ++ " violation(s)")
            mapM_ (putStrLn . ("  " ++) . renderViolation) vio
            pure (ExitFailure 1)

-- | @vprof encode REQUEST.json OUT.pb@: the binary form of a JSON request.
encodeCommand :: Parser (IO ExitCode)
encodeCommand = run
  <$> strArgument (metavar "REQUEST" <> help "a ProfileRequest in JSON (or binary)")
  <*> strArgument (metavar "OUT.pb" <> help "where to write the binary ProfileRequest")
  <*> optional (option (eitherReader uint64) (long "request-id" <> metavar "N" <> help "request_id to set (0 to 2^64 - 1; default: the request's own)"))
  where
    uint64 str = case reads str :: [(Integer, String)] of
      [(k, "")] | k >= 0 && k <= 18446744073709551615 -> Right (fromIntegral k)
      _ -> Left ("--request-id " ++ str ++ ": expected a whole number from 0 to 18446744073709551615 (a uint64)")
    run inp out rid = do
      clash <- Out.overwritesInput [("the request", inp)] [("OUT.pb", out)]
      er <- maybe (readRequestWithId inp) (pure . Left) clash
      case er of
        Left e -> Out.failIn "encode" e
        Right (own, rq) -> do
          ok <- Out.writing "vprof encode" out (B.writeFile out (encodeBare (requestToMsg (maybe own id rid) rq)))
          pure (if ok then ExitSuccess else ExitFailure 2)
