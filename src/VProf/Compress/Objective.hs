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
  , prepare
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
  ) where

import qualified Data.Vector.Unboxed as U
import Linear (Quaternion (..), V3 (..), quadrance, (*^), (^+^), (^-^), (^/))

import VProf.Compress.Geometry
import VProf.Compress.Types
import VProf.Compress.Vec

-- | A recording made ready for fitting: quaternions sign-aligned, interval velocities.
data Prepared = Prepared
  { prT  :: !(U.Vector Double)
  , prP  :: !V3s
  , prQ  :: !Qs
  , prV  :: !V3s                      -- ^ length N−1
  , prDt :: !(U.Vector Double)        -- ^ length N−1
  }

prepare :: Recording -> Prepared
prepare (Recording (Track t p q)) = Prepared t p (alignHemisphere q) v dt
  where
    n = U.length t
    dt = U.generate (n - 1) (\i -> t U.! (i + 1) - t U.! i)
    v = pgenerate (n - 1) (\i -> (pindex p (i + 1) ^-^ pindex p i) ^/ (dt U.! i))

-- | A path as plain arrays (times, positions, orientations).
data PathA = PathA
  { paT :: !(U.Vector Double)
  , paP :: !V3s
  , paQ :: !Qs
  } deriving (Show, Eq)

toPathA :: Path -> PathA
toPathA (Path (Track t p q)) = PathA t p q

fromPathA :: PathA -> Path
fromPathA (PathA t p q) = Path (Track t p q)

-- | Pose of a (possibly locally modified) path at a time.
type Interp = Double -> (V3 Double, Quaternion Double)

pathInterp :: PathA -> Interp
pathInterp (PathA t p q) = interpolate t p q

-- | Indices [i0, i1] of the samples with lo <= t <= hi (empty when i1 < i0).
samplesIn :: Prepared -> Double -> Double -> (Int, Int)
samplesIn pr lo hi = (lowerBound lo, upperBound hi - 1)
  where
    ts = prT pr
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
  | otherwise = go j0 (V3 0 0 0) 0
  where
    n = U.length (prT pr)
    j0 = max 0 (i0 - 1)
    j1 = min (n - 1) (i1 + 1)
    go !i !prev !s
      | i > j1 = s
      | otherwise =
          let (ph, qh) = f (U.unsafeIndex (prT pr) i)
              poseTerm
                | i < i0 || i > i1 = 0
                | otherwise =
                    let ep = quadrance (pindex (prP pr) i ^-^ ph)
                        eo = if wo == 0 then 0 else let a = qangle (pindex (prQ pr) i) qh in a * a
                    in wp * ep + wo * eo
              velTerm
                | wv == 0 || i == j0 = 0
                | otherwise =
                    let vh = (ph ^-^ prev) ^/ U.unsafeIndex (prDt pr) (i - 1)
                    in wv * quadrance (pindex (prV pr) (i - 1) ^-^ vh)
          in go (i + 1) ph (s + poseTerm + velTerm)
{-# INLINE rangeCost #-}

-- | The whole objective E of a path.
totalCost :: Prepared -> Weights -> PathA -> Double
totalCost pr w pa = rangeCost pr w (pathInterp pa) 0 (U.length (prT pr) - 1)

-- | Per-sample time-synchronous errors: (position error m, orientation error rad), and
-- per-interval velocity error (m/s, length N−1).
pointErrors :: Prepared -> PathA -> (U.Vector Double, U.Vector Double, U.Vector Double)
pointErrors pr (PathA t p q) = (ep, eo, ev)
  where
    seg = segmentIndices t (prT pr)
    n = U.length (prT pr)
    hatsL = [ interpolateAt t p q (U.unsafeIndex seg i) (U.unsafeIndex (prT pr) i) | i <- [0 .. n - 1] ]
    hatsP = pfromList (map fst hatsL) :: V3s
    hatsQ = pfromList (map snd hatsL) :: Qs
    ep = U.generate n (\i -> sqrt (quadrance (pindex (prP pr) i ^-^ pindex hatsP i)))
    eo = U.generate n (\i -> qangle (pindex (prQ pr) i) (pindex hatsQ i))
    ev = U.generate (n - 1) $ \i ->
      let vh = (pindex hatsP (i + 1) ^-^ pindex hatsP i) ^/ (prDt pr U.! i)
      in sqrt (quadrance (pindex (prV pr) i ^-^ vh))

-- | A segment prepared for fast repeated interpolation (slerp constants computed once).
data Seg = Seg !Double !Double !(V3 Double) !(V3 Double) !(Quaternion Double) !(Quaternion Double) !Double !Double

mkSeg :: Double -> Double -> V3 Double -> V3 Double -> Quaternion Double -> Quaternion Double -> Seg
mkSeg t0 t1 p0 p1 q0 q1raw =
  let d0 = qdot q0 q1raw
      (d, q1) = if d0 < 0 then (negate d0, negate <$> q1raw) else (d0, q1raw)
      th = if d > 0.9999995 then 0 else acos (min 1 d)
  in Seg t0 t1 p0 (p1 ^-^ p0) q0 q1 th (if th == 0 then 0 else sin th)
{-# INLINE mkSeg #-}

segPose :: Seg -> Double -> (V3 Double, Quaternion Double)
segPose (Seg t0 t1 p0 dp (Quaternion a u) (Quaternion b v) th sth) t =
  let s = max 0 (min 1 ((t - t0) / (t1 - t0)))
      p = p0 ^+^ s *^ dp
  in if th == 0
       then let w = (1 - s) * a + s * b
                x = (1 - s) *^ u ^+^ s *^ v
                nn = sqrt (w * w + quadrance x)
            in (p, Quaternion (w / nn) (x ^/ nn))
       else let c1 = sin ((1 - s) * th) / sth
                c2 = sin (s * th) / sth
            in (p, Quaternion (c1 * a + c2 * b) (c1 *^ u ^+^ c2 *^ v))
{-# INLINE segPose #-}

-- | 'rangeCost' for a path that, between times ta and tc, runs through the waypoints
-- (ta, pa, qa), (tb, pb, qb), (tc, pc, qc) and elsewhere follows @outside@. Used by the
-- time search of one waypoint, where it is evaluated many times.
twoSegmentCost :: Prepared -> Weights -> Interp
               -> Double -> Double -> Double -> V3 Double -> V3 Double -> V3 Double
               -> Quaternion Double -> Quaternion Double -> Quaternion Double
               -> Int -> Int -> Double
twoSegmentCost pr w outside ta tb tc pa pb pc qa qb qc =
  let s1 = mkSeg ta tb pa pb qa qb
      s2 = mkSeg tb tc pb pc qb qc
      f t | t < ta || t > tc = outside t
          | t <= tb = segPose s1 t
          | otherwise = segPose s2 t
  in rangeCost pr w f
