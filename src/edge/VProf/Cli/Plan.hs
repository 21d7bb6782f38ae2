{-# LANGUAGE OverloadedStrings #-}
-- | @vprof plan@: a path (RAPID @.mod@, TUM or CSV as @vprof compress@ writes them, or the targets
-- of a selection task file) and a robot to a timed, checked joint trajectory. A task file also
-- gives the cell, the base, the tool with its capsule, the clearance and the bodies left out of
-- the cell check, so that the task a user checked with @vprof select@ is planned as it stands.
--
-- > vprof plan PATH|TASK.yaml --robot NAME [--tip LINK] [--base "X Y Z [RX RY RZ]"] [--tool "X Y Z [RX RY RZ]"]
-- >   [--speed v500] [--zone z10|fine] [--acceleration A] [--jerk J] [--dt S] [--start "Q..."]
-- >   [--environment FILE.obj --clearance M] [--time-budget S] [--format summary|csv|json] [-o FILE]
-- >   [--plot FILE.png]
--
-- Exit codes: 0 a legal trajectory, 1 the plan stops (the reason and s), has no legal profile or
-- is not done within its time budget (default 60 s), 2 invalid input.
module VProf.Cli.Plan
  ( planCommand
  , parseSpeedData
  , parseZoneData
  ) where

import Control.Exception (IOException, evaluate, try)
import qualified Data.Aeson as A
import qualified Data.ByteString.Builder as BB
import qualified Data.ByteString.Char8 as B
import qualified Data.ByteString.Lazy.Char8 as BL
import Data.Char (toLower)
import Data.List (intercalate, isPrefixOf)
import Data.Maybe (fromMaybe, isJust, isNothing)
import qualified Data.Vector as V
import qualified Data.Vector.Unboxed as U
import GHC.Clock (getMonotonicTime)
import Numeric (showFFloat)
import Options.Applicative
import VProf.Plot.File (plotPath)
import System.Exit
import System.FilePath (takeExtension)
import System.IO
import System.Timeout (timeout)

import VProf.Cli.Kinematics (degreesTooWide, loadRobot)
import qualified VProf.Cli.Output as Out
import VProf.Format.IOError (ioReason)
import VProf.Compress.Clean (fileLocator, nonUnitWarning, renderCleanWarning)
import VProf.Compress.Format.Path (PathFile (..), readPathFile)
import VProf.Compress.Types (Track (..))
import VProf.Geometry.Bvh (buildBvh)
import VProf.Geometry.Format.Scene (SceneFile (..), loadScene)
import VProf.Geometry.Vec (P3 (..), Q4 (..), ptoList)
import VProf.Kinematics.Collision (CollisionOptions (..), collisionModel, defaultCollisionOptions, unknownBody)
import VProf.Kinematics.Model
import VProf.Kinematics.Transform (Quat (..), Tf, V3 (..), compose, fromRpy, identity, toQuat, translation)
import VProf.Plan
import VProf.Plot.Plan (plotPlan)
import VProf.Profile.Result (resultLegal)
import VProf.Select.Format.Task (readTaskFileWarned, taskFileInputs)
import VProf.Select.Task (MeshPlacement (..), Target (..), Task (..))
import VProf.Units
import VProf.Validation

data OutFormat = Summary | Csv | Json deriving (Eq)

data PlanOpts = PlanOpts
  { poPath :: FilePath, poRobot :: String, poTip :: Maybe String, poBase :: Maybe [Double], poTool :: Maybe [Double]
  , poSpeed :: Double, poZone :: Zone, poAcc :: Double, poJerk :: Double, poDt :: Double
  , poStart :: Maybe [Double], poDeg :: Bool
  , poEnv :: Maybe FilePath, poEnvScale :: Maybe Double, poClearance :: Maybe Double, poIgnore :: [Int]
  , poBudget :: Double
  , poFormat :: Maybe OutFormat, poOutput :: Maybe FilePath, poPlot :: Maybe FilePath }

-- | RAPID speed data: @vN@ is N mm/s (v5 … v7000, or any N); the TCP speed in m/s.
parseSpeedData :: String -> Either String Double
parseSpeedData s = case map toLower s of
  'v' : num | Just v <- readD num, finite v, v > 0 -> Right (v / 1000)
  _ -> Left ("--speed " ++ show s ++ ": expected RAPID speed data vN, N the TCP speed in mm/s > 0 (e.g. v500)")

-- | RAPID zone data: @fine@ (stop at every waypoint) or @zN@, N the zone radius in mm.
parseZoneData :: String -> Either String Zone
parseZoneData s = case map toLower s of
  "fine" -> Right Fine
  'z' : num | Just z <- readD num, finite z, z > 0 && z < minZoneMm ->
    Left ("--zone " ++ show s ++ ": a zone below " ++ show minZoneMm ++ " mm would be driven no faster than a stop"
          ++ " (the corner's speed goes with its radius) and costs a long plan; use fine (or z0) for a stop")
  'z' : num | Just z <- readD num, finite z, z >= 0 -> Right (if z == 0 then Fine else Blend ((z / 1000) *~ meter))
  _ -> Left ("--zone " ++ show s ++ ": expected RAPID zone data zN, N the zone radius in mm >= 0 (e.g. z10), or fine")

-- | The smallest zone radius taken, mm ('minZone').
minZoneMm :: Double
minZoneMm = minZone * 1000

readD :: String -> Maybe Double
readD w = case reads w of
  [(d, "")] -> Just d
  _ -> case reads ('0' : w) of
    [(d, "")] | take 1 w == "." -> Just d
    _ -> Nothing

planCommand :: Parser (IO ExitCode)
planCommand = runPlan <$> (PlanOpts
  <$> strArgument (metavar "PATH|TASK" <> help "the path: RAPID .mod, CSV (time,x,y,z,qw,qx,qy,qz; m) or TUM (other extensions), as vprof compress writes them; or a selection task file (.yaml/.yml/.json), whose targets are the waypoints and whose cell, base, tool, tool capsule, clearance and ignored bodies are used (the options below replace them)")
  <*> strOption (long "robot" <> metavar "NAME" <> help "a library robot (vprof robots lists them) or a robot file (.yaml/.json/.urdf)")
  <*> optional (strOption (long "tip" <> metavar "LINK" <> help "with a URDF --robot: the last link of the chain (default: the only leaf)"))
  <*> optional (option (eitherReader (pose "--base")) (long "base" <> metavar "\"X Y Z [RX RY RZ]\""
        <> help "the robot base in the path's frame: position in m, roll pitch yaw in degrees (default: the path's frame)"))
  <*> optional (option (eitherReader (pose "--tool")) (long "tool" <> metavar "\"X Y Z [RX RY RZ]\""
        <> help "the TCP in the flange frame: position in m, roll pitch yaw in degrees (default: the flange)"))
  <*> option (eitherReader parseSpeedData) (long "speed" <> metavar "vN" <> value 0.5
        <> help "the TCP speed limit as RAPID speed data, N in mm/s (default: v500)")
  <*> option (eitherReader parseZoneData) (long "zone" <> metavar "zN|fine" <> value (Blend (0.01 *~ meter))
        <> help "the corner zone as RAPID zone data: zN blends within N mm of each waypoint, fine stops there (default: z10)")
  <*> option (eitherReader (positive "--acceleration")) (long "acceleration" <> metavar "A" <> value defaultAcceleration
        <> help "the TCP acceleration range ±A, m/s² (default 2)")
  <*> option (eitherReader (positive "--jerk")) (long "jerk" <> metavar "J" <> value defaultJerk
        <> help "the TCP jerk range ±J, m/s³ (default 20)")
  <*> option (eitherReader dtR) (long "dt" <> metavar "S" <> value defaultTimeStep
        <> help "the controller's time step, s (default 0.004)")
  <*> optional (option (eitherReader (numbers "--start" 0)) (long "start" <> metavar "\"Q...\""
        <> help "the start configuration (rad and m; degrees with --deg); default: the first waypoint's solution nearest mid-limits"))
  <*> switch (long "deg" <> help "--start in degrees")
  <*> optional (strOption (long "environment" <> metavar "FILE.obj"
        <> help "keep the robot clear of this Wavefront OBJ scene (in the path's frame)"))
  <*> optional (option auto (long "scale" <> metavar "S"
        <> help "with --environment: its coordinates times S are metres (0.001 for millimetres; default 1; a task file's meshes have their own)"))
  <*> optional (option (eitherReader nonNeg) (long "clearance" <> metavar "M"
        <> help "with --environment: the least distance between the robot's capsules and the scene, m (default: the task's, else 0.01)"))
  <*> many (option (eitherReader bodyNumber) (long "ignore-body" <> metavar "N"
        <> help "with --environment: leave body N out of the scene check (1 = the first link); repeatable"))
  <*> option (eitherReader budgetR) (long "time-budget" <> metavar "S" <> value defaultPlanBudget
        <> help ("wall-clock budget of the planning, s (default " ++ showNumber defaultPlanBudget ++ ", at most 3600): a plan not done by then is exit 1"))
  <*> optional (option (eitherReader fmt) (long "format" <> metavar "summary|csv|json"
        <> help "what to write (default: summary; with -o, from the file's extension)"))
  <*> optional (strOption (short 'o' <> long "output" <> metavar "FILE" <> help "write the trajectory here (.json: JSON, any other extension: CSV); the summary goes to stdout"))
  <*> optional (option (eitherReader (plotPath [".png", ".svg"])) (long "plot" <> metavar "FILE.png|.svg" <> help "plot the TCP speed and its limit over s, the joint speeds against their limits over t")))
  where
    numbers what k s = case mapM readD (words (map (\c -> if c == ',' then ' ' else c) s)) of
      Just xs | k == 0 || length xs == k, all finite xs -> Right xs
      _ -> Left (what ++ " " ++ show s ++ ": expected " ++ (if k == 0 then "numbers" else show k ++ " numbers"))
    pose what s = case numbers what 0 s of
      Right xs | any ((> maxCoordinate) . abs) (take 3 xs) ->
                   Left (what ++ " " ++ show s ++ ": the position " ++ tooFarRule)
               | any ((> maxAngleDeg) . abs) (drop 3 xs) ->
                   Left (what ++ " " ++ show s ++ ": " ++ tooWideInRule)
               | length xs `elem` [3, 6] -> Right xs
      Right _ -> Left (what ++ " " ++ show s ++ ": expected 3 numbers X Y Z (m) or 6, X Y Z (m) RX RY RZ (degrees)")
      Left e -> Left e
    positive what s = case readD s of
      Just x | finite x && x > 0 -> Right x
      _ -> Left (what ++ " " ++ show s ++ ": expected a finite number > 0")
    bodyNumber str = case reads str :: [(Int, String)] of
      [(k, "")] | k >= 1 -> Right k
      _ -> Left ("--ignore-body " ++ show str ++ ": expected a body number >= 1 (1 = the first link)")
    nonNeg s = case readD s of
      Just x | finite x && x >= 0 -> if x <= maxCoordinate then Right x else Left ("--clearance " ++ s ++ " m: " ++ tooLongRule)
      _ -> Left ("--clearance " ++ show s ++ " m: expected a finite number >= 0")
    budgetR s = case readD s of
      Just x | finite x && x > 0 && x <= 3600 -> Right x
      _ -> Left ("--time-budget " ++ show s ++ " s: expected a number > 0 and at most 3600")
    dtR s = case readD s of
      Just x | finite x && x > 0 && x <= 1 -> Right x
      _ -> Left ("--dt " ++ show s ++ " s: expected a number > 0 and at most 1")
    fmt s = case map toLower s of
      "summary" -> Right Summary
      "csv" -> Right Csv
      "json" -> Right Json
      _ -> Left ("--format " ++ show s ++ ": expected summary, csv or json")

failWith :: String -> IO ExitCode
failWith = Out.failIn "plan"

poseTf :: [Double] -> Tf
poseTf = \case
  [x, y, z] -> fromRpy (V3 x y z) (V3 0 0 0)
  [x, y, z, a, b, c] -> fromRpy (V3 x y z) (V3 (rad a) (rad b) (rad c))
  _ -> identity
  where rad d = d * pi / 180

-- | The path's poses; quaternions off unit length are normalised, with the warning that
-- @vprof compress@ gives for them on stderr.
readPath :: FilePath -> IO (Either String Track)
readPath f = do
  r <- try (B.readFile f) :: IO (Either IOException B.ByteString)
  case r of
    Left e -> pure (Left (f ++ ": cannot read it: " ++ ioReason e))
    Right src -> do
      let path = readPathFile f src
      -- the normalisation is said only of a path that is read (a quaternion too far from a
      -- unit is refused, and "normalised" before the refusal contradicted it)
      mapM_ (\w -> hPutStrLn stderr ("vprof plan: warning: " ++ f ++ ": " ++ renderCleanWarning fileLocator w))
            (either (const Nothing) (nonUnitWarning . pfSamples) path)
      pure (pfTrack <$> path)

-- | The core's field names in this command's terms.
optionName :: String -> Maybe UserField
optionName = \case
  "speed" -> Just (UserField "--speed" "mm/s" 1000)
  "zone" -> Just (UserField "--zone" "mm" 1)
  "acceleration" -> Just (UserField "--acceleration" "m/s²" 1)
  "jerk" -> Just (UserField "--jerk" "m/s³" 1)
  "dt" -> Just (UserField "--dt" "s" 1)
  "start" -> Just (UserField "--start" "" 1)
  f | "start[" `isPrefixOf` f -> Just (UserField ("--start" ++ drop 5 f) "" 1)
  _ -> Nothing

-- | What the path argument gives: the waypoints in the world and, from a task file, the task.
data PathInput = PathInput [Waypoint] (Maybe Task)

isTaskFile :: FilePath -> Bool
isTaskFile f = map toLower (takeExtension f) `elem` [".yaml", ".yml", ".json"]

readPathInput :: FilePath -> IO (Either String PathInput)
readPathInput f
  | isTaskFile f = do
      et <- readTaskFileWarned f
      case et of
        Left es -> pure (Left (intercalate "; " es))
        Right (t, warns) -> do
          mapM_ (hPutStrLn stderr . ("vprof plan: warning: " ++)) warns
          pure (Right (PathInput [ tfWaypoint (tgPose g) | g <- taskTargets t ] (Just t)))
  | otherwise = fmap (\tr -> PathInput [ waypoint (x, y, z) (w, a, b, c)
                                       | (P3 x y z, Q4 w a b c) <- zip (ptoList (tPos tr)) (ptoList (tRot tr)) ] Nothing)
                  <$> readPath f
  where
    tfWaypoint p = let V3 x y z = translation p; Quat w a b c = toQuat p in waypoint (x, y, z) (w, a, b, c)

runPlan :: PlanOpts -> IO ExitCode
runPlan o = do
  named <- if isTaskFile (poPath o) then taskFileInputs (poPath o) else pure []
  clash <- Out.overwritesInput ([("the path", poPath o), ("the robot file", poRobot o)] ++ [ ("the environment", f) | Just f <- [poEnv o] ] ++ named)
                               ([ ("-o", f) | Just f <- [poOutput o] ] ++ [ ("--plot", f) | Just f <- [poPlot o] ])
  er <- loadRobot (poTip o) (poRobot o)
  ep <- readPathInput (poPath o)
  case (er, ep) of
    _ | Just msg <- clash -> failWith msg
    (Left e, _) -> failWith ("--robot: " ++ e)
    (_, Left e) -> failWith e
    -- a task's payload above the robot's rating: the robot cannot carry the task's tool and
    -- part, as 'vprof select' rejects it (the plan stops before it is planned)
    (Right r0, Right (PathInput _ (Just task)))
      | Just rated <- robotPayload r0, rated < taskPayload task -> do
          hPutStrLn stderr ("vprof plan: payload: " ++ robotName r0 ++ " is rated " ++ showNumber rated ++ " kg, and "
                            ++ poPath o ++ " needs " ++ showNumber (taskPayload task) ++ " kg")
          pure (ExitFailure 1)
    (Right r0, Right (PathInput wps mtask)) -> do
      env <- loadEnv mtask
      case env of
        Left e -> failWith e
        Right menv -> do
          -- the options replace the task's base and tool; without a task they default to identity
          let base = maybe (maybe identity taskBase mtask) poseTf (poBase o)
              tool = maybe (maybe identity taskTool mtask) poseTf (poTool o)
              r = r0 { robotBase = base `compose` robotBase r0, robotTool = robotTool r0 `compose` tool }
              clearance = maybe (maybe 0.01 taskClearance mtask) id (poClearance o)
              start = fmap (\qs -> U.fromList [ if poDeg o && jointKind j == Revolute then q * pi / 180 else q
                                              | (j, q) <- zip (robotJoints r ++ repeat (Joint "" Prismatic (Limits 0 0) Nothing Nothing)) qs ]) (poStart o)
              rq = (planRequest r wps)
                     { prZone = poZone o, prStart = start, prSpeed = poSpeed o *~ mps
                     , prAcceleration = poAcc o *~ mps2, prJerk = poJerk o *~ mps3, prTimeStep = poDt o *~ second
                     , prTrack = defaultTrackOptions { toEnvironment = fmap (\(cm, bvh) -> Environment cm bvh clearance) (menv r) } }
              -- body numbers to leave out of the scene check that name none of the robot's bodies, and
              hasCapsule = isJust (mtask >>= taskToolCapsule)
              noScene = isNothing (poEnv o) && null (maybe [] taskEnvironment mtask)
              unknown what bs = [ what ++ ": " ++ e | b <- bs, Just e <- [unknownBody r hasCapsule b] ]
              badOptions = unknown "--ignore-body" (poIgnore o) ++ unknown (poPath o ++ ": ignore_bodies") (maybe [] taskIgnoreBodies mtask)
                -- options that act on a scene, given without one (neither --environment nor
                -- the task's), would go unused
                ++ [ "--clearance " ++ showNumber c ++ " m: needs an environment to keep clear of (--environment FILE.obj, or a task file's)"
                   | Just c <- [poClearance o], noScene ]
                ++ [ "--ignore-body " ++ show b ++ ": needs an environment to leave the body out of (--environment FILE.obj, or a task file's)"
                   | b <- take 1 (poIgnore o), noScene ]
                ++ degreesTooWide "--start" (poDeg o) r (concat (poStart o))
                ++ [ "--deg: needs --start, the only values it puts in degrees (the output is in rad)"
                   | poDeg o, isNothing (poStart o) ]
                ++ [ "--scale " ++ showNumber sc ++ ": needs --environment FILE.obj, the scene it scales (a task file's meshes have their own scale)"
                   | Just sc <- [poEnvScale o], isNothing (poEnv o) ]
                -- (a start of the wrong length, named as typed: in degrees with --deg)
                ++ [ "--start \"" ++ unwords (map showNumber qs) ++ "\"" ++ (if poDeg o then " (deg)" else "") ++ ": expected "
                     ++ show (dof r) ++ " joint values for " ++ robotName r ++ ", got " ++ show (length qs)
                   | Just qs <- [poStart o], length qs /= dof r ]
          if not (null badOptions) then failWith (intercalate "; " badOptions) else do
            t0 <- getMonotonicTime
            -- the plan computed within the budget: every sample's joint speeds, the verdicts, or
            -- the failure's words (the output is written after it, as the profile's is)
            done <- timeout (round (poBudget o * 1e6)) $ evaluate $ case planPath rq of
              x@(Left f) -> length (describePlanFailure f) `seq` x
              x@(Right p) -> U.sum (trQd (planTrajectory p)) `seq` all resultLegal (planProfiles p) `seq` planLegal p `seq` x
            case done of
              Nothing -> do
                hPutStrLn stderr ("vprof plan: the plan was not done within --time-budget " ++ showNumber (poBudget o)
                                  ++ " s at --dt " ++ showNumber (poDt o) ++ " s: try a coarser --dt or a larger --time-budget")
                pure (ExitFailure 1)
              Just (Left (InvalidPlan es)) -> failWith (intercalate "; " (map renderFieldError (inUserTerms optionName es)))
              Just (Left f) -> do
                hPutStrLn stderr ("vprof plan: " ++ describePlanFailure f)
                pure (ExitFailure 1)
              Just (Right plan) -> do
                t1 <- getMonotonicTime
                let outFmt = case (poFormat o, poOutput o) of
                      (Just f, _) -> f
                      (Nothing, Just file) | map toLower (takeExtension file) == ".json" -> Json
                                           | otherwise -> Csv
                      (Nothing, Nothing) -> Summary
                    summary = renderSummary r plan (t1 - t0)
                    body = case outFmt of
                      Summary -> BL.pack summary
                      Csv -> renderTrajectoryCsv (planTrajectory plan)
                      Json -> A.encode (planJson r plan)
                -- an output that cannot be written is a bad output (exit 2), naming it
                let writing = Out.writing "vprof plan"
                okOut <- case poOutput o of
                  Just file -> do
                    ok <- writing file (BL.writeFile file body)
                    if ok then writing "the summary to standard output" (putStr summary) else pure False
                  Nothing -> do
                    ok <- writing "standard output" (BL.putStr body)
                    if outFmt == Summary then pure () else hPutStr stderr summary
                    pure ok
                okPlot <- maybe (pure True) (\f -> writing f (plotPlan f r plan)) (poPlot o)
                pure $ if not (okOut && okPlot) then ExitFailure 2
                       else if planLegal plan && all resultLegal (planProfiles plan) then ExitSuccess else ExitFailure 1
  where
    -- --environment replaces the task's cell; the ignored bodies of both are left out
    loadEnv mtask = case (poEnv o, maybe [] taskEnvironment mtask) of
      (Nothing, []) -> pure (Right (const Nothing))
      (Just path, _) -> scene [SceneFile path (fromMaybe 1 (poEnvScale o)) identity] "--environment: "
      (Nothing, meshes) -> scene [SceneFile (mpFile m) (mpScale m) (mpPose m) | m <- meshes] (poPath o ++ ": environment: ")
      where
        ignore = poIgnore o ++ maybe [] taskIgnoreBodies mtask
        capsule = mtask >>= taskToolCapsule
        scene files what = do
          sc <- loadScene files
          pure $ case sc of
            Left e -> Left (what ++ e)
            Right tris -> let bvh = buildBvh tris
                          in Right (\r -> Just (collisionModel defaultCollisionOptions { coSceneIgnore = ignore, coTool = capsule } r, bvh))

num :: Int -> Double -> String
num d x = showFFloat (Just d) x ""

renderSummary :: Robot -> Plan -> Double -> String
renderSummary r p secs = unlines $
  [ "robot:         " ++ robotName r
  , "route:         " ++ num 1 (routeLength rt * 1000) ++ " mm through " ++ show (length (rtPoints rt)) ++ " waypoints, "
      ++ show (length (rtStops rt)) ++ " stop(s) between the ends"
      ++ (case length [ () | pc <- V.toList (rtPieces rt), pcKind pc == Turn ] of
            0 -> ""
            k -> ", " ++ show k ++ " turn(s) in place (" ++ showNumber (turnRadius * 1000) ++ " mm of route per rad)")
  , "duration:      " ++ num 3 (planDuration p) ++ " s"
  , "samples:       " ++ show (trajectoryCount tr) ++ " (dt " ++ showNumber dt ++ " s)"
  , "IK samples:    " ++ show (trackedCount (planTracked p)) ++ " along the route"
  , "peak speed:    " ++ num 1 (1000 * U.maximum (trV tr)) ++ " mm/s"
  , "zones:         " ++ show (length zs)
  , "  " ++ pad 12 "from [mm]" ++ pad 12 "to [mm]" ++ pad 14 "limit [mm/s]" ++ "binding" ]
  ++ [ "  " ++ pad 12 (num 1 (1000 * lzStart z)) ++ pad 12 (num 1 (1000 * lzEnd z)) ++ pad 14 (num 1 (1000 * lzSpeed z))
       ++ describeBinding r (lzBinding z)
     | z <- shown ]
  ++ [ "  ... " ++ show (length zs - length shown) ++ " more (the JSON output lists every zone)" | length zs > length shown ]
  ++ [ "legal:         " ++ (if planLegal p && all resultLegal (planProfiles p) then "yes" else "no")
     , "compute time:  " ++ num 1 (secs * 1000) ++ " ms" ]
  where
    rt = planRoute p
    tr = planTrajectory p
    dt = if trajectoryCount tr > 1 then trTime tr U.! 1 - trTime tr U.! 0 else 0
    zs = planZoneList p
    shown = take 30 zs
    pad n s = s ++ replicate (max 1 (n - length s)) ' '

renderTrajectoryCsv :: Trajectory -> BL.ByteString
renderTrajectoryCsv tr = BB.toLazyByteString $
  BB.string7 (intercalate "," (["t", "s", "v", "a", "j"] ++ [ "q" ++ show i | i <- [1 .. n] ] ++ [ "qd" ++ show i | i <- [1 .. n] ]))
  <> BB.char7 '\n'
  <> mconcat [ row k | k <- [0 .. trajectoryCount tr - 1] ]
  where
    n = trDof tr
    row k = BB.string7 (intercalate "," (map show' ([trTime tr U.! k, trS tr U.! k, trV tr U.! k, trA tr U.! k, trJ tr U.! k]
                                                    ++ U.toList (trajectoryQ tr k) ++ U.toList (trajectoryQd tr k))))
            <> BB.char7 '\n'
    show' x = showFFloat Nothing x ""

planJson :: Robot -> Plan -> A.Value
planJson r p = A.object
  [ "robot" A..= robotName r
  , "route_length_m" A..= routeLength (planRoute p)
  , "duration_s" A..= planDuration p
  , "legal" A..= (planLegal p && all resultLegal (planProfiles p))
  , "stops_m" A..= rtStops (planRoute p)
  , "stretches" A..= [ A.object [ "start_m" A..= a, "end_m" A..= b, "acceleration_mps2" A..= up, "braking_mps2" A..= brake ]
                     | ((a, b), (brake, up)) <- zip (planStretches p) (planAccelerations p) ]
  , "zones" A..= [ A.object [ "start_m" A..= lzStart z, "end_m" A..= lzEnd z, "speed_mps" A..= lzSpeed z
                            , "binding" A..= describeBinding r (lzBinding z) ]
                 | z <- planZoneList p ]
  , "samples" A..= [ A.object [ "t" A..= (trTime tr U.! k), "s" A..= (trS tr U.! k), "v" A..= (trV tr U.! k)
                              , "a" A..= (trA tr U.! k), "j" A..= (trJ tr U.! k)
                              , "q" A..= U.toList (trajectoryQ tr k), "qd" A..= U.toList (trajectoryQd tr k) ]
                   | k <- [0 .. trajectoryCount tr - 1] ]
  ]
  where tr = planTrajectory p
