{-# LANGUAGE OverloadedStrings #-}
-- | The @vprof select@ command: which robots can do a task in its cell.
--
-- > vprof select TASK [--robots all|NAME,...] [--tip LINK] [--format table|json] [--plot FILE.png]
--
-- TASK is a task file (docs/select.md). Robots are library names or robot files. The table is the
-- ranking, then each robot's failures with their reasons; JSON carries per robot and per target
-- the joint solution (rad, m), clearance, manipulability and failure. Exit codes: 0 when at least
-- one robot reaches every target, 1 when none does, 2 invalid input.
module VProf.Cli.Select
  ( selectCommand
  , SelectArgs (..)
  , runSelect
  ) where

import Control.Monad (when)
import qualified Data.Aeson as A
import qualified Data.ByteString.Lazy.Char8 as BLC
import Data.Char (toLower)
import Data.Containers.ListUtils (nubOrdOn)
import Data.List (intercalate)
import Data.Maybe (isJust)
import qualified Data.Vector.Unboxed as U
import GHC.Conc (getNumCapabilities)
import Numeric (showFFloat)
import Options.Applicative
import VProf.Plot.File (plotPath)
import System.Exit
import System.FilePath (hasExtension, takeExtension)
import System.IO

import VProf.Cli.Kinematics (loadRobot)
import VProf.Geometry.Bvh (buildBvh)
import VProf.Geometry.Format.Scene (SceneFile (..), loadScene)
import VProf.Kinematics.Library (libraryRobots)
import VProf.Kinematics.Collision (unknownBody)
import VProf.Kinematics.Model (Robot (..))
import VProf.Plot.Select (plotSelection)
import VProf.Select.Format.Task (readTaskFileWarned, taskFileInputs)
import qualified VProf.Cli.Output as Out
import VProf.Select.Parallel (evaluateRobots)
import VProf.Select.Selection
import VProf.Select.Task

data Format = Table | Json deriving (Eq)

data SelectArgs = SelectArgs
  { saTask :: FilePath
  , saRobots :: String
  , saTip :: Maybe String
  , saFormat :: Format
  , saPlot :: Maybe FilePath
  }

selectCommand :: Parser (IO ExitCode)
selectCommand = runSelect <$> (SelectArgs
  <$> strArgument (metavar "TASK" <> help "the task file (YAML or JSON; docs/select.md)")
  <*> strOption (long "robots" <> metavar "all|NAME,..." <> value "all" <> showDefault
        <> help "the robots to check: all of the library, or library names and robot files, comma-separated")
  <*> optional (strOption (long "tip" <> metavar "LINK" <> help "the last link of the chain of every URDF in --robots (default: each URDF's only leaf)"))
  <*> option (eitherReader fmt) (long "format" <> metavar "table|json" <> value Table <> help "output format (default: table)")
  <*> optional (option (eitherReader (plotPath [".png", ".svg"])) (long "plot" <> metavar "FILE.png|.svg" <> help "draw the cell and the best robot at its targets (top and side views)")))
  where
    fmt s = case map toLower s of
      "table" -> Right Table
      "json" -> Right Json
      _ -> Left ("--format: unknown format " ++ show s ++ " (table or json)")

failWith :: String -> IO ExitCode
failWith = Out.failIn "select"

splitComma :: String -> [String]
splitComma s = case break (== ',') s of
  (a, []) -> [a]
  (a, _ : rest) -> a : splitComma rest

runSelect :: SelectArgs -> IO ExitCode
runSelect a = do
  -- a plot file that cannot be written (or that is an input) is a bad option, said before the work
  named <- taskFileInputs (saTask a)
  clash <- Out.overwritesInput (("the task file", saTask a) : named) [ ("--plot", f) | Just f <- [saPlot a] ]
  et <- maybe (readTaskFileWarned (saTask a)) (\m -> pure (Left [m])) clash
  case et of
    Left es -> failWith (intercalate "\n  " es)
    Right (task, warns) -> do
      mapM_ (hPutStrLn stderr . ("vprof select: warning: " ++)) warns
      robots <- loadRobots (saTip a) (saRobots a)
      case robots of
        Left e -> failWith e
        Right rs
          -- a body number none of the robots has would be left out of nothing: a slip (plan
          -- and ik refuse one their robot lacks; here a robot with fewer bodies may lack it)
          | (b : _) <- [ b | b <- taskIgnoreBodies task
                           , all (\(_, r) -> isJust (unknownBody r (isJust (taskToolCapsule task)) b)) rs ] ->
              let most = maximum [ length (robotLinks r) | (_, r) <- rs ]
                  tool = isJust (taskToolCapsule task)
              in failWith (saTask a ++ ": ignore_bodies: body " ++ show b ++ " is not a body of any robot selected (at most "
                           ++ show most ++ ": " ++ intercalate ", " [ k | (k, r) <- rs, length (robotLinks r) == most ]
                           ++ (if tool then "; " ++ show (most + 1) ++ " with the tool capsule" else "") ++ ")")
          | otherwise -> do
          scene <- loadScene [SceneFile (mpFile m) (mpScale m) (mpPose m) | m <- taskEnvironment task]
          case scene of
            Left e -> failWith ("environment: " ++ e)
            Right mesh -> do
              let bvh = buildBvh mesh
              caps <- getNumCapabilities
              -- the robots are independent: one worker per core
              evaluated <- evaluateRobots caps defaultSelectOptions task bvh rs
              let ranked = scoreAndRank evaluated
              -- an output that cannot be written is a bad output (exit 2), naming it
              let writing = Out.writing "vprof select"
              okOut <- writing "standard output" $ case saFormat a of
                Table -> putStr (renderTable task ranked)
                Json -> BLC.putStrLn (A.encode (selectionJson task ranked))
              okPlot <- case (saPlot a, filter robotComplete ranked ++ filter (\r -> rrReached r > 0) ranked) of
                (Just file, best : _) -> do
                  let robot = head [placeRobot task r | (k, r) <- rs, k == rrKey best]
                  ok <- writing file (plotSelection file task mesh robot best)
                  ok <$ when ok (hPutStrLn stderr ("vprof select: wrote " ++ file ++ " (" ++ rrKey best ++ ")"))
                (Just _, []) -> True <$ hPutStrLn stderr "vprof select: no plot: no robot reaches any target"
                _ -> pure True
              pure $ if not (okOut && okPlot) then ExitFailure 2
                     else if any robotComplete ranked then ExitSuccess else ExitFailure 1

-- | "all" or a comma-separated list of library names and robot files; the tip link, if given,
-- for every URDF among them.
loadRobots :: Maybe String -> String -> IO (Either String [(String, Robot)])
loadRobots tip spec
  | Just t <- tip, not (any isUrdf names) =
      pure (Left ("--tip " ++ show t ++ ": names the last link of a URDF's chain, and --robots " ++ show spec ++ " names no .urdf file"))
  | map toLower spec == "all" = pure $ case [k | (k, Left _) <- libraryRobots] of
      [] -> Right [(k, r) | (k, Right r) <- libraryRobots]
      bad -> Left ("library robots broken: " ++ unwords bad)
  | otherwise = do
      rs <- mapM (\n -> fmap (n,) <$> loadRobot (if isUrdf n then tip else Nothing) n) names
      pure $ case [e | Left e <- rs] of
        [] | null rs -> Left ("--robots: no robot named in " ++ show spec)
           | otherwise -> Right [r | Right r <- rs]
        es -> Left ("--robots: " ++ intercalate "; " es)
  where
    -- a robot named twice is evaluated and ranked once (library names ignore case)
    names = nubOrdOn (\n -> if hasExtension n then n else map toLower n) (filter (not . null) (splitComma spec))
    isUrdf n = map toLower (takeExtension n) == ".urdf"

num :: Int -> Double -> String
num d x = showFFloat (Just d) x ""

-- | s in a column n wide, and at least one space after it.
pad :: Int -> String -> String
pad n s = s ++ replicate (max 1 (n - length s)) ' '

renderTable :: Task -> [RobotResult] -> String
renderTable task rs = unlines $
  [ show (length (taskTargets task)) ++ " targets" ++ (if taskPath task then " (and the segments between them, every " ++ num 1 (1000 * taskPathStep task) ++ " mm)" else "")
    ++ ", payload " ++ num 2 (taskPayload task) ++ " kg, clearance " ++ num 1 (1000 * taskClearance task) ++ " mm"
    ++ (if null (taskEnvironment task) then " (no environment: nothing to keep clear of)" else "")
  , ""
  , pad 5 "rank" ++ pad wRobot "robot" ++ pad 10 "reached" ++ pad 24 "min clearance" ++ pad 12 "min manip." ++ pad 12 "cycle" ++ "score" ]
  ++ [ pad 5 (show i) ++ pad wRobot (rrKey r)
       ++ case rrRejected r of
            Just why -> "rejected: " ++ why
            Nothing ->
              pad 10 (show (rrReached r) ++ "/" ++ show (rrTotal r))
              ++ pad 24 (maybe "-" (\(c, b) -> num 1 (1000 * c) ++ " mm (" ++ b ++ ")") (rrMinClearance r))
              ++ pad 12 (maybe "-" (\w -> showFFloat (Just 4) w "") (rrMinManipulability r))
              ++ pad 12 (maybe "-" (\t -> num 2 t ++ " s") (rrCycleTime r))
              ++ num 1 (rrScore r)
     | (i, r) <- zip [1 :: Int ..] rs ]
  ++ concatMap failures rs
  where
    -- the robot column: as wide as the longest name (a robot file's path) and two spaces
    wRobot = maximum (22 : map ((+ 2) . length . rrKey) rs)
    failures r =
      let ts = [ "    " ++ trLabel t ++ ": " ++ f | t <- rrTargets r, Just f <- [trFailure t] ]
          ss = [ "    " ++ f | s <- rrSegments r, Just f <- [sgFailure s] ]
      in if null ts && null ss then [] else ("" : (rrKey r ++ ": " ++ show (length ts + length ss) ++ " failure(s)") : ts ++ ss)

selectionJson :: Task -> [RobotResult] -> A.Value
selectionJson task rs = A.object
  [ "targets" A..= length (taskTargets task)
  , "payload_kg" A..= taskPayload task
  , "clearance_m" A..= taskClearance task
  , "path" A..= taskPath task
  , "robots" A..= [ robotJson i r | (i, r) <- zip [1 :: Int ..] rs ] ]
  where
    robotJson i r = A.object
      [ "rank" A..= i, "robot" A..= rrKey r, "name" A..= rrName r
      , "rejected" A..= rrRejected r
      , "reached" A..= rrReached r, "total" A..= rrTotal r, "complete" A..= robotComplete r
      , "min_clearance_m" A..= fmap fst (rrMinClearance r), "min_clearance_body" A..= fmap snd (rrMinClearance r)
      , "min_manipulability" A..= rrMinManipulability r
      , "cycle_time_s" A..= rrCycleTime r, "cycle_time_note" A..= rrCycleNote r
      , "score" A..= rrScore r
      , "targets" A..= map targetJson (rrTargets r)
      , "segments" A..= [ A.object ["from" A..= sgFrom s, "samples" A..= sgSamples s, "failure" A..= sgFailure s] | s <- rrSegments r ] ]
    targetJson t = A.object
      [ "target" A..= trLabel t, "joints" A..= fmap U.toList (trJoints t), "branch" A..= trBranch t
      , "clearance_m" A..= trClearance t, "clearance_body" A..= trClearanceBody t
      , "manipulability" A..= trManipulability t, "failure" A..= trFailure t ]
