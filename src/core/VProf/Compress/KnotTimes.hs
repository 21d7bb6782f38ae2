{-# LANGUAGE BangPatterns #-}
-- | Waypoint times and positions optimised together (docs/compress.md, "Knot times"):
-- Levenberg–Marquardt on the position error Σ|p_i − p̂(t_i)|² over the times and positions
-- of the waypoints ja+1 .. jb−1 of a stretch (waypoints ja and jb and everything outside
-- held), each accepted step followed by the exact least-squares positions for the new times
-- (variable projection: the error is then a function of the times alone, and a step is
-- kept only when that falls). The error is piecewise smooth in the times (a sample changes
-- segment when a time passes it), so the Gauss–Newton model holds between such crossings
-- and the damping takes care of the rest. A waypoint and its neighbour share one 8-unknown
-- block, so each step is one band solve ("VProf.Numeric.BandSolve"), O(samples + waypoints).
module VProf.Compress.KnotTimes
  ( Knots (..)
  , knotSse
  , stretchSse
  , sampleErrors
  , worstSample
  , solveStretchPositions
  , solveSlicePositions
  , refineStretch
  , refineAll
  ) where

import Control.Monad (forM_, when)
import Control.Monad.ST (runST)
import qualified Data.Vector.Unboxed as U
import qualified Data.Vector.Unboxed.Mutable as MU

import VProf.Compress.Objective (Prepared (..), samplesIn)
import VProf.Compress.Types (Ends (..))
import VProf.Geometry.Vec
import VProf.Numeric.BandSolve (solveBandSPD)
import VProf.Numeric.BandedLeastSquares

-- | Waypoint times (strictly increasing) and positions.
data Knots = Knots { kT :: !(U.Vector Double), kP :: !V3s } deriving (Show, Eq)

-- | Position SSE of the samples with T_ja <= t <= T_jb.
stretchSse :: Prepared -> Knots -> Int -> Int -> Double
stretchSse pr kn ja jb = stretchFold (\s _ e2 -> s + e2) 0 pr kn ja jb

-- | Each sample's position error (m) against the whole path, in the samples' order: all of
-- them when the path's first and last times are the first and last sample's.
sampleErrors :: Prepared -> Knots -> U.Vector Double
sampleErrors pr kn = U.fromList (reverse (stretchFold (\acc _ e2 -> sqrt e2 : acc) [] pr kn 0 (U.length (kT kn) - 1)))

-- | The sample of the largest position error (its index, the error in m).
worstSample :: Prepared -> Knots -> (Int, Double)
worstSample pr kn = fmap sqrt (stretchFold (\acc@(_, w) i e2 -> if e2 > w then (i, e2) else acc) (0, -1)
                                           pr kn 0 (U.length (kT kn) - 1))

-- | A strict left fold over the samples with T_ja <= t <= T_jb of (sample index, squared
-- position error).
stretchFold :: (a -> Int -> Double -> a) -> a -> Prepared -> Knots -> Int -> Int -> a
{-# INLINE stretchFold #-}
stretchFold f a0 pr (Knots ts ps) ja jb = go i0 ja a0
  where
    (i0, i1) = samplesIn pr (ts U.! ja) (ts U.! jb)
    st = rcT pr
    go !i !j !s
      | i > i1 = s
      | otherwise =
          let t = U.unsafeIndex st i
              j' = advance j t
              t0 = U.unsafeIndex ts j'; t1 = U.unsafeIndex ts (j' + 1)
              u = max 0 (min 1 ((t - t0) / (t1 - t0)))
              ph = pindex ps j' ^+^ u *^ (pindex ps (j' + 1) ^-^ pindex ps j')
          in go (i + 1) j' (f s i (quadrance (pindex (rcP pr) i ^-^ ph)))
    advance j t | j + 1 < jb && U.unsafeIndex ts (j + 1) <= t = advance (j + 1) t
                | otherwise = j

-- | Position SSE of the whole recording.
knotSse :: Prepared -> Knots -> Double
knotSse pr k = stretchSse pr k 0 (U.length (kT k) - 1)

-- | Exact least-squares positions of the waypoints ja+1 .. jb−1 for their times (ends of the
-- stretch held, except the path's own first and last waypoint when 'rcEnds' frees them).
-- Unchanged when the system is singular.
solveStretchPositions :: Prepared -> Knots -> Int -> Int -> Knots
solveStretchPositions pr = solveSlicePositions pr (True, True)

-- | 'solveStretchPositions' for knots that are a slice of a path: whether the slice's first
-- and last waypoint are the path's own (and so free when 'rcEnds' frees them).
solveSlicePositions :: Prepared -> (Bool, Bool) -> Knots -> Int -> Int -> Knots
solveSlicePositions pr (atStart, atEnd) kn ja jb =
  solveStretchWith (free && atStart && ja == 0) (free && atEnd && jb == plength (kP kn) - 1) pr kn ja jb
  where free = rcEnds pr == EndsFree

-- | The stretch's least-squares positions, its first and last waypoint free or held.
solveStretchWith :: Bool -> Bool -> Prepared -> Knots -> Int -> Int -> Knots
solveStretchWith freeA freeB pr kn@(Knots ts ps) ja jb
  | jb - ja < 2 && not (freeA || freeB) = kn
  | otherwise = case sol of
      Right xs -> Knots ts (pgenerate (plength ps) (\j -> if j >= ja && j <= jb then pindex xs (j - ja) else pindex ps j))
      Left _ -> kn
  where
    m = jb - ja + 1
    (i0, i1) = samplesIn pr (ts U.! ja) (ts U.! jb)
    st = rcT pr
    lam = 1e-9 * fromIntegral (max 1 (i1 - i0 + 1)) / fromIntegral m
    sol = runST $ do
      bs <- newBand m 1
      let go !i !j
            | i > i1 = pure ()
            | otherwise = do
                let t = U.unsafeIndex st i
                    j' = advance j t
                    t0 = U.unsafeIndex ts j'; t1 = U.unsafeIndex ts (j' + 1)
                    u = max 0 (min 1 ((t - t0) / (t1 - t0)))
                addObs2 bs 1 (j' - ja) (1 - u) u (pindex (rcP pr) i)
                go (i + 1) j'
      go i0 ja
      forM_ [0 .. m - 1] $ \l -> addObs bs lam [(l, 1)] (pindex ps (ja + l))
      when (not freeA) $ pinValue bs 0 (pindex ps ja)
      when (not freeB) $ pinValue bs (m - 1) (pindex ps jb)
      solveBand bs
    advance j t | j + 1 < jb && U.unsafeIndex ts (j + 1) <= t = advance (j + 1) t
                | otherwise = j

-- | One Gauss–Newton system for the stretch: unknowns (x, y, z, τ) of each free waypoint,
-- the normal matrix damped by μ (relative to its diagonal). The step, or Nothing.
gnStep :: Prepared -> Knots -> Int -> Int -> Double -> Maybe (U.Vector Double)
gnStep pr (Knots ts ps) ja jb mu = solveBandSPD nu b damped g
  where
    nf = jb - ja - 1            -- free waypoints
    nu = 4 * nf
    b = 7
    (i0, i1) = samplesIn pr (ts U.! ja) (ts U.! jb)
    st = rcT pr
    ix i j = i * (b + 1) + j - i + b
    -- base unknown index of waypoint j, or −1 when it is held
    base j = if j > ja && j < jb then 4 * (j - ja - 1) else -1
    (a, g) = runST $ do
      am <- MU.replicate (nu * (b + 1)) 0
      gm <- MU.replicate nu 0
      let add r c v = when (r >= 0 && c >= 0 && c <= r) $ MU.unsafeModify am (+ v) (ix r c)
          addG r v = when (r >= 0) $ MU.unsafeModify gm (+ v) r
          go !i !j
            | i > i1 = pure ()
            | otherwise = do
                let t = U.unsafeIndex st i
                    j' = advance j t
                    t0 = U.unsafeIndex ts j'; t1 = U.unsafeIndex ts (j' + 1)
                    dt = t1 - t0
                    u = max 0 (min 1 ((t - t0) / dt))
                    p0 = pindex ps j'; p1 = pindex ps (j' + 1)
                    P3 dx dy dz = p1 ^-^ p0
                    P3 rx ry rz = pindex (rcP pr) i ^-^ (p0 ^+^ u *^ (p1 ^-^ p0))
                    b0 = base j'; b1 = base (j' + 1)
                    inside = t > t0 && t < t1
                    -- d p̂ / d τ_j = −D (1−u)/Δt,  d p̂ / d τ_{j+1} = −D u/Δt (0 at a waypoint)
                    ct0 = if inside then negate (1 - u) / dt else 0
                    ct1 = if inside then negate u / dt else 0
                    tau0 = if b0 >= 0 then b0 + 3 else -1
                    tau1 = if b1 >= 0 then b1 + 3 else -1
                    coord c d r = do
                      let p0i = if b0 >= 0 then b0 + c else -1
                          p1i = if b1 >= 0 then b1 + c else -1
                          !v0 = 1 - u; !v1 = u; !v2 = d * ct0; !v3 = d * ct1
                          row ri vi = when (ri >= 0) $ do
                            addG ri (vi * r)
                            add ri p0i (vi * v0)
                            add ri p1i (vi * v1)
                            add ri tau0 (vi * v2)
                            add ri tau1 (vi * v3)
                      row p0i v0
                      row p1i v1
                      when inside $ do
                        row tau0 v2
                        row tau1 v3
                coord 0 dx rx
                coord 1 dy ry
                coord 2 dz rz
                go (i + 1) j'
      go i0 ja
      (,) <$> U.unsafeFreeze am <*> U.unsafeFreeze gm
    diagMean = let ds = [ a U.! ix r r | r <- [0 .. nu - 1] ] in max 1e-300 (sum ds / fromIntegral (max 1 nu))
    damped = U.imap (\e v -> let r = e `div` (b + 1); c = e `mod` (b + 1)
                             in if c == b && r < nu then v + mu * v + 1e-9 * diagMean else v) a
    advance j t | j + 1 < jb && U.unsafeIndex ts (j + 1) <= t = advance (j + 1) t
                | otherwise = j

-- | Levenberg–Marquardt over the waypoints strictly between ja and jb (at most @iters@
-- accepted steps). Returns the refined knots and the stretch's SSE; never worse than the
-- positions solved for the times given.
refineStretch :: Prepared -> Int -> Int -> Int -> Knots -> (Knots, Double)
refineStretch pr iters ja jb kn0
  | jb - ja < 2 = (kn0, stretchSse pr kn0 ja jb)
  | otherwise = loop iters 1e-3 kp0 (stretchSse pr kp0 ja jb)
  where
    kp0 = solveStretchPositions pr kn0 ja jb
    span' = (kT kn0 U.! jb) - (kT kn0 U.! ja)
    -- waypoints at least half a sample step apart ('rcMinGap'): a step may not bring two
    -- closer than that, nor closer than they are when they already are (an irregular recording's
    -- start can have such a pair), nor ever within 1e-9 of the stretch
    floorGap = 1e-9 * span'
    admitted old new = new > floorGap && new >= min (rcMinGap pr) old
    loop 0 _ kn f = (kn, f)
    loop m mu kn f = case tryMu (10 :: Int) mu of
      Nothing -> (kn, f)
      Just (kn', f', mu')
        | f - f' <= 1e-9 * f -> (kn', f')
        | otherwise -> loop (m - 1) (max 1e-9 (mu' / 3)) kn' f'
      where
        ts = kT kn
        tryMu 0 _ = Nothing
        tryMu c mu1 = case gnStep pr kn ja jb mu1 of
          Nothing -> tryMu (c - 1) (mu1 * 4)
          Just dx ->
            let ts' = U.imap (\j t -> if j > ja && j < jb then t + dx U.! (4 * (j - ja - 1) + 3) else t) ts
                ordered = U.and (U.generate (jb - ja) (\l -> admitted (ts U.! (ja + l + 1) - ts U.! (ja + l)) (ts' U.! (ja + l + 1) - ts' U.! (ja + l))))
                kn' = solveStretchPositions pr (Knots ts' (kP kn)) ja jb
                f' = stretchSse pr kn' ja jb
            in if ordered && f' < f then Just (kn', f', mu1) else tryMu (c - 1) (mu1 * 4)

-- | 'refineStretch' over the whole path (first and last waypoint held).
refineAll :: Prepared -> Int -> Knots -> (Knots, Double)
refineAll pr iters kn = refineStretch pr iters 0 (U.length (kT kn) - 1) kn
