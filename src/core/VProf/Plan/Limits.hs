{-# LANGUAGE BangPatterns, RecordWildCards #-}
-- | The TCP speed limit along the route, from the robot and the route's geometry, and the
-- piecewise-constant speed zones of a profile request that never exceed it.
--
-- The joint path q(s) is the smooth interpolant of the tracked samples ('JointPath'). On every
-- step [s_k, s_{k+1}] of the grid the limit is the least of: the TCP speed limit; every joint's
-- speed limit over its largest slope on the step, q̇max_i / max|q_i'|; every joint's share
-- (1 − 'loAccelerationShare') of its acceleration limit over its largest curvature on the step,
-- √((1 − share)·q̈max_i / max|q_i''|); and on a blend of radius r the centripetal bound √(a_max·r).
-- The other share bounds the tangential part q_i'·a of the joint acceleration through the TCP
-- acceleration of each stretch ('tangentialLimit'). The zones take the minimum over their steps,
-- rounded down to a geometric ladder of speeds (so that zones are not tiny), and zones shorter
-- than a minimum length are merged into their neighbour, again by the minimum: a zone's limit is
-- never above the limit of any step it touches. See docs/plan.md.
module VProf.Plan.Limits
  ( Binding (..)
  , describeBinding
  , LimitOptions (..)
  , defaultJointAcceleration
  , StepLimits (..)
  , stepLimits
  , stepLimitsOn
  , defaultAccelerationShare
  , tangentialLimit
  , LimitZone (..)
  , limitZones
  , quantiseDown
  , speedLadder
  , minZoneLength
  ) where

import Data.List (foldl')
import qualified Data.Vector as V
import qualified Data.Vector.Unboxed as U

import VProf.Kinematics.Model
import VProf.Plan.Route
import VProf.Plan.Track

-- | What sets the limit.
data Binding
  = ByTcp                       -- ^ the TCP speed limit
  | ByJointSpeed !Int           -- ^ joint i's speed limit (0-based)
  | ByJointAcceleration !Int    -- ^ joint i's acceleration limit (the conservative rule)
  | ByCorner                    -- ^ the centripetal acceleration in a blend
  deriving (Eq, Show)

describeBinding :: Robot -> Binding -> String
describeBinding r = \case
  ByTcp -> "TCP speed"
  ByJointSpeed i -> jointName (robotJoints r !! i) ++ " speed"
  ByJointAcceleration i -> jointName (robotJoints r !! i) ++ " acceleration"
  ByCorner -> "corner"

data LimitOptions = LimitOptions
  { loTcpSpeed         :: !Double            -- ^ m/s
  , loTcpAcceleration  :: !Double            -- ^ m/s², the centripetal bound in blends
  , loJointSpeed       :: !(U.Vector Double) -- ^ per joint, rad/s or m/s (infinite: none)
  , loJointAcceleration :: !(U.Vector Double) -- ^ per joint, rad/s² or m/s² (infinite: none)
  , loAccelerationShare :: !Double            -- ^ the share of q̈max_i for the tangential part q_i'·a
  }

-- | Half of every joint's acceleration limit for the tangential part q_i'·a, half for the
-- curvature part q_i''·v².
defaultAccelerationShare :: Double
defaultAccelerationShare = 0.5

-- | The joint acceleration limit used when the robot file publishes none: twice the speed
-- limit per second (full speed within half a second); no limit when no speed is published.
defaultJointAcceleration :: Joint -> Double
defaultJointAcceleration j = case (jointMaxAcceleration j, jointMaxVelocity j) of
  (Just a, _) -> a
  (Nothing, Just v) -> 2 * v
  _ -> 1 / 0

-- | The limit of every step of the grid (N values for N+1 samples) and what sets it.
data StepLimits = StepLimits
  { slS       :: !(U.Vector Double)     -- ^ the grid s_0..s_N
  , slLimit   :: !(U.Vector Double)     -- ^ N: the limit on [s_k, s_{k+1}] (m/s)
  , slBinding :: !(V.Vector Binding)    -- ^ N
  } deriving (Show)

stepLimits :: LimitOptions -> Route -> Tracked -> StepLimits
stepLimits lo rt tk = stepLimitsOn lo rt (jointPath (rtStops rt) tk)

stepLimitsOn :: LimitOptions -> Route -> JointPath -> StepLimits
stepLimitsOn LimitOptions{..} rt jp = StepLimits ss (U.fromList (map fst lims)) (V.fromList (map snd lims))
  where
    tk = jpTracked jp
    ss = tkS tk
    nS = U.length ss
    n = tkDof tk
    curvShare = 1 - loAccelerationShare
    lims = [ step k | k <- [0 .. nS - 2] ]
    step k =
      let mid = 0.5 * (ss U.! k + ss U.! (k + 1))
          r = routeRadiusAt rt mid
          bounds = [ stepBounds jp k i | i <- [0 .. n - 1] ]
          cands = (loTcpSpeed, ByTcp)
                : [ (sqrt (loTcpAcceleration * r), ByCorner) | not (isInfinite r) ]
               ++ [ (vi / d, ByJointSpeed i)
                  | (i, (d, _)) <- zip [0 ..] bounds, let vi = loJointSpeed U.! i, not (isInfinite vi), d > 0 ]
               ++ [ (sqrt (curvShare * ai / c), ByJointAcceleration i)
                  | (i, (_, c)) <- zip [0 ..] bounds, let ai = loJointAcceleration U.! i, not (isInfinite ai), c > 0 ]
      in foldl' (\a b -> if fst b < fst a then b else a) (head cands) (tail cands)

-- | The TCP acceleration that keeps the tangential part of every joint's acceleration within its
-- share on the stretch [a, b]: the least of share·q̈max_i / max|q_i'| over the steps in it and the
-- joints (infinite when nothing bounds it). The caller takes the lesser of this and the asked
-- acceleration.
tangentialLimit :: LimitOptions -> JointPath -> Double -> Double -> Double
tangentialLimit LimitOptions{..} jp a b = foldl' min (1 / 0)
  [ loAccelerationShare * ai / d
  | k <- [0 .. U.length ss - 2], ss U.! k >= a - 1e-12, ss U.! (k + 1) <= b + 1e-12
  , i <- [0 .. n - 1], let ai = loJointAcceleration U.! i, not (isInfinite ai)
  , let (d, _) = stepBounds jp k i, d > 0 ]
  where
    ss = tkS (jpTracked jp)
    n = tkDof (jpTracked jp)

-- | One zone of the profile request: [start, end) at a speed, with what binds it.
data LimitZone = LimitZone
  { lzStart   :: !Double   -- ^ m
  , lzEnd     :: !Double   -- ^ m
  , lzSpeed   :: !Double   -- ^ m/s
  , lzBinding :: !Binding
  } deriving (Eq, Show)

-- | Zones shorter than this (m) are merged into the next one.
minZoneLength :: Double
minZoneLength = 0.005

-- | The ratio between neighbouring speeds of the ladder.
speedLadder :: Double
speedLadder = 0.95

-- | The largest speed of the ladder top·0.95^m (m = 0, 1, …) that is at most v.
quantiseDown :: Double -> Double -> Double
quantiseDown top v
  | v >= top = top
  | v <= 0 = 0
  | otherwise =
      let m = ceiling (log (v / top) / log speedLadder - 1e-12) :: Int
          c = top * speedLadder ^^ m
      in if c <= v then c else top * speedLadder ^^ (m + 1)

-- | The zones of the steps in [a, b] (a and b samples of the grid; a < b): step limits rounded
-- down to the ladder under the top speed, runs of equal speed joined, then every run shorter than
-- 'minZoneLength' removed by lowering speeds only: a short run with a lower neighbour takes the
-- highest lower neighbour's speed (it joins that zone); a short dip (both neighbours faster)
-- widens into its neighbours step by step at its own speed. Speeds only ever go down, so every
-- zone stays at or under the limit of every step it covers.
limitZones :: Double -> StepLimits -> Double -> Double -> [LimitZone]
limitZones top StepLimits{..} a b
  | null ks = []
  | otherwise = [ LimitZone (slS U.! (k0 + i)) (slS U.! (k0 + j)) v (bindingOn i j) | (i, j, v) <- runsOf final ]
  where
    ks = [ k | k <- [0 .. U.length slLimit - 1], slS U.! k >= a - 1e-12, slS U.! (k + 1) <= b + 1e-12 ]
    k0 = head ks
    m = length ks
    raw = U.slice k0 m slLimit
    len i j = slS U.! (k0 + j) - slS U.! (k0 + i)
    q0 = U.map (quantiseDown top) raw
    -- runs (first step, one past the last step, speed)
    runsOf q = go 0
      where
        go i | i >= m = []
             | otherwise = let v = q U.! i
                               j = maybe m (+ i) (U.findIndex (/= v) (U.drop i q))
                           in (i, j, v) : go j
    final = settle q0
    settle q =
      let rs = runsOf q
          indexed = zip3 [0 :: Int ..] rs (drop 1 (map Just rs) ++ [Nothing])
          prevs = Nothing : map Just rs
          short = [ (r, p, nx) | ((_, r@(i, j, _), nx), p) <- zip indexed prevs, len i j < minZoneLength - 1e-12 ]
      in case (rs, short) of
           ([_], _) -> q
           (_, []) -> q
           (_, (r, p, nx) : _) -> settle (fix q r p nx)
    fix q (i, j, v) p nx =
      let lower = [ w | Just (_, _, w) <- [p, nx], w < v ]
      in if not (null lower)
           then U.imap (\k x -> if k >= i && k < j then maximum lower else x) q
           else -- a dip: widen by one step on each side at its own speed (never raising a step)
             U.imap (\k x -> if k == i - 1 || k == j then min x v else x) q
    bindingOn i j =
      let k = i + U.minIndex (U.slice i (j - i) raw) in slBinding V.! (k0 + k)
