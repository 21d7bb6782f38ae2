-- | A textbook standard-DH forward kinematics, written apart from the solver as a test
-- oracle: 4×4 homogeneous matrices as lists of rows, one link
-- A = Rz(θ)·Tz(d)·Tx(a)·Rx(α) multiplied out as in Spong & Vidyasagar (3.10), and
-- T = base · A1 ⋯ An · tool.
module Support.DhOracle
  ( DhRow (..), Mat4, fkOracle, fkFrames, matMul, ident4, poseError
  ) where

import Data.List (transpose)

-- | One revolute row: θ offset, d, a, α (m, rad).
data DhRow = DhRow { rowOffset, rowD, rowA, rowAlpha :: Double } deriving (Show)

type Mat4 = [[Double]]

ident4 :: Mat4
ident4 = [[if i == j then 1 else 0 | j <- [0 .. 3 :: Int]] | i <- [0 .. 3 :: Int]]

matMul :: Mat4 -> Mat4 -> Mat4
matMul x y = [[sum (zipWith (*) r c) | c <- transpose y] | r <- x]

linkMatrix :: DhRow -> Double -> Mat4
linkMatrix (DhRow off d a al) q =
  let th = q + off
      ct = cos th; st = sin th; ca = cos al; sa = sin al
  in [ [ct, -st * ca, st * sa, a * ct]
     , [st, ct * ca, -ct * sa, a * st]
     , [0, sa, ca, d]
     , [0, 0, 0, 1] ]

-- | base · A1(q1) ⋯ An(qn) · tool.
fkOracle :: [DhRow] -> Mat4 -> Mat4 -> [Double] -> Mat4
fkOracle rows base tool qs = foldl matMul base (zipWith linkMatrix rows qs) `matMul` tool

-- | base · A1 ⋯ Ak for k = 0 .. n (the link frames).
fkFrames :: [DhRow] -> Mat4 -> [Double] -> [Mat4]
fkFrames rows base qs = scanl matMul base (zipWith linkMatrix rows qs)

-- | Largest absolute difference of the top three rows (rotation and translation).
poseError :: Mat4 -> Mat4 -> Double
poseError x y = maximum (zipWith (\r s -> maximum (map abs (zipWith (-) r s))) (take 3 x) (take 3 y))
