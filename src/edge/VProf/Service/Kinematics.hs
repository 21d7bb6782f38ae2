-- | The daemon's robot kinematics: one 'FkRequestMsg' in, one 'FkResponseMsg' out, and one
-- 'IkRequestMsg' in, one 'IkResponseMsg' out; never an exception. Validation problems come back
-- as INVALID_ARGUMENT naming the first field (every problem joined in the message); a target
-- without a solution as INFEASIBLE (beyond reach, limits, orientation, collisions) or
-- NOT_CONVERGED (the numerical solver's budget); anything unexpected as INTERNAL. The compute
-- time is measured on the monotonic clock.
module VProf.Service.Kinematics
  ( serveFk
  , serveIk
  , fkTimeLimit
  , ikTimeLimit
  ) where

import Control.Exception (SomeException, evaluate, try)
import qualified Data.ByteString as B
import Data.ProtocolBuffers (Encode, getField, putField)
import GHC.Clock (getMonotonicTime)

import VProf.Kinematics
import VProf.Kinematics.Collision (Clearance (..))
import VProf.Select.Ik (Candidate (..), SelectIkFailure (..), solveCollisionFreeIO)
import VProf.Wire.Kinematics
import VProf.Validation (renderFieldErrors)
import VProf.Wire.Messages

-- | Seconds an FK request may take before the server's grace (an inline URDF is parsed too).
fkTimeLimit :: Double
fkTimeLimit = 10

-- | Seconds an IK request may take before the server's grace: its time budget (the default for
-- an absent or invalid one, at most an hour) and 30 s for parsing an inline robot and, with an
-- environment, building its hierarchy and checking every solution's clearance.
ikTimeLimit :: IkRequestMsg -> Double
ikTimeLimit m
  | isNaN b || isInfinite b || b <= 0 = 1 + 30
  | otherwise = min b 3600 + 30
  where b = orDefault (getField (ikqTimeBudget m)) :: Double

invalid :: [FieldError] -> (String, String)
invalid errs = (case errs of (e : _) -> feField e; [] -> "", renderFieldErrors errs)

timed :: IO a -> IO (Either SomeException a, Double)
timed act = do
  t0 <- getMonotonicTime
  r <- try act
  t1 <- getMonotonicTime
  pure (r, t1 - t0)

-- | Every lazy part of a response computed (by encoding it), so that a bug shows up here, inside
-- the handler's 'try', and the compute time covers the work.
forced :: Encode a => a -> IO a
forced msg = evaluate (B.length (encodeBare msg)) >> pure msg

serveFk :: FkRequestMsg -> IO FkResponseMsg
serveFk m = do
  let rid = orDefault (getField (fkqRequestId m))
  (r, secs) <- timed $ case fkFromMsg m of
    Left errs -> let (f, msg) = invalid errs in evaluate (length f + length msg) >> pure (Left (f, msg))
    Right q -> Right <$> forced (fkToMsg rid 0 q)
  pure $ case r of
    Left e -> fkError rid secs ErrInternal "" ("internal error: " ++ show e)
    Right (Left (f, msg)) -> fkError rid secs ErrInvalidArgument f msg
    Right (Right msg) -> msg { fksComputeTime = putField (nonDefault secs) }

serveIk :: IkRequestMsg -> IO IkResponseMsg
serveIk m = do
  let rid = orDefault (getField (ikqRequestId m))
  (r, secs) <- timed $ case ikFromMsg m of
    Left errs -> let (f, msg) = invalid errs in evaluate (length f + length msg) >> pure (Left (Nothing, ErrInvalidArgument, f, msg))
    Right q -> do
      res <- solve q
      case res of
        Left (code, f, msg) -> evaluate (length f + length msg) >> pure (Left (Just q, code, f, msg))
        Right sols -> do
          let shown = if ikAllSolutions (iqOptions q) then sols else take 1 sols
          Right <$> forced (ikToMsg rid 0 q shown)
  pure $ case r of
    Left e -> ikError rid secs Nothing ErrInternal "" ("internal error: " ++ show e)
    Right (Left (q, code, f, msg)) -> ikError rid secs (iqKinematics <$> q) code f msg
    Right (Right msg) -> msg { ikrComputeTime = putField (nonDefault secs) }
  where
    robotOf = chainRobot . kinChain . iqKinematics
    solve q = case iqScene q of
      Nothing -> do
        res <- solveIkIO (iqBudget q) (iqOptions q) (iqKinematics q) (iqTarget q) (iqSeed q)
        pure $ case res of
          Left f -> Left (ikFailureToError (robotOf q) Nothing (IkFailed f))
          Right [] -> Left (ikFailureToError (robotOf q) Nothing (IkFailed (Unreachable "no solution" 0)))
          Right sols -> Right [ (s, Nothing) | s <- sols ]
      Just (bvh, cm, so) -> do
        res <- solveCollisionFreeIO (iqBudget q) so (iqKinematics q) cm bvh (iqTarget q) (iqSeed q)
        pure $ case res of
          Left f -> Left (ikFailureToError (robotOf q) (Just so) f)
          Right cs -> Right [ (cdSolution c, clrDistance <$> cdClearance c) | c <- cs ]
