-- | An oracle of profile legality, written apart from "VProf.Profile.Legality" (which the
-- generator itself uses to decide that a profile is done, so a test that asks it whether the
-- generator's profile is legal cannot fail). It reads only the data of a 'Problem' and a
-- 'Profile' and recomputes everything else from the velocity samples with code of its own:
-- distances, accelerations and jerks from their definitions (docs/profile-generator.md), the
-- speed limit over a step from the zones as a map from start to speed (the zone with the
-- greatest start at or before a point holds there, the first before its start; a step is
-- bound by every zone that holds somewhere on its closed interval of distance).
--
-- Comparisons take a rounding allowance as the product's checker does (a limit L is met by
-- up to @tol · max 1 |L|@), but the allowance is a parameter, and the arrival test of the
-- crawl rule has its own: a caller that wants a verdict free of rounding asks twice, once
-- with the allowance a little below the checker's (and the arrival's a little above) — a
-- profile legal then is legal beyond doubt — and once the other way round.
module Support.LegalityOracle
  ( Allowance (..)
  , checkerAllowance
  , oracleViolations
  , oracleLegal
  , Verdict (..)
  , oracleVerdict
  ) where

import Data.List (foldl')
import qualified Data.Map.Strict as M
import qualified Data.Vector.Unboxed as U

import VProf.Profile.Request (Problem (..))
import VProf.Profile.Sampled (Profile (..))

-- | The relative allowance on every limit, and the one of the arrival test (crawl).
data Allowance = Allowance { alLimits :: !Double, alArrival :: !Double }

-- | The product checker's rounding slack on both.
checkerAllowance :: Allowance
checkerAllowance = Allowance 1e-9 1e-9

-- | The rules broken, each with the sample where first seen (names as the product's).
oracleViolations :: Allowance -> Problem -> Profile -> [(String, Int)]
oracleViolations al pb (Profile dt vv aStart aEnd)
  | null vs = [("empty", 0)]
  | isNaN dt || isInfinite dt || dt <= 0 || any (\x -> isNaN x || isInfinite x) vs = [("non_finite", 0)]
  | otherwise = concatMap firstOf
      [ ("negative_velocity", [ k | (k, x) <- ix vs, x < negate (room 0) ])
      , ("speed", speedBreaks)
      , ("acceleration", [ k | (k, a) <- ix accs, a > aHi + room aHi || a < aLo - room aLo ])
      , ("jerk", [ k | (k, j) <- ix jerksAll, j > jHi + room jHi || j < jLo - room jLo ])
      , ("start_velocity", [ 0 | abs (head vs - pbV0 pb) > room (pbV0 pb) ])
      , ("end_velocity", [ n | abs (last vs - pbVEnd pb) > room (pbVEnd pb) ])
      , ("route_end", [ n | abs (last ss - len) > pbTol pb + room len ])
      , ("overshoot", [ k | (k, s) <- ix ss, s > len + pbTol pb + room len ])
      , ("crawl", take 1 [ k | k <- [0 .. n - 1], arrived k ])
      ]
  where
    vs = U.toList vv
    n = length vs - 1
    ix = zip [0 :: Int ..]
    room l = alLimits al * max 1 (abs l)
    near l = alArrival al * max 1 (abs l)
    len = pbLength pb
    aLo = pbAMin pb; aHi = pbAMax pb; jLo = pbJMin pb; jHi = pbJMax pb
    firstOf (name, ks) = take 1 [ (name, k) | k <- ks ]
    -- s_0 = 0, s_{k+1} = s_k + dt (v_k + v_{k+1}) / 2
    ss = reverse (foldl' (\acc (a, b) -> (head acc + dt * (a + b) / 2) : acc) [0] (zip vs (drop 1 vs)))
    accs = zipWith (\a b -> (b - a) / dt) vs (drop 1 vs)
    -- the jerk into the first acceleration, between the accelerations, out of the last
    accsAll = [aStart] ++ accs ++ [aEnd]
    jerksAll = zipWith (\a b -> (b - a) / dt) accsAll (drop 1 accsAll)
    zones = M.fromList (zip (U.toList (pbZoneStarts pb)) (U.toList (pbZoneSpeeds pb)))
    holdingAt x = maybe (snd (M.findMin zones)) snd (M.lookupLE x zones)
    -- every zone holding somewhere on [a, b]: the one at a and every one starting in (a, b]
    limitOn a b = let (lo, hi) = (min a b, max a b)
                      (_, above) = M.split lo zones
                      (inside, atHi, _) = M.splitLookup hi above
                  in minimum (holdingAt lo : M.elems inside ++ maybe [] pure atHi)
    speedBreaks
      | n == 0 = [ 0 | head vs > limitOn 0 0 + room (limitOn 0 0) ]
      | otherwise = [ k | (k, ((v1, v2), (s1, s2))) <- ix (zip (zip vs (drop 1 vs)) (zip ss (drop 1 ss)))
                        , let l = limitOn s1 s2, max v1 v2 > l + room l ]
    ssV = U.fromList ss
    accV = U.fromList accs
    accBefore k = if k == 0 then aStart else accV U.! (k - 1)
    arrived k = let j = (aEnd - accBefore k) / dt
                in abs (ssV U.! k - len) <= pbTol pb + near len
                   && abs (vv U.! k - pbVEnd pb) <= near (pbVEnd pb)
                   && j <= jHi + near jHi && j >= jLo - near jLo

-- | Legal under the product checker's allowance.
oracleLegal :: Problem -> Profile -> Bool
oracleLegal pb = null . oracleViolations checkerAllowance pb

data Verdict = SurelyLegal | SurelyIllegal | Borderline deriving (Eq, Show)

-- | The verdict free of rounding: legal even with the allowance 1 % tighter (and the arrival
-- test 1 % looser), illegal even with it 1 % looser (and the arrival 1 % tighter), else
-- borderline (within a hundredth of the 1e-9 slack of a limit).
oracleVerdict :: Problem -> Profile -> Verdict
oracleVerdict pb p
  | null (oracleViolations (Allowance 0.99e-9 1.01e-9) pb p) = SurelyLegal
  | not (null (oracleViolations (Allowance 1.01e-9 0.99e-9) pb p)) = SurelyIllegal
  | otherwise = Borderline
