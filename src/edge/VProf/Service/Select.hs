-- | The daemon's robot selection: one 'SelectRequestMsg' in, one 'SelectResponseMsg' out; never
-- an exception. Validation problems come back as INVALID_ARGUMENT, every one of them (each naming
-- its field); a robot that cannot do the task is not an error but a result (rejected by the
-- payload filter, or targets not reached, each with its reason and code). The robots are
-- evaluated in parallel, one worker per capability taking robots from one queue, as @vprof
-- select@ does ("VProf.Select.Parallel"); the ranking is the core's ('scoreAndRank'). The
-- compute time is measured on the monotonic clock.
module VProf.Service.Select
  ( serveSelect
  , selectTimeLimit
  ) where

import Control.Exception (SomeException, evaluate, try)
import qualified Data.ByteString as B
import Data.ProtocolBuffers (getField, putField)
import GHC.Clock (getMonotonicTime)
import GHC.Conc (getNumCapabilities)

import VProf.Kinematics.Library (libraryRobots)
import VProf.Select.Parallel (evaluateRobots)
import VProf.Select.Selection
import VProf.Wire.Kinematics (mkError)
import VProf.Wire.Messages
import VProf.Wire.Select

-- | Seconds a selection may take before the server's grace: 60 s plus 0.5 s per robot and target
-- (ten times that in a path task, whose segments are followed sample by sample), at most an hour.
selectTimeLimit :: SelectRequestMsg -> Double
selectTimeLimit m = min 3600 (60 + 0.5 * fromIntegral (robots * targets) * (if path then 10 else 1))
  where
    robots = case length (getField (slqRobots m)) of
      0 -> length libraryRobots
      n -> n
    targets = length (getField (slqTargets m))
    path = orDefault (getField (slqPath m)) :: Bool

serveSelect :: SelectRequestMsg -> IO SelectResponseMsg
serveSelect m = do
  let rid = orDefault (getField (slqRequestId m))
  t0 <- getMonotonicTime
  r <- try $ case selectFromMsg m of
    Left errs -> evaluate (length (show (map show errs))) >> pure (Left errs)
    Right q -> do
      caps <- getNumCapabilities
      evaluated <- evaluateRobots caps defaultSelectOptions (sqTask q) (sqCell q) (sqRobots q)
      let msg = selectToMsg rid 0 q (scoreAndRank evaluated)
      _ <- evaluate (B.length (encodeBare msg))
      pure (Right msg)
  t1 <- getMonotonicTime
  let secs = t1 - t0
  pure $ case r of
    Left (e :: SomeException) -> (selectErrors rid secs [])
      { slrError = putField (Just (mkError ErrInternal "" ("internal error: " ++ show e))), slrErrors = putField [] }
    Right (Left errs) -> selectErrors rid secs errs
    Right (Right msg) -> msg { slrComputeTime = putField (nonDefault secs) }
