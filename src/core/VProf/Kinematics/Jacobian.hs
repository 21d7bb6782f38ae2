{-# LANGUAGE BangPatterns, RecordWildCards #-}
-- | The geometric Jacobian of the tool frame with respect to the actuated joints, Yoshikawa's
-- manipulability and the condition number.
--
-- Rows 0–2 are the linear velocity of the tool origin, rows 3–5 the angular velocity, both in the
-- world (base) frame. Invariant: a coupled link contributes its column times the coupling
-- coefficient to every joint that drives it, so J·q̇ is the true tool twist also for the Dobot's
-- linkage and URDF mimic joints. Stored column-major (6 doubles per joint).
module VProf.Kinematics.Jacobian
  ( Jacobian
  , jacobian
  , jacobianRows
  , manipulability
  , manipulabilityQr
  , conditionNumber
  , singularValues
  , smallestSingularValueAbove
  ) where

import Control.Monad.ST (ST, runST)
import qualified Data.Vector.Unboxed as U
import qualified Data.Vector.Unboxed.Mutable as M
import qualified Numeric.LinearAlgebra as LA

import VProf.Kinematics.Forward (constAt, stepLink)
import VProf.Kinematics.Model
import VProf.Kinematics.Transform

-- | Column-major 6×n.
type Jacobian = U.Vector Double

-- | The tool transform and the Jacobian at q (one sweep storing each moving axis, then the
-- columns; all in one mutable buffer).
jacobian :: Chain -> U.Vector Double -> (Tf, Jacobian)
jacobian ch@Chain{..} q = runST $ do
  axes <- M.unsafeNew (6 * chainLinks)
  let sweep !i !a00 !a01 !a02 !ax !a10 !a11 !a12 !ay !a20 !a21 !a22 !az
        | i >= chainLinks = pure (Tf a00 a01 a02 ax a10 a11 a12 ay a20 a21 a22 az)
        | otherwise = do
            -- the link moves about the z axis of this frame, through its origin
            let b = 6 * i
            M.unsafeWrite axes b a02; M.unsafeWrite axes (b + 1) a12; M.unsafeWrite axes (b + 2) a22
            M.unsafeWrite axes (b + 3) ax; M.unsafeWrite axes (b + 4) ay; M.unsafeWrite axes (b + 5) az
            stepLink ch q i a00 a01 a02 ax a10 a11 a12 ay a20 a21 a22 az (sweep (i + 1))
      Tf b00 b01 b02 bx b10 b11 b12 by b20 b21 b22 bz = constAt chainConst 0
  tool <- sweep 0 b00 b01 b02 bx b10 b11 b12 by b20 b21 b22 bz
  j <- M.replicate (6 * chainDof) 0
  let !ex = tx tool; !ey = ty tool; !ez = tz tool
      link !i
        | i >= chainLinks = pure ()
        | otherwise = do
            let b = 6 * i
            zx <- M.unsafeRead axes b; zy <- M.unsafeRead axes (b + 1); zz <- M.unsafeRead axes (b + 2)
            ox <- M.unsafeRead axes (b + 3); oy <- M.unsafeRead axes (b + 4); oz <- M.unsafeRead axes (b + 5)
            let pr = U.unsafeIndex chainPrismatic i
                dx = ex - ox; dy = ey - oy; dz = ez - oz
                !c0 = if pr then zx else zy*dz - zz*dy
                !c1 = if pr then zy else zz*dx - zx*dz
                !c2 = if pr then zz else zx*dy - zy*dx
                !c3 = if pr then 0 else zx
                !c4 = if pr then 0 else zy
                !c5 = if pr then 0 else zz
                end = U.unsafeIndex chainTermStart (i + 1)
                terms !t
                  | t >= end = pure ()
                  | otherwise = do
                      let k = U.unsafeIndex chainTermJoint t; c = U.unsafeIndex chainTermCoeff t; o = 6 * k
                      addAt j o (c * c0); addAt j (o + 1) (c * c1); addAt j (o + 2) (c * c2)
                      addAt j (o + 3) (c * c3); addAt j (o + 4) (c * c4); addAt j (o + 5) (c * c5)
                      terms (t + 1)
            terms (U.unsafeIndex chainTermStart i)
            link (i + 1)
  link 0
  jf <- U.unsafeFreeze j
  pure (tool, jf)

addAt :: M.MVector s Double -> Int -> Double -> ST s ()
addAt v i x = M.unsafeModify v (+ x) i
{-# INLINE addAt #-}

-- | The Jacobian as 6 rows of n.
jacobianRows :: Int -> Jacobian -> [[Double]]
jacobianRows n j = [[j U.! (6 * k + r) | k <- [0 .. n - 1]] | r <- [0 .. 5]]

-- | Singular values of the 6×n Jacobian (largest first; min(6, n) of them).
singularValues :: Int -> Jacobian -> [Double]
singularValues n j
  | n == 0 = []
  | otherwise = take (min 6 n) (LA.toList (LA.singularValues (LA.fromLists (jacobianRows n j))))

-- | Whether the smallest of the 'singularValues' is above t (t ≥ 0), without them: the Gram
-- matrix G (Jᵀ·J, n × n, for n ≤ 6; J·Jᵀ, 6 × 6, above) has the squared singular values as its
-- eigenvalues, so σ_min > t exactly when G − t²·I is positive definite, which its Cholesky
-- factorisation tells (every pivot > 0): about a hundred operations instead of an SVD. Pivots
-- within rounding of 0 (σ_min within about 1e-8·σ_max of t) can go either way.
smallestSingularValueAbove :: Int -> Jacobian -> Double -> Bool
smallestSingularValueAbove n j t
  | n == 0 = False
  | otherwise = runST $ do
      let m = min 6 n
          -- G = Jᵀ·J (entries over the 6 rows) for n ≤ 6, else J·Jᵀ (over the n columns)
          g a b
            | n <= 6 = sum [ j U.! (6 * a + r) * j U.! (6 * b + r) | r <- [0 .. 5] ]
            | otherwise = sum [ j U.! (6 * k + a) * j U.! (6 * k + b) | k <- [0 .. n - 1] ]
      l <- M.replicate (m * m) 0
      let col !c
            | c >= m = pure True
            | otherwise = do
                s <- sumOver (\k -> (\x -> x * x) <$> M.read l (c * m + k)) c
                let d = g c c - t * t - s
                if not (d > 0) then pure False else do
                  let p = sqrt d
                  M.write l (c * m + c) p
                  let below !r
                        | r >= m = pure ()
                        | otherwise = do
                            s' <- sumOver (\k -> (*) <$> M.read l (r * m + k) <*> M.read l (c * m + k)) c
                            M.write l (r * m + c) ((g r c - s') / p)
                            below (r + 1)
                  below (c + 1)
                  col (c + 1)
          sumOver f e = go 0 0 where go !k !acc = if k >= e then pure acc else f k >>= \v -> go (k + 1) (acc + v)
      col 0

-- | Yoshikawa's manipulability √det(J·Jᵀ) for n ≥ 6 (√det(Jᵀ·J) for n < 6): the product of the
-- singular values.
manipulability :: Int -> Jacobian -> Double
manipulability n j = product (singularValues n j)

-- | The manipulability by a Householder QR factorisation instead of the singular values:
-- √det(J·Jᵀ) = |det R| for Jᵀ = Q·R with six joints or more, √det(Jᵀ·J) = |det R| for J = Q·R
-- below (the product of R's diagonal). Equal to 'manipulability' up to rounding (QR's accuracy is
-- the SVD's: about 1e-16 × the condition number, relative), at a fraction of its cost: for ranking
-- many joint vectors by it.
manipulabilityQr :: Int -> Jacobian -> Double
manipulabilityQr n j = runST $ do
  -- A: p rows × m columns, p ≥ m, row-major
  let (p, m) = if n >= 6 then (n, 6) else (6, n)
      at r c = if n >= 6 then U.unsafeIndex j (6 * r + c) else U.unsafeIndex j (6 * c + r)
  a <- M.unsafeNew (p * m)
  let fill !r !c
        | r >= p = pure ()
        | c >= m = fill (r + 1) 0
        | otherwise = M.unsafeWrite a (r * m + c) (at r c) >> fill r (c + 1)
      sumRows !r !acc e f = if r >= e then pure acc else f r >>= \v -> sumRows (r + 1) (acc + v) e f
      -- column c: the reflection of rows c.. that zeroes below the diagonal, applied to the
      -- columns right of c; |R_cc| = the norm of the column below the diagonal
      column !c !prod
        | c >= m = pure prod
        | otherwise = do
            nn <- sumRows c 0 p (\r -> (\v -> v * v) <$> M.unsafeRead a (r * m + c))
            if not (nn > 0) then pure 0 else do
              x0 <- M.unsafeRead a (c * m + c)
              let norm = sqrt nn
                  alpha = if x0 >= 0 then negate norm else norm
                  -- v = x − α e1: only its first entry changes; vᵀv = 2 (nn − α x0)
                  v0 = x0 - alpha
                  vv = 2 * (nn - alpha * x0)
                  vAt r = if r == c then pure v0 else M.unsafeRead a (r * m + c)
                  reflect !k
                    | k >= m = pure ()
                    | otherwise = do
                        dotv <- sumRows c 0 p (\r -> (*) <$> vAt r <*> M.unsafeRead a (r * m + k))
                        let f = 2 * dotv / vv
                            upd !r
                              | r >= p = pure ()
                              | otherwise = do
                                  vr <- vAt r
                                  M.unsafeModify a (\y -> y - f * vr) (r * m + k)
                                  upd (r + 1)
                        upd c
                        reflect (k + 1)
              if vv > 0 then reflect (c + 1) else pure ()
              column (c + 1) (prod * norm)
  if m == 0 then pure 1 else fill 0 0 >> column 0 1

-- | σ_max / σ_min (infinite at a singularity).
conditionNumber :: Int -> Jacobian -> Double
conditionNumber n j = case singularValues n j of
  [] -> 1 / 0
  svs -> let lo = minimum svs in if lo <= 0 then 1 / 0 else maximum svs / lo
