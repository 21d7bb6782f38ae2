-- | A textbook forward kinematics written apart from the library: 4×4 homogeneous matrices as
-- plain lists of rows, one elementary matrix per DH step, the URDF axis rotation by Rodrigues'
-- formula. Slow and obvious on purpose; the tests compare the library against it.
module Support.FkOracle
  ( Mat
  , mmul
  , ident
  , rx
  , rz
  , ry
  , tr
  , dhStd
  , dhMod
  , urdfJoint
  , rpyMat
  , axisAngle
  , matFromRows
  , maxDiff
  ) where

import Data.List (transpose)

type Mat = [[Double]]

mmul :: Mat -> Mat -> Mat
mmul a b = [[sum (zipWith (*) row col) | col <- transpose b] | row <- a]

ident :: Mat
ident = [[if i == j then 1 else 0 | j <- [0 .. 3 :: Int]] | i <- [0 .. 3 :: Int]]

rx, ry, rz :: Double -> Mat
rx t = [[1, 0, 0, 0], [0, cos t, -sin t, 0], [0, sin t, cos t, 0], [0, 0, 0, 1]]
ry t = [[cos t, 0, sin t, 0], [0, 1, 0, 0], [-sin t, 0, cos t, 0], [0, 0, 0, 1]]
rz t = [[cos t, -sin t, 0, 0], [sin t, cos t, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]

tr :: Double -> Double -> Double -> Mat
tr x y z = [[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z], [0, 0, 0, 1]]

-- | Standard DH: Rz(θ)·Dz(d)·Dx(a)·Rx(α).
dhStd :: Double -> Double -> Double -> Double -> Mat
dhStd th d a al = foldr1 mmul [rz th, tr 0 0 d, tr a 0 0, rx al]

-- | Modified DH: Rx(α)·Dx(a)·Rz(θ)·Dz(d).
dhMod :: Double -> Double -> Double -> Double -> Mat
dhMod al a th d = foldr1 mmul [rx al, tr a 0 0, rz th, tr 0 0 d]

-- | Rotation by angle t about the unit axis (ux, uy, uz): Rodrigues' formula.
axisAngle :: (Double, Double, Double) -> Double -> Mat
axisAngle (ux, uy, uz) t =
  let c = cos t; s = sin t; v = 1 - c
  in [ [c + ux*ux*v, ux*uy*v - uz*s, ux*uz*v + uy*s, 0]
     , [uy*ux*v + uz*s, c + uy*uy*v, uy*uz*v - ux*s, 0]
     , [uz*ux*v - uy*s, uz*uy*v + ux*s, c + uz*uz*v, 0]
     , [0, 0, 0, 1] ]

rpyMat :: (Double, Double, Double) -> Mat
rpyMat (r, p, y) = rz y `mmul` ry p `mmul` rx r

-- | A URDF joint: origin (xyz, rpy), then rotation about / translation along the (normalised) axis.
urdfJoint :: (Double, Double, Double) -> (Double, Double, Double) -> (Double, Double, Double) -> Maybe Bool -> Double -> Mat
urdfJoint (x, y, z) rpy (ax, ay, az) prismatic q =
  let n = sqrt (ax*ax + ay*ay + az*az); u = (ax / n, ay / n, az / n); (ux, uy, uz) = u
      motion = case prismatic of
        Nothing -> ident
        Just False -> axisAngle u q
        Just True -> tr (q*ux) (q*uy) (q*uz)
  in tr x y z `mmul` rpyMat rpy `mmul` motion

matFromRows :: [Double] -> Mat
matFromRows xs = take 4 (chunks xs ++ [[0, 0, 0, 1]])
  where
    chunks [] = []
    chunks ys = take 4 ys : chunks (drop 4 ys)

maxDiff :: Mat -> Mat -> Double
maxDiff a b = maximum (zipWith (\x y -> abs (x - y)) (concat (take 3 a)) (concat (take 3 b)))
