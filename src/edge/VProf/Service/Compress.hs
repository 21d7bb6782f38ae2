-- | The daemon's path compression: one 'CompressRequestMsg' in, one 'CompressedPathMsg'
-- out, never an exception. Validation problems come back as INVALID_ARGUMENT naming the
-- field (all problems joined in the message), an unmet tolerance as INFEASIBLE with the
-- path, a compression still running at 'compressTimeLimit' as NOT_CONVERGED naming what to
-- lower, anything unexpected as INTERNAL; what cleaning the recording changed goes into @warnings@; the compute time is measured on the monotonic
-- clock.
module VProf.Service.Compress
  ( serveCompress
  , serveCompressWithin
  , compressTimeLimit
  ) where

import Control.DeepSeq (force)
import Control.Exception (SomeException, evaluate, try)
import Data.ProtocolBuffers (getField)
import GHC.Clock (getMonotonicTime)
import System.Timeout (timeout)

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
-- in the message), an unmet tolerance as INFEASIBLE with the path, a compression still
-- running after 'compressTimeLimit' as NOT_CONVERGED, anything unexpected as INTERNAL.
serveCompress :: CompressRequestMsg -> IO CompressedPathMsg
serveCompress = serveCompressWithin compressTimeLimit

-- | 'serveCompress' with this many seconds for the compression.
serveCompressWithin :: Double -> CompressRequestMsg -> IO CompressedPathMsg
serveCompressWithin limitS req = do
  let rid = orDefault (getField (crqRequestId req))
  t0 <- getMonotonicTime
  -- within the time the server grants, so that the answer says what to change (past it
  -- and the grace the server could only answer INTERNAL); the try outside the timeout,
  -- which inside would catch the timeout's own exception
  r <- try $ timeout (round (limitS * 1e6)) $ case requestToDomainW req of
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
    Right Nothing ->
      let rounds = orDefault (getField (crqSearchRounds req))
          tol = orDefault (getField (crqTolerance req))
          (field, advice)
            | rounds > 0 = ("search_rounds", " (search_rounds = " ++ show rounds ++ ": each round costs about one fit; ask fewer)")
            | tol > 0 = ("tolerance", " (tolerance = " ++ showNumber tol ++ " m: the search for the fewest points fits"
                                      ++ " the recording a dozen times, and a tolerance near its noise keeps most samples;"
                                      ++ " allow a larger one, or send a shorter recording)")
            | otherwise = ("points", " (ask fewer points, or send a shorter recording)")
      in errorResponse rid secs ErrNotConverged field
           ("the compression did not finish within " ++ showNumber limitS
            ++ " s, the daemon's limit for one request" ++ advice)
    Left e -> errorResponse rid secs ErrInternal "" ("internal error: " ++ show (e :: SomeException))
    Right (Just (Left errs@(e1 : _))) ->
      errorResponse rid secs ErrInvalidArgument (feField e1) (renderFieldErrors errs)
    Right (Just (Left [])) -> errorResponse rid secs ErrInternal "" "internal error: empty error list"
    Right (Just (Right (warns, o))) -> outcomeToMsg rid secs warns o
