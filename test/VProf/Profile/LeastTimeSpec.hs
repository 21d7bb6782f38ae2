-- | The least time any legal profile needs under its jerk and acceleration limits: exact
-- where a closed form is known, below every legal profile the generator makes (the
-- checker's verdict on each, and the independent oracle's), and the refusals of requests it
-- puts over the sample cap or whose limits are below the checker's resolution for their time step.
module VProf.Profile.LeastTimeSpec (spec) where

import qualified Data.ByteString.Lazy as BL
import Data.List (isInfixOf)
import qualified Data.Vector.Unboxed as U
import System.IO.Unsafe (unsafePerformIO)
import Test.Hspec
import Test.QuickCheck hiding (generate, Result)

import Support.Arbitrary (propertyCount)
import Support.LegalityOracle (Verdict (..), oracleVerdict)
import Support.Wide (logUniform)
import VProf.Profile.Format.Json (requestFromJson)
import VProf.Profile.Generate (generate, generatePure)
import VProf.Profile.LeastTime
import VProf.Profile.Legality (check)
import VProf.Profile.Request
import VProf.Profile.Result
import VProf.Profile.Sampled (Profile (..), trapezoidDistances)
import VProf.Units

cases :: Int
cases = unsafePerformIO propertyCount
{-# NOINLINE cases #-}

inf :: Double
inf = 1 / 0

restToRest :: Double -> Double -> Double -> Limits
restToRest a j vTop = Limits { lmV0 = 0, lmA0 = 0, lmVEnd = 0, lmAEnd = 0, lmAMin = negate a, lmAMax = a, lmJMax = j, lmVTop = vTop }

-- | Requests whose jerk and acceleration bind: routes 1 cm-100 m, speed limits 0.05-30 m/s,
-- acceleration 0.01-10 and jerk 0.01-100 m/s³ in magnitude (the negative sides up to 3x
-- either way), time steps 1 ms-0.125 s, starting and ending at rest or in motion.
genBound :: Gen Request
genBound = do
  len <- logUniform 0.01 100
  v <- logUniform 0.05 30
  a <- logUniform 0.01 10
  j <- logUniform 0.01 100
  ra <- logUniform (1 / 3) 3
  rj <- logUniform (1 / 3) 3
  dt <- elements [0.001, 0.004, 0.01, 0.03125, 0.125]
  v0 <- oneof [pure 0, choose (0, v)]
  vE <- oneof [pure 0, choose (0, v)]
  pure defaultRequest
    { rqRouteLength = len *~ meter
    , rqZones = [SpeedZone (0 *~ meter) (v *~ mps)]
    , rqMinAcceleration = negate (a * ra) *~ mps2, rqMaxAcceleration = a *~ mps2
    , rqMinJerk = negate (j * rj) *~ mps3, rqMaxJerk = j *~ mps3
    , rqStartVelocity = v0 *~ mps, rqEndVelocity = vE *~ mps
    , rqTimeStep = Just (dt *~ second), rqTimeBudget = Just (2 *~ second)
    }

spec :: Spec
spec = do
  describe "the bound where the least time is known in closed form" $ do
    it "acceleration only (rest to rest, no speed limit): 2·sqrt(L/A), to 0.2 %" $
      property $ forAll ((,) <$> logUniform 1e-3 1e4 <*> logUniform 1e-3 1e2) $ \(len, a) ->
        let t = leastTime (restToRest a inf 1e12) len
            exact = 2 * sqrt (len / a)
        in counterexample (show (t, exact)) (t <= exact && t >= 0.998 * exact)
    it "jerk only (rest to rest): (24·L/J)^(1/3) to 0.2 %, below the true least time (32·L/J)^(1/3)" $
      property $ forAll ((,) <$> logUniform 1e-3 1e4 <*> logUniform 1e-3 1e3) $ \(len, j) ->
        let t = leastTime (restToRest 1e12 j 1e12) len
            bound = (24 * len / j) ** (1 / 3)
            exact = (32 * len / j) ** (1 / 3)
        in counterexample (show (t, bound, exact)) (t <= bound && t >= 0.998 * bound && t < exact)
    it "speed only: L/v (the run-ups instant)" $
      property $ forAll ((,) <$> logUniform 1e-3 1e4 <*> logUniform 1e-2 1e2) $ \(len, v) ->
        let t = leastTime (restToRest inf inf v) len
        in counterexample (show (t, len / v)) (t <= len / v && t >= 0.998 * len / v)

  it "no legal profile the generator makes is shorter than the bound (the checker's verdict on each, and the independent oracle's); at least 40 % of the requests generated (55.5 % at seed 42)" $
    withMaxSuccess (max 100 (cases `div` 5)) $ checkCoverage $ forAll genBound $ \rq ->
      -- the requests not generated pass: the share of those generated is a requirement
      let passing why = cover 40 False "generated" (label why True)
      in case validate rq of
        Left _ -> passing "refused"
        Right pb
          | problemLeastSamples pb > 20000 -> passing "over 20,000 samples (left out)"
          | otherwise -> ioProperty $ do
              r <- generate rq
              pure $ case (resOutcome r, resProfile r) of
                (Generated, Just p) ->
                  let n = fromIntegral (U.length (prVelocities p) - 1) :: Double
                  in cover 40 True "generated" $ label "generated" $ counterexample (show (n, problemLeastSamples pb))
                       (null (check pb p) && oracleVerdict pb p /= SurelyIllegal && n >= problemLeastSamples pb)
                (Failed f, _) -> passing ("not generated: " ++ takeWhile (/= ' ') (show f))
                _ -> passing "not generated"

  it "a profile may stop short of the route end within its end tolerance, and the bound counts the route less it (a 9 m route whose last 3.1 m are at 0.95 mm/s: 5.0 mm short, 91 samples fewer than its zones at their limits over the whole route)" $ do
    Right rq <- requestFromJson <$> BL.readFile "test/data/slow-end-short-9m.json"
    Right pb <- pure (validate rq)
    let r = generatePure rq
        zones = zip (U.toList (pbZoneStarts pb)) (U.toList (pbZoneSpeeds pb))
    resOutcome r `shouldBe` Generated
    Just p <- pure (resProfile r)
    let n = fromIntegral (U.length (prVelocities p) - 1) :: Double
        sEnd = U.last (trapezoidDistances (prDt p) (prVelocities p))
    check pb p `shouldBe` []
    -- short of the end, within the tolerance (1 cm)
    sEnd `shouldSatisfy` (\x -> x < pbLength pb - 1e-3 && x >= pbLength pb - pbTol pb)
    -- the zones at their limits over the whole route need more samples than it has
    n `shouldSatisfy` (< leastSamples (pbLength pb) (pbDt pb) zones)
    n `shouldSatisfy` (>= problemLeastSamples pb)

  describe "validation" $ do
    let msgs rq = either (map renderFieldError) (const []) (validate rq)
        flds rq = either (map feField) (const []) (validate rq)
        route = defaultRequest { rqRouteLength = 10 *~ meter, rqZones = [SpeedZone (0 *~ meter) (4 *~ mps)] }
    it "a jerk too weak for the time step is refused, naming the field, the speed one step makes and the least magnitude (1e-10 m/s³ stood still at 0.0 m)" $ do
      let rq = route { rqMinJerk = (-1e-10) *~ mps3, rqMaxJerk = 1e-10 *~ mps3 }
      flds rq `shouldBe` ["min_jerk", "max_jerk"]
      msgs rq `shouldSatisfy` all (\m -> "1.56e-12 m/s" `isInfixOf` m && "must be above 6.40e-8 m/s³" `isInfixOf` m)
    it "the resolution is strict: one step at the jerk must change the speed by more than 1e-9 m/s (exactly 1e-9 at 1 s spent its budget)" $ do
      let at c dt = route { rqMinJerk = negate (c / dt / dt) *~ mps3, rqMaxJerk = (c / dt / dt) *~ mps3, rqTimeStep = Just (dt *~ second) }
      flds (at 1e-9 1) `shouldBe` ["min_jerk", "max_jerk"]
      flds (at 1.01e-9 1) `shouldBe` []
      flds (at 1.01e-9 1e-4) `shouldBe` []
    it "an acceleration too weak for the time step is refused, naming it" $
      flds route { rqMaxAcceleration = 1e-9 *~ mps2 } `shouldBe` ["max_acceleration"]
    it "a jerk that puts the route over the sample cap is named (150 km at 300 m/s, 2e-3 m/s³ and 1 ms: some 1.34 million samples)" $ do
      let rq = route { rqRouteLength = 150000 *~ meter, rqZones = [SpeedZone (0 *~ meter) (300 *~ mps)]
                     , rqMinJerk = (-2e-3) *~ mps3, rqMaxJerk = 2e-3 *~ mps3, rqTimeStep = Just (1e-3 *~ second) }
          true = (32 * 150000 / 2e-3) ** (1 / 3) / 1e-3 :: Double
      true `shouldSatisfy` (> fromIntegral maxSamples)
      flds rq `shouldBe` ["max_jerk"]
      msgs rq `shouldSatisfy` all ("above the cap of 1048576 samples" `isInfixOf`)
    it "so are an acceleration and a braking that do" $ do
      let slow a b = route { rqMaxAcceleration = a *~ mps2, rqMinAcceleration = negate b *~ mps2, rqTimeStep = Just (1e-3 *~ second) }
      flds (slow 1e-5 1) `shouldBe` ["max_acceleration"]
      flds (slow 1 1e-5) `shouldBe` ["min_acceleration"]
    it "a budget spent before the first profile gives the samples the jerk needs, not only the speed limits'" $ do
      let rq = route { rqMinJerk = (-2e-3) *~ mps3, rqMaxJerk = 2e-3 *~ mps3, rqTimeStep = Just (1e-3 *~ second), rqTimeBudget = Just (1e-3 *~ second) }
      Right pb <- pure (validate rq)
      problemLeastSamples pb `shouldSatisfy` (> 40000)
      r <- generate rq
      case resOutcome r of
        Failed (NotConverged m) -> m `shouldContain` ("at least " ++ show (ceiling (problemLeastSamples pb) :: Int) ++ " samples")
        other -> expectationFailure (show other)
    it "a route of 5e-324 m (below the shortest taken) is refused for its length, not held by the bound (its doubling from zero never ended)" $ do
      flds route { rqRouteLength = 5e-324 *~ meter } `shouldBe` ["route_length"]
      leastTime (restToRest 1 1 4) 5e-324 `shouldBe` 0
