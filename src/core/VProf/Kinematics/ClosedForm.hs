{-# LANGUAGE BangPatterns, LambdaCase, RecordWildCards #-}
-- | Closed-form inverse kinematics for six-axis arms: every solution of a pose in a few
-- microseconds, each labelled with its branch (shoulder, elbow, wrist; ABB's cfx digit).
-- 'classify' recognises the family from the DH table alone (a spherical wrist with axes 2
-- and 3 parallel, or three parallel axes 2–4); 'solveAll' returns every solution within
-- the joint limits, including each joint's ±2π variants that fit, or says why there is
-- none. Pure: strict doubles, no matrices library. Derivation and the documented choices
-- at the singularities: @docs/closed-form-ik.md@.
module VProf.Kinematics.ClosedForm
  ( -- * Families
    Family (..), classify, classifyWhy
    -- * Solving
  , Solver, solverFamily, solverDh, solverFor, solveWith, solveAll, solvePrincipal, limitVariants
    -- * Branches
  , Branch (..), Shoulder (..), Elbow (..), Wrist (..)
  , branchText, branchCfx, parseBranch, allBranches
  , branchOf, selectBranch, nearestInBranch
    -- * Results
  , Solution (..), Singularity (..), IkFailure (..)
    -- * Robot table and poses
  , SixAxisDh (..), mkSixAxisDh, forwardPose
  , Pose (..), Rot (..), V3 (..)
  , identityPose, composePose, inversePose, applyPose, poseFromRowMajor, poseToRowMajor
  ) where

import Control.DeepSeq (NFData (..))
import Data.List (minimumBy, sortOn)
import Data.Ord (comparing)
import qualified Data.Vector.Unboxed as U
import qualified Data.Vector.Unboxed.Mutable as MU
import VProf.Kinematics.ClosedForm.Common
import VProf.Kinematics.ClosedForm.Parallel
import VProf.Kinematics.ClosedForm.Pieper
import VProf.Kinematics.ClosedForm.Types

-- | Tolerance of the classification: lengths (m) and sines/cosines this close to zero are zero.
tolClass :: Double
tolClass = 1e-9

-- | The family of a table, or 'Nothing'.
classify :: SixAxisDh -> Maybe Family
classify = either (const Nothing) Just . classifyWhy

-- | The family, or which condition fails. Both families need sin α1 ≠ 0 (axes 1 and 2
-- not parallel), α2 = 0 (axes 2 and 3 parallel, same sense) and a2 ≠ 0.
-- Spherical wrist: a4 = a5 = d5 = 0 and α4, α5 = ±90° (axes 4, 5, 6 meet in o4).
-- Three parallel axes: α3 = 0 as well, a3 ≠ 0, a5 = 0, α4, α5 = ±90°.
classifyWhy :: SixAxisDh -> Either String Family
classifyWhy SixAxisDh{..}
  | any ((/= 6) . U.length) [sdA, sdAlpha, sdD, sdOffset, sdLower, sdUpper] = Left "the table needs six rows"
  | U.any (\x -> isNaN x || isInfinite x) (U.concat [sdA, sdAlpha, sdD, sdOffset]) = Left "the table has a NaN or infinite entry"
  | abs (sin (al 0)) < 1e-6 = Left "axes 1 and 2 are parallel (sin α1 = 0)"
  | not (zeroAngle (al 1)) = Left "axes 2 and 3 are not parallel in the same sense (α2 ≠ 0)"
  | abs (a 1) < tolClass = Left "a2 = 0"
  | not (perp (al 3) && perp (al 4)) = Left "α4 or α5 is not ±90°"
  | abs (a 4) > tolClass = Left "a5 ≠ 0"
  | spherical = Right SphericalWrist
  | zeroAngle (al 2) && abs (a 2) > tolClass = Right ThreeParallel
  | otherwise = Left "neither a spherical wrist (a4 = a5 = d5 = 0, a3 or d4 ≠ 0) nor three parallel axes (α3 = 0, a3 ≠ 0)"
  where
    a i = sdA U.! i; al i = sdAlpha U.! i; d i = sdD U.! i
    zeroAngle x = abs (sin x) < tolClass && cos x > 0
    perp x = abs (cos x) < tolClass
    spherical = abs (a 3) < tolClass && abs (d 4) < tolClass
                && sqrt (a 2 * a 2 + (sin (al 2) * d 3) ^ (2 :: Int)) > tolClass

-- | A table checked and unpacked once, for many solves.
data Solver = Solver
  { solverFamily :: !Family
  , solverDh :: !SixAxisDh
  , solverConsts :: !Consts
  }

instance NFData Solver where rnf (Solver f d _) = rnf f `seq` rnf d

solverFor :: SixAxisDh -> Either IkFailure Solver
solverFor dh = case classifyWhy dh of
  Left why -> Left (UnknownFamily why)
  Right fam -> Right (Solver fam dh (mkConsts dh))

-- | Every solution within the joint limits (each joint's 2π variants that fit included),
-- or why there is none.
solveAll :: SixAxisDh -> Pose -> Either IkFailure [Solution]
solveAll dh target = solverFor dh >>= \s -> solveWith s target

-- | The principal solutions: each q in (−π, π], joint limits not applied; one per branch
-- (fewer where branches coincide at a singularity).
solvePrincipal :: Solver -> Pose -> Either IkFailure [Solution]
solvePrincipal Solver{..} target
  | badPose target = Left (BadTarget "the target pose has a NaN or infinite entry")
  | otherwise =
      let Consts{..} = solverConsts
          t' = composePose (composePose cBaseInv (composePose target cToolInv)) cLastInv
          raws = case solverFamily of
            SphericalWrist -> pieperRaw solverConsts t'
            ThreeParallel -> parallelRaw solverConsts t'
          toSol (Raw t1 t2 t3 t4 t5 t6 br sing) =
            let !q = U.create $ do
                  v <- MU.unsafeNew 6
                  MU.unsafeWrite v 0 (wrap (t1 - cO1)); MU.unsafeWrite v 1 (wrap (t2 - cO2))
                  MU.unsafeWrite v 2 (wrap (t3 - cO3)); MU.unsafeWrite v 3 (wrap (t4 - cO4))
                  MU.unsafeWrite v 4 (wrap (t5 - cO5)); MU.unsafeWrite v 5 (wrap (t6 - cO6))
                  pure v
            in Solution q br sing
      in case raws of
           Left e
             | e >= 0 -> Left (OutOfReach "the wrist point is outside the arm's reach" e)
             | otherwise -> Left (OutOfReach "the wrist point is closer to the shoulder than the arm can fold" e)
           Right rs -> Right (map toSol rs)

badPose :: Pose -> Bool
badPose (Pose (Rot a b c) t) = bad a || bad b || bad c || bad t
  where bad (V3 x y z) = let s = x + y + z in isNaN s || isInfinite s

-- | 'solvePrincipal', then every combination of each joint's variants q + 2πk within the
-- limits (a value within 1e-12 rad outside a limit is put on it).
solveWith :: Solver -> Pose -> Either IkFailure [Solution]
solveWith s target = solvePrincipal s target >>= limitVariants s

-- | Every combination of each joint's variants q + 2πk within the limits, of the given
-- solutions (a value within 1e-12 rad outside a limit is put on it); 'OutsideLimits' with
-- the joint that misses least when none fits. The variants of a solution reach the same
-- pose, so a caller that checks solutions can check the principal ones and expand after.
limitVariants :: Solver -> [Solution] -> Either IkFailure [Solution]
limitVariants Solver{..} principal = do
  let lo = sdLower solverDh; hi = sdUpper solverDh
      twoPi = 2 * pi
      -- joint j's variants x + 2πk within [l, h]: k from k0 to k1
      kRange j x =
        let l = lo U.! j; h = hi U.! j
        in (ceiling ((l - 1e-12 - x) / twoPi) :: Int, floor ((h + 1e-12 - x) / twoPi) :: Int)
      expand sol =
        let q = solQ sol
            ranges = U.generate 6 (\j -> kRange j (q U.! j))
            counts = U.map (\(k0, k1) -> max 0 (k1 - k0 + 1)) ranges
            total = U.product counts
            strides = U.prescanr' (*) 1 counts
            value i j =
              let (k0, _) = ranges U.! j
                  k = k0 + (i `quot` (strides U.! j)) `rem` (counts U.! j)
              in min (hi U.! j) (max (lo U.! j) (q U.! j + twoPi * fromIntegral k))
        in [sol { solQ = U.generate 6 (value i) } | i <- [0 .. total - 1]]
      out = concatMap expand principal
  if null out
    then let miss sol = [(dist j (solQ sol U.! j), j) | j <- [0 .. 5]]
             dist j x = minimum [max (lo U.! j - y) (y - hi U.! j) | k <- [-3 .. 3 :: Int], let y = x + 2 * pi * fromIntegral k]
             worst sol = maximum (miss sol)
             (d, j) = minimumBy (comparing fst) (map worst principal)
         in Left (OutsideLimits (length principal) (j + 1) d)
    else Right out

-- | The branch of a joint vector, by the same geometric rules as the solver's labels
-- ('Nothing' when the table fits neither family).
branchOf :: SixAxisDh -> U.Vector Double -> Maybe Branch
branchOf dh q = case classify dh of
  Nothing -> Nothing
  Just fam ->
    let Consts{..} = mkConsts dh
        th i = q U.! i + dh `offsetAt` i
        offsetAt d i = sdOffset d U.! i
        links n = foldl composePose identityPose
          [dhLink (th i) (sdD dh U.! i) (sdA dh U.! i) (cos (sdAlpha dh U.! i)) (sin (sdAlpha dh U.! i)) | i <- [0 .. n - 1]]
        wristPoint = poseT (links (case fam of SphericalWrist -> 4; ThreeParallel -> 5))
        t1 = th 0
        V3 px py _ = wristPoint
        sh = if cos t1 * px + sin t1 * py >= 0 then ShoulderRight else ShoulderLeft
        el = case fam of
          SphericalWrist ->
            let bb = cSa3 * cD4; rr = sqrt (cA3 * cA3 + bb * bb)
            in elbowLabel cSa1 cA2 rr (th 2 - atan2 bb cA3)
          ThreeParallel -> elbowLabel cSa1 cA2 cA3 (th 2)
        wr = if sin (th 4) < 0 then WristFlip else WristNoFlip
    in Just (Branch sh el wr)

-- | The solutions on one branch.
selectBranch :: Branch -> [Solution] -> [Solution]
selectBranch b = filter ((== b) . solBranch)

-- | The solution on a branch nearest to a seed (largest joint difference), if any.
nearestInBranch :: Branch -> U.Vector Double -> [Solution] -> Maybe Solution
nearestInBranch b seed sols = case sortOn dist (selectBranch b sols) of
  (s : _) -> Just s
  [] -> Nothing
  where dist s = U.maximum (U.map abs (U.zipWith (-) (solQ s) seed))
