-- | An independent count of IK solutions: damped least squares (Levenberg–Marquardt)
-- on the 6-D pose error of the oracle's forward kinematics, with a forward-difference
-- Jacobian, from many deterministic random seeds; converged results are wrapped into
-- (−π, π] and deduplicated. Joint limits are not applied. Slow (milliseconds), for tests.
module Support.NumericIk
  ( numericSolutions, wrapAngle, angleDist
  ) where

import Data.Bits (shiftL, shiftR, xor)
import Data.List (foldl')
import Data.Word (Word64)
import Numeric.LinearAlgebra (Matrix, Vector, fromList, fromLists, ident, linearSolve, asColumn, toList, flatten, tr, (<>), scale)
import Prelude hiding ((<>))
import Support.DhOracle

wrapAngle :: Double -> Double
wrapAngle x = let y = x - 2 * pi * fromIntegral (round (x / (2 * pi)) :: Int)
              in if y <= -pi then y + 2 * pi else y

-- | Largest joint difference modulo 2π.
angleDist :: [Double] -> [Double] -> Double
angleDist a b = maximum (zipWith (\x y -> abs (wrapAngle (x - y))) a b)

-- | Position error and orientation error ½ Σ cᵢ × c*ᵢ over the rotation's columns.
errorVec :: Mat4 -> Mat4 -> [Double]
errorVec target cur =
  let col m j = [m !! i !! j | i <- [0 .. 2]]
      crossL [a, b, c] [x, y, z] = [b * z - c * y, c * x - a * z, a * y - b * x]
      crossL _ _ = [0, 0, 0]
      pos = [target !! i !! 3 - cur !! i !! 3 | i <- [0 .. 2]]
      rot = foldl' (zipWith (+)) [0, 0, 0] [crossL (col cur j) (col target j) | j <- [0 .. 2]]
  in pos ++ map (* 0.5) rot

-- | LM from one seed; the converged joint vector if the pose error falls below 1e-13.
lm :: ([Double] -> Mat4) -> Mat4 -> [Double] -> Maybe [Double]
lm fk target = go (0 :: Int) 1e-3
  where
    go it lam q
      | it > 300 = Nothing
      | otherwise =
          let e = errorVec target (fk q)
              en = sqrt (sum (map (^ (2 :: Int)) e))
          in if en < 1e-13 then Just q else
               let h = 1e-7
                   jcols = [ map (/ h) (zipWith (-) e (errorVec target (fk (bump k h q)))) | k <- [0 .. 5 :: Int] ]
                   -- e(q + δ) ≈ e(q) − J δ with J's columns (e(q) − e(q + h eₖ))/h
                   jm = tr (fromLists jcols) :: Matrix Double
                   ev = fromList e :: Vector Double
                   a = tr jm <> jm + scale lam (ident 6)
                   g = tr jm <> asColumn ev
               in case linearSolve a g of
                    Nothing -> Nothing
                    Just dm ->
                      let d = toList (flatten dm)
                          q' = zipWith (+) q d
                          e' = errorVec target (fk q')
                          en' = sqrt (sum (map (^ (2 :: Int)) e'))
                      in if en' < en then go (it + 1) (max 1e-12 (lam / 3)) q'
                         else go (it + 1) (lam * 4) q
    bump k h q = [if i == k then x + h else x | (i, x) <- zip [0 ..] q]

-- | Every distinct solution found from @n@ seeds (deterministic xorshift), wrapped into (−π, π].
numericSolutions :: Int -> ([Double] -> Mat4) -> Mat4 -> [[Double]]
numericSolutions n fk target = foldl' add [] found
  where
    seeds = take n (chunks (map toAngle (iterate xorshift 0x9E3779B97F4A7C15)))
    toAngle w = (fromIntegral (w `mod` 1000003) / 1000003 * 2 - 1) * pi
    chunks xs = let (a, b) = splitAt 6 (drop 1 xs) in a : chunks b
    found = [map wrapAngle q | Just q <- map (lm fk target) seeds, poseError (fk q) target < 1e-11]
    add acc q = if any (\p -> angleDist p q < 1e-6) acc then acc else acc ++ [q]

xorshift :: Word64 -> Word64
xorshift x0 =
  let x1 = x0 `xor` (x0 `shiftL` 13)
      x2 = x1 `xor` (x1 `shiftR` 7)
  in x2 `xor` (x2 `shiftL` 17)
