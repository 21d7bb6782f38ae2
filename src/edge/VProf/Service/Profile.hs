-- | The daemon's velocity profiles: one 'ProfileRequestMsg' in, one 'ProfileResponseMsg'
-- out, never an exception; the request's own time budget binds the generator, and
-- 'profileTimeLimit' tells the server how long to wait for it.
module VProf.Service.Profile
  ( serveProfile
  , profileTimeLimit
  ) where

import Control.Exception (SomeException, evaluate, try)
import Data.ProtocolBuffers (getField, putField)

import VProf.Profile.Generate
import VProf.Profile.Request (Algorithm (..), defaultTimeBudget)
import VProf.Validation (literalError)
import VProf.Wire.Messages
import VProf.Wire.Profile

-- | Generate a profile for one request; the request's own time budget applies.
serveProfile :: ProfileRequestMsg -> IO ProfileResponseMsg
serveProfile m = do
  let rid = orDefault (getField (prqRequestId m))
  r <- case getEnum (getField (prqAlgorithm m)) of
    -- a number this version does not know: refused, not run as the default
    AlgorithmUnknown k -> pure (Right (resultToMsg rid (Result (Failed (InvalidRequest [literalError "algorithm" (show k)
                            "is not an algorithm: 0 (the default, band), 1 (band) or 2 (thesis)"])) Nothing [] 0 False Band 0 0 0)))
    _ -> try (generate (requestFromMsg m) >>= \res -> evaluate (resultToMsg rid res))
  pure $ case r of
    Right msg -> msg
    Left (e :: SomeException) -> (resultToMsg rid emptyResult)
      { prsError = putField (Just (errorMsg ErrInternal "" ("internal error: " ++ show e))) }
  where
    emptyResult = Result (Failed (NotConverged "internal error")) Nothing [] 0 False Band 0 0 0

-- | Seconds the generator may take for this request: its time budget (the default for
-- an absent or invalid one, at most an hour). The generator keeps to it; the server's
-- grace covers the rest.
profileTimeLimit :: ProfileRequestMsg -> Double
profileTimeLimit p
  | isNaN b || isInfinite b || b <= 0 = defaultTimeBudget
  | otherwise = min b 3600
  where b = orDefault (getField (prqTimeBudget p)) :: Double
