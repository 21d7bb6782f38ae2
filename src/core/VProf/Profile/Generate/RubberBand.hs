-- | The thesis's rubber band ("kuminauha", sections 3.2.2, 4.3 and 4.5): the profile's
-- velocities are raised one velocity step at a time, sample by sample, in repeated
-- passes, until nothing changes.
--
-- A pass visits the samples in order (sample 0 is pinned to the start velocity, the last
-- sample to the end velocity). Each sample looks at its window of five (the two before
-- and the two after): the two accelerations and three jerks it takes part in and the
-- speed limits of its two steps at the positions the samples have now. With the section
-- 4.5 corrections: one pass changes velocities in one direction only, and a sample that
-- raises itself may not raise the samples after it (no chain of raises), so it raises
-- only when its own window stays legal.
--
-- Beyond the thesis, a raise is also refused when it would push a later sample into a
-- lower zone or the route end beyond the tolerance ('sweep'), because raising a sample
-- moves every later sample forward by dv·dt. Starting from a legal profile, passes
-- therefore only ever produce legal profiles, and they never lower anything: the
-- velocities only rise, each below its speed limit, so the passes end at a fixed point
-- (a pass that changes nothing) and can never flip between two profiles (the thesis's
-- 4.25/4.26). The thesis's lowering passes, which broke other limits "for a while", are
-- not needed.
module VProf.Profile.Generate.RubberBand
  ( PassResult (..)
  , pass
  , Sweep (..)
  , sweep
  , stepMargin
  , stepLimit
  , accelerationAt
  ) where

import Control.Monad.ST (ST, runST)
import qualified Data.Vector.Unboxed as U
import qualified Data.Vector.Unboxed.Mutable as M

import VProf.Profile.Sampled (trapezoidDistances)
import VProf.Profile.Request (Problem (..))
import VProf.Profile.SpeedLimit

data PassResult = PassResult
  { prVel     :: !(U.Vector Double)
  , prChanged :: !Int
  } deriving (Show)

-- | The speed limit of a step in the band's view: the zones, and past the route end the
-- end velocity (the thesis's zero limit behind the route end).
stepLimit :: Problem -> Double -> Double -> Double
stepLimit pb a b =
  let z = minLimitOn pb a b
  in if b > pbLength pb + pbTol pb / 2 then min z (pbVEnd pb) else z
{-# INLINE stepLimit #-}

-- | How far the end @e@ of a step whose top velocity is @top@ may move forward before the
-- step touches a zone whose limit is below @top@ (infinite when there is none).
stepMargin :: Problem -> Double -> Double -> Double
stepMargin pb top e = case nextLowerZone pb e top of
  Just z -> z - e
  Nothing -> 1 / 0
{-# INLINE stepMargin #-}

-- | a_i of a profile being edited, with a_{-1} the start and a_N the end acceleration.
accelerationAt :: Problem -> M.MVector s Double -> Int -> ST s Double
accelerationAt pb v i
  | i < 0 = pure (pbA0 pb)
  | i >= M.length v - 1 = pure (pbAEnd pb)
  | otherwise = do a <- M.unsafeRead v i; b <- M.unsafeRead v (i + 1); pure ((b - a) / pbDt pb)
{-# INLINE accelerationAt #-}

-- | What one sweep needs to know of the profile as it was when the sweep began.
data Sweep = Sweep
  { swPos     :: !(Int -> Double)  -- ^ position of sample k at the start of the sweep
  , swSufMin  :: !(Int -> Double)  -- ^ the least 'stepMargin' of the steps k, k+1, … (infinite past the moving part)
  , swArrival :: !Double           -- ^ where the moving part ends (the last moving sample's next position)
  }

-- | One guarded raising sweep over samples @lo..hi@ (Gauss-Seidel: a sample sees the
-- raises before it in the same sweep), editing the profile in place. Returns how many
-- samples rose and the first of them (maxBound when none).
sweep :: Problem -> Sweep -> Int -> Int -> M.MVector s Double -> ST s (Int, Int)
sweep pb (Sweep pos0 sufMin arrival) lo hi v = do
  let dt = pbDt pb; dv = pbDv pb
      aMin = pbAMin pb; aMax = pbAMax pb; jMin = pbJMin pb; jMax = pbJMax pb
      endBudget = pbLength pb + pbTol pb / 2
      accAt = accelerationAt pb v
      -- shift: how far every sample after the last raise has moved in this sweep;
      -- sPrev: where sample k-1 is now
      go !k !shift !sPrev !count !first
        | k > hi = pure (count, first)
        | otherwise = do
            vk <- M.unsafeRead v k
            vkm <- M.unsafeRead v (k - 1)
            vkp <- M.unsafeRead v (k + 1)
            am2 <- accAt (k - 2)
            ap1 <- accAt (k + 1)
            let v' = vk + dv
                am1 = (v' - vkm) / dt      -- a_{k-1}
                a0 = (vkp - v') / dt       -- a_k
                sK = pos0 k + shift + dv * dt / 2
                sNext = pos0 (k + 1) + shift + dv * dt
                localOk =
                  am1 <= aMax && a0 >= aMin
                    && (am1 - am2) / dt <= jMax
                    && (a0 - am1) / dt >= jMin
                    && (ap1 - a0) / dt <= jMax
                    && max vkm v' <= stepLimit pb sPrev sK
                    && max v' vkp <= stepLimit pb sK sNext
                globalOk =
                  arrival + shift + dv * dt <= endBudget
                    -- strictly: a step that ends on a zone start touches that zone
                    && sufMin (k + 1) - shift - dv * dt > 0
            if localOk && globalOk
              then do
                M.unsafeWrite v k v'
                go (k + 1) (shift + dv * dt) sK (count + 1) (min first k)
              else go (k + 1) shift (pos0 k + shift) count first
  if hi < lo then pure (0, maxBound) else go lo 0 (pos0 (lo - 1)) 0 maxBound
{-# INLINE sweep #-}

-- | One guarded raising pass over the whole profile (the default generator's).
pass :: Problem -> U.Vector Double -> PassResult
pass pb v0
  | U.length v0 < 3 = PassResult v0 0
  | otherwise = runST $ do
      v <- U.thaw v0
      let n = U.length v0 - 1
          s0 = trapezoidDistances (pbDt pb) v0
          margin = U.generate n $ \i -> stepMargin pb (max (v0 U.! i) (v0 U.! (i + 1))) (s0 U.! (i + 1))
          sufMin = U.postscanr' min (1 / 0) margin `U.snoc` (1 / 0)
      (c, _) <- sweep pb (Sweep (s0 U.!) (sufMin U.!) (U.last s0)) 1 (n - 1) v
      out <- U.freeze v
      pure (PassResult out c)
