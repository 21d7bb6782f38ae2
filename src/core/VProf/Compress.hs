-- | Path compression: a recorded 6-DOF motion (time, position, orientation) in, a path of
-- few linear moves out, by the thesis's weighted least squares or by the RDP baseline.
-- Pure; files, plots and the command line live in other modules.
module VProf.Compress
  ( Method (..)
  , Settings (..)
  , defaultSettings
  , Compressed (..)
  , compress
  , knotConfigFor
  , validateSettings
  , maxSearchRounds
  , module VProf.Validation
  , module VProf.Compress.Types
  , module VProf.Compress.Metrics
  ) where

import qualified Data.Vector.Unboxed as U
import Numeric.Units.Dimensional.Prelude (Length, metre, (/~))
import Prelude

import VProf.Compress.Fit
import VProf.Compress.KnotFit
import VProf.Compress.KnotTolerance
import VProf.Compress.Metrics
import VProf.Compress.Objective
import VProf.Compress.OrientationBalance (orientationBudget)
import VProf.Compress.Rdp
import VProf.Compress.Types
import VProf.Compress.WorstPolish (toleranceBudget, worstBudget)
import VProf.Validation

-- | 'MethodKnots': the knot fit ("VProf.Compress.KnotFit") for a number of points, or to a
-- tolerance the fewest points it finds within it ("VProf.Compress.KnotTolerance"); with a
-- margin it runs the thesis algorithm, which owns that stopping rule.
-- 'MethodThesis': the thesis's grow/shrink algorithm ("VProf.Compress.Fit").
data Method = MethodKnots | MethodThesis | MethodRdp deriving (Show, Eq)

data Settings = Settings
  { sMethod    :: !Method
  , sWeights   :: !Weights
  , sPoints    :: !(Maybe Int)
  , sMargin    :: !(Maybe Double)
  , sTolerance :: !(Maybe (Length Double))  -- ^ largest position error allowed
  , sSearch    :: !Int   -- ^ rounds of the knot fit's wider search ('searchKnots'); 0: none
  , sEnds      :: !Ends  -- ^ first and last waypoint pinned to the recording's or fitted
  , sPolish    :: !Bool  -- ^ knot fit: after least squares, move the times towards the
                          -- orientation ("VProf.Compress.OrientationBalance"; not to a
                          -- tolerance, where it would cost points) and lower the largest
                          -- position error ("VProf.Compress.WorstPolish"), at up to
                          -- 'orientationBudget' and 'worstBudget' more position sum of
                          -- squares ('toleranceBudget' for the second to a tolerance);
                          -- False: least squares only
  } deriving (Show, Eq)

defaultSettings :: Settings
defaultSettings = Settings MethodKnots defaultWeights Nothing Nothing Nothing 0 EndsPinned True

-- | The most rounds of the wider search (each about one knot fit).
maxSearchRounds :: Int
maxSearchRounds = 1000

-- | A compressed path with its measures, whether the tolerance (if any) is met, the
-- weighted objective and why the point count stopped where it did.
data Compressed = Compressed
  { oPath        :: !Path
  , oMetrics     :: !Metrics
  , oToleranceMet :: !Bool
  , oObjective   :: !Double     -- ^ weighted objective of the result
  , oStop        :: !String     -- ^ why the point count stopped where it did
  } deriving (Show)

-- | Check settings against a recording of n samples: every problem at once, in SI and
-- in the core's field names (@weights.position@, @weights.orientation@,
-- @weights.velocity@, @weights@, @points@, @margin@, @tolerance@, @search@, @ends@); an interface
-- re-expresses them in its own names and units with 'inUserTerms'.
validateSettings :: Int -> Settings -> [FieldError]
validateSettings n s = concat
  [ concat [ ensureFinite f w "" (ensure (w >= 0) (fieldError f w "" "must be >= 0"))
           | (f, w) <- [("weights.position", p), ("weights.orientation", o), ("weights.velocity", v)] ]
  , ensure (not (all finite [p, v]) || p > 0 || v > 0)
      (literalError "weights" (show (p, o, v)) "the position or the velocity weight must be > 0")
  , case sPoints s of
      Just k -> ensure (k >= 2 && k <= n)
                  (literalError "points" (show k) ("must be between 2 and the number of samples, " ++ show n))
      Nothing -> []
  , case sMargin s of
      Just m -> ensureFinite "margin" m "" $ concat
        [ ensure (m >= 1) (fieldError "margin" m "" "must be a number >= 1")
        , ensure (sMethod s /= MethodRdp) (fieldError "margin" m "" "only the thesis method has a margin") ]
      Nothing -> []
  , case fmap (/~ metre) (sTolerance s) of
      Just t -> ensureFinite "tolerance" t "m" (ensure (t > 0) (fieldError "tolerance" t "m" "must be > 0"))
      Nothing -> []
  , let r = sSearch s in concat
      [ ensure (r >= 0 && r <= maxSearchRounds)
          (literalError "search" (show r) ("must be between 0 and " ++ show maxSearchRounds))
      , ensure (r == 0 || (sMethod s == MethodKnots && sMargin s == Nothing && sTolerance s == Nothing))
          (literalError "search" (show r) "only the knot fit to a number of points searches (no margin, tolerance or other method)") ]
  , ensure (sEnds s == EndsPinned || sMethod s /= MethodRdp)
      (literalError "ends" "free" "RDP keeps the first and last sample; only the knot fit and the thesis method fit the ends")
  ]
  where Weights p o v = sWeights s

-- | The knot fit's configuration for the settings, as 'compress' runs it (a count tried by
-- the search, to a tolerance): the wider search's rounds; the orientation balance at
-- 'orientationBudget' and the worst-error polish at 'worstBudget' with 'sPolish'; to a
-- tolerance no orientation balance (it costs points) and the polish at 'toleranceBudget'.
knotConfigFor :: Settings -> KnotConfig
knotConfigFor s = case sTolerance s of
  Nothing -> defaultKnotConfig { kcSearch = sSearch s, kcOrientBudget = budget orientationBudget
                               , kcWorstBudget = budget worstBudget }
  Just _ -> defaultKnotConfig { kcOrientBudget = 0, kcWorstBudget = budget toleranceBudget }
  where budget b = if sPolish s then b else 0

-- | Compress a recording. For RDP, a tolerance is the classic RDP epsilon (geometric
-- distance); for the knot fit and the thesis method it bounds the time-synchronous
-- position error, and a number of points with it is the fewest allowed.
compress :: Settings -> Recording -> Either [FieldError] Compressed
compress s rec = validated [validateSettings n s] () >> pure (case sMethod s of
    MethodKnots | sMargin s == Nothing -> case tolM of
      Nothing ->
        let k = maybe (max 2 (round (0.03 * fromIntegral n :: Double))) (max 2) (sPoints s)
            pa = fitKnots (knotConfigFor s) pr (sWeights s) k
        in Compressed (fromPathA pa) (computeMetrics pr pa) True (totalCost pr (sWeights s) pa) (show ReachedPoints)
      Just tol ->
        let pa = tfPath (fitKnotsTolerance (knotConfigFor s) pr (sWeights s) (maybe 2 id (sPoints s)) tol)
        in Compressed (fromPathA pa) (computeMetrics pr pa) True (totalCost pr (sWeights s) pa) (show ReachedTolerance)
    MethodRdp -> rdp
    _ ->
      let cfg = defaultFitConfig { fcWeights = sWeights s, fcPoints = sPoints s
                                 , fcMargin = sMargin s, fcTolerance = tolM }
          r = fitThesis cfg pr
          pa = frPath r
      in Compressed (fromPathA pa) (computeMetrics pr pa) (frToleranceMet r) (frCost r) (show (frStop r)))
  where
    rdp =
      let stop = case (sPoints s, tolM) of
            (Just k, _) -> RdpPoints k
            (Nothing, Just e) -> RdpEpsilon e
            _ -> RdpPoints (max 2 (round (0.03 * fromIntegral n :: Double)))
          pa = rdpPath pr stop
          m = computeMetrics pr pa
          tolOk = maybe True (\e -> mGeometricMax m <= e + 1e-12) tolM
      in Compressed (fromPathA pa) m tolOk (totalCost pr (sWeights s) pa) (show stop)
    pr = (prepareRecording rec) { rcEnds = sEnds s }
    tolM = fmap (/~ metre) (sTolerance s)
    n = U.length (rcT pr)
