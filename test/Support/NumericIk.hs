{-# LANGUAGE BangPatterns #-}
-- | An independent count of IK solutions: damped least squares (Levenberg–Marquardt)
-- on the 6-D pose error of a standard-DH forward kinematics, with a forward-difference
-- Jacobian, from many deterministic pseudo-random seeds; converged results (pose error
-- below 1e-10 by the list-based oracle) are wrapped into (−π, π] and deduplicated.
-- Joint limits are not applied. Its own strict FK ('fastFk', checked against the oracle
-- in the spec) keeps a thousand seeds per pose affordable.
module Support.NumericIk
  ( numericSolutions, wrapAngle, angleDist, fastFk, M34 (..), m34ToMat
  ) where

import Data.Bits (shiftL, shiftR, xor)
import Data.List (foldl')
import Data.Word (Word64)
import Support.DhOracle

wrapAngle :: Double -> Double
wrapAngle x = let y = x - 2 * pi * fromIntegral (round (x / (2 * pi)) :: Int)
              in if y <= -pi then y + 2 * pi else y

-- | Largest joint difference modulo 2π.
angleDist :: [Double] -> [Double] -> Double
angleDist a b = maximum (zipWith (\x y -> abs (wrapAngle (x - y))) a b)

-- | A homogeneous transform's top three rows.
data M34 = M34 !Double !Double !Double !Double !Double !Double !Double !Double !Double !Double !Double !Double

m34ToMat :: M34 -> Mat4
m34ToMat (M34 a b c d e f g h i j k l) = [[a, b, c, d], [e, f, g, h], [i, j, k, l], [0, 0, 0, 1]]

mul :: M34 -> M34 -> M34
mul (M34 a b c d e f g h i j k l) (M34 a' b' c' d' e' f' g' h' i' j' k' l') =
  M34 (a * a' + b * e' + c * i') (a * b' + b * f' + c * j') (a * c' + b * g' + c * k') (a * d' + b * h' + c * l' + d)
      (e * a' + f * e' + g * i') (e * b' + f * f' + g * j') (e * c' + f * g' + g * k') (e * d' + f * h' + g * l' + h)
      (i * a' + j * e' + k * i') (i * b' + j * f' + k * j') (i * c' + j * g' + k * k') (i * d' + j * h' + k * l' + l)

-- | Standard DH, identity base and tool.
fastFk :: [DhRow] -> [Double] -> M34
fastFk rows qs = foldl' mul (M34 1 0 0 0 0 1 0 0 0 0 1 0) (zipWith link rows qs)
  where
    link (DhRow off d a al) q =
      let th = q + off; ct = cos th; st = sin th; ca = cos al; sa = sin al
      in M34 ct (-st * ca) (st * sa) (a * ct) st (ct * ca) (-ct * sa) (a * st) 0 sa ca d

-- | Position error and orientation error ½ Σ cᵢ × c*ᵢ over the rotation's columns.
errorVec :: M34 -> M34 -> [Double]
errorVec (M34 ta tb tc td te tf tg th ti tj tk tl) (M34 a b c d e f g h i j k l) =
  let cr (x1, y1, z1) (x2, y2, z2) = (y1 * z2 - z1 * y2, z1 * x2 - x1 * z2, x1 * y2 - y1 * x2)
      (r1, r2, r3) = cr (a, e, i) (ta, te, ti)
      (s1, s2, s3) = cr (b, f, j) (tb, tf, tj)
      (u1, u2, u3) = cr (c, g, k) (tc, tg, tk)
  in [td - d, th - h, tl - l, 0.5 * (r1 + s1 + u1), 0.5 * (r2 + s2 + u2), 0.5 * (r3 + s3 + u3)]

norm :: [Double] -> Double
norm = sqrt . sum . map (\x -> x * x)

-- | Solve the 6×6 system a x = b by Gaussian elimination with partial pivoting.
solve6 :: [[Double]] -> [Double] -> Maybe [Double]
solve6 a0 b0 = go (zipWith (\r x -> r ++ [x]) a0 b0) []
  where
    go [] done = Just (backSub done)
    go rows done =
      let pivotRow = foldr1 (\r s -> if abs (head r) >= abs (head s) then r else s) rows
          rest = dropOne pivotRow rows
          p = head pivotRow
      in if abs p < 1e-300 then Nothing else
           let elim r = let f = head r / p in zipWith (\x y -> x - f * y) (tail r) (tail pivotRow)
           in go (map elim rest) (pivotRow : done)
    dropOne r (x : xs) | x == r = xs | otherwise = x : dropOne r xs
    dropOne _ [] = []
    backSub = foldl' (\xs row -> let coeffs = init (tail row); rhs = last row
                                     x = (rhs - sum (zipWith (*) coeffs xs)) / head row
                                 in x : xs) []

-- | LM from one seed; the converged joint vector if the pose error falls below 1e-11.
lm :: ([Double] -> M34) -> M34 -> [Double] -> Maybe [Double]
lm fk target = go (0 :: Int) 1e-2
  where
    go it lam q
      | it > 400 = Nothing
      | otherwise =
          let e = errorVec target (fk q)
              en = norm e
          in if en < 1e-11 then Just q else
               let h = 1e-7
                   cols = [map (/ h) (zipWith (-) e (errorVec target (fk (bump k h q)))) | k <- [0 .. 5 :: Int]]
                   -- e(q + δ) ≈ e(q) − J δ; J's columns are cols
                   jtj = [[sum (zipWith (*) ci cj) + (if i == j then lam else 0) | (j, cj) <- zip [0 :: Int ..] cols] | (i, ci) <- zip [0 ..] cols]
                   jte = [sum (zipWith (*) ci e) | ci <- cols]
               in case solve6 jtj jte of
                    Nothing -> Nothing
                    Just d ->
                      let q' = zipWith (+) q d
                          en' = norm (errorVec target (fk q'))
                      in if en' < en then go (it + 1) (max 1e-12 (lam / 5)) q'
                         else go (it + 1) (lam * 4) q
    bump k h q = [if i == k then x + h else x | (i, x) <- zip [0 ..] q]

-- | Every distinct solution found from @n@ seeds (deterministic xorshift), wrapped into
-- (−π, π]; each checked with the list-based oracle to 1e-10.
numericSolutions :: Int -> [DhRow] -> Mat4 -> [[Double]]
numericSolutions n rows target = foldl' add [] found
  where
    fk = fastFk rows
    tgt = case target of
      [[a, b, c, d], [e, f, g, h], [i, j, k, l], _] -> M34 a b c d e f g h i j k l
      _ -> error "4x4"
    seeds = take n (chunks (map toAngle (tail (iterate xorshift 0x9E3779B97F4A7C15))))
    toAngle w = (fromIntegral (w `mod` 1000003) / 1000003 * 2 - 1) * pi
    chunks xs = let (a, b) = splitAt 6 xs in a : chunks b
    found = [ map wrapAngle q | Just q <- map (lm fk tgt) seeds
            , poseError (fkOracle rows ident4 ident4 q) target < 1e-10 ]
    add acc q = if any (\p -> angleDist p q < 1e-6) acc then acc else acc ++ [q]

xorshift :: Word64 -> Word64
xorshift x0 =
  let x1 = x0 `xor` (x0 `shiftL` 13)
      x2 = x1 `xor` (x1 `shiftR` 7)
  in x2 `xor` (x2 `shiftL` 17)
