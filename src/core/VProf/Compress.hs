-- | Path compression: a recorded 6-DOF motion (time, position, orientation) in, a path of
-- few linear moves out, by the thesis's weighted least squares or by the RDP baseline.
-- Pure; files, plots and the command line live in other modules.
module VProf.Compress
  ( Method (..)
  , Settings (..)
  , defaultSettings
  , Outcome (..)
  , compress
  , validateSettings
  , module VProf.Compress.Types
  , module VProf.Compress.Metrics
  ) where

import qualified Data.Vector.Unboxed as U
import Numeric.Units.Dimensional.Prelude (Length, metre, (/~))
import Prelude

import VProf.Compress.Fit
import VProf.Compress.Metrics
import VProf.Compress.Objective
import VProf.Compress.Rdp
import VProf.Compress.Types

data Method = MethodThesis | MethodRdp deriving (Show, Eq)

data Settings = Settings
  { sMethod    :: !Method
  , sWeights   :: !Weights
  , sPoints    :: !(Maybe Int)
  , sMargin    :: !(Maybe Double)
  , sTolerance :: !(Maybe (Length Double))  -- ^ largest position error allowed
  } deriving (Show, Eq)

defaultSettings :: Settings
defaultSettings = Settings MethodThesis defaultWeights Nothing Nothing Nothing

data Outcome = Outcome
  { oPath        :: !Path
  , oMetrics     :: !Metrics
  , oToleranceMet :: !Bool
  , oObjective   :: !Double     -- ^ weighted objective of the result
  , oStop        :: !String     -- ^ why the point count stopped where it did
  } deriving (Show)

-- | Check settings against a recording of n samples; errors name the setting and value.
validateSettings :: Int -> Settings -> Either (String, String) ()
validateSettings n s = do
  let Weights p o v = sWeights s
      chk name ok val msg = if ok then Right () else Left (name, name ++ " = " ++ val ++ ": " ++ msg)
      finite x = not (isNaN x || isInfinite x)
  chk "weights" (all (\x -> finite x && x >= 0) [p, o, v]) (show (p, o, v)) "weights must be finite and >= 0"
  chk "weights" (p > 0 || v > 0) (show (p, o, v)) "the position or the velocity weight must be > 0"
  case sPoints s of
    Just k -> chk "points" (k >= 2 && k <= n) (show k) ("must be between 2 and the number of samples (" ++ show n ++ ")")
    Nothing -> Right ()
  case sMargin s of
    Just m -> do
      chk "margin" (finite m && m >= 1) (show m) "must be a number >= 1"
      chk "margin" (sMethod s == MethodThesis) (show m) "only the thesis method has a margin"
    Nothing -> Right ()
  case fmap (/~ metre) (sTolerance s) of
    Just t -> chk "tolerance" (finite t && t > 0) (show t) "must be > 0"
    Nothing -> Right ()

-- | Compress a recording. For RDP, a tolerance is the classic RDP epsilon (geometric
-- distance); for the thesis method it bounds the time-synchronous position error.
compress :: Settings -> Recording -> Either (String, String) Outcome
compress s rec = do
  let pr = prepare rec
      tolM = fmap (/~ metre) (sTolerance s)
      n = U.length (prT pr)
  validateSettings n s
  pure $ case sMethod s of
    MethodThesis ->
      let cfg = defaultFitConfig { fcWeights = sWeights s, fcPoints = sPoints s
                                 , fcMargin = sMargin s, fcTolerance = tolM }
          r = fitThesis cfg pr
          pa = frPath r
      in Outcome (fromPathA pa) (computeMetrics pr pa) (frToleranceMet r) (frCost r) (show (frStop r))
    MethodRdp ->
      let stop = case (sPoints s, tolM) of
            (Just k, _) -> RdpPoints k
            (Nothing, Just e) -> RdpEpsilon e
            _ -> RdpPoints (max 2 (round (0.03 * fromIntegral n :: Double)))
          pa = rdpPath pr stop
          m = computeMetrics pr pa
          tolOk = maybe True (\e -> mGeometricMax m <= e + 1e-12) tolM
      in Outcome (fromPathA pa) m tolOk (totalCost pr (sWeights s) pa) (show stop)
