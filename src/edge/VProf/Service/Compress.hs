-- | The daemon's path compression: one 'CompressRequestMsg' in, one 'CompressedPathMsg'
-- out, never an exception. Validation problems come back as INVALID_ARGUMENT naming the
-- field (all problems joined in the message), an unmet tolerance as INFEASIBLE with the
-- path, anything unexpected as INTERNAL; what cleaning the recording changed goes into @warnings@; the compute time is measured on the monotonic
-- clock.
module VProf.Service.Compress
  ( serveCompress
  , compressTimeLimit
  ) where

import Control.DeepSeq (force)
import Control.Exception (SomeException, evaluate, try)
import Data.ProtocolBuffers (getField)
import GHC.Clock (getMonotonicTime)

import VProf.Compress
import VProf.Compress.Clean (renderCleanWarning)
import VProf.Wire.Compress
import VProf.Wire.Messages

-- | Seconds a compression may take before the server's grace: a compress request carries
-- no time budget of its own.
compressTimeLimit :: Double
compressTimeLimit = 60

-- | Serve one request: validate, compress, measure the compute time. Never throws:
-- validation problems come back as INVALID_ARGUMENT naming the field (all problems joined
-- in the message), an unmet tolerance as INFEASIBLE with the path, anything unexpected as
-- INTERNAL.
serveCompress :: CompressRequestMsg -> IO CompressedPathMsg
serveCompress req = do
  let rid = orDefault (getField (crqRequestId req))
  t0 <- getMonotonicTime
  r <- try $ case requestToDomainW req of
    Left errs -> evaluate (Left errs)
    Right (rec, s, ws) -> case compress s rec of
      Left errs -> evaluate (Left errs)
      Right o -> do
        o' <- evaluate (force (oMetrics o)) >> evaluate o
        warns <- evaluate (force (map (renderCleanWarning wireLocator) ws))
        pure (Right (warns, o'))
  t1 <- getMonotonicTime
  let secs = t1 - t0
  pure $ case r of
    Left e -> errorResponse rid secs ErrInternal "" ("internal error: " ++ show (e :: SomeException))
    Right (Left errs@(e1 : _)) ->
      errorResponse rid secs ErrInvalidArgument (feField e1) (renderFieldErrors errs)
    Right (Left []) -> errorResponse rid secs ErrInternal "" "internal error: empty error list"
    Right (Right (warns, o)) -> outcomeToMsg rid secs warns o
