-- | The worst-error polish, the knot fit's last step (docs/compress.md, "The knot fit", step 6).
-- Least squares spreads the error in the square, so a sample at a sharp corner can stay far
-- above the rest: on freiburg1_xyz at 1 % of the samples the largest error was 41 mm at an
-- RMSE of 11 mm. With the waypoint times fixed, the positions are re-solved with the samples
-- above a cap weighed up, and the cap is lowered round by round: each round the cap is 95 % of
-- the path's largest error and every sample above it gains weight μ·(1 − cap/|e_i|) for good
-- (the weights grow, as a Lagrange multiplier of |e_i| <= cap would). The rounds stop when the
-- path leaves a budget: its position error's sum of squares, or its position-and-velocity
-- objective, above (1 + budget) times the given path's. Of the paths within the budget the one
-- with the lowest largest error is kept; the given path when none is lower.
module VProf.Compress.WorstPolish
  ( worstBudget
  , toleranceBudget
  , polishWorst
  , positionErrors
  ) where

import qualified Data.Vector.Unboxed as U

import VProf.Compress.Fit (solvePositionsWeighted)
import VProf.Compress.KnotTimes (Knots (..), sampleErrors)
import VProf.Compress.Objective
import VProf.Compress.Types

-- | The default budget: 0.5 % more sum of squares, a quarter of a per cent more RMSE. The
-- largest error falls fastest in the first rounds: on freiburg1_xyz at 1 % of the samples
-- 41.1 mm became 36.3 mm within this budget and 34.8 mm within twice it; at 3 % 6.07 mm
-- became 5.18 mm and 4.95 mm.
worstBudget :: Double
worstBudget = 0.005

-- | The budget of a fit to a tolerance ("VProf.Compress.KnotTolerance"), where the largest
-- error is what is asked: 5 % more sum of squares at a count. The search then finds fewer
-- points: V1_01 at 100 mm 72 instead of 81 (at this budget and at 'worstBudget'),
-- freiburg1_xyz at 30 mm 32 instead of 36.
toleranceBudget :: Double
toleranceBudget = 0.05

-- | The cap as a fraction of the largest error, the weight μ a round adds, and the rounds at
-- most (the default budget ended them after six rounds on freiburg1_xyz at 1 %).
capFraction, excessWeight :: Double
capFraction = 0.95
excessWeight = 30

maxRounds :: Int
maxRounds = 40

-- | The polish of a path's positions within a budget (a fraction, >= 0; 0: the path as it is).
polishWorst :: Double -> Prepared -> Weights -> PathA -> PathA
polishWorst budget pr w@(Weights wp _ wv) pa0
  | budget <= 0 || wp <= 0 || n < 3 || free < 1 || U.length e0 /= n || mx0 <= 0 = pa0
  | otherwise = go 0 (U.replicate n 1) e0 (mx0, pa0)
  where
    n = U.length (rcT pr)
    k = U.length (paT pa0)
    free = if rcEnds pr == EndsPinned then k - 2 else k
    e0 = positionErrors pr pa0
    mx0 = U.maximum e0
    sse0 = sumSq e0
    pv0 = pvCost pa0
    pvCost = totalCost pr (Weights wp 0 wv)
    go :: Int -> U.Vector Double -> U.Vector Double -> (Double, PathA) -> PathA
    go r sw e best@(mxB, paB)
      | r >= maxRounds = paB
      | sumSq e' > (1 + budget) * sse0 || pvCost pa > (1 + budget) * pv0 = paB
      | otherwise = go (r + 1) sw' e' (if mx < mxB then (mx, pa) else best)
      where
        cap = capFraction * U.maximum e
        sw' = U.zipWith (\s ei -> s + excessWeight * max 0 (1 - cap / max ei 1e-300)) sw e
        pa = solvePositionsWeighted pr w sw' pa0
        e' = positionErrors pr pa
        mx = U.maximum e'

-- | Each sample's time-synchronous position error (m) against the path (whose first and last
-- times are the first and last sample's, as every knot fit's are).
positionErrors :: Prepared -> PathA -> U.Vector Double
positionErrors pr (PathA ts ps _) = sampleErrors pr (Knots ts ps)

sumSq :: U.Vector Double -> Double
sumSq = U.foldl' (\s x -> s + x * x) 0
