-- | @vprof compress@: read a recording, compress it, write the path, print the table.
-- Exit codes: 0 ok, 1 tolerance not met, 2 invalid input.
module VProf.Cli.Compress
  ( compressCommand
  , CompressOptions (..)
  , compressOptions
  , runCompress
  ) where

import Control.Exception (IOException, evaluate, try)
import Control.Monad (when)
import qualified Data.Aeson as A
import qualified Data.ByteString.Char8 as B
import qualified Data.ByteString.Lazy.Char8 as BL
import Data.Char (isDigit, toLower)
import Data.List (intercalate, isPrefixOf)
import GHC.Clock (getMonotonicTime)
import Options.Applicative
import VProf.Plot.File (plotPath)
import System.Exit (ExitCode (..))
import System.Directory (doesFileExist)
import System.FilePath (dropExtension, takeExtension, takeFileName)
import System.IO (hPutStrLn, stderr)
import Numeric (showFFloat)
import Numeric.Units.Dimensional.Prelude (metre, milli, (*~))
import Prelude

import qualified VProf.Cli.Output as Out
import VProf.Format.IOError (ioReason)
import VProf.Compress
import VProf.Compress.Clean
import VProf.Format.Text (dropBom)
import VProf.Compress.Format.Csv
import VProf.Compress.Format.Kitti
import VProf.Compress.Format.Log
import VProf.Compress.Format.Motive
import VProf.Compress.Format.Qualisys
import VProf.Compress.Format.Vicon
import VProf.Compress.Format.Rapid
import VProf.Compress.Format.Tum
import VProf.Compress.Objective (prepareRecording, toPathA)
import VProf.Plot.Compress
import VProf.Compress.Format.Report

data InFormat = InTum | InLog | InCsv | InKitti | InMod deriving (Show, Eq)
data OutFormat = OutTum | OutMod | OutCsv deriving (Show, Eq)
data Stop = StopPoints Int | StopMargin Double | StopTolerance Double deriving (Show, Eq)

data CompressOptions = CompressOptions
  { coInput        :: FilePath
  , coInputFormat  :: Maybe InFormat
  , coTimes        :: Maybe FilePath
  , coWeights      :: (Double, Double, Double)
  , coStop         :: Maybe Stop
  , coMethod       :: Method
  , coSearch       :: Int
  , coEnds         :: Ends
  , coLeastSquares :: Bool
  , coOutput       :: Maybe FilePath
  , coOutputFormat :: Maybe OutFormat
  , coReport       :: Bool
  , coReportJson   :: Bool
  , coPlot         :: Maybe FilePath
  , coRapid        :: RapidOptions
  , coClean        :: CleanOptions
  , coRigidBody    :: Maybe String
  }

compressCommand :: Parser (IO ExitCode)
compressCommand = runCompress <$> compressOptions

compressOptions :: Parser CompressOptions
compressOptions = rejectFlag <$> switch (long "reject-outliers" <> help "reject isolated position spikes (outlier factor 5 unless --outlier-factor is given); a warning says how many and where") <*> compressOptions'
  where
    rejectFlag on o = let c = coClean o in
      if on && cleanRejectOutliers c == Nothing then o { coClean = c { cleanRejectOutliers = Just defaultOutlierFactor } } else o

compressOptions' :: Parser CompressOptions
compressOptions' = CompressOptions
  <$> strArgument (metavar "RECORDING" <> help "recorded motion: TUM text, CSV with a header naming its columns (vprof's own, EuRoC, ROS), an OptiTrack Motive CSV export, a Qualisys 6D TSV export, a Vicon Nexus CSV export (Segments), KITTI poses (with --times), Polhemus CSV log or RAPID .mod")
  <*> optional (option (eitherReader inFmt) (long "input-format" <> metavar "tum|csv|kitti|log|mod"
        <> help "format of RECORDING (default: an OptiTrack Motive, Qualisys 6D TSV or Vicon Nexus CSV export by its first lines, whatever the extension, read as csv; else from the extension; .csv is csv if its first line is a header, else a log; .log is a log, .mod RAPID; else csv when its first line that is not a # comment names its columns, KITTI when its first such line holds 12 numbers, or TUM)"))
  <*> optional (strOption (long "times" <> metavar "FILE"
        <> help "KITTI poses only: their times, one a line in s (KITTI's times.txt); default: RECORDING's name with _times before the extension, if that file exists"))
  <*> option (eitherReader weights) (long "weights" <> metavar "P,O,V" <> value (1, 1, 1)
        <> help "weights of position, orientation and velocity error as the thesis's vekt = [p o v], in its units (mm, degrees, m/s) (default 1,1,1)")
  <*> optional stopP
  <*> option (eitherReader method) (long "method" <> metavar "knots|thesis|rdp" <> value MethodKnots
        <> help "knots: weighted least squares with the waypoint times optimised from a line-partition start (default; to --tolerance the fewest points it finds within it; with --margin it runs thesis); thesis: the thesis's grow/shrink weighted least squares; rdp: 3-D Ramer-Douglas-Peucker baseline")
  <*> option (eitherReader searchRounds) (long "search" <> metavar "N" <> value 0
        <> help "knot fit only: N more rounds from random starts and from perturbations of the best path, the best kept (each round costs about one fit; default 0)")
  <*> option (eitherReader ends) (long "ends" <> metavar "pinned|free" <> value EndsPinned
        <> help "pinned: the first and last waypoint are the first and last sample's pose (default); free: they are fitted by least squares like the others (lower error; the path starts near, not at, the first sample; not with rdp)")
  <*> switch (long "least-squares-only" <> help "knot fit: skip the two steps after least squares, which by default move the waypoint times towards the orientation and lower the largest position error, each at up to 0.25 % more position RMSE (to a --tolerance only the second, at up to 2.5 %, for fewer points)")
  <*> optional (strOption (short 'o' <> long "output" <> metavar "OUT" <> help "write the path here"))
  <*> optional (option (eitherReader outFmt) (long "output-format" <> metavar "tum|mod|csv"
        <> help "format of OUT (default: from its extension, .mod RAPID, .csv CSV, else TUM)"))
  <*> switch (long "report" <> help "print the table of measures (thesis table 1), with the other method at the same number of points")
  <*> switch (long "report-json" <> help "print the measures as JSON")
  <*> optional (option (eitherReader (plotPath [".png", ".svg"])) (long "plot" <> metavar "FILE.png|.svg" <> help "plot raw and fitted position, orientation and speed"))
  <*> rapidP
  <*> cleanP
  <*> optional (strOption (long "rigid-body" <> metavar "NAME"
        <> help "OptiTrack Motive, Qualisys 6D or Vicon Nexus export only: the rigid body (bone, or Nexus Subject:Segment) to read, by the name in its header (default: the only one)"))
  where
    cleanP = CleanOptions
      <$> option (eitherReader dups) (long "duplicates" <> metavar "merge|drop" <> value MergeDuplicates
            <> help "samples sharing a time: merge them into one (positions averaged, quaternions sign-aligned and averaged; default) or keep the first only; either way a warning says how many and where")
      <*> optional (option (eitherReader factorD) (long "outlier-factor" <> metavar "K"
            <> help "reject isolated position spikes more than K times the local step (and the robust noise spread) away from their neighbours' line; --reject-outliers is K = 5; default: keep every sample"))
      <*> option (eitherReader posD) (long "gap-factor" <> metavar "F" <> value (cleanGapFactor defaultCleanOptions) <> showDefault
            <> help "warn about time steps longer than F times the median step")
    dups s = case map toLower s of
      "merge" -> Right MergeDuplicates
      "drop" -> Right DropDuplicates
      _ -> Left ("--duplicates " ++ s ++ ": expected merge or drop")
    posD s = case readD s of
      Just d | finite d && d > 0 -> Right d
      _ -> Left (s ++ ": expected a finite number > 0")
    -- below 1 a sample one ordinary step off its neighbours' line would be a spike
    factorD s = case readD s of
      Just d | finite d && d >= 1 && d <= 1e6 -> Right d
      _ -> Left ("--outlier-factor " ++ s ++ ": expected a number from 1 to 10^6 (times the local step; 5 is --reject-outliers)")
    stopP = (StopPoints <$> option (eitherReader posInt) (long "points" <> metavar "K" <> help "waypoints wanted (default: 3 % of the samples)"))
        <|> (StopMargin <$> option auto (long "margin" <> metavar "M" <> help "stop removing points when the error passes M times the grown path's error"))
        <|> (StopTolerance <$> option auto (long "tolerance" <> metavar "MM" <> help "largest position error allowed, mm (time-synchronous); the fewest points found within it"))
    rapidP = RapidOptions
      <$> option (eitherReader (rapidName "--rapid-module")) (long "rapid-module" <> metavar "NAME" <> value (roModule defaultRapidOptions) <> showDefault <> help "RAPID module name")
      <*> option (eitherReader (rapidName "--rapid-speed")) (long "rapid-speed" <> metavar "SPEED" <> value (roSpeed defaultRapidOptions) <> showDefault <> help "RAPID speed data")
      <*> option (eitherReader (rapidName "--rapid-zone")) (long "rapid-zone" <> metavar "ZONE" <> value (roZone defaultRapidOptions) <> showDefault <> help "RAPID zone data")
      <*> option (eitherReader (rapidName "--rapid-tool")) (long "rapid-tool" <> metavar "TOOL" <> value (roTool defaultRapidOptions) <> showDefault <> help "RAPID tool data")
      <*> option (eitherReader (rapidName "--rapid-wobj")) (long "rapid-wobj" <> metavar "WOBJ" <> value (roWobj defaultRapidOptions) <> showDefault <> help "RAPID work object")
    -- a RAPID identifier: a letter, then letters, digits or underscores, 32 characters at most
    rapidName what s
      | map toLower s `elem` rapidReserved = Left (what ++ " " ++ show s ++ ": a RAPID reserved word cannot be a name")
      | (c : cs) <- s, isAsciiLetter c, all (\x -> isAsciiLetter x || isDigit x || x == '_') cs, length s <= 32 = Right s
      | otherwise = Left (what ++ " " ++ show s ++ ": expected a RAPID identifier (a letter, then letters, digits or _; at most 32 characters)")
    isAsciiLetter x = (x >= 'a' && x <= 'z') || (x >= 'A' && x <= 'Z')
    inFmt s = case map toLower s of
      "tum" -> Right InTum
      "log" -> Right InLog
      "csv" -> Right InCsv
      "kitti" -> Right InKitti
      "mod" -> Right InMod
      _ -> Left ("--input-format " ++ s ++ ": expected tum, csv, kitti, log or mod")
    outFmt s = case map toLower s of
      "tum" -> Right OutTum
      "mod" -> Right OutMod
      "csv" -> Right OutCsv
      _ -> Left ("--output-format " ++ s ++ ": expected tum, mod or csv")
    method s = case map toLower s of
      "knots" -> Right MethodKnots
      "thesis" -> Right MethodThesis
      "rdp" -> Right MethodRdp
      _ -> Left ("--method " ++ s ++ ": expected knots, thesis or rdp")
    ends s = case map toLower s of
      "pinned" -> Right EndsPinned
      "free" -> Right EndsFree
      _ -> Left ("--ends " ++ s ++ ": expected pinned or free")
    -- read as an Integer, so that a number beyond Int is refused, not wrapped around
    searchRounds s = case reads s of
      [(r, "")] | r >= (0 :: Integer) && r <= toInteger maxSearchRounds -> Right (fromInteger r)
      _ -> Left ("--search " ++ s ++ ": expected a whole number from 0 to " ++ show maxSearchRounds)
    posInt s = case reads s of
      [(k, "")] | k >= (2 :: Integer) && k <= 1000000000 -> Right (fromInteger k)
      _ -> Left ("--points " ++ s ++ ": expected a whole number from 2 to 10^9")
    weights s = case mapM readD (splitOn ',' s) of
      Just [p, o, v] | all (\x -> finite x && x >= 0 && x <= 1e6) [p, o, v] && (p > 0 || v > 0) -> Right (p, o, v)
      _ -> Left ("--weights " ++ s ++ ": expected three numbers from 0 to 10^6, P,O,V, with P or V > 0 (only their ratios matter)")
    readD x = case reads x of
      [(d, "")] -> Just (d :: Double)
      _ -> Nothing

-- | The compression settings as this command's options, in the units it takes them in.
optionName :: String -> Maybe UserField
optionName = \case
  "points" -> Just (UserField "--points" "" 1)
  "margin" -> Just (UserField "--margin" "" 1)
  "tolerance" -> Just (UserField "--tolerance" "mm" 1000)
  "search" -> Just (UserField "--search" "" 1)
  "ends" -> Just (UserField "--ends" "" 1)
  f | "weights" `isPrefixOf` f -> Just (UserField "--weights" "" 1)
  _ -> Nothing

-- | Where a KITTI recording's times are looked for without --times: its name with _times
-- before the extension (poses.txt, poses_times.txt).
kittiTimesSibling :: FilePath -> FilePath
kittiTimesSibling file = dropExtension file ++ "_times" ++ takeExtension file

splitOn :: Char -> String -> [String]
splitOn c s = case break (== c) s of
  (a, _ : b) -> a : splitOn c b
  (a, []) -> [a]

runCompress :: CompressOptions -> IO ExitCode
runCompress o = do
  clash <- Out.overwritesInput (("the recording", file) : [ ("the times file", f) | Just f <- [coTimes o] ]) outputs
  maybe readAndRun failInput clash
  where
    -- a KITTI recording's times: --times, else the file beside it if there is one
    timesFile = case coTimes o of
      Just f -> pure (Just f)
      Nothing -> let sibling = kittiTimesSibling file
                 in doesFileExist sibling >>= \ok -> pure (if ok then Just sibling else Nothing)
    outputs = [ ("-o", f) | Just f <- [coOutput o] ] ++ [ ("--plot", f) | Just f <- [coPlot o] ]
    readAndRun = do
      src <- try (dropBom <$> B.readFile file)
      case src of
        Left e -> failInput ("cannot read " ++ file ++ ": " ++ ioReason (e :: IOException))
        Right bytes -> do
          let fmt = maybe (guessIn file bytes) id (coInputFormat o)
          parsed <- case coTimes o of
            -- a times file beside a recording that has its own times would be ignored
            Just tf | fmt /= InKitti -> pure (Left ("--times " ++ tf ++ ": only KITTI poses take a times file; " ++ file
                                                   ++ " is read as " ++ formatName fmt ++ ", whose times it holds itself"))
            _ | Just b <- coRigidBody o, not (fmt == InCsv && isMocapExport bytes) ->
                  pure (Left ("--rigid-body " ++ show b ++ ": only an OptiTrack Motive, Qualisys 6D or Vicon Nexus export names rigid bodies; " ++ file
                              ++ " is read as " ++ formatName fmt))
            _ -> parseWith fmt bytes
          case parsed of
            Left e -> failInput e
            Right (notes, samples) -> case cleanSamples fileLocator (coClean o) samples of
              Left errs -> do
                -- a KITTI recording's times (and so their order) come from its times file, line for line
                tf <- if fmt == InKitti then timesFile else pure Nothing
                failInput (maybe file (\t -> file ++ " with the times of " ++ t ++ " (the same line numbers)") tf
                           ++ ": " ++ intercalate "; " (map renderFieldError errs))
              Right cl -> do
                mapM_ (\n -> hPutStrLn stderr ("vprof compress: note: " ++ file ++ ": " ++ n)) notes
                mapM_ (\w -> hPutStrLn stderr ("vprof compress: " ++ label w ++ ": " ++ file ++ ": " ++ renderCleanWarning fileLocator w))
                      (clWarnings cl)
                go (clWarnings cl) (Recording (clTrack cl))
    -- sign flips change no orientation (q and -q are the same): a note, not a warning
    label = \case SignFlips {} -> "note"; _ -> "warning"
    failInput = Out.failIn "compress"
    -- a motion-capture system's export, whose header says what it is
    isMocapExport bytes = isMotiveCsv bytes || isQualisysTsv bytes || isViconCsv bytes
    guessIn f bytes = case map toLower (takeExtension f) of
      ".mod" -> InMod
      _ | isMocapExport bytes -> InCsv
      ".log" -> InLog
      ".csv" | hasCsvHeader bytes -> InCsv
             | otherwise -> InLog
      _ | hasNamedHeader bytes -> InCsv      -- a tab- or blank-separated file with a header of names
        | looksLikeKitti bytes -> InKitti
        | otherwise -> InTum
    file = coInput o
    formatName = \case
      InTum -> "TUM"
      InLog -> "a Polhemus log"
      InCsv -> "CSV"
      InMod -> "RAPID"
      InKitti -> "KITTI poses"
    -- a reader's answer: its error after the file's name, or its samples with the notes on how it read them
    answered :: (a -> ([String], [Sample])) -> Either String a -> IO (Either String ([String], [Sample]))
    answered notes = pure . either (Left . ((file ++ ": ") ++)) (Right . notes)
    plain = answered ((,) [])
    parseWith InTum b = plain (readTum b)
    parseWith InLog b
      -- a CSV of numbers only is taken for a Polhemus log: say so, since its units are not SI
      | coInputFormat o == Nothing && map toLower (takeExtension file) == ".csv" =
          answered ((,) ["no header: read as a Polhemus-style log (time in ms, position in mm, then qw,qx,qy,qz);"
                         ++ " for seconds and metres give the header time,x,y,z,qw,qx,qy,qz"]) (readLog b)
      | otherwise = plain (readLog b)
    parseWith InMod b = plain (readRapid b)
    parseWith InCsv b
      | isMotiveCsv b = answered (\(l, ss) -> ([describeMotive l], ss)) (readMotive (coRigidBody o) b)
      | isQualisysTsv b = answered (\(l, ss) -> ([describeQualisys l], ss)) (readQualisys (coRigidBody o) b)
      | isViconCsv b = answered (\(l, ss) -> ([describeVicon l], ss)) (readVicon (coRigidBody o) b)
      | otherwise = answered (\(l, ss) -> ([describeLayout l], ss)) (readCsv b)
    parseWith InKitti b = do
      let sibling = kittiTimesSibling file
      given <- timesFile
      case given of
        Nothing -> pure (Left (file ++ ": KITTI poses (12 numbers a line) carry no times: give --times FILE (one time in s a line, KITTI's times.txt); "
                               ++ sibling ++ " does not exist"))
        Just tf -> do
          -- the times file found beside the recording is an input too
          clash <- Out.overwritesInput [("the times file", tf)] outputs
          tb <- maybe (try (dropBom <$> B.readFile tf)) (\_ -> pure (Right B.empty)) clash
          pure $ case tb of
            _ | Just msg <- clash -> Left msg
            Left e -> Left ("cannot read the times " ++ tf ++ ": " ++ ioReason (e :: IOException))
            Right times -> case readKitti b times of
              Left e -> Left (file ++ " with the times of " ++ tf ++ ": " ++ e)
              Right ss -> Right (["read as KITTI poses (3x4 [R | t] a line, m) with the times of " ++ tf], ss)
    (wp, wo, wv) = coWeights o
    settings = Settings
      { sMethod = coMethod o
      , sWeights = thesisWeights wp wo wv
      , sPoints = case coStop o of Just (StopPoints k) -> Just k; _ -> Nothing
      , sMargin = case coStop o of Just (StopMargin m) -> Just m; _ -> Nothing
      , sTolerance = case coStop o of Just (StopTolerance t) -> Just (t *~ milli metre); _ -> Nothing
      , sSearch = coSearch o
      , sEnds = coEnds o
      , sPolish = not (coLeastSquares o)
      }
    go warns rec = do
      t0 <- getMonotonicTime
      res <- evaluate (compress settings rec)
      case res of
        Left errs -> failInput (intercalate "; " (map renderFieldError (inUserTerms optionName errs)))
        Right out -> do
          _ <- evaluate (mPoints (oMetrics out))
          t1 <- getMonotonicTime
          let k = mPoints (oMetrics out)
          case sPoints settings of
            Just asked | k < asked -> hPutStrLn stderr ("vprof compress: note: " ++ file ++ ": " ++ show k ++ " points, fewer than the "
                                                         ++ show asked ++ " asked: no further waypoint lowered the error (stop: " ++ oStop out ++ ")")
            _ -> pure ()
          -- a tolerance near the recording's noise keeps most samples: say so
          case sTolerance settings of
            Just _ | coMethod o == MethodKnots && k > 2 && 2 * k > mSamples (oMetrics out) ->
              hPutStrLn stderr ("vprof compress: note: " ++ file ++ ": " ++ show k ++ " of the " ++ show (mSamples (oMetrics out))
                                ++ " samples are waypoints: the tolerance is near the recording's noise (--report shows the errors)")
            _ -> pure ()
          let
              -- the knot fit hands a margin to the thesis method: name what ran
              ran = if coMethod o == MethodKnots && sMargin settings /= Nothing
                      then MethodThesis else coMethod o
              other = if coMethod o == MethodRdp then MethodKnots else MethodRdp
              cmpSettings = settings { sMethod = other, sPoints = Just k, sMargin = Nothing, sTolerance = Nothing, sSearch = 0
                                    , sEnds = if other == MethodRdp then EndsPinned else sEnds settings }
              name m = case m of
                MethodKnots -> "knots"
                MethodThesis -> "thesis"
                MethodRdp -> "rdp"
          cols <- if coReport o || coReportJson o
            then do
              c0 <- getMonotonicTime
              cmp <- evaluate (compress cmpSettings rec)
              cm <- case cmp of
                Right oc -> evaluate (mPoints (oMetrics oc)) >> pure (Just oc)
                Left _ -> pure Nothing
              c1 <- getMonotonicTime
              pure (ReportColumn (name ran) (oMetrics out) (Just (t1 - t0))
                    : [ ReportColumn (name other ++ " (same points)") (oMetrics oc) (Just (c1 - c0)) | Just oc <- [cm] ])
            else pure []
          when (coReport o) $ do
            putStrLn ("vprof compress " ++ coInput o ++ ": " ++ show (mSamples (oMetrics out)) ++ " samples -> "
                      ++ show k ++ " points (" ++ name ran ++ ", weights " ++ intercalate "," (map show [wp, wo, wv])
                      ++ (case sSearch settings of { 0 -> ""; 1 -> ", search 1 round"; r -> ", search " ++ show r ++ " rounds" })
                      ++ (if sEnds settings == EndsFree then ", ends free" else "")
                      ++ (if coLeastSquares o && ran == MethodKnots then ", least squares only" else "")
                      ++ ", stop: " ++ oStop out ++ ")")
            mapM_ (\w -> putStrLn (label w ++ ": " ++ renderCleanWarning fileLocator w)) warns
            putStr (renderReport (wp, wo, wv) cols)
          when (coReportJson o) $
            BL.putStrLn (A.encode (withWarnings (warningsJson fileLocator warns) (reportJson (sWeights settings) cols)))
          let tr = pathTrack (oPath out)
              outFmt f = maybe (guessOut f) id (coOutputFormat o)
              render f = case outFmt f of
                OutTum -> renderTum tr
                OutCsv -> renderCsv tr
                OutMod -> BL.pack (renderRapid (coRapid o) tr)
          -- an output that cannot be written is a bad option: exit 2 naming it
          let writing = Out.writing "vprof compress"
          okOut <- case coOutput o of
            Just f -> writing f (BL.writeFile f (render f))
            Nothing | not (coReport o || coReportJson o) && coPlot o == Nothing -> writing "the path to standard output" (BL.putStr (render ""))
                    | otherwise -> writing "standard output" (pure ())
          okPlot <- case coPlot o of
            Just f -> writing f (plotCompression f (takeFileName (coInput o) ++ ", " ++ show k ++ " points") (prepareRecording rec) (toPathA (oPath out)))
            Nothing -> pure True
          if not (okOut && okPlot) then pure (ExitFailure 2) else if oToleranceMet out
            then pure ExitSuccess
            else do
              hPutStrLn stderr ("vprof compress: tolerance not met: largest position error "
                                ++ showFFloat (Just 4) (mPositionMax (oMetrics out) * 1e3) " mm with " ++ show k ++ " points, the most"
                                ++ " the thesis method reaches (it grows to about 15 % of the samples); that path is the output."
                                ++ " For a finer one ask for more points (--points N; --report shows the largest error)"
                                ++ " or allow a larger tolerance")
              pure (ExitFailure 1)
    guessOut f = case map toLower (takeExtension f) of
      ".mod" -> OutMod
      ".csv" -> OutCsv
      _ -> case coOutputFormat o of
        Just x -> x
        Nothing -> OutTum
