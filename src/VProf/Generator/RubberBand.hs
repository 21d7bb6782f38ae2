-- | The thesis's rubber band ("kuminauha", sections 3.2.2, 4.3 and 4.5): the profile's
-- velocities are raised and lowered one velocity step at a time, sample by sample, in
-- repeated passes, until nothing changes.
--
-- One pass ('pass') visits samples 1..N−1 (sample 0 is pinned to the start velocity,
-- sample N to the end velocity). Each sample looks at its window of five (the two before
-- and the two after): the two accelerations and three jerks it takes part in and the speed
-- limits of its two steps at the positions the samples have now. With the section 4.5
-- corrections:
--
-- * one pass changes velocities in one direction only: a /lowering/ pass when the profile
--   breaks a speed limit somewhere, a /raising/ pass otherwise;
-- * a sample that raises itself may not raise the samples after it (no chain of raises):
--   it raises only when its own window stays legal;
-- * a sample that breaks a limit lowers itself even when that breaks an acceleration or
--   jerk limit for a while; its neighbours follow (the chain reaction of figure 4.4, in
--   the lowering direction), each changing at most once per pass.
--
-- Beyond the thesis, in 'Guarded' mode (the default generator) a raise is also refused when
-- it would push a later sample into a lower zone or the route end beyond the tolerance,
-- because raising a sample moves every later sample forward by dv·dt. Starting from a
-- legal seed, guarded passes therefore only ever produce legal profiles.
module VProf.Generator.RubberBand
  ( Mode (..)
  , PassResult (..)
  , pass
  , violatesSpeed
  ) where

import Control.Monad (when, forM_)
import Control.Monad.ST (ST, runST)
import Data.STRef
import qualified Data.Vector.Unboxed as U
import qualified Data.Vector.Unboxed.Mutable as M

import VProf.Profile (trapezoidDistances)
import VProf.Request (Problem (..))
import VProf.SpeedLimit

data Mode
  = Guarded  -- ^ raises keep the whole profile legal (default generator)
  | Plain    -- ^ the thesis's local rules only (thesis mode)
  deriving (Eq, Show)

data PassResult = PassResult
  { prVel     :: !(U.Vector Double)
  , prChanged :: !Int
  , prRaising :: !Bool
  } deriving (Show)

-- | a_i of the profile being edited, with a_{-1} the start and a_N the end acceleration.
accAtM :: Problem -> Int -> M.MVector s Double -> Int -> ST s Double
accAtM pb n v i
  | i < 0 = pure (pbA0 pb)
  | i >= n = pure (pbAEnd pb)
  | otherwise = do a <- M.unsafeRead v i; b <- M.unsafeRead v (i + 1); pure ((b - a) / pbDt pb)
{-# INLINE accAtM #-}

-- | The speed limit of a step in the band's view: the zones, and past the route end the
-- end velocity (the thesis's zero limit behind the route end).
stepLimit :: Problem -> Double -> Double -> Double
stepLimit pb a b =
  let z = minLimitOn pb a b
  in if b > pbLength pb + pbTol pb / 2 then min z (pbVEnd pb) else z
{-# INLINE stepLimit #-}

-- | Samples whose step before or after breaks its speed limit (band view).
violatesSpeed :: Problem -> U.Vector Double -> [Int]
violatesSpeed pb v =
  [ k | k <- [1 .. n - 1], bad (k - 1) || bad k ]
  where
    n = U.length v - 1
    s = trapezoidDistances (pbDt pb) v
    bad i = max (v U.! i) (v U.! (i + 1)) > stepLimit pb (s U.! i) (s U.! (i + 1))

-- | One pass over the profile. The frozen mask marks samples that may not change
-- (cycle settling).
pass :: Mode -> Problem -> U.Vector Bool -> U.Vector Double -> PassResult
pass mode pb frozen v0
  | U.length v0 < 3 = PassResult v0 0 True
  | mode == Plain = if null bad then blockPass True pb frozen v0 [1 .. U.length v0 - 2]
                                 else blockPass False pb frozen v0 bad
  -- guarded passes start from a legal seed and keep it legal, so there is nothing to
  -- lower; the checker certifies the end result either way
  | otherwise = raise pb frozen v0
  where bad = violatesSpeed pb v0

-- | The thesis's pass with its chain reaction (figure 4.4, with the section 4.5
-- corrections): a sample that moves asks the next one whether it may move too; the
-- samples k..m move together by one velocity step, m being the first whose step to the
-- unmoved sample m+1 stays within the acceleration and jerk limits. Inside the block the
-- accelerations do not change, so only its two ends are checked (and, raising, the speed
-- limits of its samples where they are now). Every sample moves at most once per pass and
-- only in the pass's direction. Raising visits every sample; lowering starts from the
-- samples next to a broken speed limit.
blockPass :: Bool -> Problem -> U.Vector Bool -> U.Vector Double -> [Int] -> PassResult
blockPass raising pb frozen v0 starts = runST $ do
  v <- U.thaw v0
  moved <- M.replicate (U.length v0) False
  changed <- newSTRef (0 :: Int)
  shiftRef <- newSTRef (0 :: Double)
  let n = U.length v0 - 1
      s0 = trapezoidDistances (pbDt pb) v0
      dt = pbDt pb; dv = if raising then pbDv pb else negate (pbDv pb)
      aMin = pbAMin pb; aMax = pbAMax pb; jMin = pbJMin pb; jMax = pbJMax pb
      vAt i = M.unsafeRead v i
      accAt = accAtM pb n v
      okA a = a >= aMin && a <= aMax
      okJ j = j >= jMin * dt && j <= jMax * dt
      -- the left end of a block at k: a_{k-1} changes by dv/dt
      leftOk k = do
        am2 <- accAt (k - 2); am1 <- accAt (k - 1); a0 <- accAt k
        let am1' = am1 + dv / dt
        pure (okA am1' && okJ (am1' - am2) && okJ (a0 - am1'))
      -- the right end of a block at m: a_m changes by -dv/dt
      rightOk m = do
        am1 <- accAt (m - 1); a0 <- accAt m; ap1 <- accAt (m + 1)
        let a0' = a0 - dv / dt
        pure (okA a0' && okJ (a0' - am1) && okJ (ap1 - a0'))
      free i = do mv <- M.unsafeRead moved i; pure (i >= 1 && i <= n - 1 && not mv && not (frozen U.! i))
      findRight m limit
        | m > limit = pure Nothing
        | otherwise = do
            f <- free m
            if not f then pure Nothing else do
              ok <- rightOk m
              if ok then pure (Just m) else findRight (m + 1) limit
      tryBlock k = do
        f <- free k
        when f $ do
          lok <- leftOk k
          when lok $ do
            mr <- findRight k (n - 1)
            case mr of
              Nothing -> pure ()
              Just m -> do
                vs <- mapM vAt [k .. m]
                let vs' = map (+ dv) vs
                posOk <- if raising then speedOk k m vs' else pure True
                when (all (>= 0) vs' && posOk) $ do
                  forM_ (zip [k .. m] vs') $ \(i, x) -> M.unsafeWrite v i x >> M.unsafeWrite moved i True
                  modifySTRef' changed (+ (m - k + 1))
                  modifySTRef' shiftRef (+ fromIntegral (m - k + 1) * dv * dt)
      -- raising: the block's samples stay within the limits where they are now
      -- (positions as at the start of the pass, moved on by the blocks raised before)
      speedOk k m vs' = do
        shift <- readSTRef shiftRef
        before <- vAt (k - 1)
        after <- vAt (m + 1)
        let pos i = s0 U.! i + shift
            prevOf i x = if i == k then before else x
            tops = zip3 [k .. m] vs' (drop 1 vs' ++ [after])
        pure (and [ max (prevOf i x) (max x nx) <= stepLimit pb (pos (i - 1)) (pos (i + 1)) | (i, x, nx) <- tops ])
  forM_ starts tryBlock
  out <- U.freeze v
  c <- readSTRef changed
  pure (PassResult out c raising)

-- | Guarded raising pass.
raise :: Problem -> U.Vector Bool -> U.Vector Double -> PassResult
raise pb frozen v0 = runST $ do
  v <- U.thaw v0
  let n = U.length v0 - 1
      dt = pbDt pb; dv = pbDv pb
      aMin = pbAMin pb; aMax = pbAMax pb; jMin = pbJMin pb; jMax = pbJMax pb
      s0 = trapezoidDistances dt v0
      endBudget = pbLength pb + pbTol pb / 2
      -- forward margin of each step: how far its end may move before the step touches a
      -- zone whose limit is below the step's top velocity
      margin = U.generate n $ \i ->
        let top = max (v0 U.! i) (v0 U.! (i + 1))
            e = s0 U.! (i + 1)
        in case nextLowerZone pb e top of
             Just z -> z - e
             Nothing -> 1 / 0
      sufMin = U.postscanr' min (1 / 0) margin `U.snoc` (1 / 0)
  shiftRef <- newSTRef (0 :: Double)
  prevPosRef <- newSTRef (s0 U.! 0)   -- the position of sample k-1 as it is now
  changed <- newSTRef (0 :: Int)
  let vAt i = M.unsafeRead v i
      accAt = accAtM pb n v
  forM_ [1 .. n - 1] $ \k -> do
   shift <- readSTRef shiftRef
   sPrev <- readSTRef prevPosRef
   writeSTRef prevPosRef (s0 U.! k + shift)
   when (not (frozen U.! k)) $ do
    vk <- vAt k
    vkm <- vAt (k - 1)
    vkp <- vAt (k + 1)
    am2 <- accAt (k - 2)
    ap1 <- accAt (k + 1)
    let v' = vk + dv
        am1 = (v' - vkm) / dt      -- a_{k-1}
        a0 = (vkp - v') / dt       -- a_k
        -- positions now: samples >= k moved by every raise so far (all at indices < k)
        sK = s0 U.! k + shift + dv * dt / 2
        sNext = s0 U.! (k + 1) + shift + dv * dt
        localOk =
          am1 <= aMax && a0 >= aMin
            && (am1 - am2) / dt <= jMax
            && (a0 - am1) / dt >= jMin
            && (ap1 - a0) / dt <= jMax
            && max vkm v' <= stepLimit pb sPrev sK
            && max v' vkp <= stepLimit pb sK sNext
        globalOk =
          U.last s0 + shift + dv * dt <= endBudget
            && (sufMin U.! (k + 1)) - shift - dv * dt >= 0
    when (localOk && globalOk) $ do
      M.unsafeWrite v k v'
      writeSTRef shiftRef (shift + dv * dt)
      writeSTRef prevPosRef sK
      modifySTRef' changed (+ 1)
  out <- U.freeze v
  c <- readSTRef changed
  pure (PassResult out c True)
