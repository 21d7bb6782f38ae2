-- | A standalone driver: criterion's figures for 'kinematicsBenchmarks' (arguments are passed to
-- criterion), or with @--protocol N@ the TRAC-IK protocol's success rate and times per robot.
module Main (main) where

import Control.Monad (forM_)
import Criterion.Main (defaultMain)
import System.Environment (getArgs, withArgs)
import Text.Printf (printf)

import KinematicsBench
import VProf.Kinematics
import VProf.Kinematics.Library

main :: IO ()
main = do
  args <- getArgs
  case args of
    ("--protocol" : n : robots) -> do
      let keys = if null robots then ["ur5", "franka-panda", "ur10", "abb-irb140", "kuka-lbr-iiwa14", "puma560"] else robots
      printf "%-22s %8s %9s %9s %9s %9s %9s %12s %12s\n" "robot" "solves" "success%" "mean us" "median" "p99" "cpu us" "worst pos m" "worst rot"
      forM_ keys $ \key -> do
        let Right r = lookupRobot key
        p <- tracIkProtocol (kinematicsFor r) (read n) 20261201
        printf "%-22s %8d %9.3f %9.1f %9.1f %9.1f %9.1f %12.2e %12.2e\n" key (prSolves p)
          (100 * fromIntegral (prSuccesses p) / fromIntegral (prSolves p) :: Double)
          (prMeanUs p) (prMedianUs p) (prP99Us p) (prMeanCpuUs p) (prWorstPosition p) (prWorstRotation p)
    _ -> withArgs args (defaultMain kinematicsBenchmarks)
