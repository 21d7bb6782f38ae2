-- | QuickCheck generators shared by the kinematics specs.
module Support.Gen
  ( genQ
  , libraryChains
  , forAllQ
  , turnedBy
  , snake
  , planarSnake
  ) where

import qualified Data.Vector.Unboxed as U
import Test.QuickCheck

import VProf.Geometry.Quaternion (qmul)
import VProf.Geometry.Vec (Q4 (..))
import VProf.Kinematics.Library
import VProf.Kinematics.Model

-- | A joint vector uniform within the limits (±2π for an unbounded side).
genQ :: Chain -> Gen (U.Vector Double)
genQ ch = U.fromList <$> mapM one [0 .. chainDof ch - 1]
  where
    one i =
      let lo = chainLo ch U.! i; hi = chainHi ch U.! i
          lo' = if isInfinite lo then -2 * pi else lo
          hi' = if isInfinite hi then 2 * pi else hi
      in choose (lo', hi')

-- | Every library robot, compiled (a broken file fails the test that uses it).
libraryChains :: [(String, Either [String] Chain)]
libraryChains = [(k, compile <$> r) | (k, r) <- libraryRobots]

forAllQ :: Testable p => Chain -> (U.Vector Double -> p) -> Property
forAllQ ch = forAllShow (genQ ch) (show . U.toList)

-- | A quaternion turned about a random axis (in its own frame) by an angle drawn from the
-- generator.
turnedBy :: Gen Double -> Q4 -> Gen Q4
turnedBy angle q = do
  ax <- vectorOf 3 (choose (-1, 1)) `suchThat` (\v -> sum (map (^ (2 :: Int)) v) > 1e-2)
  th <- angle
  let k = sqrt (sum (map (^ (2 :: Int)) ax)); [a, b, c] = map (* (sin (th / 2) / k)) ax
  pure (qmul q (Q4 (cos (th / 2)) a b c))

-- | A standard-DH chain of n revolute joints within ±limit rad, each link 1 cm (twists of ±90°
-- in turn): a snake of n cm.
snake :: Int -> Double -> Robot
snake n limit =
  (emptyRobot ("snake" ++ show n))
    { robotJoints = [Joint ("j" ++ show i) Revolute (Limits (-limit) limit) Nothing Nothing | i <- [0 .. n - 1]]
    , robotLinks =
        [ Link ("l" ++ show i) (Just Revolute) (DhStandard 0 0 0.01 (if even i then pi / 2 else -pi / 2)) (directDrive i 1 0) []
        | i <- [0 .. n - 1] ]
    }

-- | A planar chain of n revolute joints about z within ±limit rad, each link 1 cm along x: the
-- straight chain (every joint 0) reaches (n cm, 0, 0).
planarSnake :: Int -> Double -> Robot
planarSnake n limit =
  (emptyRobot ("planar" ++ show n))
    { robotJoints = [Joint ("j" ++ show i) Revolute (Limits (-limit) limit) Nothing Nothing | i <- [0 .. n - 1]]
    , robotLinks =
        [ Link ("l" ++ show i) (Just Revolute) (DhStandard 0 0 0.01 0) (directDrive i 1 0) []
        | i <- [0 .. n - 1] ]
    }
