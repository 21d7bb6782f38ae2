{-# LANGUAGE OverloadedStrings #-}
-- | The kinematics commands of the @vprof@ executable:
--
-- > vprof robots [NAME] [--format table|json] [--plot FILE.png [--q "Q..."] [--deg]]
-- > vprof fk ROBOT Q... [--deg] [--tip LINK] [--format table|json]
-- > vprof ik ROBOT --pose X Y Z QW QX QY QZ [--seed Q...] [--all] [--branch RUN] [--deg] [--tip LINK] [--format table|json]
--
-- ROBOT is a library name (@vprof robots@ lists them) or a robot file (@.yaml@, @.json@)
-- or a URDF (@.urdf@, with @--tip@ naming the last link; the base is the URDF's root).
-- Positions in m, orientations as unit quaternions (w, x, y, z); joint values in rad and m,
-- or degrees with @--deg@. Exit codes: 0 ok, 1 no IK solution, 2 invalid input.
module VProf.Cli.Kinematics
  ( robotsCommand
  , fkCommand
  , ikCommand
  , loadRobot
  , degreesTooWide
  , outsideLimits
  ) where

import qualified Data.Aeson as A
import qualified Data.ByteString.Char8 as B
import qualified Data.ByteString.Lazy.Char8 as BLC
import Data.Char (toLower)
import Data.Containers.ListUtils (nubOrd)
import Data.List (intercalate)
import Data.Maybe (fromMaybe)
import qualified Data.Vector.Unboxed as U
import Numeric (showEFloat, showFFloat)
import Options.Applicative
import VProf.Plot.File (plotPath)
import System.Exit
import System.FilePath (takeExtension)
import System.IO

import VProf.Kinematics
import VProf.Kinematics.Format.RobotFile (readRobotFile)
import VProf.Kinematics.Format.Urdf (UrdfOptions (..), defaultUrdfOptions, readUrdfFile)
import VProf.Kinematics.Library (libraryRobots, lookupRobot)
import VProf.Cli.Output (failIn)
import qualified VProf.Cli.Output as Out
import VProf.Compress.Format.Common (readDouble)
import VProf.Geometry.Bvh (buildBvh)
import VProf.Geometry.Format.Scene (SceneFile (..), loadScene)
import VProf.Kinematics.Collision (Clearance (..), CollisionOptions (..), collisionModel, defaultCollisionOptions, unknownBody)
import VProf.Select.Ik
import VProf.Validation (maxAngleDeg, maxCoordinate, showBound, showNumber, tooLongRule, tooWideRule)
import VProf.Plot.Robot (plotRobot)

data Format = Table | Json deriving (Eq)

formatOption :: Parser Format
formatOption = option (eitherReader f) (long "format" <> metavar "table|json" <> value Table
                                         <> help "output format (default: table)")
  where
    f s = case map toLower s of
      "table" -> Right Table
      "json" -> Right Json
      _ -> Left ("--format: unknown format " ++ show s ++ " (table or json)")

tipOption :: Parser (Maybe String)
tipOption = optional (strOption (long "tip" <> metavar "LINK" <> help "URDF only: the last link of the chain (default: the only leaf)"))

-- | A library robot or a robot file; Left is a message for the user.
loadRobot :: Maybe String -> String -> IO (Either String Robot)
loadRobot (Just t) name
  | map toLower (takeExtension name) /= ".urdf" =
      pure (Left ("--tip " ++ show t ++ ": names the last link of a URDF's chain, and " ++ show name ++ " is not a .urdf file"))
loadRobot tip name = case map toLower (takeExtension name) of
  ext | ext `elem` [".yaml", ".yml", ".json"] -> joinErrors <$> readRobotFile name
      | ext == ".urdf" -> joinErrors <$> readUrdfFile defaultUrdfOptions { urdfTip = tip } name
      | otherwise -> pure (lookupRobot name)
  where
    joinErrors = either (Left . ((name ++ ": ") ++) . intercalate "; ") Right

num :: Int -> Double -> String
num d x = showFFloat (Just d) x ""

------------------------------------------------------------------------------ robots

robotsCommand :: Parser (IO ExitCode)
robotsCommand = runPlot <$> optional (strArgument (metavar "NAME" <> help "show one robot (a library name or a robot file)"))
                    <*> tipOption <*> formatOption
                    <*> optional (option (eitherReader (plotPath [".png", ".svg"])) (long "plot" <> metavar "FILE.png|.svg"
                          <> help "draw the arm (side view x-z and top view x-y) to a PNG or SVG file"))
                    <*> optional (option (eitherReader jointNumbers) (long "q" <> metavar "\"Q...\""
                          <> help "with --plot: the joint values, as one argument (rad or m; degrees with --deg; default: mid-limits, 0 for an unbounded joint)"))
                    <*> switch (long "deg" <> help "with --plot: --q in degrees")
  where
    runPlot name tip fmt Nothing qs deg
      | Just _ <- qs = failIn "robots" "--q needs --plot FILE.png"
      | deg = failIn "robots" "--deg needs --plot FILE.png"
      | otherwise = run name tip fmt
    runPlot Nothing _ _ (Just _) _ _ = failIn "robots" "--plot needs a robot NAME (a library name or a robot file)"
    runPlot (Just name) tip _ (Just file) qs deg = do
      -- a plot file that cannot be written is a bad option, said before the robot is read
      clash <- Out.overwritesInput [("the robot file", name)] [("--plot", file)]
      er <- maybe (loadRobot tip name) (pure . Left) clash
      case er of
        Left e -> failIn "robots" e
        Right r | es@(_ : _) <- degreesTooWide "--q" deg r (concat qs) -> failIn "robots" (intercalate "; " es)
        Right r -> do
          let ch = compile r
              q = maybe (midLimits ch) (jointsFrom deg r) qs
          case checkJointVector False r q of
            es@(_ : _) -> failIn "robots" (intercalate "; " (map (renameQ . renderFieldError) es))
            [] -> do
              plotRobot file (robotName r) ch q
              putStrLn ("wrote " ++ file ++ " (" ++ robotName r ++ " at q = " ++ unwords (map (\x -> if abs x < 1e9 then num 4 x else showNumber x) (jointsTo deg r q))
                        ++ (if deg then " deg)" else " rad/m)"))
              pure ExitSuccess
    renameQ e = if take 1 e == "q" then "--q" ++ drop 1 e else e
    jointNumbers s = case finiteWords "" s of
      Right xs@(_ : _) -> Right xs
      Right [] -> Left ("expected joint values, got " ++ show s)
      Left e -> Left e
    run Nothing _ fmt = do
      let rows = [ (key, r) | (key, Right r) <- libraryRobots ]
          bad = [ (key, es) | (key, Left es) <- libraryRobots ]
      case fmt of
        Json -> BLC.putStrLn (A.encode [ robotJson key r | (key, r) <- rows ])
        Table -> do
          putStrLn (pad 22 "name" ++ pad 5 "DOF" ++ pad 10 "reach" ++ pad 10 "payload" ++ "source")
          mapM_ (\(key, r) -> putStrLn (pad 22 key ++ pad 5 (show (dof r)) ++ pad 10 (maybe "-" (\x -> num 3 x ++ " m") (robotReach r))
                                        ++ pad 10 (maybe "-" (\x -> num 2 x ++ " kg") (robotPayload r))
                                        ++ take 70 (concat (take 1 (robotSources r))))) rows
      mapM_ (\(key, es) -> hPutStrLn stderr ("vprof robots: library robot " ++ key ++ " is invalid: " ++ intercalate "; " es)) bad
      pure (if null bad then ExitSuccess else ExitFailure 1)
    run (Just name) tip fmt = do
      er <- loadRobot tip name
      case er of
        Left e -> failIn "robots" e
        Right r -> do
          case fmt of
            Json -> BLC.putStrLn (A.encode (robotJson name r))
            Table -> putStr (describeRobot r)
          pure ExitSuccess
    pad n s = take (n - 1) s ++ replicate (n - length (take (n - 1) s)) ' '

robotJson :: String -> Robot -> A.Value
robotJson key r = A.object
  [ "name" A..= key, "title" A..= robotName r, "description" A..= robotDescription r
  , "dof" A..= dof r, "reach_m" A..= robotReach r, "payload_kg" A..= robotPayload r
  , "sources" A..= robotSources r
  , "joints" A..= [ A.object [ "name" A..= jointName j, "kind" A..= show (jointKind j)
                             , "min" A..= finiteOrNull (limMin (jointLimits j)), "max" A..= finiteOrNull (limMax (jointLimits j))
                             , "max_velocity" A..= jointMaxVelocity j ]
                  | j <- robotJoints r ] ]

-- | JSON has no infinity: an unbounded (continuous) limit is null.
-- | Numbers separated by spaces or commas, each a finite double as typed: one that is not a
-- number, or beyond the range of a double (1e400 reads as infinity), is named with its place
-- (after @what: @ unless @what@ is empty, as for an option, which optparse names itself).
finiteWords :: String -> String -> Either String [Double]
finiteWords what s = mapM one (zip [1 :: Int ..] (words (map (\c -> if c == ',' then ' ' else c) s)))
  where
    -- a decimal number as the recordings' readers take it (.5, +1, 1e-3; not Haskell's 0x10)
    one (i, w) = case (readDouble (B.pack w), reads w :: [(Double, String)]) of
      (Just d, _) -> Right d
      (Nothing, [(d, "")]) | isNaN d || isInfinite d -> Left (label ++ show w ++ (if n > 1 then " (number " ++ show i ++ ")" else "")
                                     ++ " is not a finite number (a double reaches about 1.8e308)")
      _ -> Left (label ++ show w ++ (if n > 1 then " (number " ++ show i ++ ")" else "") ++ " is not a number")
    n = length (words (map (\c -> if c == ',' then ' ' else c) s))
    label = if null what then "" else what ++ ": "

finiteOrNull :: Double -> Maybe Double
finiteOrNull x = if isInfinite x || isNaN x then Nothing else Just x

describeRobot :: Robot -> String
describeRobot r = unlines $
  [ robotName r ++ " — " ++ robotDescription r
  , "DOF " ++ show (dof r) ++ ", reach " ++ maybe "not given" (\x -> num 3 x ++ " m") (robotReach r)
    ++ ", payload " ++ maybe "not given" (\x -> num 2 x ++ " kg") (robotPayload r)
  , "joints (limits in deg for revolute, mm for prismatic; speed in deg/s or mm/s):" ]
  ++ [ "  " ++ jointName j ++ ": " ++ show (jointKind j) ++ " [" ++ showL (conv j (limMin (jointLimits j))) ++ ", "
       ++ showL (conv j (limMax (jointLimits j))) ++ "]"
       ++ maybe "" (\v -> ", speed " ++ num 1 (conv j v)) (jointMaxVelocity j)
     | j <- robotJoints r ]
  ++ "sources:" : map ("  " ++) (robotSources r)
  where
    conv j x = if jointKind j == Revolute then x * 180 / pi else x * 1000
    showL x | isInfinite x = if x > 0 then "inf" else "-inf"
            | otherwise = num 2 x
------------------------------------------------------------------------------ fk

data FkOpts = FkOpts { fkRobot :: String, fkQ :: [Double], fkDeg :: Bool, fkTip :: Maybe String, fkFormat :: Format }

fkCommand :: Parser (IO ExitCode)
fkCommand = runFk <$> (FkOpts
  <$> strArgument (metavar "ROBOT" <> help "a library name, a robot file (.yaml/.json) or a URDF (.urdf)")
  <*> many (argument (eitherReader jointValue) (metavar "Q..." <> help "joint values (rad or m; degrees with --deg), one an argument"))
  <*> switch (long "deg" <> help "revolute joint values in degrees")
  <*> tipOption <*> formatOption)

-- | One joint value, one an argument: an empty argument or one that holds more than one number
-- is refused (only the first was read: "1,5", a decimal comma, was taken as 1, and "" crashed).
jointValue :: String -> Either String Double
jointValue w
  | ',' `elem` w = Left ("Q: " ++ show w ++ ": a comma; give each joint value as its own argument, with a decimal point")
  | otherwise = finiteWords "Q" w >>= \case
      [x] -> Right x
      [] -> Left ("Q: " ++ show w ++ " is not a number")
      xs -> Left ("Q: " ++ show w ++ " holds " ++ show (length xs) ++ " numbers; give each joint value as its own argument")

-- | Joint values typed in degrees (with --deg) beyond any joint's travel, each named as typed
-- (@field[i]@, in degrees): converted to radians, 1e308 degrees would be named as an infinite
-- number of radians.
degreesTooWide :: String -> Bool -> Robot -> [Double] -> [String]
degreesTooWide field deg r qs =
  [ field ++ "[" ++ show i ++ "] = " ++ showNumber x ++ " deg: " ++ tooWideRule
  | deg, (i, j, x) <- zip3 [0 :: Int ..] (robotJoints r) qs, jointKind j == Revolute, abs x > maxAngleDeg ]

-- | Joint values as typed, to the controller's SI values.
jointsFrom :: Bool -> Robot -> [Double] -> U.Vector Double
jointsFrom deg r qs = U.fromList [ if deg && jointKind j == Revolute then q * pi / 180 else q
                                 | (j, q) <- zip (robotJoints r ++ repeat (last (robotJoints r))) qs ]

jointsTo :: Bool -> Robot -> U.Vector Double -> [Double]
jointsTo deg r q = [ if deg && jointKind j == Revolute then x * 180 / pi else x | (j, x) <- zip (robotJoints r) (U.toList q) ]

runFk :: FkOpts -> IO ExitCode
runFk o = do
  er <- loadRobot (fkTip o) (fkRobot o)
  case er of
    Left e -> failIn "fk" e
    Right r | es@(_ : _) <- degreesTooWide "q" (fkDeg o) r (fkQ o) -> failIn "fk" (intercalate "; " es)
    Right r -> do
      let q = jointsFrom (fkDeg o) r (fkQ o)
      case checkJointVector False r q of
        es@(_ : _) -> failIn "fk" (intercalate "; " (map renderFieldError es))
        [] -> do
          -- a configuration the robot cannot take still has a pose (as in every kinematics
          -- library), but the user hears of it: 90 typed without --deg is 90 rad
          mapM_ (hPutStrLn stderr . ("vprof fk: warning: " ++)) (outsideLimits (fkDeg o) r q)
          let ch = compile r
              Pose (V3 x y z) (Quat w qx' qy' qz') = forwardPose ch q
              (_, jac) = jacobian ch q
              n = dof r
              manip = manipulability n jac
              cond = conditionNumber n jac
          case fkFormat o of
            Json -> BLC.putStrLn $ A.encode $ A.object
              [ "position" A..= [x, y, z], "orientation" A..= [w, qx', qy', qz']
              , "matrix" A..= toRows (forward ch q), "manipulability" A..= manip
              -- infinite at a singularity: JSON has no infinity, so null
              , "condition_number" A..= (if isInfinite cond || isNaN cond then Nothing else Just cond) ]
            Table -> putStr $ unlines
              [ "position:        " ++ unwords (map (num 6) [x, y, z]) ++ " m"
              , "orientation:     " ++ unwords (map (num 6) [w, qx', qy', qz']) ++ " (w x y z)"
              , "manipulability:  " ++ showFFloat (Just 6) manip ""
              , "condition:       " ++ (if isInfinite cond then "inf (singular)" else num 2 cond) ]
          pure ExitSuccess

-- | A line for each joint value outside its joint's limits, in the units typed.
outsideLimits :: Bool -> Robot -> U.Vector Double -> [String]
outsideLimits deg r q =
  [ "joint " ++ jointName j ++ " = " ++ shown j x ++ " is outside its limits " ++ shown j lo ++ " to " ++ shown j hi
    ++ "; the pose is computed all the same" ++ (if jointKind j == Revolute && not deg && abs x > 2 * pi + 1e-9 then " (degrees need --deg)" else "")
  | (j, x) <- zip (robotJoints r) (U.toList q)
  , let Limits lo hi = jointLimits j
        slack = 1e-9 * max 1 (abs x)
  , x < lo - slack || x > hi + slack ]
  where
    shown j v
      | jointKind j == Revolute && deg = short (v * 180 / pi) ++ "°"
      | jointKind j == Revolute = short v ++ " rad"
      | otherwise = short v ++ " m"
    short v = if abs v < 1e6 then num 4 v else showEFloat (Just 3) v ""

------------------------------------------------------------------------------ ik

data IkOpts = IkOpts
  { ikRobotName :: String, ikPose :: [Double], ikSeedQ :: Maybe [Double], ikAll :: Bool
  , ikDeg :: Bool, ikTip :: Maybe String, ikFormat :: Format, ikBudget :: Double, ikBranchWanted :: Maybe String
  , ikEnvironment :: Maybe FilePath, ikEnvScale :: Maybe Double, ikClearanceGiven :: Maybe Double, ikIgnoreBodies :: [Int] }

ikCommand :: Parser (IO ExitCode)
ikCommand = runIk <$> (IkOpts
  <$> strArgument (metavar "ROBOT" <> help "a library name, a robot file (.yaml/.json) or a URDF (.urdf)")
  <*> option (eitherReader (numbers 7)) (long "pose" <> metavar "\"X Y Z QW QX QY QZ\""
        <> help "target: position in m and a unit quaternion (w x y z), as one argument")
  <*> optional (option (eitherReader (numbers 0)) (long "seed" <> metavar "\"Q...\"" <> help "start near these joint values (default: mid-limits)"))
  <*> switch (long "all" <> help "search for every solution (the numerical solver keeps restarting), not only the nearest")
  <*> switch (long "deg" <> help "joint values in and out in degrees")
  <*> tipOption <*> formatOption
  <*> option (eitherReader budgetR) (long "time-budget" <> metavar "SECONDS" <> value 1 <> showDefault <> help "wall-clock budget of the numerical solver (> 0, at most 3600)")
  <*> optional (option (eitherReader branch) (long "branch" <> metavar "RUN|LDF|..."
        <> help "six-axis closed forms: only this branch (shoulder R/L, elbow U/D, wrist N/F)"))
  <*> optional (strOption (long "environment" <> metavar "FILE.obj"
        <> help "keep the robot clear of this Wavefront OBJ scene (in the robot's base frame)"))
  <*> optional (option auto (long "scale" <> metavar "S"
        <> help "with --environment: the scene's coordinates times S are metres (0.001 for millimetres; default 1)"))
  <*> optional (option (eitherReader nonNegClearance) (long "clearance" <> metavar "M"
        <> help "with --environment: the least distance between the robot's capsules and the scene, m (default: 0.01)"))
  <*> many (option (eitherReader bodyNumber) (long "ignore-body" <> metavar "N"
        <> help "with --environment: leave body N out of the scene check (1 = the first link, e.g. a base column on a table); repeatable")))
  where
    budgetR str = case readD str of
      Just x | not (isNaN x || isInfinite x) && x > 0 && x <= 3600 -> Right x
      _ -> Left ("--time-budget " ++ show str ++ " s: expected a number > 0 and at most 3600")
    nonNegClearance str = case readD str of
      Just x | not (isNaN x || isInfinite x) && x >= 0 -> if x <= maxCoordinate then Right x else Left ("--clearance " ++ str ++ " m: " ++ tooLongRule)
      _ -> Left ("--clearance " ++ show str ++ " m: expected a finite number >= 0")
    bodyNumber str = case reads str :: [(Int, String)] of
      [(k, "")] | k >= 1 -> Right k
      _ -> Left ("--ignore-body " ++ show str ++ ": expected a body number >= 1 (1 = the first link)")
    numbers k s = case finiteWords "" s of
      Right xs | k == 0 || length xs == k -> Right xs
      Right _ -> Left ("expected " ++ (if k == 0 then "numbers" else show k ++ " numbers") ++ ", got " ++ show s)
      Left e -> Left e
    readD w = case reads w of
      [(d, "")] -> Just (d :: Double)
      _ -> Nothing
    branch b = let u = map toUpper' b in
      if length u == 3 && head u `elem` ("RL" :: String) && u !! 1 `elem` ("UD" :: String) && u !! 2 `elem` ("NF" :: String)
        then Right u else Left ("--branch: " ++ show b ++ " is not a branch label (R or L, U or D, N or F: e.g. RUN)")
    toUpper' c = if c >= 'a' && c <= 'z' then toEnum (fromEnum c - 32) else c

-- | The clearance kept from the scene: as given, else 1 cm.
ikClearance :: IkOpts -> Double
ikClearance = fromMaybe 0.01 . ikClearanceGiven

runIk :: IkOpts -> IO ExitCode
runIk o = do
  er <- loadRobot (ikTip o) (ikRobotName o)
  case er of
    Left e -> failIn "ik" e
    Right r -> case ikPose o of
      _ | e : _ <- [ e | b <- ikIgnoreBodies o, Just e <- [unknownBody r False b] ] ->
            failIn "ik" ("--ignore-body: " ++ e)
      _ | es@(_ : _) <- degreesTooWide "--seed" (ikDeg o) r (concat (ikSeedQ o)) -> failIn "ik" (intercalate "; " es)
      -- options that act on a scene, given without one, would go unused
      _ | Nothing <- ikEnvironment o, Just c <- ikClearanceGiven o ->
            failIn "ik" ("--clearance " ++ showNumber c ++ " m: needs --environment FILE.obj, the scene to keep clear of")
      _ | Nothing <- ikEnvironment o, b : _ <- ikIgnoreBodies o ->
            failIn "ik" ("--ignore-body " ++ show b ++ ": needs --environment FILE.obj, the scene to leave the body out of")
      _ | Nothing <- ikEnvironment o, Just sc <- ikEnvScale o ->
            failIn "ik" ("--scale " ++ showNumber sc ++ ": needs --environment FILE.obj, the scene it scales")
      [x, y, z, w, qx', qy', qz']
        | any ((> maxCoordinate) . abs) [x, y, z] ->
            failIn "ik" ("--pose: the position (" ++ unwords (map show [x, y, z]) ++ ") m is more than "
                      ++ showBound maxCoordinate ++ " m from the robot's base, beyond any reach (is the unit right?)")
        | abs (sqrt (w * w + qx' * qx' + qy' * qy' + qz' * qz') - 1) > 1e-6 ->
            failIn "ik" ("--pose: the quaternion (" ++ unwords (map show [w, qx', qy', qz']) ++ ") is not a unit quaternion")
        | otherwise -> do
            let target = fromQuat (V3 x y z) (Quat w qx' qy' qz')
                seed = jointsFrom (ikDeg o) r <$> ikSeedQ o
                opts = defaultIkOptions { ikAllSolutions = ikAll o }
            scene <- loadEnvironment
            case scene of
              Left e -> failIn "ik" e
              Right env -> do
                res <- solveWithin env r target seed opts
                answer r res
      _ -> failIn "ik" "--pose: expected 7 numbers"
  where
    loadEnvironment = case ikEnvironment o of
      Nothing -> pure (Right Nothing)
      Just path
        | isNaN (ikClearance o) || isInfinite (ikClearance o) || ikClearance o < 0 ->
            pure (Left ("--clearance = " ++ show (ikClearance o) ++ " m: must be a finite number >= 0"))
        | otherwise -> fmap (Just . buildBvh) <$> loadScene [SceneFile path (fromMaybe 1 (ikEnvScale o)) identity]
    -- every solution with its clearance to the scene (m), or why there is none: Left a usage
    -- error (exit 2), Right a reason (exit 1)
    solveWithin env r target seed opts = case env of
      Nothing -> either (Left . ikFail r) (Right . map (, Nothing)) <$> solveIkIO (ikBudget o) opts (kinematicsFor r) target seed
      Just bvh ->
        let sopts = defaultSelectIkOptions { siIk = opts, siClearance = ikClearance o }
            cm = collisionModel defaultCollisionOptions { coSceneIgnore = ikIgnoreBodies o } r
        in flip fmap (solveCollisionFreeIO (ikBudget o) sopts (kinematicsFor r) cm bvh target seed) $ \case
             Left (IkFailed f) -> Left (ikFail r f)
             Left f -> Left (Right (describeSelectIkFailure sopts f))
             Right cs -> Right [ (cdSolution c, clrDistance <$> cdClearance c) | c <- cs ]
    order = maybe "nearest the seed" (const "largest clearance (then nearest the seed)") (ikEnvironment o)
    ikFail _ (InvalidRequest es) = Left es
    ikFail r f = Right (describeFailureFor r f)
    answer r res = case res of
              Left (Left es) -> failIn "ik" (intercalate "; " es)
              Left (Right why) -> do
                case ikFormat o of
                  Json -> BLC.putStrLn (A.encode (A.object [ "error" A..= why ]))
                  Table -> hPutStrLn stderr ("vprof ik: " ++ why)
                pure (ExitFailure 1)
              Right found
                | Just b <- ikBranchWanted o, not (null found), all ((== Nothing) . solBranch . fst) found ->
                    failIn "ik" ("--branch " ++ b ++ ": " ++ robotName r ++ " has no six-axis closed form, so its solutions have no branch")
              Right found -> do
                let sols0 = map fst found
                    clearanceOf s = lookup (solJoints s) [ (solJoints x, c) | (x, Just c) <- found ]
                    sols = maybe sols0 (\b -> filter ((== Just b) . solBranch) sols0) (ikBranchWanted o)
                    shown = if ikAll o then sols else take 1 sols
                    branchMiss = "no solution on branch " ++ maybe "" id (ikBranchWanted o) ++ "; the pose's solutions are on "
                                 ++ unwords (nubOrd [ b | Just b <- map solBranch sols0 ])
                case ikFormat o of
                  Json | null sols -> BLC.putStrLn (A.encode (A.object [ "error" A..= branchMiss, "solutions" A..= ([] :: [A.Value]) ]))
                  Json -> BLC.putStrLn $ A.encode $ A.object
                    [ "solutions" A..= [ A.object [ "q" A..= jointsTo (ikDeg o) r (solJoints s), "branch" A..= solBranch s
                                                  , "position_error" A..= solPositionError s
                                                  , "rotation_error" A..= solRotationError s
                                                  , "clearance_m" A..= clearanceOf s ]
                                       | s <- shown ] ]
                  Table
                    | null sols -> hPutStrLn stderr ("vprof ik: " ++ branchMiss)
                    | otherwise -> do
                    putStrLn $ show (length sols) ++ " solution(s) within the joint limits"
                      ++ maybe "" (const (" and clear of the environment by " ++ num 3 (ikClearance o) ++ " m")) (ikEnvironment o)
                      ++ (if ikAll o || length sols == 1 then ", " ++ order ++ " first"
                          else "; the " ++ order ++ " (--all lists them)")
                      ++ (if ikDeg o then (if any ((== Prismatic) . jointKind) (robotJoints r) then " (deg, m)" else " (deg)") else " (rad, m)")
                    mapM_ (\s -> putStrLn ("  " ++ maybe "" (++ "  ") (solBranch s) ++ unwords (map (num 6) (jointsTo (ikDeg o) r (solJoints s)))
                                           ++ "   error " ++ showEFloat (Just 1) (solPositionError s) "" ++ " m, "
                                           ++ (if ikDeg o then showEFloat (Just 1) (solRotationError s * 180 / pi) "" ++ " deg"
                                               else showEFloat (Just 1) (solRotationError s) "" ++ " rad")
                                           ++ maybe "" (\c -> "   clearance " ++ num 1 (1000 * c) ++ " mm") (clearanceOf s))) shown
                pure (if null sols then ExitFailure 1 else ExitSuccess)
