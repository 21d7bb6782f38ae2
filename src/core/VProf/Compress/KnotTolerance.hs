-- | The knot fit to a tolerance: the fewest waypoints whose path keeps every sample's
-- time-synchronous position error within a bound. The knot fit ("VProf.Compress.KnotFit")
-- minimises the error's sum of squares for a given count; this searches the count. It
-- keeps a bracket, the largest count tried whose largest error is above the bound and the
-- smallest tried within it, and narrows it until the two are adjacent: by interpolating
-- log error against log count (a linear fit's error on a smooth motion falls about as
-- 1/k²) and, every other step, by halving. A count whose fit breaks the bound gets a few
-- exchanges that aim at the largest error ('repairWorst') before it is judged, since the
-- fit's times are chosen for the sum of squares. The largest error need not fall
-- monotonically with the count, so a count below the bracket can meet the bound too: the
-- answer is the fewest the search found, not a proven minimum (docs/compress.md, "To a
-- tolerance"). Every sample a waypoint (the recording itself) meets any bound, so the
-- bound is always met.
module VProf.Compress.KnotTolerance
  ( ToleranceFit (..)
  , fitKnotsTolerance
  , repairWorst
  ) where

import Data.List (sortBy)
import Data.Ord (comparing)
import qualified Data.Vector.Unboxed as U

import VProf.Compress.Fit (maxPositionError)
import VProf.Compress.KnotFit
import VProf.Compress.KnotTimes
import VProf.Compress.Objective
import VProf.Compress.Types
import VProf.Geometry.Vec (pindex)

-- | The path found, its largest position error (m) and every count tried with its largest
-- error, in the order tried.
data ToleranceFit = ToleranceFit
  { tfPath     :: !PathA
  , tfMaxError :: !Double
  , tfTried    :: ![(Int, Double)]
  } deriving (Show)

-- | The fewest waypoints, at least @kMin@ (at least 2), whose knot fit keeps the largest
-- time-synchronous position error within @tol@ (m, > 0).
fitKnotsTolerance :: KnotConfig -> Prepared -> Weights -> Int -> Double -> ToleranceFit
fitKnotsTolerance cfg pr w kMin0 tol = go (0 :: Int) lo0 hi0 [] k0
  where
    n = U.length (rcT pr)
    kMin = max 2 (min n kMin0)
    recording = PathA (rcT pr) (rcP pr) (rcQ pr)
    -- the knot fit to k points; where it breaks the bound, also its knots after the
    -- exchanges for the largest error ('repairWorst'), the lower largest error kept
    fit k | k >= n = (recording, 0)
          | otherwise =
              let kn = optimiseKnots cfg pr (startKnots cfg pr k)
                  pa = finishKnots cfg pr w kn
                  e = maxPositionError pr pa
              in if e <= tol then (pa, e) else case repairWorst pr (kcIterations cfg) tol kn of
                   Nothing -> (pa, e)
                   Just kn' -> let pa' = finishKnots cfg pr w kn'
                                   e' = maxPositionError pr pa'
                               in if e' < e then (pa', e') else (pa, e)
    -- the bracket's ends: the largest count too few (its largest error; below kMin nothing
    -- is allowed, its error unknown) and the smallest within the bound (its path; at first
    -- n, the recording itself, error 0)
    lo0 = (kMin - 1, Nothing)
    hi0 = (n, (recording, 0))
    k0 = max kMin (min n (round (0.03 * fromIntegral n :: Double)))
    go step lo hi@(kh, (pah, eh)) tried k
      | kh - fst lo <= 1 = ToleranceFit pah eh (reverse tried)
      | otherwise =
          let kk = inside lo hi k
              (pa, e) = fit kk
              (lo', hi') = if e <= tol then (lo, (kk, (pa, e))) else ((kk, Just e), hi)
          in go (step + 1) lo' hi' ((kk, e) : tried) (next step lo' hi')
    inside (kl, _) (kh, _) k = max (kl + 1) (min (kh - 1) k)
    -- the next count to try inside the bracket
    next step lo@(kl, el) hi@(kh, (_, eh)) = inside lo hi $ case el of
      -- nothing too few tried yet: below the smallest count within the bound by the 1/k²
      -- law with a tenth to spare, at least a quarter of the way to kMin
      Nothing -> min (kh - (kh - kl) `div` 4) (floor (fromIntegral kh * sqrt (eh / tol) * 0.9 :: Double))
      Just e
        -- nothing within the bound tried yet (the recording aside): above the largest
        -- count too few by the same law, a tenth to spare; halfway to the recording where
        -- the law points past it (a bound near the recording's noise)
        | eh == 0 -> let g = fromIntegral kl * sqrt (e / tol) * 1.1 :: Double
                     -- (compared as a double: a bound of 1e-39 m made it past any Int, and
                     -- the count overflowed into a walk up one count a fit)
                     in if g >= fromIntegral kh then mid else ceiling g
        -- both ends tried: halving every other step, else log error interpolated in log
        -- count at the bound
        | even step -> mid
        | otherwise ->
            let lk = log (fromIntegral kl) + (log e - log tol) / (log e - log eh)
                                               * (log (fromIntegral kh) - log (fromIntegral kl)) :: Double
            in round (exp lk)
      where mid = kl + (kh - kl) `div` 2

-- | Exchanges for the largest error: while the worst sample's error is above the bound, a
-- waypoint is inserted at its time (on the recording's position there) and one removed
-- where that costs the least position error (of the four cheapest, not an end of the worst
-- sample's segment), the positions around the insertion re-solved and the times and
-- positions around the removal refined; kept when the largest error falls. Stops when the
-- bound is met, when no exchange lowers the largest error, or when the worst sample is
-- closer than 'rcMinGap' to a waypoint (at most 'repairExchanges'). Nothing when no
-- exchange was kept.
repairWorst :: Prepared -> Int -> Double -> Knots -> Maybe Knots
repairWorst pr iters tol kn0 = go repairExchanges kn0 (worstSample pr kn0)
  where
    go :: Int -> Knots -> (Int, Double) -> Maybe Knots
    go r kn (i, e)
      | e <= tol || r <= 0 || k < 4 = kept
      | otherwise = case [ c | Just c <- map exchange cands ] of
          (kn', w') : _ -> go (r - 1) kn' w'
          [] -> kept
      where
        ts = kT kn
        k = U.length ts
        tw = rcT pr U.! i
        s = max 0 (min (k - 2) (U.length (U.takeWhile (<= tw) ts) - 1))
        kept = if r < repairExchanges then Just kn else Nothing
        roomy = tw - ts U.! s >= rcMinGap pr && ts U.! (s + 1) - tw >= rcMinGap pr
        cands | roomy = map snd (take 4 (sortBy (comparing fst)
                          [ (removalCost pr kn j, j) | j <- [1 .. k - 2], j /= s, j /= s + 1 ]))
              | otherwise = []
        exchange j =
          let kn1 = insertKnotAt s tw (pindex (rcP pr) i) kn
              -- the inserted waypoint's index after the removal, and the removed one's place
              (kn2, ins) = if j > s then (dropKnot (j + 1) kn1, s + 1) else (dropKnot j kn1, s)
              k2 = U.length (kT kn2)
              kn3 = solveSlicePositions pr (True, True) kn2 (max 0 (ins - 2)) (min (k2 - 1) (ins + 2))
              (kn4, _) = refineStretch pr iters (max 0 (j - 3)) (min (k2 - 1) (j + 2)) kn3
              w4 = worstSample pr kn4
          in if snd w4 < e * (1 - 1e-9) then Just (kn4, w4) else Nothing

-- | The most exchanges 'repairWorst' keeps: the largest errors are a few places (each
-- exchange costs a removal estimate at every waypoint and a pass over the samples).
repairExchanges :: Int
repairExchanges = 16
