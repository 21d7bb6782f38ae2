-- | The wide world of requests (issue "the generator on any valid request"): time steps from
-- 2⁻⁷ to 2⁻² s and non-powers of two (0.01, 0.02, 0.05, 0.1 s); speed limits 0.01–30 m/s;
-- acceleration and jerk magnitudes 0.05–50 with asymmetric ranges up to 3×; 1–500 zones,
-- sometimes with a cluster of tiny zones (1 mm–0.5 m); routes from 5 cm to 5 km, all
-- log-uniform; start and end at rest or in motion. The same distribution as
-- @bench/fuzz-requests@, drawn with QuickCheck so that the properties shrink and replay.
-- Every request it draws passes the contract's field rules; a request the sample cap refuses
-- is valid input that gets a clear refusal, and the properties count it apart. A second
-- distribution, 'genFine', draws the fine time steps of real controllers (0.1-1 ms), as
-- @bench/fuzz-requests --fine@ does; a third, 'genTiny', the routes of a few micrometres
-- to centimetres (a probe's approach, a fine adjustment) at steps of 1 µs to 10 ms.
module Support.Wide
  ( WideRequest (..)
  , genWide
  , FineRequest (..)
  , genFine
  , TinyRequest (..)
  , genTiny
  , wideTimeSteps
  , lowered
  , logUniform
  ) where

import Data.List (nub, sort)
import Test.QuickCheck

import VProf.Profile.Request
import VProf.Units

newtype WideRequest = WideRequest Request deriving (Show)

instance Arbitrary WideRequest where
  arbitrary = WideRequest <$> genWide

-- | The controller time steps drawn: powers of two and the common non-powers.
wideTimeSteps :: [Double]
wideTimeSteps = [2 ** negate k | k <- [2 .. 7]] ++ [0.01, 0.02, 0.05, 0.1]

-- | A log-uniform draw in [lo, hi].
logUniform :: Double -> Double -> Gen Double
logUniform lo hi = (\u -> exp (log lo + u * (log hi - log lo))) <$> choose (0, 1)

-- | Four significant digits, so that counterexamples read well (and zone starts stay distinct
-- after the 'nub').
sig4 :: Double -> Double
sig4 0 = 0
sig4 x = let e = floor (logBase 10 (abs x)) :: Int
             k = 10 ^^ (3 - e) :: Double
         in fromIntegral (round (x * k) :: Integer) / k

genWide :: Gen Request
genWide = do
  len <- sig4 <$> logUniform 0.05 5000
  oneZone <- (< (0.2 :: Double)) <$> choose (0, 1)
  nz <- if oneZone then pure 1 else min 500 . floor <$> logUniform 1 500
  cuts <- vectorOf (nz - 1) (choose (0, len))
  cluster <- (\u -> nz > 3 && u < (0.3 :: Double)) <$> choose (0, 1)
  starts0 <-
    if cluster
      then do
        at <- choose (0, len)
        w <- logUniform 0.001 0.5
        pure (take (nz `div` 2) cuts ++ [min len (at + fromIntegral k * w) | k <- [1 .. nz - 1 - nz `div` 2]])
      else pure cuts
  let starts = 0 : nub (sort [s | s <- map sig4 starts0, s > 0, s < len])
  vmax <- logUniform 0.01 30
  speeds <- vectorOf (length starts) (max 0.01 . sig4 . (vmax *) <$> logUniform 0.05 1)
  aMag <- sig4 <$> logUniform 0.05 50
  jMag <- sig4 <$> logUniform 0.05 50
  ra <- logUniform (1 / 3) 3
  rj <- logUniform (1 / 3) 3
  flipA <- arbitrary
  let (aMin, aMax) = if flipA then (negate aMag, sig4 (aMag * ra)) else (negate (sig4 (aMag * ra)), aMag)
      (jMin, jMax) = (negate (sig4 (jMag * rj)), jMag)
  dt <- elements wideTimeSteps
  startMoving <- (< (0.4 :: Double)) <$> choose (0, 1)
  endMoving <- (< (0.3 :: Double)) <$> choose (0, 1)
  (v0, a0) <- if startMoving then movingState (head speeds) aMin aMax else pure (0, 0)
  (vE, aE) <- if endMoving then movingState (last speeds) aMin aMax else pure (0, 0)
  pure defaultRequest
    { rqRouteLength = len *~ meter
    , rqZones = zipWith (\s v -> SpeedZone (s *~ meter) (v *~ mps)) starts speeds
    , rqMinAcceleration = aMin *~ mps2, rqMaxAcceleration = aMax *~ mps2
    , rqMinJerk = jMin *~ mps3, rqMaxJerk = jMax *~ mps3
    , rqStartVelocity = v0 *~ mps, rqStartAcceleration = a0 *~ mps2
    , rqEndVelocity = vE *~ mps, rqEndAcceleration = aE *~ mps2
    , rqTimeStep = Just (dt *~ second)
    }
  where
    movingState lim aMin aMax = do
      v <- sig4 <$> choose (0, lim)
      a <- sig4 <$> ((*) <$> choose (aMin, aMax) <*> choose (0, 1))
      pure (min lim v, max aMin (min aMax a))

newtype FineRequest = FineRequest Request deriving (Show)

instance Arbitrary FineRequest where
  arbitrary = FineRequest <$> genFine

-- | The fine-step distribution of @bench/fuzz-requests --fine@: time steps 0.1-1 ms
-- (log-uniform), where a braking takes thousands of steps and rounding shows in the jerk;
-- routes 1-300 m with 1-30 zones at 0.03-30 m/s, shortened (zones and all) where the zones at
-- their limits would take more than half the cap of samples, so that the request stays valid
-- and the answer has room for its brakings; acceleration 0.3-10 and jerk 0.3-30 in magnitude
-- (log-uniform, the negative side up to 2x either way); a third start in motion, half end in
-- it (with zero acceleration).
genFine :: Gen Request
genFine = do
  len0 <- logUniform 1 300
  nz <- (1 +) . floor <$> logUniform 1 30
  cuts <- vectorOf (nz - 1) (choose (0, len0))
  let starts0 = 0 : nub (sort [ s | s <- map sig4 cuts, s > 0, s < len0 ])
  vmax <- logUniform 0.3 30
  speeds <- vectorOf (length starts0) (sig4 . (vmax *) <$> logUniform 0.1 1)
  dt <- sig4 <$> logUniform 1e-4 1e-3
  let ends0 = drop 1 starts0 ++ [len0]
      least = sum (zipWith3 (\a b v -> (b - a) / v) starts0 ends0 speeds) / dt
      f = if least > fromIntegral maxSamples / 2 then fromIntegral maxSamples / 2 / least else 1
      len = len0 * f
      starts = map (* f) starts0
  aMag <- logUniform 0.3 10
  jMag <- logUniform 0.3 30
  ra <- logUniform 0.5 2
  rj <- logUniform 0.5 2
  startMoving <- (< (1 / 3 :: Double)) <$> choose (0, 1)
  endMoving <- (< (0.5 :: Double)) <$> choose (0, 1)
  v0 <- if startMoving then choose (0, head speeds) else pure 0
  vE <- if endMoving then choose (0, last speeds) else pure 0
  pure defaultRequest
    { rqRouteLength = len *~ meter
    , rqZones = zipWith (\s v -> SpeedZone (s *~ meter) (v *~ mps)) starts speeds
    , rqMinAcceleration = negate (aMag * ra) *~ mps2, rqMaxAcceleration = aMag *~ mps2
    , rqMinJerk = negate (jMag * rj) *~ mps3, rqMaxJerk = jMag *~ mps3
    , rqStartVelocity = v0 *~ mps, rqEndVelocity = vE *~ mps
    , rqTimeStep = Just (dt *~ second)
    }

newtype TinyRequest = TinyRequest Request deriving (Show)

instance Arbitrary TinyRequest where
  arbitrary = TinyRequest <$> genTiny

-- | Short routes at any step: 10 µm to 5 cm, one zone at 1 mm/s to 2 m/s, time steps of 1 µs
-- to 10 ms, acceleration 0.05-50 and jerk 0.05-10⁴ in magnitude (symmetric), all
-- log-uniform; a limit whose step would move the speed by no more than 2e-9 m/s (twice the
-- resolution validation keeps) is raised 1-100 times above that. Two in five start in
-- motion, half end in it, at up to the limit. Where one step covers a good part of the
-- route, or the route's samples run to hundreds of thousands, the request is valid and hard
-- (the cap refuses the longest).
genTiny :: Gen Request
genTiny = do
  len <- logUniform 1e-5 0.05
  dt <- logUniform 1e-6 1e-2
  v <- logUniform 1e-3 2
  a0 <- logUniform 0.05 50
  j0 <- logUniform 0.05 1e4
  ja <- logUniform 1 100
  aa <- logUniform 1 100
  let j = if j0 * dt * dt <= 2e-9 then 2e-9 / (dt * dt) * ja else j0
      a = if a0 * dt <= 2e-9 then 2e-9 / dt * aa else a0
  startMoving <- (< (0.4 :: Double)) <$> choose (0, 1)
  endMoving <- (< (0.5 :: Double)) <$> choose (0, 1)
  v0 <- if startMoving then choose (0, v) else pure 0
  vE <- if endMoving then choose (0, v) else pure 0
  pure defaultRequest
    { rqRouteLength = len *~ meter
    , rqZones = [SpeedZone (0 *~ meter) (v *~ mps)]
    , rqMinAcceleration = negate a *~ mps2, rqMaxAcceleration = a *~ mps2
    , rqMinJerk = negate j *~ mps3, rqMaxJerk = j *~ mps3
    , rqStartVelocity = v0 *~ mps, rqEndVelocity = vE *~ mps
    , rqTimeStep = Just (dt *~ second)
    }

-- | The request with every zone lowered to its lowest limit (one zone), when its start and end
-- velocities still fit under it.
lowered :: Request -> Maybe Request
lowered rq
  | si (rqStartVelocity rq) > vLow || si (rqEndVelocity rq) > vLow = Nothing
  | otherwise = Just rq { rqZones = [SpeedZone (0 *~ meter) (vLow *~ mps)] }
  where
    vLow = minimum (map (si . zoneSpeed) (rqZones rq))
