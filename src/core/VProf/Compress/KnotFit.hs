{-# LANGUAGE BangPatterns #-}
-- | The knot fit, vprof's default compression for a given number of points (docs/compress.md,
-- "The knot fit"): where the waypoints are matters more than the values at them, so it
-- starts from a line partition of the samples ("VProf.Compress.Partition": waypoints at the
-- boundaries of k−1 groups with the least line-fit error), optimises all waypoint times
-- together with the positions ("VProf.Compress.KnotTimes"), then tries exchanges (a waypoint
-- removed where it is least useful and one inserted where the error is largest, both places
-- re-optimised, kept only if the position error falls), optimises the times again, and
-- finally solves the orientations (Gauss–Newton, "VProf.Compress.Fit") and the positions
-- under the full weighted objective for those times. The times are chosen for the position
-- error alone; two last steps, each within a small budget of the least-squares position
-- error, move them towards the orientation ("VProf.Compress.OrientationBalance") and lower
-- the largest position error ("VProf.Compress.WorstPolish"). First and last waypoint pinned
-- to the first and last sample unless 'rcEnds' frees them. On request a
-- wider search ('searchKnots') runs the same optimisation from a start that keeps continuity
-- exactly ("VProf.Compress.KnotDP"), from random starts and from perturbations of the best
-- path.
module VProf.Compress.KnotFit
  ( KnotConfig (..)
  , defaultKnotConfig
  , fitKnots
  , startKnots
  , continuousStart
  , exchangeKnots
  , optimiseKnots
  , searchKnots
  , finishKnots
  , removalCost
  , dropKnot
  , insertKnotAt
  ) where

import Data.Bits (shiftR, xor)
import Data.List (nub, sort, sortBy)
import Data.Word (Word64)
import Data.Ord (comparing)
import qualified Data.Vector.Unboxed as U

import VProf.Compress.Fit (TimeMode (..), solveOrientations, solvePositions, updatePathWith)
import VProf.Compress.KnotDP (continuousKnots)
import VProf.Compress.KnotTimes
import VProf.Compress.Objective
import VProf.Compress.OrientationBalance (balanceOrientation, orientationBudget)
import VProf.Compress.Partition (linePartition)
import VProf.Compress.Types
import VProf.Compress.WorstPolish (polishWorst, worstBudget)
import VProf.Geometry.Polyline (polylineAt)
import VProf.Geometry.Vec

data KnotConfig = KnotConfig
  { kcWindowFactor :: !Int   -- ^ longest group of the start partition, in mean groups (w = factor·n/(k−1))
  , kcIterations   :: !Int   -- ^ accepted Levenberg–Marquardt steps per refinement
  , kcExchanges    :: !Int   -- ^ exchange passes at most
  , kcOrientRounds :: !Int   -- ^ Gauss–Newton rounds for the orientations at most
  , kcPolish       :: !Int   -- ^ rounds of the thesis's update under the full weights at the end
  , kcSearch       :: !Int   -- ^ rounds of the wider search ('searchKnots'); 0: none
  , kcOrientBudget :: !Double -- ^ the orientation balance's budget ('balanceOrientation'); 0: none
  , kcWorstBudget  :: !Double -- ^ the worst-error polish's budget ('polishWorst'); 0: none
  } deriving (Show, Eq)

defaultKnotConfig :: KnotConfig
defaultKnotConfig = KnotConfig 4 100 30 10 3 0 orientationBudget worstBudget

-- | The start: k waypoint times at the boundaries of a line partition into k−1 groups
-- (midway between a group's last sample and the next group's first), positions the
-- recording's at those times.
startKnots :: KnotConfig -> Prepared -> Int -> Knots
startKnots cfg pr k = Knots ts (pgenerate k (\j -> fst (polylineAt st (rcP pr) (rcQ pr) (ts U.! j))))
  where
    st = rcT pr
    bs = startPartition cfg pr k
    ts = U.generate k $ \j ->
      if j == 0 then U.head st
      else if j == k - 1 then U.last st
      else let b = bs U.! j in 0.5 * (st U.! (b - 1) + st U.! b)

-- | The boundaries of the start's line partition into k−1 groups.
startPartition :: KnotConfig -> Prepared -> Int -> U.Vector Int
startPartition cfg pr k = linePartition (rcT pr) (rcP pr) m (startWindow cfg pr k)
  where m = k - 1

-- | The longest group of the start partition, in samples.
startWindow :: KnotConfig -> Prepared -> Int -> Int
startWindow cfg pr k = let n = U.length (rcT pr); m = k - 1 in min n (kcWindowFactor cfg * ((n + m - 1) `div` m))

-- | The continuous start ("VProf.Compress.KnotDP"): waypoint j searched at the samples
-- between the line partition's boundaries j−s and j+s (s = @spread@; everywhere when 0),
-- @beam@ functions per state, positions the exact least squares for those times. The line
-- partition's start when the search finds no path.
continuousStart :: KnotConfig -> Int -> Int -> Prepared -> Int -> Knots
continuousStart cfg spread beam pr k
  | isInfinite v = startKnots cfg pr k
  | otherwise = solveStretchPositions pr (Knots ts (pgenerate k (\j -> pindex (rcP pr) (idx U.! j)))) 0 (k - 1)
  where
    st = rcT pr
    n = U.length st
    m = k - 1
    bs = startPartition cfg pr k
    band j | spread <= 0 = (1, n - 2)
           | otherwise = (bs U.! max 0 (j - spread) - 1, bs U.! min m (j + spread))
    w = 2 * startWindow cfg pr k
    (idx, v) = continuousKnots pr k beam band w
    ts = U.map (st U.!) idx

-- | Exchange passes: each pass estimates, for every interior waypoint, the cost of removing
-- it (its neighbours' positions re-solved) and, for every segment, the gain of a waypoint
-- inserted at its middle (the nearby positions re-solved); the most promising pairs far
-- enough apart that their stretches do not overlap are tried with both stretches
-- re-optimised ('refineStretch'), and the first that lowers the position error is kept.
-- Stops at the first pass that keeps nothing.
exchangeKnots :: Prepared -> Int -> Int -> Knots -> Knots
exchangeKnots pr iters passes kn0 = go passes kn0
  where
    go 0 kn = kn
    go p kn
      | k < 6 = kn
      | otherwise = case tryPairs pairs of
          Nothing -> kn
          Just kn' -> go (p - 1) kn'
      where
        ts = kT kn
        k = U.length ts
        rems = take 8 (sortBy (comparing fst) [ (removalDelta kn j, j) | j <- [1 .. k - 2] ])
        -- (a segment too short to halve keeps its waypoints 'rcMinGap' apart: no insertion)
        ins = take 10 (sortBy (comparing fst) [ (insertionDelta kn s, s) | s <- [0 .. k - 2], ts U.! (s + 1) - ts U.! s >= 2 * rcMinGap pr ])
        pairs = take 12 (sortBy (comparing fst) [ (dr + di, (j, s)) | (dr, j) <- rems, (di, s) <- ins, s >= j + 4 || s <= j - 5 ])
        tryPairs [] = Nothing
        tryPairs ((_, (j, s)) : rest) = case exchange kn j s of
          Just kn' -> Just kn'
          Nothing -> tryPairs rest
    removalDelta = removalCost pr
    -- insert into segment s at its middle: stretch s−1 .. s+2 becomes s−1 .. s+3
    insertionDelta kn s =
      let k = U.length (kT kn)
          ja = max 0 (s - 1); jb = min (k - 1) (s + 2)
          sub = sliceKnots ja jb kn
          m = jb - ja
          ki = solveSlicePositions pr (ja == 0, jb == k - 1) (insertKnot (s - ja) sub) 0 (m + 1)
      in stretchSse pr ki 0 (m + 1) - stretchSse pr sub 0 m
    -- the exchange with both stretches re-optimised (3 waypoints each side held outside)
    exchange kn j s =
      let k = U.length (kT kn)
          f0 = knotSse pr kn
          -- insert first at the higher index so the lower index stays valid
          kn1 | s > j = dropKnot j (insertKnot s kn)
              | otherwise = insertKnot s (dropKnot j kn)
          newIns = if s > j then s else s + 1      -- index of the inserted waypoint in kn1
          remAt = if s > j then j else j + 1       -- index of j's later neighbour in kn1
          k1 = U.length (kT kn1)
          w1 = (max 0 (newIns - 3), min (k1 - 1) (newIns + 3))
          w2 = (max 0 (remAt - 3), min (k1 - 1) (remAt + 2))
          (kn2, _) = uncurry (refineStretch pr iters) w1 kn1
          (kn3, _) = uncurry (refineStretch pr iters) w2 kn2
          f3 = knotSse pr kn3
      in if k1 == k && f3 < f0 * (1 - 1e-9) then Just kn3 else Nothing
    insertKnot s kn = insertKnotAt s (0.5 * (kT kn U.! s + kT kn U.! (s + 1)))
                                     (0.5 *^ (pindex (kP kn) s ^+^ pindex (kP kn) (s + 1))) kn

-- | The estimated change of the position error when interior waypoint j is removed: the
-- stretch j−2 .. j+2 becomes j−2 .. j+1 with its interior positions re-solved (worked on
-- a slice, so an estimate costs only the stretch's samples).
removalCost :: Prepared -> Knots -> Int -> Double
removalCost pr kn j =
  let k = U.length (kT kn)
      ja = max 0 (j - 2); jb = min (k - 1) (j + 2)
      sub = sliceKnots ja jb kn
      m = jb - ja
      kr = solveSlicePositions pr (ja == 0, jb == k - 1) (dropKnot (j - ja) sub) 0 (m - 1)
  in stretchSse pr kr 0 (m - 1) - stretchSse pr sub 0 m

-- | Waypoints ja .. jb alone.
sliceKnots :: Int -> Int -> Knots -> Knots
sliceKnots ja jb (Knots ts (V3s v)) = Knots (U.slice ja (jb - ja + 1) ts) (V3s (U.slice (3 * ja) (3 * (jb - ja + 1)) v))

-- | Waypoint j removed.
dropKnot :: Int -> Knots -> Knots
dropKnot j (Knots ts ps) = Knots (U.ifilter (\i _ -> i /= j) ts) (pifilter (/= j) ps)

-- | A waypoint at time t and position pm inserted into segment s (t inside it).
insertKnotAt :: Int -> Double -> P3 -> Knots -> Knots
insertKnotAt s t pm (Knots ts ps) =
  let kk = U.length ts
  in Knots (U.generate (kk + 1) (\i -> if i <= s then ts U.! i else if i == s + 1 then t else ts U.! (i - 1)))
           (pgenerate (kk + 1) (\i -> if i <= s then pindex ps i else if i == s + 1 then pm else pindex ps (i - 1)))

-- | Steps 2 and 3 of the fit from given knots: all times and positions refined together,
-- the exchanges, and the refinement again when an exchange was kept.
optimiseKnots :: KnotConfig -> Prepared -> Knots -> Knots
optimiseKnots cfg pr kn0 = if kn2 == kn1 then kn1 else fst (refineAll pr (kcIterations cfg) kn2)
  where
    kn1 = fst (refineAll pr (kcIterations cfg) kn0)
    kn2 = exchangeKnots pr (kcIterations cfg) (kcExchanges cfg) kn1

-- | The wider search ('kcSearch' rounds; none by default): the first round starts from the
-- continuous dynamic program ('continuousStart', waypoint j within the line partition's
-- boundaries j−2 .. j+2, one function per state), later odd rounds afresh from k−2 interior
-- times drawn uniformly over the recording, even rounds from the best path so far with two
-- interior waypoints (drawn at random) removed and two inserted at the middle of segments
-- drawn from those with the largest error; each start is optimised as the fit's own
-- ('optimiseKnots') and kept when its position error is lower. The draws are a fixed
-- pseudo-random sequence, so a run is repeatable. Never worse than the knots given.
searchKnots :: KnotConfig -> Prepared -> Knots -> Knots
searchKnots cfg pr kn0
  | kcSearch cfg <= 0 || k < 4 = kn0
  | otherwise = go 1 (splitmix 0x5eed) kn0 (knotSse pr kn0)
  where
    k = U.length (kT kn0)
    st = rcT pr
    tA = U.head st; tB = U.last st
    go r g best fBest
      | r > kcSearch cfg = best
      | otherwise =
          let (start, g') | r == 1 = (continuousStart cfg 2 1 pr k, g)
                          | odd r = randomStart g
                          | otherwise = perturbed g best
              cand = optimiseKnots cfg pr start
              f = knotSse pr cand
          in if U.length (kT cand) == k && f < fBest && spaced cand then go (r + 1) g' cand f else go (r + 1) g' best fBest
    -- every waypoint at least 'rcMinGap' after the one before (a round's start that is not,
    -- a perturbation's or the dynamic program's on an irregular recording, cannot win)
    spaced kn = let ts = kT kn in U.and (U.zipWith (\a b -> b - a >= rcMinGap pr * (1 - 1e-9)) ts (U.tail ts))
    -- k−2 uniform interior times 'rcMinGap' apart and from the ends (a draw too close to
    -- another is drawn again; after 100 draws a waypoint, the line partition's start)
    randomStart g0 = draw g0 (100 * k :: Int) []
      where
        gap = rcMinGap pr
        draw g budget acc
          | length acc == k - 2 = (atTimes (U.fromList ([tA] ++ sort acc ++ [tB])), g)
          | budget <= 0 = (startKnots cfg pr k, g)
          | otherwise = let (u, g') = unit g
                            t = tA + u * (tB - tA)
                        in if t - tA >= gap && tB - t >= gap && all (\a -> abs (t - a) >= gap) acc
                             then draw g' (budget - 1) (t : acc) else draw g' (budget - 1) acc
    perturbed g0 kn =
      let ts = kT kn
          (d1, g1) = below (k - 2) g0
          (d2, g2) = below (k - 2) g1
          drops = nub [1 + d1, 1 + d2]
          worst = map snd (sortBy (comparing fst) [ (negate (stretchSse pr kn s (s + 1)), s) | s <- [0 .. k - 2] ])
          pool = take (min (k - 1) 9) worst
          (e1, g3) = below (length pool) g2
          (e2, g4) = below (length pool) g3
          ins = [ 0.5 * (ts U.! s + ts U.! (s + 1)) | s <- nub [pool !! e1, pool !! e2] ]
          kept = [ ts U.! j | j <- [0 .. k - 1], j `notElem` drops ]
          times = U.fromList (nub (sort (kept ++ take (length drops) (ins ++ filler kept))))
          filler kp = [ 0.5 * (a + b) | (a, b) <- zip kp (drop 1 kp) ]
      in if U.length times == k then (atTimes times, g4) else randomStart g4
    atTimes ts = Knots ts (pgenerate (U.length ts) (\j -> fst (polylineAt st (rcP pr) (rcQ pr) (ts U.! j))))

-- | SplitMix64 (Steele, Lea and Flood 2014): the state's step ...
splitmix :: Word64 -> Word64
splitmix x = x + 0x9e3779b97f4a7c15

-- | ... and the output drawn from a state.
mix :: Word64 -> Word64
mix z0 = let z1 = (z0 `xor` (z0 `shiftR` 30)) * 0xbf58476d1ce4e5b9
             z2 = (z1 `xor` (z1 `shiftR` 27)) * 0x94d049bb133111eb
         in z2 `xor` (z2 `shiftR` 31)

-- | A uniform draw in [0, 1).
unit :: Word64 -> (Double, Word64)
unit g = (fromIntegral (mix g `shiftR` 11) / 9007199254740992, splitmix g)

-- | A uniform draw in [0, m).
below :: Int -> Word64 -> (Int, Word64)
below m g = let (u, g') = unit g in (min (m - 1) (floor (u * fromIntegral m)), g')

-- | The whole knot fit to k points (2 <= k <= samples).
fitKnots :: KnotConfig -> Prepared -> Weights -> Int -> PathA
fitKnots cfg pr w k0
  | k >= n = PathA (rcT pr) (rcP pr) (rcQ pr)
  | otherwise = finishKnots cfg pr w (searchKnots cfg pr (optimiseKnots cfg pr (startKnots cfg pr k)))
  where
    n = U.length (rcT pr)
    k = max 2 k0

-- | Steps 4 to 6 of the fit: the values at the knots' times under the full weights
-- (orientations by Gauss–Newton, positions by least squares, then the thesis's update
-- rounds), the times re-balanced towards the orientation ('balanceOrientation'), then the
-- worst-error polish of the positions ('polishWorst').
finishKnots :: KnotConfig -> Prepared -> Weights -> Knots -> PathA
finishKnots cfg pr w (Knots ts ps) =
  polishWorst (kcWorstBudget cfg) pr w
    (balanceOrientation (kcOrientBudget cfg) pr w (polish (orient (solvePositions pr w (PathA ts ps qs0)))))
  where
    st = rcT pr
    k = U.length ts
    qs0 = pgenerate k (\j -> snd (polylineAt st (rcP pr) (rcQ pr) (ts U.! j)))
    oriW = Weights 0 1 0
    polish pa = if kcPolish cfg > 0 then updatePathWith pr w TimesAll (kcPolish cfg) pa else pa
    orient pa = rounds (kcOrientRounds cfg) pa (totalCost pr oriW pa)
    rounds 0 pa _ = pa
    rounds r pa c =
      let pa' = solveOrientations pr w pa
          c' = totalCost pr oriW pa'
      in if c' < c * (1 - 1e-5) then rounds (r - 1 :: Int) pa' c' else if c' < c then pa' else pa
