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
  ) where

import qualified Data.Vector.Unboxed as U
import Linear (Quaternion, V3, quadrance, (^-^), (^/))

import VProf.Compress.Geometry
import VProf.Compress.Types

-- | A recording made ready for fitting: quaternions sign-aligned, interval velocities.
data Prepared = Prepared
  { prT  :: !(U.Vector Double)
  , prP  :: !(U.Vector (V3 Double))
  , prQ  :: !(U.Vector (Quaternion Double))
  , prV  :: !(U.Vector (V3 Double))   -- ^ length N−1
  , prDt :: !(U.Vector Double)        -- ^ length N−1
  }

prepare :: Recording -> Prepared
prepare (Recording (Track t p q)) = Prepared t p (alignHemisphere q) v dt
  where
    n = U.length t
    dt = U.generate (n - 1) (\i -> t U.! (i + 1) - t U.! i)
    v = U.generate (n - 1) (\i -> (p U.! (i + 1) ^-^ p U.! i) ^/ (dt U.! i))

-- | A path as plain arrays (times, positions, orientations).
data PathA = PathA
  { paT :: !(U.Vector Double)
  , paP :: !(U.Vector (V3 Double))
  , paQ :: !(U.Vector (Quaternion Double))
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
  | otherwise = poseSum + velSum
  where
    n = U.length (prT pr)
    j0 = max 0 (i0 - 1)
    j1 = min (n - 1) (i1 + 1)
    hats = U.generate (j1 - j0 + 1) (\k -> f (U.unsafeIndex (prT pr) (j0 + k)))
    hatP i = fst (U.unsafeIndex hats (i - j0))
    poseSum = go i0 0 where
      go !i !s | i > i1 = s
               | otherwise =
                   let (ph, qh) = U.unsafeIndex hats (i - j0)
                       ep = quadrance (U.unsafeIndex (prP pr) i ^-^ ph)
                       eo = if wo == 0 then 0 else let a = qangle (U.unsafeIndex (prQ pr) i) qh in a * a
                   in go (i + 1) (s + wp * ep + wo * eo)
    velSum
      | wv == 0 = 0
      | otherwise = go j0 0 where
          go !i !s | i >= min j1 (n - 1) = s
                   | otherwise =
                       let vh = (hatP (i + 1) ^-^ hatP i) ^/ U.unsafeIndex (prDt pr) i
                       in go (i + 1) (s + wv * quadrance (U.unsafeIndex (prV pr) i ^-^ vh))

-- | The whole objective E of a path.
totalCost :: Prepared -> Weights -> PathA -> Double
totalCost pr w pa = rangeCost pr w (pathInterp pa) 0 (U.length (prT pr) - 1)

-- | Per-sample time-synchronous errors: (position error m, orientation error rad), and
-- per-interval velocity error (m/s, length N−1).
pointErrors :: Prepared -> PathA -> (U.Vector Double, U.Vector Double, U.Vector Double)
pointErrors pr (PathA t p q) = (ep, eo, ev)
  where
    seg = segmentIndices t (prT pr)
    hats = U.imap (\i j -> interpolateAt t p q j (U.unsafeIndex (prT pr) i)) seg
    ep = U.zipWith (\x (ph, _) -> sqrt (quadrance (x ^-^ ph))) (prP pr) hats
    eo = U.zipWith (\x (_, qh) -> qangle x qh) (prQ pr) hats
    n = U.length (prT pr)
    ev = U.generate (n - 1) $ \i ->
      let vh = (fst (hats U.! (i + 1)) ^-^ fst (hats U.! i)) ^/ (prDt pr U.! i)
      in sqrt (quadrance (prV pr U.! i ^-^ vh))
