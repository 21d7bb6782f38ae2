-- | The daemon's path planning: one 'PlanRequestMsg' in, one 'PlanResponseMsg' out; never an
-- exception. Validation problems come back as INVALID_ARGUMENT, every one of them (each naming its
-- field); a plan that stops (out of reach, a joint limit, a singularity, a jump, a collision) or
-- has no legal profile as INFEASIBLE with its status, the distance along the route and the pose
-- there; a plan not done within the request's time budget as NOT_CONVERGED; anything unexpected
-- as INTERNAL. The plan is the core's ('planPath'), as @vprof plan@ makes it. The compute time is
-- measured on the monotonic clock.
module VProf.Service.Plan
  ( servePlan
  , planTimeLimit
  ) where

import Control.Exception (SomeException, evaluate, try)
import qualified Data.ByteString as B
import Data.ProtocolBuffers (getField, putField)
import GHC.Clock (getMonotonicTime)
import System.Timeout (timeout)

import VProf.Plan (planPath)
import VProf.Wire.Messages
import VProf.Wire.Plan

-- | Seconds a plan may take before the server's grace: its time budget (the default for an absent
-- or invalid one, at most an hour) and 30 s for reading an inline robot and building the
-- environment's hierarchy.
planTimeLimit :: PlanRequestMsg -> Double
planTimeLimit m = planBudgetOf m + 30

servePlan :: PlanRequestMsg -> IO PlanResponseMsg
servePlan m = do
  let rid = orDefault (getField (plqRequestId m))
  t0 <- getMonotonicTime
  r <- try $ case planFromMsg m of
    Left errs -> forced (planErrors rid 0 errs)
    Right q -> do
      -- the whole answer, encoded, within the budget: planning and the conversion of its samples
      done <- timeout (round (pqBudget q * 1e6)) $
        forced (either (planFailureToMsg rid 0 q) (planToMsg rid 0 q) (planPath (pqRequest q)))
      case done of
        Just msg -> pure msg
        Nothing -> do
          t1 <- getMonotonicTime
          pure (planBudgetMsg rid (t1 - t0) q)
  t1 <- getMonotonicTime
  pure $ case r of
    Left (e :: SomeException) -> planInternal rid (t1 - t0) (show e)
    Right msg -> msg { plrComputeTime = putField (nonDefault (t1 - t0)) }
  where
    -- every lazy part computed (by encoding it), so that a bug shows up inside the 'try' and the
    -- budget covers the work
    forced msg = evaluate (B.length (encodeBare msg)) >> pure msg
