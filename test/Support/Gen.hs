-- | QuickCheck generators shared by the kinematics specs.
module Support.Gen
  ( genQ
  , libraryChains
  , forAllQ
  ) where

import qualified Data.Vector.Unboxed as U
import Test.QuickCheck

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
