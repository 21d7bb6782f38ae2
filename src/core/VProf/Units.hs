{-# LANGUAGE DataKinds #-}
{-# LANGUAGE TypeOperators #-}
-- | The physical quantities of vprof, from the @dimensional@ package, and the two
-- conversions the rest of the library needs at its boundaries.
--
-- The generator, the checker and the wire code agree on SI units: a 'Double' that has
-- left a 'Quantity' through 'si' is in metres, seconds, m/s, m/s² or m/s³. Conversions
-- happen once, at the edges; hot loops work on unboxed SI doubles.
module VProf.Units
  ( Length, Time, Velocity, Acceleration, Jerk, DJerk
  , meter, second, mps, mps2, mps3
  , si, fromSI
  , (*~), (/~)
  ) where

import Numeric.Units.Dimensional (siUnit, KnownDimension)
import Numeric.Units.Dimensional.Coercion (unQuantity)
import Numeric.Units.Dimensional.Dimensions.TypeLevel (type (/))
import Numeric.Units.Dimensional.Prelude
  ( Length, Time, Velocity, Acceleration, Quantity, Unit, Metricality (..)
  , DVelocity, DAcceleration, DTime
  , meter, second, (*~), (/~), (/), (^), pos2, pos3)
import Prelude hiding ((/), (^))

-- | Jerk, the rate of change of acceleration (m/s³). @dimensional@ has no name for it.
type DJerk = DAcceleration / DTime
type Jerk = Quantity DJerk

mps :: Unit 'NonMetric DVelocity Double
mps = meter / second

mps2 :: Unit 'NonMetric DAcceleration Double
mps2 = meter / second ^ pos2

mps3 :: Unit 'NonMetric DJerk Double
mps3 = meter / second ^ pos3

-- | The SI magnitude of a quantity (m, s, m/s, m/s², m/s³).
si :: Quantity d Double -> Double
si = unQuantity

-- | A quantity from its SI magnitude; the dimension comes from the type.
fromSI :: KnownDimension d => Double -> Quantity d Double
fromSI x = x *~ siUnit
