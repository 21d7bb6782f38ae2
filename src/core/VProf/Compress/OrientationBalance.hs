-- | The orientation's share of the waypoint times, step 5 of the knot fit (docs/compress.md,
-- "The knot fit"). The times are chosen for the position error alone; with the thesis's
-- weights one degree counts as one millimetre, which on a recording whose position error is
-- centimetres or metres leaves the orientation out of the choice. This step moves the times
-- (the thesis's update rounds, "VProf.Compress.Fit") under orientation weights raised to a
-- scale of the path's own: m* times the user's, where m* makes the two terms of the given path
-- equal, tried at m*/16, m*/8, … m* (those above 1), each from the path the last left. The
-- rounds stop at the first path whose position sum of squares, or position-and-velocity
-- objective, is above (1 + budget) times the given path's; of the paths within the budget
-- the one with the lowest orientation error is kept, the given path when none is lower.
module VProf.Compress.OrientationBalance
  ( orientationBudget
  , balanceOrientation
  , multipliers
  ) where

import qualified Data.Vector.Unboxed as U

import VProf.Compress.Fit (TimeMode (..), updatePathWith)
import VProf.Compress.Objective
import VProf.Compress.Types

-- | The default budget: 0.5 % more position sum of squares (a quarter of a per cent more
-- RMSE). On KITTI 00 at 3 % of the samples it lowered the orientation RMSE from 3.58° to
-- 3.32° with the position RMSE 0.04 % lower; on freiburg1_xyz at 1 % from 1.999° to 1.988°.
orientationBudget :: Double
orientationBudget = 0.005

-- | The update rounds per weight (the thesis method's polish has as many).
roundsPerWeight :: Int
roundsPerWeight = 3

-- | The multipliers of the orientation weight tried, in order: m*/16, m*/8, m*/4, m*/2 and
-- m* for the given position and orientation terms (weighted), those above 1; none when
-- either term is zero or not finite.
multipliers :: Double -> Double -> [Double]
multipliers posTerm oriTerm
  | not (posTerm > 0 && oriTerm > 0) || isInfinite mStar || isNaN mStar = []
  | otherwise = filter (> 1) [ mStar / 2 ^ i | i <- [4, 3, 2, 1, 0 :: Int] ]
  where mStar = posTerm / oriTerm

-- | The times of a path re-balanced towards the orientation within a budget (a fraction,
-- >= 0; 0: the path as it is). The number of waypoints, the end times and pinned ends do
-- not move; the positions and orientations are those of the thesis's update rounds (the
-- positions the exact least squares for their times).
balanceOrientation :: Double -> Prepared -> Weights -> PathA -> PathA
balanceOrientation budget pr w@(Weights wp wo wv) pa0
  | budget <= 0 || wp <= 0 || wo <= 0 || U.length (paT pa0) < 3 || null steps = pa0
  | otherwise = go steps pa0 (ori0, pa0)
  where
    posSse = totalCost pr (Weights 1 0 0)
    oriSse = totalCost pr (Weights 0 1 0)
    pvCost = totalCost pr (Weights wp 0 wv)
    sse0 = posSse pa0
    pv0 = pvCost pa0
    ori0 = oriSse pa0
    steps = multipliers (wp * sse0) (wo * ori0)
    go [] _ (_, paB) = paB
    go (m : ms) pa best@(oriB, paB)
      | posSse pa1 > (1 + budget) * sse0 || pvCost pa1 > (1 + budget) * pv0 = paB
      | otherwise = go ms pa1 (if ori1 < oriB then (ori1, pa1) else best)
      where
        pa1 = updatePathWith pr w { wOrientation = wo * m } TimesAll roundsPerWeight pa
        ori1 = oriSse pa1
