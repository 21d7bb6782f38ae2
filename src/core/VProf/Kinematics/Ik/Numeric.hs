{-# LANGUAGE BangPatterns, RecordWildCards #-}
-- | Numerical inverse kinematics for any chain: Levenberg–Marquardt on the full 6-D pose error
-- (position in m, rotation vector in rad, both in the base frame), projected onto the joint limits,
-- started from the seed and then from random configurations within the limits.
--
-- One step solves (JᵀJ + λI)·δ = Jᵀe with λ = μ·E (E = ½|e|², Chan–Lawrence/Sugihara damping: a
-- Gauss–Newton step near the solution, a short gradient step far from it); a descent ends when
-- it converges, after its iteration count, or when E has not dropped by a tenth for a few steps,
-- and the solver restarts. The random starts come from a pure SplitMix64 generator
-- seeded by the caller, so a solve is a pure function of its inputs; 'solveNumericIO' adds a
-- wall-time budget, looked at between two iterations. A target beyond the chain's reach (of the
-- tool, or of the wrist at the target's orientation) or with an orientation its tool cannot take
-- fails before any descent. Invariant: a returned solution
-- is within the limits and its forward kinematics matches the target to the tolerances (the
-- check is the convergence test).
module VProf.Kinematics.Ik.Numeric
  ( solveNumeric
  , solveNumericIO
  , Prepared
  , prepareNumeric
  , solveNumericWith
  , solveNumericIOWith
  , Attempt (..)
  , attempts
  , descend
  , Descent (..)
  , descent
  , outcome
  , followUntil
  , lmStep
  , refineOnto
  , lmStepPrimal
  , lmStepDual
  , reachBound
  , Wrist (..)
  , wrists
  , wristCheck
  , orientationTilt
  , SplitMix (..)
  , nextDouble
  ) where

import Control.Monad.ST (ST, runST)
import Data.Bits (shiftR, xor)
import qualified Data.Vector.Unboxed as U
import qualified Data.Vector.Unboxed.Mutable as M
import Data.Word (Word64)
import Numeric (showFFloat)
import GHC.Clock (getMonotonicTimeNSec)

import VProf.Kinematics.Forward
import VProf.Kinematics.Ik.Types
import VProf.Kinematics.Jacobian
import VProf.Kinematics.Model
import VProf.Kinematics.Transform

--------------------------------------------------------------------------------------------------
-- A tiny pure generator (SplitMix64, Steele–Lea–Flood 2014)

newtype SplitMix = SplitMix Word64

nextWord :: SplitMix -> (Word64, SplitMix)
nextWord (SplitMix s) =
  let s' = s + 0x9E3779B97F4A7C15
      z1 = (s' `xor` (s' `shiftR` 30)) * 0xBF58476D1CE4E5B9
      z2 = (z1 `xor` (z1 `shiftR` 27)) * 0x94D049BB133111EB
  in (z2 `xor` (z2 `shiftR` 31), SplitMix s')

-- | Uniform in [0, 1).
nextDouble :: SplitMix -> (Double, SplitMix)
nextDouble g = let (w, g') = nextWord g in (fromIntegral (w `shiftR` 11) * (1 / 9007199254740992), g')

--------------------------------------------------------------------------------------------------

-- | The outcome of one descent from one start.
data Attempt = Attempt
  { attJoints :: !(U.Vector Double)
  , attPosition :: !Double   -- ^ m
  , attRotation :: !Double   -- ^ rad
  , attConverged :: !Bool
  , attIterations :: !Int    -- ^ Jacobian evaluations spent
  }

-- | The starts: the seed, then uniform random configurations within the limits (±π for an
-- unbounded side). A long chain (more than 12 joints) alternates those with the seed moved by a
-- random fraction of each joint's range, the fraction growing from 1 % by half each time up to
-- the whole range: a uniform draw crumples a snake of hundreds of joints and its seed (the
-- middle of the limits, often straight) is singular, where the seed bent a little converges.
starts :: Word64 -> Chain -> U.Vector Double -> [U.Vector Double]
starts s ch seed
  | n > 12 = seed : interleave (near 0.01 (SplitMix (s `xor` 0x5851F42D4C957F2D))) (go (SplitMix s))
  | otherwise = seed : go (SplitMix s)
  where
    n = chainDof ch
    lo i = let l = chainLo ch U.! i in if isInfinite l then -pi else l
    hi i = let h = chainHi ch U.! i in if isInfinite h then pi else h
    go g = let (q, g') = draw 0 g [] in U.fromListN n q : go g'
    draw i g acc
      | i >= n = (reverse acc, g)
      | otherwise = let (u, g') = nextDouble g in draw (i + 1) g' (lo i + u * (hi i - lo i) : acc)
    -- the seed moved by up to ±f of each range (clamped to the limits), f ×1.5 a start
    near f g = let (q, g') = nudge f 0 g [] in U.fromListN n q : near (min 1 (1.5 * f)) g'
    nudge f i g acc
      | i >= n = (reverse acc, g)
      | otherwise =
          let (u, g') = nextDouble g
              x = seed U.! i + f * (2 * u - 1) * (hi i - lo i)
          in nudge f (i + 1) g' (max (chainLo ch U.! i) (min (chainHi ch U.! i) x) : acc)
    interleave (a : as) (b : bs) = a : b : interleave as bs
    interleave as [] = as
    interleave [] bs = bs

-- | Every descent from every start, lazily.
attempts :: IkOptions -> Bool -> Chain -> Tf -> U.Vector Double -> [Attempt]
attempts opts limited ch target seed =
  map (descend opts limited ch target) (starts (ikRandomSeed opts) ch seed)

-- | The 6-D error e = (p_t − p, log(R_t·Rᵀ)).
poseError :: Tf -> Tf -> (Double, Double, Double, Double, Double, Double)
poseError target t =
  let V3 wx wy wz = rotationLog (compose target (inverse t) {tx = 0, ty = 0, tz = 0})
  in (tx target - tx t, ty target - ty t, tz target - tz t, wx, wy, wz)

-- | One Levenberg–Marquardt descent from a start (limits enforced when the flag is set): its
-- outcome.
descend :: IkOptions -> Bool -> Chain -> Tf -> U.Vector Double -> Attempt
descend opts limited ch target q0 = outcome (descent opts limited ch target q0)

-- | A descent as the stream of its iterates, so that a caller with a clock can stop it between
-- two iterations: 'Going' holds the iterate's state as an unfinished attempt and the rest.
data Descent = Done !Attempt | Going !Attempt Descent

-- | The last iterate of a descent.
outcome :: Descent -> Attempt
outcome (Done a) = a
outcome (Going _ d) = outcome d

-- | The iterates of one Levenberg–Marquardt descent from a start, lazily.
descent :: IkOptions -> Bool -> Chain -> Tf -> U.Vector Double -> Descent
descent IkOptions{..} limited ch target q0 = loop 0 (1 / 0) 0 (clampQ q0)
  where
    n = chainDof ch
    rev = chainRevoluteJoint ch
    lo i = U.unsafeIndex (chainLo ch) i
    hi i = U.unsafeIndex (chainHi ch) i
    clampQ q
      | limited = U.imap (\i x -> if U.unsafeIndex rev i then project (lo i) (hi i) x else max (lo i) (min (hi i) x)) q
      | otherwise = q
    -- best: the lowest E so far; since: iterations since it dropped by a tenth
    loop :: Int -> Double -> Int -> U.Vector Double -> Descent
    loop !it !best !since !q =
      let (t, j) = jacobian ch q
          e@(e0, e1, e2, e3, e4, e5) = poseError target t
          pe = sqrt (e0 * e0 + e1 * e1 + e2 * e2)
          re = sqrt (e3 * e3 + e4 * e4 + e5 * e5)
          en = 0.5 * (pe * pe + re * re)
          (best', since') = if en < 0.9 * best then (en, 0) else (best, since + 1)
      in if pe <= ikTolPosition && re <= ikTolRotation then Done (Attempt q pe re True (it + 1))
         else if it >= ikMaxIterations || since' > stallLimit then Done (Attempt q pe re False (it + 1))
         else
           let lam = ikDampingGain * en + 1e-12
               delta0 = lmStep n j e lam noMask
               -- joints at a bound that the step pushes outward are frozen and the step solved again
               frozen = U.imap (\i d -> pushesOut i (U.unsafeIndex q i) d) delta0
               delta
                 | limited && U.or frozen = lmStep n j e lam frozen
                 | otherwise = delta0
           in Going (Attempt q pe re False (it + 1)) (loop (it + 1) best' since' (clampQ (U.zipWith (+) q delta)))
    noMask = U.replicate n False
    pushesOut i x d =
      let w = 1e-9 * (1 + abs x)
          wraps = U.unsafeIndex rev i && hi i - lo i >= 2 * pi
      in not wraps && ((x >= hi i - w && d > 0) || (x <= lo i + w && d < 0))

-- | Joint values near q whose tool pose is the target's to rounding: Gauss–Newton steps (the
-- Levenberg–Marquardt step at its floor damping, 'lmStep' with λ = 0) from q, at most three,
-- each kept only while it lowers the pose error |e|² (metres and radians); q itself when the
-- first does not. Meant for a q already close to the target, such as a joint path interpolated
-- between exact IK samples (the error there is of the interpolation's size, micrometres), where
-- each step squares the error's relative size.
refineOnto :: Chain -> Tf -> U.Vector Double -> U.Vector Double
refineOnto ch target q0 = go (3 :: Int) q0 (jacobian ch q0)
  where
    n = chainDof ch
    noMask = U.replicate n False
    size (a, b, c, d, e, f) = a * a + b * b + c * c + d * d + e * e + f * f
    go k q (t, j) =
      let e = poseError target t
          q' = U.zipWith (+) q (lmStep n j e 0 noMask)
          next@(t', _) = jacobian ch q'
          better = U.all (\x -> not (isNaN x || isInfinite x)) q' && size (poseError target t') < size e
      in if k == 0 || size e == 0 || not better then q else go (k - 1) q' next

-- | A descent followed until it ends or the clock passes the deadline (ns, checked before each
-- iteration after the first); Left the last iterate reached when the deadline cut it.
followUntil :: Word64 -> Descent -> IO (Either Attempt Attempt)
followUntil deadline = go
  where
    go (Done a) = pure (Right a)
    go (Going a rest) = do
      now <- getMonotonicTimeNSec
      if now > deadline then pure (Left a) else go rest

-- | A descent whose error has not dropped by a tenth for this many iterations restarts.
stallLimit :: Int
stallLimit = 5

-- | Back within [lo, hi]: by whole turns when the range allows (revolute joints with a range of a
-- turn or more), else by clamping.
project :: Double -> Double -> Double -> Double
project lo hi x
  | x > hi = let y = x - 2 * pi * fromIntegral (ceiling ((x - hi) / (2 * pi)) :: Int) in if y >= lo then y else hi
  | x < lo = let y = x + 2 * pi * fromIntegral (ceiling ((lo - x) / (2 * pi)) :: Int) in if y <= hi then y else lo
  | otherwise = x

-- | δ = (JᵀJ + λI)⁻¹ Jᵀe; masked joints get δ = 0 (their columns of J taken as zero). Up to
-- 'primalJoints' joints by the n×n system; beyond, by the same step in its 6×6 form
-- δ = Jᵀ(JJᵀ + λI)⁻¹e (the two are equal for λ > 0: Jᵀ(JJᵀ + λI) = (JᵀJ + λI)Jᵀ), whose cost grows
-- linearly in n, not as n³: one step on a chain of 2000 joints took over a second the n×n way.
-- λ is at least 'lambdaFloor' of the trace of JᵀJ (see 'damped').
lmStep :: Int -> Jacobian -> (Double, Double, Double, Double, Double, Double) -> Double -> U.Vector Bool -> U.Vector Double
lmStep n j e lam mask
  | n <= primalJoints = lmStepPrimal n j e lam mask
  | otherwise = lmStepDual n j e lam mask

-- | Chains of up to this many joints take the n×n form of the step (as cheap as the 6×6 form
-- there).
primalJoints :: Int
primalJoints = 12

-- | The damped system solved with λ, at least 'lambdaFloor' of the trace of JᵀJ (the sum of the
-- squares of J's unmasked entries). Near a solution λ = μ·E is tiny, and where J has less than
-- full rank (a redundant arm, a singular configuration) JᵀJ + λI is then singular to rounding:
-- the factorisation's rounding, about n·ε of the trace, outweighs λ, and its step solves another
-- system, one that can be long and raise the linear model's error |J·δ − e| above |e| (or not be
-- finite). The floor keeps the matrix's condition number within 10¹³. Should the
-- factorisation still break down (a pivot at or under 'pivotFloor' of its diagonal entry, or a
-- step not finite), λ is raised tenfold until it holds; a zero step if it never does (a
-- Jacobian or error that is not finite).
damped :: (Double -> Maybe (U.Vector Double)) -> Int -> Jacobian -> U.Vector Bool -> Double -> U.Vector Double
damped attempt n j mask lam0 = go (0 :: Int) (max lam0 (lambdaFloor * trace))
  where
    trace = U.sum (U.imap (\i x -> if U.unsafeIndex mask (i `quot` 6) then 0 else x * x) (U.take (6 * n) j))
    go !tries lam = case attempt lam of
      Just d | U.all (\x -> not (isNaN x || isInfinite x)) d -> d
      _ | tries >= 40 -> U.replicate n 0
        | otherwise -> go (tries + 1) (10 * lam)

-- | The 6×6 form of 'lmStep'.
lmStepDual :: Int -> Jacobian -> (Double, Double, Double, Double, Double, Double) -> Double -> U.Vector Bool -> U.Vector Double
lmStepDual n j (e0, e1, e2, e3, e4, e5) lam0 mask = damped attempt n j mask lam0
 where
 attempt lam = runST $ do
  a <- M.replicate 36 0
  let col k r = if U.unsafeIndex mask k then 0 else U.unsafeIndex j (6 * k + r)
      accumulate !k
        | k >= n = pure ()
        | otherwise = do
            let go !r !c
                  | r >= 6 = pure ()
                  | c > r = go (r + 1) 0
                  | otherwise = M.unsafeModify a (+ col k r * col k c) (r * 6 + c) >> go r (c + 1)
            go 0 0
            accumulate (k + 1)
  accumulate 0
  mapM_ (\r -> M.unsafeModify a (+ lam) (r * 6 + r)) [0 .. 5]
  ok <- cholesky 6 a
  if not ok then pure Nothing else do
    y <- U.thaw (U.fromListN 6 [e0, e1, e2, e3, e4, e5])
    solveFactored 6 a y
    yv <- U.unsafeFreeze y
    pure (Just (U.generate n (\k -> U.sum (U.imap (\r yr -> col k r * yr) yv))))

-- | The n×n form of 'lmStep', by Cholesky.
lmStepPrimal :: Int -> Jacobian -> (Double, Double, Double, Double, Double, Double) -> Double -> U.Vector Bool -> U.Vector Double
lmStepPrimal n j (e0, e1, e2, e3, e4, e5) lam0 mask = damped attempt n j mask lam0
 where
 attempt lam = runST $ do
  a <- M.new (n * n)
  x <- M.unsafeNew n
  let col k r = if U.unsafeIndex mask k then 0 else U.unsafeIndex j (6 * k + r)
      grad !k
        | k >= n = pure ()
        | otherwise = do
            M.unsafeWrite x k (col k 0 * e0 + col k 1 * e1 + col k 2 * e2 + col k 3 * e3 + col k 4 * e4 + col k 5 * e5)
            grad (k + 1)
  grad 0
  let fill !r !c
        | r >= n = pure ()
        | c > r = fill (r + 1) 0
        | otherwise = do
            let s = col r 0 * col c 0 + col r 1 * col c 1 + col r 2 * col c 2 + col r 3 * col c 3 + col r 4 * col c 4 + col r 5 * col c 5
                v = if r == c then s + lam else s
            M.unsafeWrite a (r * n + c) v
            fill r (c + 1)
  fill 0 0
  ok <- cholesky n a
  if not ok then pure Nothing else do
    solveFactored n a x
    Just <$> U.unsafeFreeze x

-- | Solve L·Lᵀ·x = b in place (b in x on entry) with the lower Cholesky factor of 'cholesky' in
-- the n×n row-major a: forward L·y = b, then back Lᵀ·x = y.
solveFactored :: Int -> M.MVector s Double -> M.MVector s Double -> ST s ()
solveFactored n a x = fwd 0 >> back (n - 1)
  where
    fwd !r
      | r >= n = pure ()
      | otherwise = do
          s <- sumTo r (\k -> (*) <$> M.unsafeRead a (r * n + k) <*> M.unsafeRead x k)
          br <- M.unsafeRead x r
          d <- M.unsafeRead a (r * n + r)
          M.unsafeWrite x r ((br - s) / d)
          fwd (r + 1)
    back !r
      | r < 0 = pure ()
      | otherwise = do
          s <- sumFrom (r + 1) n (\k -> (*) <$> M.unsafeRead a (k * n + r) <*> M.unsafeRead x k)
          yr <- M.unsafeRead x r
          d <- M.unsafeRead a (r * n + r)
          M.unsafeWrite x r ((yr - s) / d)
          back (r - 1)

sumTo :: Int -> (Int -> ST s Double) -> ST s Double
sumTo m f = go 0 0
  where
    go !k !acc
      | k >= m = pure acc
      | otherwise = f k >>= \v -> go (k + 1) (acc + v)
{-# INLINE sumTo #-}

sumFrom :: Int -> Int -> (Int -> ST s Double) -> ST s Double
sumFrom k0 m f = go k0 0
  where
    go !k !acc
      | k >= m = pure acc
      | otherwise = f k >>= \v -> go (k + 1) (acc + v)
{-# INLINE sumFrom #-}

-- | In-place lower Cholesky factor of a symmetric positive definite matrix (lower triangle used);
-- False, part-way, at a pivot not above 'pivotFloor' of its diagonal entry: there the matrix is
-- singular to rounding (the pivot is a difference of nearly equal numbers, and the factor built
-- on it solves a system that is not the one asked).
cholesky :: Int -> M.MVector s Double -> ST s Bool
cholesky n a = outer 0
  where
    outer !c
      | c >= n = pure True
      | otherwise = do
          s <- sumTo c (\k -> (\v -> v * v) <$> M.unsafeRead a (c * n + k))
          d0 <- M.unsafeRead a (c * n + c)
          let p = d0 - s
              d = sqrt p
              rows !r
                | r >= n = pure ()
                | otherwise = do
                    s' <- sumTo c (\k -> (*) <$> M.unsafeRead a (r * n + k) <*> M.unsafeRead a (c * n + k))
                    v <- M.unsafeRead a (r * n + c)
                    M.unsafeWrite a (r * n + c) ((v - s') / d)
                    rows (r + 1)
          if not (p > pivotFloor * d0) || isInfinite p
            then pure False
            else M.unsafeWrite a (c * n + c) d >> rows (c + 1) >> outer (c + 1)

-- | See 'damped'.
pivotFloor, lambdaFloor :: Double
pivotFloor = 1e-12
lambdaFloor = 1e-13

-- | A point the arm cannot move and an upper bound of the distance from it to the tool origin
-- (m). The point is the origin of the deepest link frame that no joint moves: the base, then,
-- while the next constant translation lies on the axes of the revolute joints before it (a
-- column's height d₁ on the first axis), the frame at its end (the shoulder). The bound is the
-- sum of the constant translations after that point plus the largest travel of each prismatic
-- joint from it on: by the triangle inequality no configuration takes the tool farther. A target
-- beyond it has no solution at any joint values; measured from the shoulder rather than the base
-- it leaves out the column, which points nowhere but up.
reachBound :: Chain -> (V3, Double)
reachBound ch = reachFrom ch (shoulderOf ch)

reachFrom :: Chain -> Shoulder -> (V3, Double)
reachFrom ch (Shoulder s frames) = (translation (frames !! s), reachTo ch s (chainLinks ch))

-- | The shoulder's depth (see 'reachBound') and the link frames at zero joint values: frames !! k
-- is base · M₀ · C₁ · … · C_k, the frame in which link k turns (or slides) about z; the last is
-- the tool's. Only the fixed frames' origins and the axes' relations are used, the same at every
-- joint value.
data Shoulder = Shoulder !Int [Tf]

shoulderOf :: Chain -> Shoulder
shoulderOf ch@Chain{..} = Shoulder fixedDepth frames
  where
    q0 = U.replicate chainDof 0
    frames = scanl (\acc i -> motion (chainPrismatic U.! i) (linkVar ch q0 i) acc `compose` constAt chainConst (i + 1))
                   (constAt chainConst 0) [0 .. chainLinks - 1]
    fixedDepth = length (takeWhile id [fixedAfter k | k <- [0 .. chainLinks - 1]])
    -- the origin after link k's motion and C_{k+1} stays put, given that before it does: link k
    -- turns (a slide moves it) and C_{k+1}'s translation, carried back through the frames before,
    -- lies on each revolute axis it passes
    fixedAfter k = not (chainPrismatic U.! k) && onAxes k (translation (constAt chainConst (k + 1)))
    onAxes j v
      | j < 0 || v3Norm v == 0 = True
      | not (chainPrismatic U.! j) && not (alongZ v) = False
      | otherwise = onAxes (j - 1) (rotateBy (constAt chainConst j) v)
    alongZ (V3 x y z) = abs x <= 1e-12 * abs z && abs y <= 1e-12 * abs z
    rotateBy t (V3 x y z) =
      V3 (r00 t * x + r01 t * y + r02 t * z) (r10 t * x + r11 t * y + r12 t * z) (r20 t * x + r21 t * y + r22 t * z)

-- | An upper bound of the distance between the origins of link frames a and b (a ≤ b, see
-- 'Shoulder'): the constant translations C_{a+1} … C_b plus the largest travel of each prismatic
-- link a … b−1 (triangle inequality).
reachTo :: Chain -> Int -> Int -> Double
reachTo Chain{..} a b =
  sum [v3Norm (translation (constAt chainConst i)) | i <- [a + 1 .. b]]
    + sum [maximum (map abs (travel i)) | i <- [a .. b - 1], chainPrismatic U.! i]
  where
    -- the extreme values a prismatic link variable takes over the joint box
    travel i =
      let ts = [chainTermStart U.! i .. chainTermStart U.! (i + 1) - 1]
          lo k = let l = chainLo U.! k in if isInfinite l then 0 else l
          hi k = let h = chainHi U.! k in if isInfinite h then 0 else h
          ext f = chainOffset U.! i + sum [f (c * lo k) (c * hi k) | t <- ts, let k = chainTermJoint U.! t; c = chainTermCoeff U.! t]
      in [ext min, ext max]

-- | A wrist point: a point on the last joint's axis that the last joints turn about, so that it
-- moves with the tool, and a bound of its distance from the shoulder. Where the axes of the last
-- w revolute joints all pass through one point (a spherical wrist: w = 3), that point is fixed in
-- the tool's frame whatever those joints do, and lies at a fixed distance r along the axis of
-- the first of them, link a, from that link's frame origin; so its distance from the shoulder is
-- at most the reach from the shoulder to frame a ('reachTo') plus r. For a target, the point is
-- where the target puts it, and a target that puts it beyond the bound has no solution: a
-- tighter test than the tool's own reach, which counts the wrist-to-tool offset at full length
-- whatever the target's orientation. Candidates: the last axis's frame origin and, where the last
-- two axes cross, their crossing; each is followed back through the axes that pass through it.
-- Fields: the point in the tool's frame, the shoulder, the bound (m), and how many axes meet.
data Wrist = Wrist {wristInTool :: !V3, wristShoulder :: !V3, wristBound :: !Double, wristAxes :: !Int}

wrists :: Chain -> [Wrist]
wrists ch = wristsFrom ch (shoulderOf ch)

wristsFrom :: Chain -> Shoulder -> [Wrist]
wristsFrom ch@Chain{..} (Shoulder s frames)
  | chainLinks < 2 || chainPrismatic U.! (chainLinks - 1) = []
  | otherwise = [ w | p <- candidates, Just w <- [follow p] ]
  where
    tool = frames !! chainLinks
    origin k = translation (frames !! k)
    axis k = rotationColumn 2 (frames !! k)
    lastL = chainLinks - 1
    scale = 1 + sum [v3Norm (translation (constAt chainConst i)) | i <- [0 .. chainLinks]]
    eps = 1e-9 * scale
    -- the distance of point p from link k's axis
    offAxis k p = let d = v3Sub p (origin k); z = axis k in v3Norm (v3Sub d (v3Scale (v3Dot d z) z))
    candidates = origin lastL : [ x | not (chainPrismatic U.! (lastL - 1)), Just x <- [crossing (lastL - 1) lastL]
                                    , v3Norm (v3Sub x (origin lastL)) > eps ]
    -- where the axes of links i and j cross (nearest points within eps, not parallel)
    crossing i j =
      let p1 = origin i; d1 = axis i; p2 = origin j; d2 = axis j
          n = v3Cross d1 d2
          nn = v3Dot n n
          w0 = v3Sub p1 p2
          t1 = v3Dot (v3Cross w0 d2) n / nn
          t2 = v3Dot (v3Cross w0 d1) n / nn
          x1 = v3Add p1 (v3Scale (negate t1) d1)
          x2 = v3Add p2 (v3Scale (negate t2) d2)
      in if nn < 1e-18 || v3Norm (v3Sub x1 x2) > eps then Nothing else Just (v3Scale 0.5 (v3Add x1 x2))
    -- link a: the first of the trailing revolute links whose axes all pass through p
    follow p =
      let a = last (lastL : takeWhile (\k -> not (chainPrismatic U.! k) && offAxis k p <= eps) [lastL, lastL - 1 .. s + 1])
          r = v3Norm (v3Sub p (origin a))
          inTool = applyPoint (inverse tool) p
      in if a <= s then Nothing
         else Just (Wrist inTool (origin s) (reachTo ch s a + r) (chainLinks - a))

-- | A target that puts a wrist point ('wrists') farther from the shoulder than its bound, by
-- more than the tolerances allow (a pose within them moves the point by at most the position
-- tolerance plus the rotation tolerance times the point's distance from the tool), fails at
-- once: the largest excess.
wristCheck :: IkOptions -> Chain -> Tf -> Maybe IkFailure
wristCheck opts ch = wristCheckOf (wrists ch) opts

wristCheckOf :: [Wrist] -> IkOptions -> Tf -> Maybe IkFailure
wristCheckOf ws opts target =
  case [ (d - wristBound w, d, w) | w <- ws
       , let d = v3Norm (v3Sub (applyPoint target (wristInTool w)) (wristShoulder w))
       , d > wristBound w + (ikTolPosition opts + ikTolRotation opts * v3Norm (wristInTool w)) * 1.0001 ] of
    [] -> Nothing
    xs -> let (excess, d, w) = foldr1 (\x y -> if fst3 x >= fst3 y then x else y) xs
          in Just (Unreachable (wristWords d w) excess)
  where
    fst3 (x, _, _) = x
    mm x = showFFloat (Just 1) (x * 1000) " mm"
    wristWords d w =
      "the wrist point (" ++ (if wristAxes w >= 2 then "where the last " ++ show (wristAxes w) ++ " joint axes meet, " else "on the last joint's axis, ")
      ++ mm (v3Norm (wristInTool w)) ++ " from the tool point) is " ++ mm d ++ " from the shoulder at this orientation; the arm reaches it within "
      ++ mm (wristBound w)

-- | When every revolute link of the chain turns about one common direction (a SCARA), the tool
-- can only turn about that direction: the angle (rad) between it and its image under the rotation
-- from the tool's orientation at mid-limits to the target's, which every solution's rotation error
-- is at least; Nothing for any other chain. (Axes parallel at one configuration stay parallel at
-- all: turning about a direction keeps the directions parallel to it.)
orientationTilt :: Chain -> Tf -> Maybe Double
orientationTilt ch target = case axes 0 (constAt (chainConst ch) 0) of
  [] -> Nothing
  a0 : rest
    | all (\x -> v3Norm (v3Cross a0 x) <= 1e-12 * v3Norm a0 * v3Norm x) rest ->
        let a = v3Scale (1 / v3Norm a0) a0
            ref = forward ch q0
            -- target · refᵀ applied to a (rotation parts only)
            V3 bx by bz = rotate ref True a
            b = rotate target False (V3 bx by bz)
        in Just (atan2 (v3Norm (v3Cross a b)) (v3Dot a b))
    | otherwise -> Nothing
  where
    q0 = midLimits ch
    -- the world direction of each revolute link's axis at mid-limits
    axes i acc
      | i >= chainLinks ch = []
      | otherwise =
          let pr = chainPrismatic ch U.! i
              next = motion pr (linkVar ch q0 i) acc `compose` constAt (chainConst ch) (i + 1)
          in [V3 (r02 acc) (r12 acc) (r22 acc) | not pr] ++ axes (i + 1) next
    rotate t transposed (V3 x y z)
      | transposed = V3 (r00 t * x + r10 t * y + r20 t * z) (r01 t * x + r11 t * y + r21 t * z) (r02 t * x + r12 t * y + r22 t * z)
      | otherwise = V3 (r00 t * x + r01 t * y + r02 t * z) (r10 t * x + r11 t * y + r12 t * z) (r20 t * x + r21 t * y + r22 t * z)

-- | A target whose orientation is farther than the rotation tolerance from every orientation the
-- tool can take ('orientationTilt') fails at once, without a descent.
orientationCheck :: IkOptions -> Chain -> Tf -> Maybe IkFailure
orientationCheck opts ch target = case orientationTilt ch target of
  Just tilt | tilt > ikTolRotation opts * 1.0001 + 1e-12 -> Just (OrientationUnreachable tilt)
  _ -> Nothing

-- | A target farther from the shoulder than the chain reaches ('reachBound') by more than the
-- position tolerance fails at once, without a descent.
reachCheck :: IkOptions -> (V3, Double) -> Tf -> Maybe IkFailure
reachCheck opts (origin, bound) target
  | dist > bound + ikTolPosition opts * 1.0001 = Just (BeyondReach dist bound)
  | otherwise = Nothing
  where
    dist = v3Norm (v3Sub (translation target) origin)

-- | What the checks before any descent need of a chain, worked out once per chain
-- ('prepareNumeric'; 'VProf.Kinematics.Ik.prepareChain' keeps it with the chain): the
-- shoulder and the tool's reach from it ('reachBound'), and the wrist points (about a
-- microsecond a solve for a seven-axis arm otherwise, a tenth of a solve). Both come from one
-- pass over the chain's frames at zero.
data Prepared = Prepared (V3, Double) [Wrist]

prepareNumeric :: Chain -> Prepared
prepareNumeric ch = let sh = shoulderOf ch in Prepared (reachFrom ch sh) (wristsFrom ch sh)

-- | The failures known before any descent: an orientation the tool cannot take, a target out of
-- reach, a wrist point out of reach at the target's orientation.
precheck :: Prepared -> IkOptions -> Chain -> Tf -> Maybe IkFailure
precheck (Prepared reach ws) opts ch target = case orientationCheck opts ch target of
  Just f -> Just f
  Nothing -> case reachCheck opts reach target of
    Just f -> Just f
    Nothing -> wristCheckOf ws opts target

-- | How many descents without limits the diagnosis of a failed solve tries, and how long each.
probeStarts, probeIterations :: Int
probeStarts = 20
probeIterations = 100

-- | Pure solve: the seed and up to 'ikMaxRestarts' random starts.
solveNumeric :: IkOptions -> Chain -> Tf -> Maybe (U.Vector Double) -> Either IkFailure [IkSolution]
solveNumeric opts ch = solveNumericWith (prepareNumeric ch) opts ch

-- | 'solveNumeric' with the chain's 'Prepared' checks.
solveNumericWith :: Prepared -> IkOptions -> Chain -> Tf -> Maybe (U.Vector Double) -> Either IkFailure [IkSolution]
solveNumericWith prep opts ch target seedM
  | Just f <- precheck prep opts ch target = Left f
  | otherwise = finish prep opts ch target seed (take (1 + ikMaxRestarts opts) (attempts opts True ch target seed)) probe
  where
    seed = maybe (midLimits ch) id seedM
    probe = take probeStarts (attempts opts {ikMaxIterations = probeIterations} False ch target seed)

-- | Like 'solveNumeric', also stopping when the wall-time budget (seconds) is spent: checked
-- between two iterations of a descent, so that a long chain's descent does not overrun it; the
-- diagnosis of a failure (the descents without limits) shares the same budget.
solveNumericIO :: Double -> IkOptions -> Chain -> Tf -> Maybe (U.Vector Double) -> IO (Either IkFailure [IkSolution])
solveNumericIO budget opts ch = solveNumericIOWith (prepareNumeric ch) budget opts ch

-- | 'solveNumericIO' with the chain's 'Prepared' checks.
solveNumericIOWith :: Prepared -> Double -> IkOptions -> Chain -> Tf -> Maybe (U.Vector Double) -> IO (Either IkFailure [IkSolution])
solveNumericIOWith prep _ opts ch target _
  | Just f <- precheck prep opts ch target = pure (Left f)
solveNumericIOWith prep budget opts ch target seedM = do
  t0 <- getMonotonicTimeNSec
  let deadline = t0 + round (max 0 budget * 1e9)
      -- the descents in turn until one ends that stops the run, or the deadline cuts one
      follow stop acc (d : rest) = do
        r <- followUntil deadline d
        case r of
          Left cut -> pure (reverse (cut : acc))
          Right a
            | stop a -> pure (reverse (a : acc))
            | otherwise -> follow stop (a : acc) rest
      follow _ acc [] = pure (reverse acc)
      descents o limited = map (descent o limited ch target) (starts (ikRandomSeed opts) ch seed)
  as <- follow (\a -> attConverged a && not (ikAllSolutions opts)) [] (take (1 + ikMaxRestarts opts) (descents opts True))
  case finish prep opts ch target seed as [] of
    Right sols -> pure (Right sols)
    Left _ -> do
      -- no solution: the diagnosis's descents without limits, in what is left of the budget
      probe <- follow (const False) [] (take probeStarts (descents opts {ikMaxIterations = probeIterations} False))
      pure (finish prep opts ch target seed as probe)
  where
    seed = maybe (midLimits ch) id seedM

-- | The solutions among the descents, or the diagnosis of none: beyond reach, outside the limits
-- (a descent without limits, of the probe, converged outside them), or not converged.
finish :: Prepared -> IkOptions -> Chain -> Tf -> U.Vector Double -> [Attempt] -> [Attempt] -> Either IkFailure [IkSolution]
finish (Prepared (origin, bound) _) opts ch target seed as probe =
  case found of
    [] -> Left diagnose
    sols -> Right (sortBySeed (dedupe sols))
  where
    taken = if ikAllSolutions opts then as else takeUntil attConverged as
    found =
      [ IkSolution q pe re (seedDistance q seed) Nothing
      | Attempt q _ _ True _ <- taken
      , withinLimits (ikLimitTolerance opts) ch q
      , let (pe, re) = residual (forward ch q) target
      , pe <= ikTolPosition opts * 1.0001 && re <= ikTolRotation opts * 1.0001 ]
    dedupe [] = []
    dedupe (s : rest) = s : dedupe [r | r <- rest, seedDistance (solJoints r) (solJoints s) > 1e-4]
    dist = v3Norm (v3Sub (translation target) origin)
    names = map jointName (robotJoints (chainRobot ch))
    diagnose
      | dist > bound = BeyondReach dist bound
      | otherwise =
          -- does the pose have solutions if the limits are lifted?
          let outside = [limitViolations (ikLimitTolerance opts) ch (attJoints a) | a <- probe, attConverged a]
          in case [v | v <- outside, not (null v)] of
               (v : _) -> OutsideLimits [[(names !! i, x) | (i, x) <- v]]
               [] -> let best = minimumOn (\a -> attPosition a + attRotation a) as
                     in maybe (NotConverged (1 / 0) (1 / 0)) (\a -> NotConverged (attPosition a) (attRotation a)) best
    minimumOn _ [] = Nothing
    minimumOn f xs = Just (foldr1 (\a b -> if f a <= f b then a else b) xs)

takeUntil :: (a -> Bool) -> [a] -> [a]
takeUntil _ [] = []
takeUntil p (x : xs) = if p x then [x] else x : takeUntil p xs
