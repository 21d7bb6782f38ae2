{-# LANGUAGE FlexibleContexts #-}
{-# LANGUAGE BangPatterns #-}
-- | The thesis's objective (section 2.4.3, @dist2lines2.m@): the weighted sum of squared
-- errors between every raw sample and the path's pose at that sample's own time:
--
-- > E = wp Σ |p_i − p̂(t_i)|² + wo Σ angle(q_i, q̂(t_i))² + wv Σ |v_i − v̂_i|²
--
-- where v_i = (p_{i+1} − p_i)/(t_{i+1} − t_i) is the recording's velocity over sample
-- interval i and v̂_i = (p̂(t_{i+1}) − p̂(t_i))/(t_{i+1} − t_i) the path's mean velocity
-- over the same interval (constant within a segment, as in @finnFeilHast2.m@).
module VProf.Compress.Objective
  ( Prepared (..)
  , prepareRecording
  , PathA (..)
  , toPathA
  , fromPathA
  , Interp
  , pathInterp
  , totalCost
  , rangeCost
  , samplesIn
  , pointErrors
  , twoSegmentCost
  , RangeSums
  , rangeSums
  , rangeCostFrom
  , Seg
  , mkSeg
  , segPose
  ) where

import Data.List (sort)
import qualified Data.Vector.Unboxed as U


import VProf.Geometry.Polyline
import VProf.Geometry.Quaternion
import VProf.Compress.Types
import VProf.Geometry.Vec

-- | A recording made ready for fitting: quaternions sign-aligned, interval velocities, and
-- whether a path's first and last waypoint are pinned to the first and last sample
-- ('prepareRecording' pins them; set 'rcEnds' to fit them).
data Prepared = Prepared
  { rcT  :: !(U.Vector Double)
  , rcP  :: !V3s
  , rcQ  :: !Qs
  , rcV  :: !V3s                      -- ^ length N−1
  , rcDt :: !(U.Vector Double)        -- ^ length N−1
  , rcInvDt :: !(U.Vector Double)     -- ^ 1 / dt
  , rcEnds :: !Ends
  , rcMinGap :: !Double               -- ^ the least time between two waypoints (s): 'minKnotGap'
  }

prepareRecording :: Recording -> Prepared
prepareRecording (Recording (Track t p q)) = Prepared t p (alignHemisphere q) v dt (U.map (1 /) dt) EndsPinned (minKnotGap dt)
  where
    n = U.length t
    dt = U.generate (n - 1) (\i -> t U.! (i + 1) - t U.! i)
    v = pgenerate (n - 1) (\i -> (pindex p (i + 1) ^-^ pindex p i) ^/ (dt U.! i))

-- | The least time between two waypoints: half the median sample step. The position error is
-- measured at the samples only, so a segment with no sample in it is free to jump: two
-- waypoints microseconds apart gave a segment hundreds of times faster than the recording.
-- Half a step keeps every start (waypoints at samples or midway between them) admissible.
minKnotGap :: U.Vector Double -> Double
minKnotGap dt
  | U.null dt = 0
  | otherwise = 0.5 * (sortU dt U.! (U.length dt `div` 2))
  where sortU = U.fromList . sort . U.toList

-- | A path as plain arrays (times, positions, orientations).
data PathA = PathA
  { paT :: !(U.Vector Double)
  , paP :: !V3s
  , paQ :: !Qs
  } deriving (Show, Eq)

toPathA :: Path -> PathA
toPathA (Path (Track t p q)) = PathA t p q

-- | The path as written: its quaternions sign-aligned, each in the hemisphere of the one before
-- (q and −q are one orientation and the fit interpolates the short way, so the path is the same;
-- a reader that slerps without choosing the short way would otherwise turn the long way round).
fromPathA :: PathA -> Path
fromPathA (PathA t p q) = Path (Track t p (alignHemisphere q))

-- | Pose of a (possibly locally modified) path at a time.
type Interp = Double -> (P3, Q4)

pathInterp :: PathA -> Interp
pathInterp (PathA t p q) = tableInterp (mkSegTable t p q)

-- | Indices [i0, i1] of the samples with lo <= t <= hi (empty when i1 < i0).
samplesIn :: Prepared -> Double -> Double -> (Int, Int)
samplesIn pr lo hi = (lowerBound lo, upperBound hi - 1)
  where
    ts = rcT pr
    n = U.length ts
    -- first index with t >= x
    lowerBound x = go 0 n where
      go a b | a >= b = a
             | otherwise = let m = (a + b) `div` 2 in if U.unsafeIndex ts m < x then go (m + 1) b else go a m
    -- first index with t > x
    upperBound x = go 0 n where
      go a b | a >= b = a
             | otherwise = let m = (a + b) `div` 2 in if U.unsafeIndex ts m <= x then go (m + 1) b else go a m

-- | Weighted cost of the samples i0..i1 whose pose is given by the interpolator, plus the
-- velocity terms of every sample interval that touches one of them.
rangeCost :: Prepared -> Weights -> Interp -> Int -> Int -> Double
rangeCost pr (Weights wp wo wv) f i0 i1
  | i1 < i0 = 0
  | otherwise = go j0 (P3 0 0 0) 0
  where
    n = U.length (rcT pr)
    j0 = max 0 (i0 - 1)
    j1 = min (n - 1) (i1 + 1)
    go !i !prev !s
      | i > j1 = s
      | otherwise =
          let (!ph, !qh) = f (U.unsafeIndex (rcT pr) i)
              poseTerm
                | i < i0 || i > i1 = 0
                | otherwise =
                    let ep = quadrance (pindex (rcP pr) i ^-^ ph)
                        eo = if wo == 0 then 0 else let a = qangle (pindex (rcQ pr) i) qh in a * a
                    in wp * ep + wo * eo
              velTerm
                | wv == 0 || i == j0 = 0
                | otherwise =
                    let vh = U.unsafeIndex (rcInvDt pr) (i - 1) *^ (ph ^-^ prev)
                    in wv * quadrance (pindex (rcV pr) (i - 1) ^-^ vh)
          in go (i + 1) ph (s + poseTerm + velTerm)
{-# INLINE rangeCost #-}

-- | Prefix sums of the per-sample pose terms and per-interval velocity terms of a path,
-- so that 'rangeCost' of the unchanged path over any range costs O(1).
data RangeSums = RangeSums !(U.Vector Double) !(U.Vector Double)

rangeSums :: Prepared -> Weights -> PathA -> RangeSums
rangeSums pr (Weights wp wo wv) pa = RangeSums (U.scanl (+) 0 pose) (U.scanl (+) 0 vel)
  where
    n = U.length (rcT pr)
    f = pathInterp pa
    hatsL = [ f (U.unsafeIndex (rcT pr) i) | i <- [0 .. n - 1] ]
    hp = pfromList (map fst hatsL) :: V3s
    hq = pfromList (map snd hatsL) :: Qs
    pose = U.generate n $ \i ->
      let ep = quadrance (pindex (rcP pr) i ^-^ pindex hp i)
          eo = if wo == 0 then 0 else let a = qangle (pindex (rcQ pr) i) (pindex hq i) in a * a
      in wp * ep + wo * eo
    vel = U.generate (n - 1) $ \i ->
      if wv == 0 then 0
      else let vh = U.unsafeIndex (rcInvDt pr) i *^ (pindex hp (i + 1) ^-^ pindex hp i)
           in wv * quadrance (pindex (rcV pr) i ^-^ vh)

-- | 'rangeCost' of the path the sums were made from.
rangeCostFrom :: Prepared -> RangeSums -> Int -> Int -> Double
rangeCostFrom pr (RangeSums ps vs) i0 i1
  | i1 < i0 = 0
  | otherwise = (ps U.! (i1 + 1) - ps U.! i0) + (vs U.! j1 - vs U.! j0)
  where
    n = U.length (rcT pr)
    j0 = max 0 (i0 - 1)
    j1 = min (n - 1) (i1 + 1)

-- | The whole objective E of a path.
totalCost :: Prepared -> Weights -> PathA -> Double
totalCost pr w pa = rangeCost pr w (pathInterp pa) 0 (U.length (rcT pr) - 1)

-- | Per-sample time-synchronous errors: (position error m, orientation error rad), and
-- per-interval velocity error (m/s, length N−1).
pointErrors :: Prepared -> PathA -> (U.Vector Double, U.Vector Double, U.Vector Double)
pointErrors pr (PathA t p q) = (ep, eo, ev)
  where
    seg = segmentIndices t (rcT pr)
    n = U.length (rcT pr)
    tbl = mkSegTable t p q
    hatsL = [ tableAt tbl (U.unsafeIndex seg i) (U.unsafeIndex (rcT pr) i) | i <- [0 .. n - 1] ]
    hatsP = pfromList (map fst hatsL) :: V3s
    hatsQ = pfromList (map snd hatsL) :: Qs
    ep = U.generate n (\i -> sqrt (quadrance (pindex (rcP pr) i ^-^ pindex hatsP i)))
    eo = U.generate n (\i -> qangle (pindex (rcQ pr) i) (pindex hatsQ i))
    ev = U.generate (n - 1) $ \i ->
      let vh = (pindex hatsP (i + 1) ^-^ pindex hatsP i) ^/ (rcDt pr U.! i)
      in sqrt (quadrance (pindex (rcV pr) i ^-^ vh))

-- | A segment prepared for fast repeated interpolation (slerp constants computed once).
data Seg = Seg !Double !Double !(P3) !(P3) !(Q4) !(Q4) !Double !Double

mkSeg :: Double -> Double -> P3 -> P3 -> Q4 -> Q4 -> Seg
mkSeg t0 t1 p0 p1 q0 q1raw =
  let d0 = qdot q0 q1raw
      (d, q1) = if d0 < 0 then (negate d0, qneg q1raw) else (d0, q1raw)
      th = if d > 0.9999995 then 0 else acos (min 1 d)
  in Seg t0 t1 p0 (p1 ^-^ p0) q0 q1 th (if th == 0 then 0 else sin th)
{-# INLINE mkSeg #-}

segPose :: Seg -> Double -> (P3, Q4)
segPose (Seg t0 t1 p0 dp (Q4 a1 b1 c1 d1) (Q4 a2 b2 c2 d2) th sth) t =
  let s = max 0 (min 1 ((t - t0) / (t1 - t0)))
      p = p0 ^+^ s *^ dp
      (k1, k2) = if th == 0 then (1 - s, s) else (sinF ((1 - s) * th) / sth, sinF (s * th) / sth)
      q = Q4 (k1 * a1 + k2 * a2) (k1 * b1 + k2 * b2) (k1 * c1 + k2 * c2) (k1 * d1 + k2 * d2)
      !q' = if th == 0 then qnormalize q else q
      !p' = p
  in (p', q')
{-# INLINE segPose #-}

-- | 'rangeCost' for a path that, between times ta and tc, runs through the waypoints
-- (ta, pa, qa), (tb, pb, qb), (tc, pc, qc) and elsewhere follows @outside@. Used by the
-- time search of one waypoint, where it is evaluated many times.
twoSegmentCost :: Prepared -> Weights -> Interp
               -> Double -> Double -> Double -> P3 -> P3 -> P3
               -> Q4 -> Q4 -> Q4
               -> Int -> Int -> Double
twoSegmentCost pr w outside ta tb tc pa pb pc qa qb qc i0 i1 =
  let s1 = mkSeg ta tb pa pb qa qb
      s2 = mkSeg tb tc pb pc qb qc
      f t | t < ta || t > tc = outside t
          | t <= tb = segPose s1 t
          | otherwise = segPose s2 t
      {-# INLINE f #-}
  in rangeCost pr w f i0 i1
