-- | A lower bound on the duration of any legal profile from its dynamic limits: the speed
-- limits alone say that every zone takes at least its length over its limit
-- ("VProf.Profile.Request"'s 'leastSamples'), but a weak jerk or acceleration can make a
-- route take far longer (a 10 m route with a jerk of 1e-8 m/s³ takes some 3,200 s, not
-- the 2.5 s of its 4 m/s limit). The bound lets validation refuse a request whose
-- profile cannot fit the sample cap, naming the limit that makes it long, and tells a
-- user who ran out of time budget how many samples the route needs.
--
-- At every time t of a legal profile of duration T, the speed is at most what the
-- fastest run-up from the start state reaches by t (acceleration rising at the jerk limit
-- up to its limit, the speed at most the highest limit) and at most what the same run-up
-- backwards in time from the end state reaches by T − t (a braking to the end state, seen
-- from the end, is a run-up). The route is at most the integral of the smaller of the two,
-- which grows with T; the least T for which it reaches the route length is the bound.
-- See docs/profile-generator.md, "The least time".
module VProf.Profile.LeastTime
  ( Limits (..)
  , leastTime
  , reachSpeed
  , reachDistance
  , reachesWithin
  ) where

-- | The limits a bound is taken under (SI units). A relaxed bound (say, without the jerk
-- limit) is the same with that field infinite.
data Limits = Limits
  { lmV0   :: !Double   -- ^ start velocity
  , lmA0   :: !Double   -- ^ start acceleration
  , lmVEnd :: !Double   -- ^ end velocity
  , lmAEnd :: !Double   -- ^ end acceleration
  , lmAMin :: !Double   -- ^ < 0
  , lmAMax :: !Double   -- ^ > 0
  , lmJMax :: !Double   -- ^ > 0 (a run-up raises the acceleration at it, from either end)
  , lmVTop :: !Double   -- ^ the highest speed limit
  } deriving (Show)

-- | The highest speed a run-up reaches t seconds after a state of speed @v0@ and
-- acceleration @a0@: the acceleration rising at @j@ up to @aCap@, the speed capped at
-- @vTop@ (and never below zero).
reachSpeed :: Double -> Double -> Double -> Double -> Double -> Double -> Double
reachSpeed v0 a0 aCap j vTop t = max 0 (min vTop v)
  where
    t1 = if isInfinite j then 0 else max 0 ((aCap - a0) / j)   -- when the acceleration reaches its cap
    v | t <= t1 = v0 + a0 * t + j * t * t / 2
      | otherwise = v0 + (if t1 > 0 then a0 * t1 + j * t1 * t1 / 2 else 0) + aCap * (t - t1)

-- | An upper bound on the distance a legal profile of duration @tEnd@ covers: an upper
-- Riemann sum, on 'cells' equal steps, of the smaller of the forward and backward
-- run-ups' speeds (both rise with their own time, so on a step the larger ends bound
-- them). Each step's term grows with @tEnd@, so the bound does too.
reachDistance :: Limits -> Double -> Double
reachDistance lm tEnd = go 0 0
  where
    go :: Int -> Double -> Double
    go i acc
      | i >= cells = acc
      | otherwise = go (i + 1) (acc + h * min (fwd (fromIntegral (i + 1) * h)) (bwd (tEnd - fromIntegral i * h)))
    h = tEnd / fromIntegral cells
    fwd = reachSpeed (lmV0 lm) (lmA0 lm) (lmAMax lm) (lmJMax lm) vTop
    bwd = reachSpeed (lmVEnd lm) (negate (lmAEnd lm)) (negate (lmAMin lm)) (lmJMax lm) vTop
    vTop = topSpeed lm

cells :: Int
cells = 1024

-- | The highest speed a profile under the limits can have: the highest limit, or the start
-- or end velocity where one is above it.
topSpeed :: Limits -> Double
topSpeed lm = maximum [lmVTop lm, lmV0 lm, lmVEnd lm]

-- | Can a legal profile under the limits cover @len@ within @t@ seconds, as far as the bound
-- knows ('reachDistance' ≥ @len@)? Then 'leastTime' is at most @t@: one evaluation of the
-- bound, where 'leastTime' takes some thirty.
reachesWithin :: Limits -> Double -> Double -> Bool
reachesWithin lm len t = reachDistance lm t >= len

-- | The least duration (s) in which a legal profile under the limits can cover @len@ (m):
-- the least T with 'reachDistance' ≥ @len@, by doubling and then bisection to a relative
-- 1e-6 (the lower end kept, so the answer stays a lower bound). Zero for a route of no
-- length (or one whose length over the top speed is below the doubles); infinite when no
-- speed can be reached at all.
leastTime :: Limits -> Double -> Double
leastTime lm len
  | not (lo0 > 0) = 0              -- a route so short that len / vTop is below the doubles
  | reachDistance lm hugeTime < len = 1 / 0
  | otherwise = bisect lo0 (grow lo0)
  where
    vTop = topSpeed lm
    lo0 = len / vTop / 2          -- below the bound: at vTop the whole way takes len / vTop
    hugeTime = 1e15
    grow t = if t >= hugeTime || reachDistance lm t >= len then t else grow (2 * t)
    bisect lo hi
      | hi - lo <= 1e-6 * hi = lo
      | reachDistance lm mid >= len = bisect lo mid
      | otherwise = bisect mid hi
      where mid = (lo + hi) / 2
