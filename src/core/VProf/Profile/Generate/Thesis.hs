-- | Thesis mode (@--algorithm thesis@): the thesis's windowed iteration from a profile at
-- rest, with the core's corrections, run until it reaches its fixed point.
--
-- The thesis starts from an all-zero profile over a fixed horizon and lets every sample
-- rise. Raised everywhere at once, the whole horizon lifts together into a slow plateau
-- that reaches the route end long before any speed limit binds (or, unguarded, runs past
-- it and has to be lowered again, which is how the thesis's profiles overshot and never
-- settled). Here the band /grows from its start/: the samples behind the standstill rise
-- as the windowed rule allows, and the first sample at rest (the /front/) starts moving
-- only in a pass after one in which the sample before it did not rise. The raises are
-- guarded as in the default generator ('sweep': no raise pushes a later sample into a
-- lower zone or past the route end), so every pass keeps the profile legal, velocities
-- only rise, and the band ends at a fixed point: the front stands at the route end and no
-- sample can rise any more. When the front cannot rise alone, it rises in a chain with
-- the samples before it (the thesis's chain reaction, 'chainAtFront').
--
-- The pace of the front sets how hard the band brakes ahead of it: about dv per sample
-- per pass, gentler than the limits allow, and that braking is what is left before
-- lower zones and the route end, where the guards freeze it. Thesis-mode profiles are
-- therefore a few per cent (long routes) to a third (short ones) slower than the default
-- generator's. Letting the front wait longer (until the whole band has settled, or a
-- fixed number of passes) does not help: the band then saturates its jerk limits
-- everywhere, no single sample can rise any more, and it stalls far below its limits.
--
-- A moving start is braked to rest first (the thesis extended its profile before the
-- start for the same purpose; 'restWithinJerk', planned inside the jerk range where the
-- rounding of the velocities would put it beyond); the band then raises those samples
-- where their windows allow. A moving end state is reached from rest: the band lands at
-- rest where the end state's run-in begins (the hardest braking to rest from the end
-- state, backwards in time, on the 'mirror', planned as the start's), so the profile
-- stops once before it: legal, but slower than the default generator's meet.
--
-- Only the samples that can still change are visited: a sample whose window and
-- position did not change in the last pass and whose forward margins only shrank cannot
-- rise now either, so each pass starts two samples before the first that rose in the
-- previous one and ends at the front.
module VProf.Profile.Generate.Thesis
  ( Stage (..)
  , thesisStages
  , thesisHorizon
  ) where

import Control.Monad.ST (ST, runST)
import qualified Data.Vector.Unboxed as U
import qualified Data.Vector.Unboxed.Mutable as M
import Numeric (showFFloat)

import VProf.Profile.Generate.RubberBand (Sweep (..), accelerationAt, stepLimit, stepMargin, sweep)
import VProf.Profile.Generate.Seed (SeedFailure (..), mirror, restWithinJerk)
import VProf.Profile.Sampled (trapezoidDistances)
import VProf.Profile.Problem (endsInMotion)
import VProf.Profile.Request (Problem (..), maxSamples)

-- | The profile after a number of passes.
data Stage = Stage
  { stgVel     :: !(U.Vector Double)  -- ^ the whole profile: the band up to its front, then the end's run-in
  , stgPasses  :: !Int
  , stgChanged :: !Int                -- ^ samples raised by the last pass
  , stgDone    :: !Bool               -- ^ the fixed point: a pass that tried the front changed nothing
  }

-- | The band between chunks of passes.
data Band = Band
  { bV         :: !(U.Vector Double)  -- ^ the velocities over the horizon (zeros after the front)
  , bS         :: !(U.Vector Double)  -- ^ their positions (valid up to the front)
  , bFront     :: !Int                -- ^ the first sample at rest with only rest after it
  , bLo        :: !Int                -- ^ the first sample that may still rise
  , bSettled   :: !Bool               -- ^ the sample before the front did not rise in the last pass: the front may move
  , bPasses    :: !Int
  }

-- | Samples of the initial horizon: the time to drive every zone at its limit, plus the
-- time to speed up and slow down at every zone change, with a margin. The band grows it
-- when the front reaches its end.
thesisHorizon :: Problem -> Int
thesisHorizon pb =
  let starts = U.toList (pbZoneStarts pb) ++ [pbLength pb]
      speeds = U.toList (pbZoneSpeeds pb)
      cruise = sum (zipWith3 (\a b v -> (b - a) / v) starts (drop 1 starts) speeds)
      ramp v = v / pbAMax pb + v / abs (pbAMin pb) + pbAMax pb / pbJMax pb + abs (pbAMin pb) / abs (pbJMin pb)
      changes = sum (map ramp speeds)
      t = 1.2 * cruise + changes + 2
  in min maxSamples (max 4 (ceiling (t / pbDt pb)))

-- | The stages of thesis mode: the starting profile, then one stage per chunk of passes,
-- the last at the fixed point (or at the iteration cap). 'Left' when the start cannot
-- be braked to rest or the end state's run-in does not fit (the caller decides whether
-- that is an infeasible request).
thesisStages :: Problem -> Either SeedFailure [Stage]
thesisStages pb = do
  tailV <- runIn
  let dE = if U.null tailV then 0 else U.last (trapezoidDistances (pbDt pb) tailV)
      bandPb = pb { pbLength = pbLength pb - dE, pbVEnd = 0, pbAEnd = 0 }
  if pbLength bandPb < 0
    then Left (LandingFailed ("thesis mode reaches the end state from rest, and its run-in needs "
                              ++ showFFloat (Just 3) dE " m, more than route_length"))
    else Right ()
  braking <- restWithinJerk bandPb
  let m = U.length braking
      aRest = if m >= 2 then (U.last braking - braking U.! (m - 2)) / pbDt pb else pbA0 pb
      -- at rest with the acceleration back at zero (one more sample at rest), and the
      -- front one sample further: rising alone from there changes no acceleration that
      -- the braking left at a limit
      seg = if aRest /= 0 then braking `U.snoc` 0 else braking
      n0 = max (thesisHorizon bandPb) (U.length seg + 4)
      v0 = seg U.++ U.replicate (n0 + 1 - U.length seg) 0
      b0 = Band v0 (trapezoidDistances (pbDt pb) v0) (U.length seg) 1 False 0
      -- the band's front and the run-in's first sample: two samples at rest, so that
      -- the acceleration is zero between the braking and the run-in
      assemble b = U.take (bFront b + 1) (bV b) U.++ tailV
      go b = let (b', changed, done) = chunk bandPb (pbMaxIter pb) b
                 st = Stage (assemble b') (bPasses b') changed done
             in st : if done || bPasses b' >= pbMaxIter pb then [] else go b'
  pure (Stage (assemble b0) 0 0 False : go b0)
  where
    moving = endsInMotion pb
    -- the end state's run-in from rest: the hardest braking to rest from the end state
    -- on the mirror, reversed (0 .. v_end); nothing when the end is at rest
    runIn
      | not moving = Right U.empty
      | otherwise = U.reverse <$> restWithinJerk (mirror pb)

-- | Passes per stage, for a horizon of @n@ samples: the wall-clock budget is checked
-- between stages, and each stage copies the profile out, so long profiles take longer
-- stages (a stage's passes cost about as much as its copies).
chunkPasses :: Int -> Int
chunkPasses n = max 256 (n `div` 16)

-- | Up to 'chunkPasses' passes (fewer at the cap or the fixed point): the band after them,
-- the samples raised by the last pass, and whether it is the fixed point.
--
-- A pass sweeps from 'bLo' to the sample before the front and, when that sample did not
-- rise in the previous pass, on to the front: the front rises alone if its window
-- allows, else with the samples before it in a chain ('chainAtFront'). A pass that
-- tried the front and changed nothing is the fixed point.
chunk :: Problem -> Int -> Band -> (Band, Int, Bool)
chunk pb cap b0 = runST $ do
  v <- U.thaw (bV b0)
  s <- U.thaw (bS b0)
  suf <- M.replicate (M.length v + 1) (1 / 0)
  let stop = min cap (bPasses b0 + chunkPasses (U.length (bV b0)))
      dt = pbDt pb
      loop b vm sm sufm
        | bPasses b >= stop = finish b vm sm 0 False
        | otherwise = do
            let f = bFront b; lo = bLo b; settled = bSettled b; passes = bPasses b
            (vm', sm', sufm') <- ensureRoom f vm sm sufm
            let n = M.length vm' - 1
            -- forward margins of the moving steps after lo, as suffix minima
            let fillSuf j
                  | j <= lo = pure ()
                  | otherwise = do
                      a <- M.unsafeRead vm' j; c <- M.unsafeRead vm' (j + 1)
                      e <- M.unsafeRead sm' (j + 1); nxt <- M.unsafeRead sufm' (j + 1)
                      M.unsafeWrite sufm' j (min (stepMargin pb (max a c) e) nxt)
                      fillSuf (j - 1)
            M.unsafeWrite sufm' f (1 / 0)
            fillSuf (f - 1)
            sNow <- U.unsafeFreeze sm'
            sufNow <- U.unsafeFreeze sufm'
            let pos k = U.unsafeIndex sNow (min k (f + 1))
                sufMin k = if k >= f then 1 / 0 else U.unsafeIndex sufNow k
                sw a z = sweep pb (Sweep pos sufMin (U.unsafeIndex sNow f)) a z vm'
            oldPred <- M.unsafeRead vm' (f - 1)
            (count, first) <- do
              r@(c, _) <- sw lo (min (n - 1) (if settled then f else f - 1))
              vf <- M.unsafeRead vm' f
              if not settled || vf > 0 || f > n - 1 then pure r
              else do
                (c', first') <- chainAtFront pb f pos vm'
                pure (c + c', min (snd r) first')
            sm'' <- U.unsafeThaw sNow
            sufm'' <- U.unsafeThaw sufNow
            vf <- M.unsafeRead vm' f
            newPred <- M.unsafeRead vm' (f - 1)
            let f' = if settled && vf > 0 then f + 1 else f
            -- positions from the first raised sample up to the new front's next
                refill j
                  | j > min n (f' + 1) = pure ()
                  | otherwise = do
                      a <- M.unsafeRead vm' (j - 1); c <- M.unsafeRead vm' j; p <- M.unsafeRead sm'' (j - 1)
                      M.unsafeWrite sm'' j (p + (a + c) * dt / 2)
                      refill (j + 1)
            if count > 0 then refill first else pure ()
            let lo' = if count == 0 then f' else max 1 (first - 2)
                b' = Band U.empty U.empty f' lo' (f' == f && newPred == oldPred) (passes + 1)
            if count == 0 && settled
              then finish b' vm' sm'' 0 True
              else if passes + 1 >= stop
                then finish b' vm' sm'' count False
                else loop b' vm' sm'' sufm''
      finish b vm sm count done = do
        vOut <- U.freeze vm
        sOut <- U.freeze sm
        pure (b { bV = vOut, bS = sOut }, count, done)
  loop b0 v s suf

-- | The chain reaction at the front (the thesis's figure 4.4): when the front cannot rise
-- alone, it asks the sample before it, which asks the one before it, and so on until
-- one can rise without breaking its own window on the left; then the whole block up to
-- the front rises by one step. Inside the block the accelerations do not change, so
-- only its two ends and the speed limits of its steps (at their new positions) and the
-- route end are checked. Returns the samples raised and the first of them.
chainAtFront :: Problem -> Int -> (Int -> Double) -> M.MVector s Double -> ST s (Int, Int)
chainAtFront pb f pos v = do
  let dt = pbDt pb; dv = pbDv pb
      aMin = pbAMin pb; aMax = pbAMax pb; jMin = pbJMin pb; jMax = pbJMax pb
      accAt = accelerationAt pb v
      -- the left end at k: a_{k-1} rises by dv/dt
      leftOk k = do
        am2 <- accAt (k - 2); am1 <- accAt (k - 1); a0 <- accAt k
        let am1' = am1 + dv / dt
        pure (am1' <= aMax && (am1' - am2) / dt <= jMax && (a0 - am1') / dt >= jMin)
      findLeft k
        | k < 1 = pure Nothing
        | otherwise = do ok <- leftOk k; if ok then pure (Just k) else findLeft (k - 1)
  -- the right end at the front: a_f falls by dv/dt (v_f and v_{f+1} are at rest)
  aPrev <- accAt (f - 1)
  aNext <- accAt (f + 1)
  let af' = negate dv / dt
      rightOk = af' >= aMin && (af' - aPrev) / dt >= jMin && (aNext - af') / dt <= jMax
  mk <- if rightOk && f >= 2 then findLeft (f - 1) else pure Nothing
  case mk of
    Nothing -> pure (0, maxBound)
    Just k -> do
      old <- mapM (M.unsafeRead v) [k - 1 .. f + 1]
      let vNew i x = if i >= k && i <= f then x + dv else x
          vs = zipWith vNew [k - 1 ..] old
          -- sample i >= k moves on by the raises before it and half its own
          sNew i | i < k = pos i
                 | i <= f = pos i + fromIntegral (i - k) * dv * dt + dv * dt / 2
                 | otherwise = pos f + fromIntegral (f - k + 1) * dv * dt
          steps = zip3 [k - 1 .. f] vs (drop 1 vs)
          speedOk = and [ max x y <= stepLimit pb (sNew i) (sNew (i + 1)) | (i, x, y) <- steps ]
          endOk = sNew (f + 1) <= pbLength pb + pbTol pb / 2
      if speedOk && endOk
        then do
          mapM_ (\i -> M.unsafeModify v (+ dv) i) [k .. f]
          pure (f - k + 1, k)
        else pure (0, maxBound)

-- | Room for the front to advance: the horizon doubles (up to the sample cap) when the
-- front comes within three samples of its end. New samples are at rest, at the front's
-- position.
ensureRoom :: Int -> M.MVector s Double -> M.MVector s Double -> M.MVector s Double
           -> ST s (M.MVector s Double, M.MVector s Double, M.MVector s Double)
ensureRoom f v s suf
  | f + 3 <= n || n >= maxSamples = pure (v, s, suf)
  | otherwise = do
      let extra = min n (maxSamples - n)
      v' <- M.grow v extra
      s' <- M.grow s extra
      suf' <- M.grow suf extra
      pEnd <- M.unsafeRead s n
      M.set (M.slice (n + 1) extra v') 0
      M.set (M.slice (n + 1) extra s') pEnd
      M.set (M.slice (n + 1) extra suf') (1 / 0)
      pure (v', s', suf')
  where n = M.length v - 1
