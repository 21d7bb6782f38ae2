-- | Robot selection on several cores: every robot through the core's 'evaluateRobot', for
-- @vprof select@ and the daemon alike.
module VProf.Select.Parallel
  ( evaluateRobots
  ) where

import Control.Concurrent.Async (replicateConcurrently_)
import Control.Concurrent.MVar (newEmptyMVar, putMVar, readMVar)
import Control.Exception (evaluate)
import Data.IORef (atomicModifyIORef', newIORef)
import Data.List (sortOn)

import VProf.Geometry.Bvh (Bvh)
import VProf.Kinematics.Ik (Kinematics (..), Method (..), kinematicsFor)
import VProf.Kinematics.Model (Robot)
import VProf.Select.Selection
import VProf.Select.Task (Task)

-- | Every robot evaluated (each result fully forced), in the robots' order, by k workers that
-- each take the next robot from one queue, so that a slow robot holds up no other; the robots
-- whose IK is numerical (restarts, the slowest) are queued first, so that no long one starts
-- last.
evaluateRobots :: Int -> SelectOptions -> Task -> Bvh -> [(String, Robot)] -> IO [RobotResult]
evaluateRobots k opts task bvh robots = do
  slots <- mapM (const newEmptyMVar) robots
  let jobs = sortOn (\(i, _, (_, r)) -> (numerical r, i)) (zip3 [0 :: Int ..] slots robots)
      numerical r = case kinMethod (kinematicsFor r) of
        NumericLM -> 0 :: Int
        _ -> 1
  queue <- newIORef jobs
  let worker = do
        next <- atomicModifyIORef' queue (\js -> case js of [] -> ([], Nothing); j : rest -> (rest, Just j))
        case next of
          Nothing -> pure ()
          Just (_, slot, (key, robot)) -> do
            let res = evaluateRobot opts task bvh key robot
            _ <- evaluate (length (show res))
            putMVar slot res
            worker
  replicateConcurrently_ (max 1 (min k (length robots))) worker
  mapM readMVar slots
