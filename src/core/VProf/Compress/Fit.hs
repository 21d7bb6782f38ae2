{-# LANGUAGE FlexibleContexts #-}
{-# OPTIONS_GHC -fno-spec-constr #-}
-- (-fno-spec-constr: GHC 9.0.2 panics in SpecConstr on the shrink loop, "Template variable unbound in rewrite rule")
{-# LANGUAGE BangPatterns #-}
{-# LANGUAGE ScopedTypeVariables #-}
-- | The thesis's compression algorithm (section 4, appendix A: @initP2@, @updateP@,
-- @increaseP@, @decreaseP@, @Algoritme5@), pure, with exact least-squares updates:
--
-- * start: split the samples into consecutive groups in time (about 10 % of the samples
--   become waypoints), first and last waypoint pinned to the first and last sample;
-- * update ('updatePath'): with the waypoint times fixed, all positions at once by linear
--   least squares (band normal equations, "VProf.Numeric.BandedLeastSquares"), orientations by
--   Gauss–Newton steps in the tangent space (same band structure), then each waypoint's
--   time by golden-section search between its neighbours; repeated until the improvement
--   stops (at most 40 rounds);
-- * grow by 50 % (insert where it lowers the error most), then shrink 5 % at a time
--   (remove where it raises the error least, then update) until the requested number of
--   points, or the error passes margin × the grown path's error, or the largest position
--   error would pass the tolerance;
-- * beyond the thesis, exchanges at the final count ('swapPass': move a waypoint from
--   where it is least useful to where one is most needed, kept only if the objective
--   falls), then update rounds to convergence. The greedy shrink decides once which
--   waypoints survive; the exchanges undo its worst decisions (8 % of the objective on
--   EuRoC V1_01). Still a heuristic: fits at neighbouring weights can end in local
--   optima about 2 % apart (see the weight tests in "VProf.Compress.RealDataSpec").
module VProf.Compress.Fit
  ( FitConfig (..)
  , defaultFitConfig
  , StopReason (..)
  , FitResult (..)
  , fitThesis
  , initialPath
  , updatePath
  , growPath
  , shrinkStep
  , solvePositions
  , solvePositionsWeighted
  , solveOrientations
  , updateTimes
  , TimeMode (..)
  , updatePathWith
  , shrinkStepN
  , swapPass
  , insertionGains
  , removalCosts
  , maxPositionError
  ) where

import Control.Monad (forM_, when)
import Control.Monad.ST (runST)
import Data.List (sortBy)
import Data.Ord (comparing)
import qualified Data.IntSet as IS
import qualified Data.Vector.Unboxed as U


import VProf.Numeric.BandedLeastSquares
import VProf.Geometry.Polyline
import VProf.Geometry.Quaternion
import VProf.Compress.Objective
import VProf.Compress.Types
import VProf.Geometry.Vec

data FitConfig = FitConfig
  { fcWeights      :: !Weights
  , fcPoints       :: !(Maybe Int)     -- ^ waypoints wanted
  , fcMargin       :: !(Maybe Double)  -- ^ stop when E > margin × E(grown path)
  , fcTolerance    :: !(Maybe Double)  -- ^ m, largest time-synchronous position error
  , fcMaxRounds    :: !Int             -- ^ update rounds after start and growth (thesis: 40)
  , fcShrinkRounds :: !Int             -- ^ update rounds after each removal step
  , fcInitFraction :: !Double          -- ^ waypoints of the first draft / samples (thesis: 0.10)
  , fcSwapTries    :: !Int             -- ^ exchanges tried before a pass gives up ('swapPass')
  , fcSwapBudget   :: !Int             -- ^ exchanges tried in all
  } deriving (Show, Eq)

defaultFitConfig :: FitConfig
defaultFitConfig = FitConfig defaultWeights Nothing Nothing Nothing 40 1 0.10 4 10

-- | Why the fit stopped. 'FewerSuffice': fewer points than asked, because no further
-- waypoint lowered the error (a recording that a few straight moves fit exactly).
data StopReason = ReachedPoints | ReachedMargin | ReachedTolerance | ReachedMinimum | FewerSuffice
  deriving (Show, Eq)

data FitResult = FitResult
  { frPath        :: !PathA
  , frCost        :: !Double     -- ^ weighted objective of the result
  , frGrownCost   :: !Double     -- ^ weighted objective of the grown path
  , frGrownPoints :: !Int
  , frStop        :: !StopReason
  , frToleranceMet :: !Bool
  , frHistory     :: ![(Int, Double)]  -- ^ (points, objective) after each shrink step
  } deriving (Show)

----------------------------------------------------------------------------- start

-- | K waypoints at the sample times that split the recording into K−1 equal groups.
initialPath :: Prepared -> Int -> PathA
initialPath pr k0 = PathA (pbackpermute (rcT pr) idx) (pbackpermute (rcP pr) idx) (pbackpermute (rcQ pr) idx)
  where
    n = U.length (rcT pr)
    k = max 2 (min n k0)
    idx = U.generate k (\j -> round (fromIntegral j * fromIntegral (n - 1) / fromIntegral (k - 1) :: Double))

----------------------------------------------------------------------------- update

-- | Rounds of (positions, orientations, times) until the objective stops improving.
updatePath :: Prepared -> Weights -> Int -> PathA -> PathA
updatePath pr w = updatePathWith pr w TimesAll

-- | Which waypoint times an update round moves.
data TimeMode = TimesAll | TimesNone | TimesOf IS.IntSet

-- | 'updatePath' with a choice of which waypoint times move; stops when a round lowers
-- the objective by less than 0.3 %.
updatePathWith :: Prepared -> Weights -> TimeMode -> Int -> PathA -> PathA
updatePathWith pr w mode = updatePathUntil pr w mode 3e-3

-- | 'updatePathWith' stopping when a round lowers the objective by less than the
-- fraction @stopBelow@ of it (or after @maxRounds@ rounds).
updatePathUntil :: Prepared -> Weights -> TimeMode -> Double -> Int -> PathA -> PathA
updatePathUntil pr w mode stopBelow maxRounds pa0
  | maxRounds <= 0 = pa0
  -- a round never raises the error (the position solve is exact, the orientation step and
  -- every waypoint move are kept only when they lower it), so one round needs no check
  | maxRounds == 1 = step (0 :: Int) pa0
  | otherwise = go 0 pa0 (totalCost pr w pa0)
  where
    -- after a removal only the touched waypoints' orientations move (in their joint update)
    step r pa = case mode of
      TimesOf _ -> times r (solvePositions pr w pa)
      _ -> times r (solveOrientations pr w (solvePositions pr w pa))
    -- round r searches each time within (1/3)/2^r of the way to its neighbours
    frac r = max (1 / 60) ((1 / 3) / 2 ^ r)
    times r pa = case mode of
      TimesAll -> updateTimes pr w (frac r) (const True) pa
      TimesNone -> pa
      TimesOf set -> updateTimes pr w (frac r) (`IS.member` set) pa
    go r pa c
      | r >= maxRounds = pa
      | otherwise =
          let pa1 = step r pa
              c1 = totalCost pr w pa1
          in if c1 >= c then pa
             else if c - c1 <= stopBelow * c then pa1
             else go (r + 1) pa1 c1

-- | With waypoint times fixed, the positions of all waypoints minimising
-- wp Σ|p_i − p̂(t_i)|² + wv Σ|v_i − v̂_i|², endpoints pinned unless 'rcEnds' frees them.
-- Exact linear least squares.
solvePositions :: Prepared -> Weights -> PathA -> PathA
solvePositions pr w = solvePositionsWeighted pr w (U.replicate (U.length (rcT pr)) 1)

-- | 'solvePositions' with sample i's position term weighted by @sw ! i@ as well (>= 0;
-- "VProf.Compress.WorstPolish" weighs up the samples far from the path).
solvePositionsWeighted :: Prepared -> Weights -> U.Vector Double -> PathA -> PathA
solvePositionsWeighted pr (Weights wp _ wv) sw pa@(PathA ts ps qs)
  | wp == 0 && wv == 0 = pa
  | otherwise = case sol of
      Right ps' -> PathA ts ps' qs
      Left _ -> pa
  where
    st = rcT pr
    n = U.length st
    k = U.length ts
    seg = segmentIndices ts st
    alpha i = let j = seg U.! i
                  t0 = ts U.! j; t1 = ts U.! (j + 1)
              in max 0 (min 1 ((st U.! i - t0) / (t1 - t0)))
    band | wv == 0 = 1
         | otherwise = max 1 (U.maximum (U.generate (n - 1) (\i -> seg U.! (i + 1) + 1 - seg U.! i)))
    lam = 1e-9 * (wp + wv) * fromIntegral n / fromIntegral k
    sol = runST $ do
      bs <- newBand k band
      forM_ [0 .. n - 1] $ \i -> do
        let a = alpha i
        addObs2 bs (wp * sw U.! i) (seg U.! i) (1 - a) a (pindex (rcP pr) i)
      when (wv > 0) $ forM_ [0 .. n - 2] $ \i -> do
        let d = rcDt pr U.! i
            j0 = seg U.! i; a0 = alpha i
            j1 = seg U.! (i + 1); a1 = alpha (i + 1)
        addObs bs wv [(j1, (1 - a1) / d), (j1 + 1, a1 / d), (j0, negate (1 - a0) / d), (j0 + 1, negate a0 / d)]
               (pindex (rcV pr) i)
      forM_ [0 .. k - 1] $ \j -> addObs bs lam [(j, 1)] (pindex ps j)
      when (rcEnds pr == EndsPinned) $ do
        pinValue bs 0 (phead (rcP pr))
        pinValue bs (k - 1) (plast (rcP pr))
      solveBand bs

-- | Gauss–Newton steps for the orientations: the error of sample i is the rotation vector
-- e_i = log(q_i q̂_iᶜ); a correction δ_j at each waypoint moves q̂(t_i) by about
-- (1−a)δ_j + aδ_{j+1}; the δ minimising Σ|e_i − δ(t_i)|² is a band least-squares problem.
-- A step is kept only if it lowers the orientation error (halved up to twice otherwise).
-- With orientation weight 0 the waypoints take the recording's orientation at their time.
solveOrientations :: Prepared -> Weights -> PathA -> PathA
solveOrientations pr (Weights _ wo _) pa@(PathA ts ps qs)
  | wo == 0 = PathA ts ps (pgenerate (U.length ts) (\j -> snd (polylineAt (rcT pr) (rcP pr) (rcQ pr) (ts U.! j))))
  | otherwise = iter (1 :: Int) pa
  where
    st = rcT pr
    n = U.length st
    k = U.length ts
    oriCost x = rangeCost pr (Weights 0 1 0) (pathInterp x) 0 (n - 1)
    iter 0 x = x
    iter m x@(PathA _ _ q0) =
      let c0 = oriCost x
          seg = segmentIndices ts st
          alpha i = let j = seg U.! i
                        t0 = ts U.! j; t1 = ts U.! (j + 1)
                    in max 0 (min 1 ((st U.! i - t0) / (t1 - t0)))
          tbl = mkSegTable ts ps q0
          deltas = runST $ do
            bs <- newBand k 1
            forM_ [0 .. n - 1] $ \i -> do
              let j = seg U.! i
                  a = alpha i
                  qh = snd (tableAt tbl j (pindex (rcT pr) i))
                  e = qlog (qmul (pindex (rcQ pr) i) (qconj qh))
              addObs2 bs 1 j (1 - a) a e
            forM_ [0 .. k - 1] $ \j -> addObs bs (1e-9 * fromIntegral n / fromIntegral k) [(j, 1)] (P3 0 0 0)
            when (rcEnds pr == EndsPinned) $ do
              pinValue bs 0 (P3 0 0 0)
              pinValue bs (k - 1) (P3 0 0 0)
            solveBand bs
          apply s ds = PathA ts ps (pgenerate k (\j -> normQ (qmul (qexp (s *^ pindex ds j)) (pindex q0 j))))
          tryStep ds = case [x' | s <- [1, 0.5, 0.25], let x' = apply s ds, oriCost x' < c0] of
            (x' : _) -> Just x'
            [] -> Nothing
      in case deltas of
           Left _ -> x
           Right ds -> case tryStep ds of
             Just x' -> iter (m - 1) (pinQ x')
             Nothing -> x
    pinQ x'@(PathA t p q)
      | rcEnds pr == EndsFree = x'
      | otherwise = PathA t p (pupdate q [(0, phead (rcQ pr)), (k - 1, plast (rcQ pr))])
    _unused = qs

normQ :: Q4 -> Q4
normQ = qnormalize

-- | One Gauss–Seidel sweep over the interior waypoints: each time moves, by golden-section
-- search between its neighbours, to where the error of the samples of its two segments is
-- least (position and orientation of the waypoint held).
updateTimes :: Prepared -> Weights -> Double -> (Int -> Bool) -> PathA -> PathA
updateTimes pr w frac which pa0@(PathA ts0 _ _)
  | k <= 2 = pa0
  | otherwise = sweep 1 pa0
  where
    k = U.length ts0
    sweep j pa@(PathA ts ps qs)
      | j >= k - 1 = pa
      | not (which j) = sweep (j + 1) pa
      | otherwise =
          let lo = ts U.! (j - 1); hi = ts U.! (j + 1); cur = ts U.! j
              (i0, i1) = samplesIn pr lo hi
              pA = pindex ps (j - 1); pC = pindex ps (j + 1)
              qA = pindex qs (j - 1); qC = pindex qs (j + 1)
              costAt tau pj qj = twoSegmentCost pr w (polylineAt ts ps qs) lo tau hi pA pj pC qA qj qC i0 i1
              -- best position and orientation of waypoint j for a time tau
              fitAt tau = fitMiddle pr w lo tau hi pA (pindex ps j) pC qA (pindex qs j) qC i0 i1
              f tau = let (pj, qj) = fitAt tau in costAt tau pj qj
              -- never closer to a neighbour than 'rcMinGap' (half a sample step) unless it
              -- already is, nor within a thousandth of the two segments
              gapLo = max (1e-3 * (hi - lo)) (min (rcMinGap pr) (cur - lo))
              gapHi = max (1e-3 * (hi - lo)) (min (rcMinGap pr) (hi - cur))
              -- search near the current time: a third of the way to each neighbour
              best = golden f (max (lo + gapLo) (cur - (cur - lo) * frac)) (min (hi - gapHi) (cur + (hi - cur) * frac)) 8
              (pb, qb) = fitAt best
              cNew = costAt best pb qb
              cOld = costAt cur (pindex ps j) (pindex qs j)
              pa' = if cNew < cOld
                      then PathA (ts U.// [(j, best)]) (pupdate ps [(j, pb)]) (pupdate qs [(j, qb)])
                      else pa
          in sweep (j + 1) pa'

-- | The thesis's @fitMiddle@: with the neighbours fixed and waypoint j at time tau, the
-- position minimising the position error of the samples i0..i1 (closed-form weighted
-- least squares in one 3-vector) and one Gauss–Newton step for its orientation.
fitMiddle :: Prepared -> Weights -> Double -> Double -> Double -> P3 -> P3 -> P3 -> Q4 -> Q4 -> Q4
          -> Int -> Int -> (P3, Q4)
fitMiddle pr (Weights wp wo _) ta tb tc pA pB pC qA qB qC i0 i1 = go i0 (P3 0 0 0) 0 (P3 0 0 0) 0
  where
    s1 = mkSeg ta tb pA pB qA qB
    s2 = mkSeg tb tc pB pC qB qC
    go !i !accP !accC !accQ !accCq
      | i > i1 =
          let pB' = if wp > 0 && accC > 1e-12 then accP ^/ accC else pB
              qB' = if wo > 0 && accCq > 1e-12 then qnormalize (qmul (qexp (accQ ^/ accCq)) qB) else qB
          in (pB', qB')
      | otherwise =
          let t = U.unsafeIndex (rcT pr) i
              pi' = pindex (rcP pr) i
              !first = t <= tb
              !c = if first then max 0 (min 1 ((t - ta) / (tb - ta)))
                           else 1 - max 0 (min 1 ((t - tb) / (tc - tb)))
              !base = if first then (1 - c) *^ pA else (1 - c) *^ pC
              !e | wo <= 0 = P3 0 0 0
                | first = qlog (qmul (pindex (rcQ pr) i) (qconj (snd (segPose s1 t))))
                | otherwise = qlog (qmul (pindex (rcQ pr) i) (qconj (snd (segPose s2 t))))
          in go (i + 1) (accP ^+^ c *^ (pi' ^-^ base)) (accC + c * c) (accQ ^+^ c *^ e) (accCq + c * c)

golden :: (Double -> Double) -> Double -> Double -> Int -> Double
golden f a0 b0 iters = loop a0 b0 (1 / 0) (1 / 0) x1 x2 (f x1) (f x2) iters
  where
    r = (sqrt 5 - 1) / 2
    x1 = b0 - r * (b0 - a0)
    x2 = a0 + r * (b0 - a0)
    loop a b fa fb c d fc fd m
      | m <= 0 = finish a b fa fb c d fc fd
      | fc < fd = let b' = d; d' = c; c' = b' - r * (b' - a) in loop a b' fa fd c' d' (f c') fc (m - 1)
      | otherwise = let a' = c; c' = d; d' = a' + r * (b - a') in loop a' b fc fb c' d' fd (f d') (m - 1)
    -- one parabolic step through the best point and its neighbours, kept if it is better
    finish a b fa fb c d fc fd =
      let (xb, fbest) = if fc < fd then (c, fc) else (d, fd)
          pts = if fc < fd then (a, fa, c, fc, d, fd) else (c, fc, d, fd, b, fb)
          (u, fu, v, fv, w, fw) = pts
          num = (v - u) ^ (2 :: Int) * (fv - fw) - (v - w) ^ (2 :: Int) * (fv - fu)
          den = (v - u) * (fv - fw) - (v - w) * (fv - fu)
          xp = v - 0.5 * num / den
      in if isInfinite fu || isInfinite fw || den == 0 || isNaN xp || xp <= a || xp >= b
           then xb
           else let fp = f xp in if fp < fbest then xp else xb

----------------------------------------------------------------------------- grow / shrink

-- | Insert up to m waypoints, each in a different segment, at the interior sample whose
-- error is largest, choosing the segments where the insertion lowers the error most.
growPath :: Prepared -> Weights -> Int -> PathA -> PathA
growPath pr w m pa
  | m <= 0 = pa
  | otherwise = insertSamples pr [ i | (_, _, i) <- take m (sortBy (comparing (\(g, _, _) -> negate g)) gains) ] pa
  where gains = [ c | c@(g, _, _) <- insertionGains pr w pa, g > 0 ]

-- | For every segment with a sample strictly inside: (how much inserting a waypoint at
-- its sample of largest pose error lowers the error, segment, sample index). The new
-- waypoint takes the sample's pose; nothing else moves.
insertionGains :: Prepared -> Weights -> PathA -> [(Double, Int, Int)]
insertionGains pr w pa@(PathA ts ps qs) = [ (g, j, i) | j <- [0 .. k - 2], Just (g, i) <- [candidate j] ]
  where
    tbl = mkSegTable ts ps qs
    sums = rangeSums pr w pa
    k = U.length ts
    candidate j =
      let t0 = ts U.! j; t1 = ts U.! (j + 1)
          (i0, i1) = samplesIn pr t0 t1
          inner = [ i | i <- [i0 .. i1], rcT pr U.! i > t0, rcT pr U.! i < t1 ]
          errAt i = let (ph, qh) = interpolateAt ts ps qs j (rcT pr U.! i)
                        a = qangle (pindex (rcQ pr) i) qh
                    in wPosition w * quadrance (pindex (rcP pr) i ^-^ ph) + wOrientation w * a * a
      in case inner of
           [] -> Nothing
           _ -> let i = snd (maximum [ (errAt x, x) | x <- inner ])
                    before = rangeCostFrom pr sums i0 i1
                    ti = rcT pr U.! i
                    f t | t < ti = lin t0 ti (pindex ps j) (pindex (rcP pr) i) (pindex qs j) (pindex (rcQ pr) i) t
                        | otherwise = lin ti t1 (pindex (rcP pr) i) (pindex ps (j + 1)) (pindex (rcQ pr) i) (pindex qs (j + 1)) t
                    g t | t < t0 || t > t1 = tableInterp tbl t
                        | otherwise = f t
                    after = rangeCost pr w g i0 i1
                in Just (before - after, i)
    lin ta tb pa' pb qa qb t =
      let s = max 0 (min 1 ((t - ta) / (tb - ta)))
      in (pa' ^+^ s *^ (pb ^-^ pa'), slerpShort qa qb s)

-- | Waypoints added at the given samples (time, position and orientation of the sample).
insertSamples :: Prepared -> [Int] -> PathA -> PathA
insertSamples pr idx (PathA ts ps qs) =
  PathA (U.fromList (map fst3 merged)) (pfromList (map snd3 merged)) (pfromList (map thd3 merged))
  where
    newPts = [ (rcT pr U.! i, pindex (rcP pr) i, pindex (rcQ pr) i) | i <- idx ]
    old = zip3 (U.toList ts) (ptoList ps) (ptoList qs)
    merged = mergeOn fst3 old (sortBy (comparing fst3) newPts)
    fst3 (a, _, _) = a
    snd3 (_, b, _) = b
    thd3 (_, _, c) = c

mergeOn :: Ord b => (a -> b) -> [a] -> [a] -> [a]
mergeOn _ [] ys = ys
mergeOn _ xs [] = xs
mergeOn f (x : xs) (y : ys)
  | f x <= f y = x : mergeOn f xs (y : ys)
  | otherwise = y : mergeOn f (x : xs) ys

-- | For every interior waypoint j: (how much removing it raises the error, j), its
-- neighbours joined by one segment and nothing else moved.
removalCosts :: Prepared -> Weights -> PathA -> [(Double, Int)]
removalCosts pr w pa@(PathA ts ps qs) = [ (cost j, j) | j <- [1 .. k - 2] ]
  where
    tbl = mkSegTable ts ps qs
    sums = rangeSums pr w pa
    k = U.length ts
    cost j =
      let t0 = ts U.! (j - 1); t1 = ts U.! (j + 1)
          (i0, i1) = samplesIn pr t0 t1
          before = rangeCostFrom pr sums i0 i1
          sg = mkSeg t0 t1 (pindex ps (j - 1)) (pindex ps (j + 1)) (pindex qs (j - 1)) (pindex qs (j + 1))
          g t | t < t0 || t > t1 = tableInterp tbl t
              | otherwise = segPose sg t
          {-# INLINE g #-}
      in rangeCost pr w g i0 i1 - before

-- | The path without the waypoints of the set.
removeWaypoints :: IS.IntSet -> PathA -> PathA
removeWaypoints removed (PathA ts ps qs) = PathA (keep ts) (keep ps) (keep qs)
  where
    keep :: Packed v e => v -> v
    keep = pifilter (\j -> not (IS.member j removed))

-- | Remove up to m interior waypoints (no two neighbours), those whose removal raises the
-- error least.
shrinkStep :: Prepared -> Weights -> Int -> PathA -> PathA
shrinkStep pr w m pa = fst (shrinkStepN pr w m pa)

-- | 'shrinkStep', also giving the new indices of the neighbours of removed waypoints.
shrinkStepN :: Prepared -> Weights -> Int -> PathA -> (PathA, IS.IntSet)
shrinkStepN pr w m pa@(PathA ts _ _)
  | k <= 2 || m <= 0 = (pa, IS.empty)
  | otherwise = (removeWaypoints removed pa, touched)
  where
    newIndex j = j - IS.size (fst (IS.split j removed))
    touched = IS.fromList [ newIndex x | r <- IS.toList removed, x <- [r - 1, r + 1]
                                       , x > 0, x < k - 1, not (IS.member x removed) ]
    k = U.length ts
    ranked = map snd (sortBy (comparing fst) (removalCosts pr w pa))
    pick !s _ [] = s
    pick !s !c (j : js)
      | c >= m = s
      | IS.member (j - 1) s || IS.member (j + 1) s = pick s c js
      | otherwise = pick (IS.insert j s) (c + 1) js
    removed = pick IS.empty (0 :: Int) ranked

-- | Exchange moves at a fixed number of points: remove a waypoint whose removal costs
-- little and insert one where an insertion gains much (in a segment not next to it),
-- re-fit the waypoints around both places ('updatePathWith' on the two waypoints either
-- side of each place, two rounds), and keep the exchange only if the whole objective
-- falls. The estimates (nothing re-fitted) only rank the pairs of the cheapest five
-- removals and the best five insertions: a removal's estimate is far too high, because
-- the neighbours would move into the gap. Up to @perPass@ pairs are tried, most promising
-- first; after a kept exchange the candidates are computed anew; at most @maxTries@
-- exchanges are tried in all.
swapPass :: Prepared -> Weights -> Int -> Int -> PathA -> PathA
swapPass pr w perPass maxTries pa0 = go maxTries pa0 (totalCost pr w pa0)
  where
    go tries pa c
      | tries <= 0 || U.length (paT pa) <= 3 = pa
      | otherwise =
          let rems = take 5 (sortBy (comparing fst) (removalCosts pr w pa))
              ins = take 5 (sortBy (comparing (\(g, _, _) -> negate g)) (insertionGains pr w pa))
              pairs = take perPass (sortBy (comparing fst)
                        [ (r - g, (j, i)) | (r, j) <- rems, (g, s, i) <- ins, s /= j - 1, s /= j ])
              attempt t [] = (Nothing, t)
              attempt (t :: Int) ((_, (j, i)) : rest)
                | t <= 0 = (Nothing, t)
                | otherwise =
                    let pa' = exchange pa j i
                        c' = totalCost pr w pa'
                    in if c' < c then (Just (pa', c'), t - 1) else attempt (t - 1) rest
          in case attempt tries pairs of
               (Nothing, _) -> pa
               (Just (pa', c'), left) -> go left pa' c'
    exchange pa@(PathA ts _ _) j i =
      let ti = rcT pr U.! i
          near = [ts U.! (j - 1), ts U.! (j + 1), ti]
          moved = insertSamples pr [i] (removeWaypoints (IS.singleton j) pa)
          ts' = paT moved
          k' = U.length ts'
          at t = maybe [] (: []) (U.findIndex (== t) ts')
          touched = IS.fromList [ x | t <- near, y <- at t, x <- [y - 2 .. y + 2], x > 0, x < k' - 1 ]
      in updatePathWith pr w (TimesOf touched) 2 moved

----------------------------------------------------------------------------- driver

-- | After the shrink: exchanges ('swapPass'), then full update rounds (all times move)
-- until a round gains less than 1e-6 of the objective. Each round costs O(samples), so
-- the rounds are capped at 10,000 / samples (at least 3, at most 'fcMaxRounds'): short
-- recordings are polished to convergence, 3,000 samples get 3 rounds (the speed target).
finalPolish :: FitConfig -> Prepared -> PathA -> PathA
finalPolish cfg pr = updatePathUntil pr w TimesAll 1e-6 rounds . swapPass pr w (fcSwapTries cfg) (fcSwapBudget cfg)
  where
    w = fcWeights cfg
    rounds = min (fcMaxRounds cfg) (max 3 (10000 `div` U.length (rcT pr)))

maxPositionError :: Prepared -> PathA -> Double
maxPositionError pr pa = let (ep, _, _) = pointErrors pr pa in U.maximum ep

-- | The whole algorithm. The number of points defaults to about 3 % of the samples when
-- neither a margin nor a tolerance is given.
fitThesis :: FitConfig -> Prepared -> FitResult
fitThesis cfg pr
  | target >= n = let pa = PathA (rcT pr) (rcP pr) (rcQ pr); c = totalCost pr w pa
                  in FitResult pa c c n ReachedPoints (tolOk pa) [(n, c)]
  | otherwise = shrinkLoop grown cg [(U.length (paT grown), cg)] False
  where
    w = fcWeights cfg
    n = U.length (rcT pr)
    target = case (fcPoints cfg, fcMargin cfg, fcTolerance cfg) of
      (Just p, _, _) -> max 2 p
      (Nothing, Nothing, Nothing) -> max 2 (round (0.03 * fromIntegral n :: Double))
      _ -> 2
    k0 = min n (max (max 2 (round (fcInitFraction cfg * fromIntegral n)))
                    (ceiling (fromIntegral target / 1.5 :: Double)))
    start = updatePathWith pr w TimesNone (fcMaxRounds cfg) (initialPath pr k0)
    mGrow = min (n - k0) (max 1 (round (0.5 * fromIntegral k0 :: Double)))
    grown = updatePathWith pr w TimesAll 1 (updatePathWith pr w TimesNone (fcMaxRounds cfg) (growPath pr w mGrow start))
    cg = totalCost pr w grown
    tolOk pa = maybe True (\tol -> maxPositionError pr pa <= tol) (fcTolerance cfg)
    grownTolOk = tolOk grown
    -- final polish: full update rounds (all times move); kept unless it breaks the tolerance
    result pa0 _ why hist =
      let pol = finalPolish cfg pr pa0
          pa = if tolOk pol || not (tolOk pa0) then pol else pa0
          why' = if maybe False (> U.length (paT pa)) (fcPoints cfg) then FewerSuffice else why
      in FitResult pa (totalCost pr w pa) cg (U.length (paT grown)) why' (tolOk pa) (reverse hist)
    shrinkLoop pa c hist single
      | kk <= target = result pa c (if target > 2 || fcPoints cfg /= Nothing then ReachedPoints else ReachedMinimum) hist
      | not grownTolOk = result pa c ReachedTolerance hist
      | otherwise =
          let m0 = if single then 1 else max 1 (round (0.05 * fromIntegral kk :: Double))
              m = min m0 (kk - target)
              (removedPa, touched) = shrinkStepN pr w m pa
              pa' = updatePathWith pr w (TimesOf touched) (fcShrinkRounds cfg) removedPa
              c' = totalCost pr w pa'
              marginBad = maybe False (\mg -> c' > mg * cg) (fcMargin cfg)
              tolBad = not (tolOk pa')
              kk' = U.length (paT pa')
          in if kk' == kk then result pa c ReachedMinimum hist
             else if marginBad || tolBad
               then if m > 1 then shrinkLoop pa c hist True
                    else result pa c (if marginBad then ReachedMargin else ReachedTolerance) hist
             else shrinkLoop pa' c' ((kk', c') : hist) single
      where kk = U.length (paT pa)
