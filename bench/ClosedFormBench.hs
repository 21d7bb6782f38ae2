-- | Criterion benchmarks of the closed-form IK (issue 13): all solutions of one pose for
-- a UR5 (three parallel axes) and an ABB IRB 140 (spherical wrist), over 1000 poses from
-- random joint vectors within the limits (each checked first: the original q must be
-- among the solutions). Criterion's time divided by 1000 is the time per pose.
-- 'solvePrincipal' gives each distinct solution once; 'solveWith' adds the limits and
-- every ±2π variant within them (64 per solution on a UR5 with ±360° joints).
--
-- > ghc -O2 -main-is ClosedFormBench.closedFormMain -isrc/core -ibench -outputdir /tmp/cf-build-o2 -o /tmp/cf-bench bench/ClosedFormBench.hs
-- > /tmp/cf-bench
module ClosedFormBench (closedFormBenchmarks, closedFormMain, benchRobots) where

import Control.DeepSeq (force)
import Criterion.Main
import qualified Data.Vector.Unboxed as U
import VProf.Kinematics.ClosedForm

deg :: Double -> Double
deg = (* (pi / 180))

-- | UR5 (Universal Robots' DH) and IRB 140 (ARTE), as in @shared/reference/robots.md@.
benchRobots :: [(String, SixAxisDh)]
benchRobots =
  [ ("UR5", mk [0, -0.425, -0.39225, 0, 0, 0] [90, 0, 0, 90, -90, 0] [0.089159, 0, 0, 0.10915, 0.09465, 0.0823]
              (replicate 6 0) (replicate 6 (-360, 360)))
  , ("IRB 140", mk [0.070, 0.360, 0, 0, 0, 0] [-90, 0, -90, 90, -90, 0] [0.352, 0, 0, 0.380, 0, 0.065]
              [0, -90, 0, 0, 0, 180] [(-180, 180), (-90, 110), (-230, 50), (-400, 400), (-115, 115), (-400, 400)])
  ]
  where
    mk a al d off lim = case mkSixAxisDh a (map deg al) d (map deg off) (map (deg . fst) lim) (map (deg . snd) lim) of
      Just dh -> dh
      Nothing -> error "bench table"

-- | 1000 joint vectors within the limits (a fixed linear congruential sequence) and their poses.
poses :: SixAxisDh -> [(U.Vector Double, Pose)]
poses dh = [ (q, forwardPose dh q) | k <- [0 .. 999 :: Int]
           , let q = U.generate 6 (\j -> joint k j) ]
  where
    joint k j =
      let l = sdLower dh U.! j
          h = sdUpper dh U.! j
          u = (fromIntegral ((k * 7919 + j * 104729 + k * j * 31 + 17) `mod` 9973) + 0.5) / 9973
      in l + (h - l) * u

checked :: Solver -> [(U.Vector Double, Pose)] -> [Pose]
checked solver ps = [ if ok then p else error ("closed form misses a pose: " ++ show q) | (q, p) <- ps
                    , let ok = case solveWith solver p of
                                 Right sols -> any (\s -> U.maximum (U.map abs (U.zipWith (-) (solQ s) q)) < 1e-6) sols
                                 Left _ -> False ]

-- | Stand-alone: criterion on 'closedFormBenchmarks'.
closedFormMain :: IO ()
closedFormMain = defaultMain closedFormBenchmarks

closedFormBenchmarks :: [Benchmark]
closedFormBenchmarks =
  [ bgroup ("closed-form IK/" ++ name ++ " (1000 poses)")
      [ env (pure (force (checked solver (poses dh)))) $ \ps ->
          bench "all solutions, principal" $ nf (map (either (const 0) length . solvePrincipal solver)) ps
      , env (pure (force (checked solver (poses dh)))) $ \ps ->
          bench "all solutions within limits with 2pi variants" $ nf (map (either (const 0) length . solveWith solver)) ps
      , env (pure (force (map fst (poses dh)))) $ \qs ->
          bench "forward kinematics (reference)" $ nf (map (poseToRowMajor . forwardPose dh)) qs
      ]
  | (name, dh) <- benchRobots, let Right solver = solverFor dh ]
