{-# LANGUAGE BangPatterns, RecordWildCards #-}
-- | The TCP speed limit along the route, from the robot and the route's geometry, and the
-- piecewise-constant speed zones of a profile request that never exceed it.
--
-- The joint path q(s) is the smooth interpolant of the tracked samples ('JointPath'). With
-- q̈_i = q_i'·a + q_i''·v², a stretch whose TCP acceleration stays within ±A keeps every joint's
-- acceleration limit when, on every step [s_k, s_{k+1}] of the grid, v² ≤ (q̈max_i − A·max|q_i'|)
-- / max|q_i''| (the slope and curvature maxima of the step). So the limit of a step at a given A
-- is the least of: the TCP speed limit; every joint's speed limit over its largest slope,
-- q̇max_i / max|q_i'|; that curvature bound for every joint; and on a blend of radius r the
-- centripetal bound √(a_max·r). A must stay below q̈max_i / max|q_i'| on every step of the
-- stretch ('tangentialCeiling'); the planner chooses it per stretch (a larger A accelerates
-- harder and leaves less for the corners). The zones take the minimum over their steps, rounded
-- down to a geometric ladder of speeds (so that zones are not tiny), and zones shorter than a
-- minimum length are merged into their neighbour, again by the minimum: a zone's limit is never
-- above the limit of any step it touches. See docs/plan.md.
module VProf.Plan.Limits
  ( Binding (..)
  , describeBinding
  , LimitOptions (..)
  , defaultJointAcceleration
  , PathBounds
  , pathBounds
  , StepLimits (..)
  , stepLimitsAt
  , tangentialCeiling
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
  | ByJointAcceleration !Int    -- ^ joint i's acceleration limit (its curvature part)
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
  }

-- | The joint acceleration limit used when the robot file publishes none: twice the speed
-- limit per second (full speed within half a second); no limit when no speed is published.
defaultJointAcceleration :: Joint -> Double
defaultJointAcceleration j = case (jointMaxAcceleration j, jointMaxVelocity j) of
  (Just a, _) -> a
  (Nothing, Just v) -> 2 * v
  _ -> 1 / 0

-- | Per step of the grid and joint, the largest |q_i'| and |q_i''| on the step ('stepBounds'),
-- computed once: N × n values each, row-major.
data PathBounds = PathBounds
  { pbS         :: !(U.Vector Double)   -- ^ the grid s_0..s_N
  , pbSlope     :: !(U.Vector Double)
  , pbCurvature :: !(U.Vector Double)
  , pbDof       :: !Int
  }

pathBounds :: JointPath -> PathBounds
pathBounds jp = PathBounds ss (U.map fst b) (U.map snd b) n
  where
    ss = tkS (jpTracked jp)
    n = tkDof (jpTracked jp)
    b = U.generate (max 0 (U.length ss - 1) * n) (\x -> let (k, i) = x `divMod` n in stepBounds jp k i)

-- | The limit of every step of the grid (N values for N+1 samples) and what sets it.
data StepLimits = StepLimits
  { slS       :: !(U.Vector Double)     -- ^ the grid s_0..s_N
  , slLimit   :: !(U.Vector Double)     -- ^ N: the limit on [s_k, s_{k+1}] (m/s)
  , slBinding :: !(V.Vector Binding)    -- ^ N
  } deriving (Show)

-- | The limits of the steps of [a, b] (a and b samples of the grid) with the TCP acceleration
-- within ±A there: a grid of its own, from a to b.
stepLimitsAt :: LimitOptions -> Route -> PathBounds -> Double -> Double -> Double -> StepLimits
stepLimitsAt LimitOptions{..} rt PathBounds{..} acc a b =
  StepLimits (U.slice k0 (m + 1) pbS) (U.fromList (map fst lims)) (V.fromList (map snd lims))
  where
    (k0, m) = stepRange pbS a b
    n = pbDof
    lims = [ step k | k <- [k0 .. k0 + m - 1] ]
    step k =
      let mid = 0.5 * (pbS U.! k + pbS U.! (k + 1))
          r = routeRadiusAt rt mid
          d i = pbSlope U.! (k * n + i)
          c i = pbCurvature U.! (k * n + i)
          cands = (loTcpSpeed, ByTcp)
                : [ (sqrt (loTcpAcceleration * r), ByCorner) | not (isInfinite r) ]
               ++ [ (vi / d i, ByJointSpeed i)
                  | i <- [0 .. n - 1], let vi = loJointSpeed U.! i, not (isInfinite vi), d i > 0 ]
               ++ [ (sqrt (max 0 (ai - acc * d i) / c i), ByJointAcceleration i)
                  | i <- [0 .. n - 1], let ai = loJointAcceleration U.! i, not (isInfinite ai), c i > 0 ]
      in foldl' (\x y -> if fst y < fst x then y else x) (head cands) (tail cands)

-- | The first step of [a, b] and the number of its steps.
stepRange :: U.Vector Double -> Double -> Double -> (Int, Int)
stepRange ss a b =
  let k0 = maybe 0 id (U.findIndex (>= a - 1e-12) ss)
      k1 = maybe (U.length ss - 1) (subtract 1) (U.findIndex (> b + 1e-12) ss)   -- the last sample <= b
  in (k0, max 0 (k1 - k0))

-- | The TCP acceleration at which the tangential part q_i'·a alone reaches a joint's
-- acceleration limit somewhere on [a, b]: the least of q̈max_i / max|q_i'| over its steps and the
-- joints (infinite when nothing bounds it). A stretch's acceleration must stay below it.
tangentialCeiling :: LimitOptions -> PathBounds -> Double -> Double -> Double
tangentialCeiling LimitOptions{..} PathBounds{..} a b = foldl' min (1 / 0)
  [ ai / d
  | k <- [k0 .. k0 + m - 1], i <- [0 .. pbDof - 1]
  , let ai = loJointAcceleration U.! i, not (isInfinite ai)
  , let d = pbSlope U.! (k * pbDof + i), d > 0 ]
  where
    (k0, m) = stepRange pbS a b

-- | One zone of the profile request: [start, end) at a speed, with what binds it.
data LimitZone = LimitZone
  { lzStart   :: !Double   -- ^ m
  , lzEnd     :: !Double   -- ^ m
  , lzSpeed   :: !Double   -- ^ m/s
  , lzBinding :: !Binding
  } deriving (Eq, Show)

-- | Zones shorter than this (m) are merged into the next one.
minZoneLength :: Double
minZoneLength = 0.001

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
