-- | The twelve six-axis arms of @shared/reference/robots.md@ as test fixtures: standard DH
-- (d, a in m; α, θ offset and limits in degrees as printed there).
module Support.Robots
  ( Fixture (..), fixtures, fixtureRows, fixtureDh, fixtureByName
  ) where

import qualified Data.Vector.Unboxed as U
import Support.DhOracle
import VProf.Kinematics.ClosedForm

data Fixture = Fixture
  { fxName :: String
  , fxD, fxA, fxAlphaDeg, fxOffsetDeg :: [Double]
  , fxLimitsDeg :: [(Double, Double)]
  }

deg :: Double -> Double
deg x = x * pi / 180

sym :: Double -> (Double, Double)
sym x = (-x, x)

fixtures :: [Fixture]
fixtures =
  [ Fixture "Puma 560" [0.67183, 0, 0.15005, 0.4318, 0, 0] [0, 0.4318, 0.0203, 0, 0, 0]
      [90, 0, -90, 90, -90, 0] [0, 0, 0, 0, 0, 0]
      [sym 160, (-45, 225), (-225, 45), (-110, 170), sym 100, sym 266]
  , Fixture "IRB 120" [0.290, 0, 0, 0.302, 0, 0.072] [0, 0.270, 0.070, 0, 0, 0]
      abbAlpha abbOffset [sym 165, sym 110, (-110, 70), sym 160, sym 120, sym 400]
  , Fixture "IRB 140" [0.352, 0, 0, 0.380, 0, 0.065] [0.070, 0.360, 0, 0, 0, 0]
      abbAlpha abbOffset [sym 180, (-90, 110), (-230, 50), sym 400, sym 115, sym 400]
  , Fixture "IRB 1600" [0.4865, 0, 0, 0.600, 0, 0.065] [0.150, 0.475, 0, 0, 0, 0]
      abbAlpha abbOffset [sym 200, (-63, 136), (-235, 55), sym 200, sym 115, sym 400]
  , Fixture "IRB 6700" [0.78, 0, 0, 1.1425, 0, 0.2] [0.32, 1.125, 0.2, 0, 0, 0]
      abbAlpha abbOffset [sym 180, (-40, 160), (-180, 70), sym 300, sym 120, sym 360]
  , Fixture "KR 6-2" [0.675, 0, 0, -0.67, 0, -0.115] [0.26, 0.68, -0.035, 0, 0, 0]
      [-90, 0, 90, -90, 90, 180] [0, -90, 0, 0, 0, 0]
      [sym 185, (-155, 35), (-130, 154), sym 350, sym 130, sym 350]
  , Fixture "KR5 arc" [0.4, 0, 0, -0.62, 0, -0.115] [0.18, 0.6, 0.12, 0, 0, 0]
      [-90, 0, 90, -90, 90, 180] [0, 0, 0, 0, 0, 0]
      [sym 155, (-180, 65), (-15, 158), sym 350, sym 130, sym 350]
  , ur "UR3" [0.1519, 0, 0, 0.11235, 0.08535, 0.0819] [0, -0.24365, -0.21325, 0, 0, 0]
  , ur "UR5" [0.089159, 0, 0, 0.10915, 0.09465, 0.0823] [0, -0.425, -0.39225, 0, 0, 0]
  , ur "UR10" [0.1273, 0, 0, 0.163941, 0.1157, 0.0922] [0, -0.612, -0.5723, 0, 0, 0]
  , ur "UR5e" [0.1625, 0, 0, 0.1333, 0.0997, 0.0996] [0, -0.425, -0.3922, 0, 0, 0]
  , ur "UR10e" [0.1807, 0, 0, 0.17415, 0.11985, 0.11655] [0, -0.6127, -0.57155, 0, 0, 0]
  ]
  where
    abbAlpha = [-90, 0, -90, 90, -90, 0]
    abbOffset = [0, -90, 0, 0, 0, 180]
    ur n d a = Fixture n d a [90, 0, 0, 90, -90, 0] [0, 0, 0, 0, 0, 0] (replicate 6 (sym 360))

fixtureByName :: String -> Fixture
fixtureByName n = head ([f | f <- fixtures, fxName f == n] ++ error ("no fixture " ++ n))

fixtureRows :: Fixture -> [DhRow]
fixtureRows f = zipWith4' DhRow (map deg (fxOffsetDeg f)) (fxD f) (fxA f) (map deg (fxAlphaDeg f))
  where zipWith4' g (a : as) (b : bs) (c : cs) (d : ds) = g a b c d : zipWith4' g as bs cs ds
        zipWith4' _ _ _ _ _ = []

fixtureDh :: Fixture -> SixAxisDh
fixtureDh f = SixAxisDh
  { sdA = v (fxA f), sdAlpha = v (map deg (fxAlphaDeg f)), sdD = v (fxD f)
  , sdOffset = v (map deg (fxOffsetDeg f))
  , sdLower = v (map (deg . fst) (fxLimitsDeg f)), sdUpper = v (map (deg . snd) (fxLimitsDeg f))
  , sdBase = identityPose, sdTool = identityPose }
  where v = U.fromListN 6
