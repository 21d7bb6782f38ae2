-- | Kinematics benchmarks: forward kinematics per library robot, the Dobot closed form, and the
-- numerical IK on the TRAC-IK protocol (random q within limits, target = FK(q), seed at
-- mid-limits, tolerance 1e-5, 5 ms per solve) for UR5 and Panda. 'tracIkProtocol' also runs the
-- protocol outside criterion, for success rate, percentiles and the worst residual.
module KinematicsBench
  ( kinematicsBenchmarks
  , ProtocolResult (..)
  , tracIkProtocol
  , protocolTargets
  ) where

import Control.Monad (forM)
import Criterion (Benchmark, bench, bgroup, nf, nfIO)
import Data.List (sort)
import qualified Data.Vector.Unboxed as U
import Data.Word (Word64)
import GHC.Clock (getMonotonicTimeNSec)
import System.CPUTime (getCPUTime)

import VProf.Kinematics
import VProf.Kinematics.Ik.Numeric (SplitMix (..), nextDouble, orientationTilt, reachBound)
import VProf.Kinematics.Library

lib :: String -> Kinematics
lib n = either error kinematicsFor (lookupRobot n)

-- | n random joint vectors uniform within the limits and their FK targets.
protocolTargets :: Chain -> Int -> Word64 -> [(U.Vector Double, Tf)]
protocolTargets ch n s = take n (go (SplitMix s))
  where
    d = chainDof ch
    go g = let (q, g') = draw d g [] in (q, forward ch q) : go g'
    draw 0 g acc = (U.fromListN d (reverse acc), g)
    draw k g acc =
      let i = d - k
          lo = max (-2 * pi) (chainLo ch U.! i)
          hi = min (2 * pi) (chainHi ch U.! i)
          (u, g') = nextDouble g
      in draw (k - 1) g' (lo + u * (hi - lo) : acc)

protocolOptions :: IkOptions
protocolOptions = defaultIkOptions {ikTolPosition = 1e-5, ikTolRotation = 1e-5, ikMaxRestarts = 100000}

data ProtocolResult = ProtocolResult
  { prSolves :: Int
  , prSuccesses :: Int
  , prMeanUs, prMedianUs, prP99Us :: Double
  , prMeanCpuUs :: Double                       -- ^ CPU time: what the solver costs on a busy machine
  , prWorstPosition, prWorstRotation :: Double  -- ^ over the successes (m, rad)
  }
  deriving (Show)

-- | The TRAC-IK protocol: n solves, each with a 5 ms wall-time budget, timed one by one.
tracIkProtocol :: Kinematics -> Int -> Word64 -> IO ProtocolResult
tracIkProtocol k n s = do
  let ch = kinChain k
      seed = midLimits ch
  rs <- forM (protocolTargets ch n s) $ \(_, t) -> do
    c0 <- getCPUTime
    t0 <- getMonotonicTimeNSec
    r <- solveIkIO 0.005 protocolOptions k t (Just seed)
    let res = case r of
          Right (sol : _) -> Just (residual (forward ch (solJoints sol)) t)
          _ -> Nothing
    t1 <- res `seq` getMonotonicTimeNSec
    c1 <- getCPUTime
    pure ((fromIntegral (t1 - t0) / 1000 :: Double, fromIntegral (c1 - c0) / 1e6 :: Double), res)
  let times = sort (map (fst . fst) rs)
      oks = [x | (_, Just x) <- rs]
      at :: Double -> Double
      at p = times !! min (n - 1) (floor (p * fromIntegral n))
  pure ProtocolResult
    { prSolves = n, prSuccesses = length oks
    , prMeanUs = sum times / fromIntegral n, prMedianUs = at 0.5, prP99Us = at 0.99
    , prMeanCpuUs = sum (map (snd . fst) rs) / fromIntegral n
    , prWorstPosition = maximum (0 : map fst oks), prWorstRotation = maximum (0 : map snd oks) }

kinematicsBenchmarks :: [Benchmark]
kinematicsBenchmarks =
  [ bgroup "kinematics/fk"
      [ bench key (nf (forward ch) q)
      | (key, Right r) <- libraryRobots, let ch = compile r, let q = midLimits ch U.// [(0, 0.3)] ]
  , bgroup "kinematics/jacobian"
      [ bench key (nf (snd . jacobian ch) q)
      | key <- ["ur5", "franka-panda"], let ch = kinChain (lib key), let q = midLimits ch U.// [(0, 0.3)] ]
  , bgroup "kinematics/ik-dobot"
      [ bench key (nf (\t -> solveIk defaultIkOptions k t Nothing) target)
      | key <- ["dobot-magician-lite", "dobot-magician"]
      , let k = lib key; ch = kinChain k; target = forward ch (U.fromList [0.4, 0.5, 0.3, -0.6]) ]
  , bgroup "kinematics/ik-numeric-precheck"
      -- the checks before any descent (reach bound, orientation a planar chain cannot take) beside
      -- a solve from a seed near the answer, as a plan's per-sample tracking solves
      [ b
      | key <- ["franka-panda", "kuka-lbr-iiwa14"]
      , let k = lib key; ch = kinChain k; q = midLimits ch U.// [(0, 0.3), (1, 0.4)]
            t = forward ch q; near = U.map (+ 0.002) q
      , b <- [ bench (key ++ "/reach-bound") (nf (snd . reachBound) ch)
             , bench (key ++ "/orientation-tilt") (nf (orientationTilt ch) t)
             , bench (key ++ "/seeded-solve") (nf (\t' -> either (const 0) length (solveIk defaultIkOptions k t' (Just near))) t) ] ]
  , bgroup "kinematics/ik-numeric-tracik (100 solves)"
      [ bench key $ nfIO $ forM targets $ \t -> solveIkIO 0.005 protocolOptions k t (Just seed)
      | key <- ["ur5", "franka-panda"]
      , let k = lib key; ch = kinChain k; seed = midLimits ch; targets = map snd (protocolTargets ch 100 7) ]
  ]
