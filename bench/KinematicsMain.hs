{-# OPTIONS_GHC -fno-full-laziness #-}
{-# LANGUAGE OverloadedStrings #-}
-- | A standalone driver (benchmark @vprof-kinematics-compare@):
--
-- * no mode argument: criterion's figures for 'kinematicsBenchmarks' (arguments are passed to
--   criterion);
-- * @--protocol N [robot …]@: the TRAC-IK protocol's success rate and times per robot;
-- * @--compare IN.json OUT.json@: for each robot and joint vector of IN, the target pose by
--   vprof's forward kinematics, then the closed form (all solutions) and the numerical solver
--   on that pose, each timed over many repetitions after a warm-up, with whether the original q
--   is among the solutions up to 2π wraps (the input of @bench/compare-kinematics@);
-- * @--fk IN.json OUT.json@: vprof's forward kinematics of given joint vectors (to check a
--   peer's solutions against the same model);
-- * @--numeric IN.json OUT.json@: the TRAC-IK protocol for any robot (the 7-axis arms): per joint
--   vector the target by FK, one numerical solve from mid-limits timed once (one warm-up solve
--   per robot), its residual; and the robot's compiled chain as constant transforms and z axes
--   (@model@), from which the peers build the same arm.
--
-- Full laziness is off in this module so that a timed repetition cannot be floated out of its
-- loop (as criterion does for its own loops).
module Main (main) where

import Control.DeepSeq (NFData, force, rnf)
import Control.Exception (evaluate)
import Control.Monad (forM, forM_)
import Criterion.Main (defaultMain)
import qualified Data.Aeson as A
import Data.Aeson ((.:), (.:?), (.=))
import qualified Data.ByteString.Lazy as BL
import Data.Maybe (fromMaybe)
import qualified Data.Vector.Unboxed as U
import GHC.Clock (getMonotonicTimeNSec)
import System.Environment (getArgs, withArgs)
import System.Exit (exitFailure)
import System.IO (hPutStrLn, stderr)
import Text.Printf (printf)

import KinematicsBench
import VProf.Kinematics
import qualified VProf.Kinematics.ClosedForm as CF
import VProf.Kinematics.Ik.SixAxis (sixAxisSolver)
import VProf.Kinematics.Library

main :: IO ()
main = do
  args <- getArgs
  case args of
    ["--compare", inp, out] -> compareMode inp out
    ["--fk", inp, out] -> fkMode inp out
    ["--numeric", inp, out] -> numericMode inp out
    ("--protocol" : n : robots) -> do
      let keys = if null robots then ["ur5", "franka-panda", "ur10", "abb-irb140", "kuka-lbr-iiwa14", "puma560"] else robots
      putStrLn (printf "%-22s %8s %9s %9s %9s %9s %9s %12s %12s" ("robot" :: String) ("solves" :: String) ("success%" :: String)
        ("mean us" :: String) ("median" :: String) ("p99" :: String) ("cpu us" :: String) ("worst pos m" :: String) ("worst rot" :: String))
      forM_ keys $ \key -> do
        let Right r = lookupRobot key
        p <- tracIkProtocol (kinematicsFor r) (read n) 20261201
        printf "%-22s %8d %9.3f %9.1f %9.1f %9.1f %9.1f %12.2e %12.2e\n" key (prSolves p)
          (100 * fromIntegral (prSuccesses p) / fromIntegral (prSolves p) :: Double)
          (prMeanUs p) (prMedianUs p) (prP99Us p) (prMeanCpuUs p) (prWorstPosition p) (prWorstRotation p)
    _ -> withArgs args (defaultMain kinematicsBenchmarks)

--------------------------------------------------------------------------------------------------
-- Timing

-- | Seconds per call of @f x@, the result forced each time, over @n@ calls timed as one block
-- with the monotonic clock (after one untimed warm-up call).
{-# NOINLINE timeNf #-}
timeNf :: NFData b => Int -> (a -> b) -> a -> IO Double
timeNf n f x = do
  _ <- evaluate (force (f x))
  t0 <- getMonotonicTimeNSec
  let go :: Int -> IO ()
      go 0 = pure ()
      go k = evaluate (rnf (f x)) >> go (k - 1)
  go n
  t1 <- getMonotonicTimeNSec
  pure (fromIntegral (t1 - t0) / fromIntegral (max 1 n) * 1e-9)

-- | Like 'timeNf' for an IO action.
{-# NOINLINE timeIO #-}
timeIO :: NFData b => Int -> (a -> IO b) -> a -> IO Double
timeIO n f x = do
  _ <- f x >>= evaluate . force
  t0 <- getMonotonicTimeNSec
  let go :: Int -> IO ()
      go 0 = pure ()
      go k = (f x >>= evaluate . rnf) >> go (k - 1)
  go n
  t1 <- getMonotonicTimeNSec
  pure (fromIntegral (t1 - t0) / fromIntegral (max 1 n) * 1e-9)

--------------------------------------------------------------------------------------------------
-- The comparison

data Request = Request
  { rqRepsClosed :: Int        -- ^ repetitions per pose for the closed form and FK
  , rqRepsFacade :: Int        -- ^ repetitions per pose for the IK facade (limits, 2π variants, FK check)
  , rqRepsNumeric :: Int       -- ^ repetitions per pose for the numerical solver
  , rqBudget :: Double         -- ^ numerical solver's wall-time budget per solve (s)
  , rqTol :: Double            -- ^ numerical tolerance (m and rad)
  , rqRobots :: [(String, [[Double]])]
  }

instance A.FromJSON Request where
  parseJSON = A.withObject "request" $ \o -> do
    rc <- o .:? "reps_closed_form"
    rf <- o .:? "reps_facade"
    rn <- o .:? "reps_numeric"
    b <- o .:? "numeric_budget_s"
    t <- o .:? "numeric_tol"
    rs <- o .: "robots"
    robots <- forM rs $ A.withObject "robot" $ \r -> (,) <$> r .: "key" <*> r .: "qs"
    pure (Request (fromMaybe 200 rc) (fromMaybe 5 rf) (fromMaybe 3 rn) (fromMaybe 0.005 b) (fromMaybe 1e-5 t) robots)

readRequest :: FilePath -> IO Request
readRequest p = do
  bs <- BL.readFile p
  case A.eitherDecode bs of
    Right r -> pure r
    Left e -> hPutStrLn stderr ("vprof-kinematics-compare: " ++ p ++ ": " ++ e) >> exitFailure

robotOrDie :: String -> IO Robot
robotOrDie key = case lookupRobot key of
  Right r -> pure r
  Left e -> hPutStrLn stderr ("vprof-kinematics-compare: " ++ key ++ ": " ++ e) >> exitFailure

-- | Largest joint difference after taking each difference modulo 2π into (−π, π].
wrapDistance :: U.Vector Double -> U.Vector Double -> Double
wrapDistance a b = U.maximum (U.map abs (U.zipWith (\x y -> wrapPi (x - y)) a b))
  where wrapPi d = d - 2 * pi * fromIntegral (round (d / (2 * pi)) :: Int)

recoverTol :: Double
recoverTol = 1e-6

dhJson :: CF.SixAxisDh -> A.Value
dhJson dh = A.object
  [ "a" .= U.toList (CF.sdA dh), "alpha" .= U.toList (CF.sdAlpha dh), "d" .= U.toList (CF.sdD dh)
  , "offset" .= U.toList (CF.sdOffset dh), "lower" .= U.toList (CF.sdLower dh), "upper" .= U.toList (CF.sdUpper dh)
  , "base" .= CF.poseToRowMajor (CF.sdBase dh), "tool" .= CF.poseToRowMajor (CF.sdTool dh) ]

compareMode :: FilePath -> FilePath -> IO ()
compareMode inp out = do
  Request{..} <- readRequest inp
  let numOpts = defaultIkOptions {ikTolPosition = rqTol, ikTolRotation = rqTol, ikMaxRestarts = 100000}
  robots <- forM rqRobots $ \(key, qss) -> do
    r <- robotOrDie key
    let k = kinematicsFor r
        ch = kinChain k
        numeric = (prepareChain ch) {kinMethod = NumericLM}
        seed = midLimits ch
        solverM = sixAxisSolver ch
    hPutStrLn stderr ("vprof-kinematics-compare: " ++ key ++ ", " ++ show (length qss) ++ " poses")
    poses <- forM qss $ \qs -> do
      let q = U.fromList qs
          target = forward ch q
      fkS <- timeNf rqRepsClosed (forward ch) q
      cf <- case solverM of
        Nothing -> pure A.Null
        Just solver -> do
          let Just pose = CF.poseFromRowMajor (toRows4 target)
          tP <- timeNf rqRepsClosed (CF.solvePrincipal solver) pose
          tF <- timeNf rqRepsFacade (\t -> solveIk defaultIkOptions k t Nothing) target
          tFk <- timeNf rqRepsClosed (CF.forwardPose (CF.solverDh solver)) q
          let principal = either (const []) id (CF.solvePrincipal solver pose)
              facade = either (const []) id (solveIk defaultIkOptions k target Nothing)
              err = either (Just . show) (const Nothing) (CF.solvePrincipal solver pose)
              qsP = map CF.solQ principal
              resid = [residual (forward ch s) target | s <- qsP]
          pure $ A.object
            [ "us" .= (tP * 1e6), "facade_us" .= (tF * 1e6), "fk_us" .= (tFk * 1e6)
            , "count" .= length principal, "facade_count" .= length facade
            , "solutions" .= map U.toList qsP
            , "branches" .= map (CF.branchText . CF.solBranch) principal
            , "singular" .= map (map show . CF.solSingular) principal
            , "max_pos_err" .= maximum (0 : map fst resid), "max_rot_err" .= maximum (0 : map snd resid)
            , "recovered" .= any (\s -> wrapDistance s q < recoverTol) qsP
            , "facade_recovered" .= any (\s -> wrapDistance (solJoints s) q < recoverTol) facade
            , "error" .= err ]
      tN <- timeIO rqRepsNumeric (\t -> solveIkIO rqBudget numOpts numeric t (Just seed)) target
      rN <- solveIkIO rqBudget numOpts numeric target (Just seed)
      let num = case rN of
            Right (s : _) -> A.object
              [ "us" .= (tN * 1e6), "ok" .= True, "q" .= U.toList (solJoints s)
              , "pos_err" .= solPositionError s, "rot_err" .= solRotationError s
              , "recovered" .= (wrapDistance (solJoints s) q < 1e-4) ]
            Right [] -> A.object ["us" .= (tN * 1e6), "ok" .= False, "error" .= ("no solution" :: String)]
            Left e -> A.object ["us" .= (tN * 1e6), "ok" .= False, "error" .= describeFailure e]
      pure (A.object ["q" .= qs, "pose" .= toRows4 target, "fk_us" .= (fkS * 1e6), "cf" .= cf, "num" .= num])
    pure $ A.object
      [ "key" .= key, "name" .= robotName r
      , "family" .= fmap (show . CF.solverFamily) solverM
      , "dh" .= fmap (dhJson . CF.solverDh) solverM
      , "poses" .= poses ]
  BL.writeFile out (A.encode (A.object
    [ "reps_closed_form" .= rqRepsClosed, "reps_facade" .= rqRepsFacade, "reps_numeric" .= rqRepsNumeric
    , "numeric_budget_s" .= rqBudget, "numeric_tol" .= rqTol
    , "robots" .= robots ]))

fkMode :: FilePath -> FilePath -> IO ()
fkMode inp out = do
  Request{..} <- readRequest inp
  robots <- forM rqRobots $ \(key, qss) -> do
    ch <- compile <$> robotOrDie key
    pure (A.object ["key" .= key, "poses" .= [toRows4 (forward ch (U.fromList qs)) | qs <- qss]])
  BL.writeFile out (A.encode (A.object ["robots" .= robots]))

-- | The TRAC-IK protocol, one timed solve per pose, and the chain for the peers: per moving link
-- the constant transform before it (row-major 3×4), whether it slides, its drive offset and its
-- (joint, coefficient) terms; the constant transform after the last link to the tool; the limits.
numericMode :: FilePath -> FilePath -> IO ()
numericMode inp out = do
  Request{..} <- readRequest inp
  let opts = defaultIkOptions {ikTolPosition = rqTol, ikTolRotation = rqTol, ikMaxRestarts = 100000}
  robots <- forM rqRobots $ \(key, qss) -> do
    r <- robotOrDie key
    let ch = compile r
        k = (prepareChain ch) {kinMethod = NumericLM}
        seed = midLimits ch
        m = chainLinks ch
        terms i = [ (chainTermJoint ch U.! t, chainTermCoeff ch U.! t)
                  | t <- [chainTermStart ch U.! i .. chainTermStart ch U.! (i + 1) - 1] ]
        model = A.object
          [ "dof" .= chainDof ch, "lower" .= U.toList (chainLo ch), "upper" .= U.toList (chainHi ch)
          , "links" .= [ A.object [ "before" .= toRows (constAt (chainConst ch) i), "prismatic" .= (chainPrismatic ch U.! i)
                                  , "offset" .= (chainOffset ch U.! i), "terms" .= terms i ]
                       | i <- [0 .. m - 1] ]
          , "tool" .= toRows (constAt (chainConst ch) m) ]
    hPutStrLn stderr ("vprof-kinematics-compare: " ++ key ++ ", " ++ show (length qss) ++ " numerical solves")
    case qss of
      (q0 : _) -> solveIkIO rqBudget opts k (forward ch (U.fromList q0)) (Just seed) >>= evaluate . force >> pure ()
      [] -> pure ()
    poses <- forM qss $ \qs -> do
      let q = U.fromList qs
          target = forward ch q
      _ <- evaluate (force (toRows target))
      t0 <- getMonotonicTimeNSec
      res <- solveIkIO rqBudget opts k target (Just seed) >>= evaluate . force
      t1 <- getMonotonicTimeNSec
      let us = fromIntegral (t1 - t0) / 1000 :: Double
      pure $ case res of
        Right (s : _) ->
          let (pe, re) = residual (forward ch (solJoints s)) target
          in A.object [ "pose" .= toRows4 target, "us" .= us, "ok" .= (pe <= rqTol && re <= rqTol)
                      , "pos_err" .= pe, "rot_err" .= re ]
        Right [] -> A.object ["pose" .= toRows4 target, "us" .= us, "ok" .= False, "error" .= ("no solution" :: String)]
        Left e -> A.object ["pose" .= toRows4 target, "us" .= us, "ok" .= False, "error" .= describeFailure e]
    pure (A.object ["key" .= key, "name" .= robotName r, "model" .= model, "poses" .= poses])
  BL.writeFile out (A.encode (A.object ["numeric_budget_s" .= rqBudget, "numeric_tol" .= rqTol, "robots" .= robots]))
