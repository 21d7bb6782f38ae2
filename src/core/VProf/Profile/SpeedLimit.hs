-- | The speed-limit function over distance: piecewise constant zones, looked up by binary
-- search. Positions before 0 see the first zone, positions past the route end the last.
module VProf.Profile.SpeedLimit
  ( zoneIndex
  , limitAt
  , minLimitOn
  , nextLowerZone
  ) where

import qualified Data.Vector.Unboxed as U

import VProf.Profile.Request (Problem (..))

-- | The index of the zone holding at @s@: the last zone whose start is <= s.
zoneIndex :: Problem -> Double -> Int
zoneIndex pb s = go 0 (U.length starts - 1)
  where
    starts = pbZoneStarts pb
    -- invariant: starts[lo] <= s or lo == 0; answer in [lo, hi]
    go !lo !hi
      | lo >= hi = lo
      | otherwise =
          let mid = (lo + hi + 1) `div` 2
          in if U.unsafeIndex starts mid <= s then go mid hi else go lo (mid - 1)
{-# INLINE zoneIndex #-}

-- | The speed limit at position @s@.
limitAt :: Problem -> Double -> Double
limitAt pb s = U.unsafeIndex (pbZoneSpeeds pb) (zoneIndex pb s)
{-# INLINE limitAt #-}

-- | The lowest speed limit anywhere on the closed interval [a, b] (a <= b).
minLimitOn :: Problem -> Double -> Double -> Double
minLimitOn pb a b
  | i == j = U.unsafeIndex speeds i
  | otherwise = go (i + 1) (U.unsafeIndex speeds i)
  where
    speeds = pbZoneSpeeds pb
    i = zoneIndex pb a
    j = zoneIndex pb b
    go !k !m
      | k > j = m
      | otherwise = go (k + 1) (min m (U.unsafeIndex speeds k))
{-# INLINE minLimitOn #-}

-- | The start of the first zone after position @s@ whose limit is below @v@, if any.
nextLowerZone :: Problem -> Double -> Double -> Maybe Double
nextLowerZone pb s v = go (zoneIndex pb s + 1)
  where
    n = U.length (pbZoneStarts pb)
    go k
      | k >= n = Nothing
      | U.unsafeIndex (pbZoneSpeeds pb) k < v = Just (U.unsafeIndex (pbZoneStarts pb) k)
      | otherwise = go (k + 1)
