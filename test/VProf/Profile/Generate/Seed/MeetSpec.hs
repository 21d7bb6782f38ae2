-- | The two-sided meet at fine time steps. Where the rounding of the velocities alone puts
-- a full-jerk ramp beyond the checker's slack, the passes plan inside the jerk range and
-- the joins are judged on the request's own range. The meet's seed is near the rubber
-- band's fixed point: a cruise goes without its dent where the route end allows, and the
-- peak plateau is raised where the band could not raise it in time, so the band converges
-- in a few hundred passes where it took thousands, or never did.
module VProf.Profile.Generate.Seed.MeetSpec (spec) where

import Control.Monad (forM_)
import qualified Data.Vector.Unboxed as U
import Test.Hspec

import Support.Arbitrary (problemOf)
import Support.Routes (violations)
import VProf.Profile.Generate.RubberBand (PassResult (..), pass)
import VProf.Profile.Generate.Seed (seed)
import VProf.Profile.Generate.Seed.Meet (meetWith)
import VProf.Profile.Generate.Seed.Brake (fullJerkHolds, jerkPlanMargins)
import VProf.Profile.Generate.Seed.Join (MeetContext (..), meetContext)
import VProf.Profile.Generate.Seed.Strategy (Strategy (..), closestJoin, endLevelPlateau, limitCruise, peakCloseSteps, peakPlateau, probeLevel, topEndLevel)
import VProf.Profile.Legality (Rule (..), Violation (..), check)
import VProf.Profile.Sampled (Profile (..))
import VProf.Profile.Problem.Transform (scaleJerk)
import VProf.Profile.Request
import VProf.Units

-- | The rubber band's passes from a profile to its fixed point, at most @cap@ of them: the
-- number of passes that changed something, and the fixed point (Nothing past the cap).
passesToFixedPoint :: Int -> Problem -> U.Vector Double -> (Int, Maybe (U.Vector Double))
passesToFixedPoint cap pb = go 0
  where go n v | n > cap = (n, Nothing)
               | otherwise = let PassResult v' c = pass pb v in if c == 0 then (n, Just v) else go (n + 1) v'

-- | A moving end from its request: the ranges, zones and ends given, at a time step.
movingEnd :: Double -> [(Double, Double)] -> (Double, Double, Double, Double) -> (Double, Double) -> Double -> Problem
movingEnd len zones (aMin, aMax, jMin, jMax) (v0, vEnd) dt = problemOf defaultRequest
  { rqRouteLength = len *~ meter
  , rqZones = [ SpeedZone (s *~ meter) (v *~ mps) | (s, v) <- zones ]
  , rqMinAcceleration = aMin *~ mps2, rqMaxAcceleration = aMax *~ mps2
  , rqMinJerk = jMin *~ mps3, rqMaxJerk = jMax *~ mps3
  , rqStartVelocity = v0 *~ mps, rqEndVelocity = vEnd *~ mps
  , rqTimeStep = Just (dt *~ second) }

-- | examples/moving-start-end.json (120 m, 7 then 5 m/s from 70 m, ±1 m/s², ±1 m/s³, from
-- 2 to 1 m/s) at a 0.5 ms step.
movingStartEnd05ms :: Problem
movingStartEnd05ms = movingEnd 120 [(0, 7), (70, 5)] (-1, 1, -1, 1) (2, 1) 5e-4

-- | A moving end at a 0.1 ms step: 93.4 m from rest to 3.42 m/s, 5.37 then 11.58 m/s from
-- 30.2 m, a 1.12 m/s³ jerk: a velocity of 10 m/s rounds to its last bit by 2.3e-7 of the
-- jerk in the checker's second difference, beyond its slack of 1e-9.
movingEnd01ms :: Problem
movingEnd01ms = movingEnd 93.38801014400026 [(0, 5.374920748716298), (30.24394904513428, 11.58263053261702)]
  (-1.4465375257404167, 1.510635967458992, -8.479482389077123, 1.1151613421994393) (0, 3.423276662641864) 1e-4

-- | A moving end at a 0.2 ms step whose envelope peaks at 3.50 m/s between a 0.44 m/s and a
-- 2.55 m/s zone: the peak plateau's first level, 0.1 % below the top, is a million velocity
-- steps (3.7e-9 m/s) below it.
peakAt02ms :: Problem
peakAt02ms = movingEnd 23.854638629956025 [(0, 0.43742836974685645), (0.7355858026368827, 17.22487903798239), (21.383101055004506, 2.5468160290529123)]
  (-0.4279434196474358, 1.7773072030000365, -1.0390448548249425, 0.4020435210162162) (0, 0.4065368449362723) 2e-4

-- | A 44 m route at 0.112 ms through 2 zones ending at 4 m/s (bench/fuzz-requests --fine
-- seed 5, request 13), whose meet joins only on the peak plateau, 0.1 % below an envelope
-- top of 8.25 m/s: 2.2 million velocity steps to search.
peakAt0112ms :: Problem
peakAt0112ms = movingEnd 44.03734688675029 [(0, 27.091167), (31.821324578565523, 13.669146)]
  (-7.034337804212263, 5.747520758639441, -1.54121810377749, 0.8233518645113116) (0, 3.9981282774608173) 1.119e-4

-- | bench/fuzz-requests --fine seed 46, request 50 (drawn at 0.1321 ms), at a time step: 3.96 m
-- from rest to 1.67 m/s, the last zone 2.05 m/s from 1.39 m, jerk -0.286..0.448 m/s³. The
-- route only just reaches the end velocity ('leastTimeToEnd'), and its profile ends in a
-- cruise at it.
endLevel4m :: Double -> Problem
endLevel4m = movingEnd 3.958235324647846 [(0, 4.013166), (0.018760048354779794, 6.839272), (1.3940730741735639, 2.049364)]
  (-2.5422451857949087, 1.6848342236030847, -0.28618482936528533, 0.44834570881533864) (0, 1.667106929672738)

-- | The least time in which a profile from rest reaches a velocity with its acceleration
-- back at zero, under a jerk range alone: the acceleration is at most j_max·t from the
-- start and at most |j_min|·(T − t) towards the end, so the velocity gained within T is at
-- most a_p²/2·(1/j_max + 1/|j_min|) with a_p their crossing, and T = a_p·(1/j_max + 1/|j_min|).
leastTimeToEnd :: Problem -> Double
leastTimeToEnd pb = let w = 1 / pbJMax pb + 1 / negate (pbJMin pb); ap = sqrt (2 * pbVEnd pb / w) in ap * w

-- | The duration of velocities cut at their arrival (as the generator gives them).
cutDuration :: Problem -> U.Vector Double -> Double
cutDuration pb v = case [ k | Violation Crawl k _ _ <- check pb (Profile (pbDt pb) v (pbA0 pb) (pbAEnd pb)) ] of
  k : _ -> fromIntegral k * pbDt pb
  [] -> fromIntegral (U.length v - 1) * pbDt pb

-- | The meet's context as the seed makes it: the passes planned inside the jerk range where
-- the full jerk cannot hold.
contextOf :: Problem -> Either String MeetContext
contextOf pb = either (Left . show) Right (meetContext True pb q)
  where q = if fullJerkHolds pb then pb else scaleJerk (1 - head (jerkPlanMargins pb)) pb

spec :: Spec
spec = describe "the two-sided meet at fine time steps" $ do
  it "the peak plateau's search ends at a level that joins within 64 velocity steps of one that does not (both probed again), its join legal, on moving ends at 0.112 and 0.2 ms" $
    forM_ [("44 m at 0.112 ms", peakAt0112ms), ("23.9 m at 0.2 ms", peakAt02ms)] $ \(name, pb) ->
      case contextOf pb of
        Left f -> expectationFailure (name ++ ": " ++ f)
        Right c -> do
          let top = mcTop c
              dv = pbDv pb
              v0 = top * (1 - 0.001)
          case probeLevel c v0 of
            (m0, p0 : _) -> do
              let (vOk, vNo, p) = closestJoin c (top, Nothing) (v0, m0) p0
              (name, vNo - vOk <= peakCloseSteps * dv) `shouldBe` (name, True)
              (name, vOk >= v0 && vNo <= top) `shouldBe` (name, True)
              (name, violations pb p) `shouldBe` (name, [])
              (name, not (null (snd (probeLevel c vOk)))) `shouldBe` (name, True)
              (name, vNo == top || null (snd (probeLevel c vNo))) `shouldBe` (name, True)
            _ -> expectationFailure (name ++ ": the level 0.1 % below the top does not join")

  it "a moving end at 0.1 ms: the limit cruise alone, and the peak plateau alone, join passes planned inside the jerk range into a profile legal for the request (judged on the narrowed range, no strategy but the softened plateau joined, after 20 s)" $
    mapM_ (\s -> case meetWith [s] movingEnd01ms of
                   Right v -> violations movingEnd01ms v `shouldBe` []
                   Left f -> expectationFailure (strategyName s ++ ": " ++ show f))
          [limitCruise, peakPlateau]

  it "a route that only just reaches its end velocity, at 2 ms and 0.13 ms: the end-level plateau joins (a cruise at the end velocity that arrives before its last sample, legal but for that crawl), alone and as the meet's seed, within 0.7 % of the least time; refused for its crawl, no plateau joined and the seed went through rest (5.99 s at 2 ms, none within 20 s at 0.13 ms)" $
    forM_ [2e-3, 1.321e-4] $ \dt -> do
      let pb = endLevel4m dt
          least = leastTimeToEnd pb
      least `shouldSatisfy` (\t -> t > 4.36 && t < 4.37)
      forM_ [("end-level plateau at the top", meetWith [topEndLevel] pb), ("end-level plateau", meetWith [endLevelPlateau] pb), ("the seed", seed pb)] $ \(name, r) ->
        case r of
          Right v -> do
            (dt, name, violations pb v) `shouldBe` (dt, name, [])
            (dt, name, cutDuration pb v) `shouldSatisfy` (\(_, _, t) -> t >= least && t <= 1.007 * least)
          Left f -> expectationFailure (show dt ++ ", " ++ name ++ ": " ++ show f)

  it "moving-start-end at 0.5 ms: the seed is the band's fixed point at once (its cruise's dent took the band 7,075 passes and more, one velocity step a pass)" $
    case seed movingStartEnd05ms of
      Right v -> do
        violations movingStartEnd05ms v `shouldBe` []
        fst (passesToFixedPoint 8 movingStartEnd05ms v) `shouldSatisfy` (<= 2)
      Left f -> expectationFailure (show f)

  it "a peak plateau a million velocity steps below the envelope's top at 0.2 ms is raised: the band reaches its fixed point within 1,000 passes, legal (from 0.1 % below the top it had not after 20,000)" $
    case seed peakAt02ms of
      Right v -> do
        violations peakAt02ms v `shouldBe` []
        case passesToFixedPoint 1000 peakAt02ms v of
          (_, Just f) -> violations peakAt02ms f `shouldBe` []
          (n, Nothing) -> expectationFailure ("no fixed point after " ++ show n ++ " passes")
      Left f -> expectationFailure (show f)
