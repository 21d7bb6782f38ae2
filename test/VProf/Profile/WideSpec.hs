-- | The generator's promises over the wide world of requests ("Support.Wide"): every answer
-- is a legal, converged profile that arrives without crawling, an infeasibility that an
-- independent proof confirms, a refusal by the sample cap naming route_length (or the zone
-- that alone needs more samples), or
-- NOT_CONVERGED when the time budget runs out; no answer carries more than the cap of
-- samples; the wall time, measured here, stays within the budget and a quarter second. The
-- same over the fine time steps of real controllers ("Support.Wide".'genFine') and over
-- routes of micrometres to centimetres ('genTiny'). And
-- two metamorphic properties: the default generator is never slower than thesis mode, and
-- lowering the speed limits never makes a profile faster (both within one time step, and
-- of the full search's answers: within a tight budget the search may stop early).
module VProf.Profile.WideSpec (spec) where

import Control.Monad (forM_)
import qualified Data.ByteString.Lazy as BL
import qualified Data.Aeson as A
import qualified Data.Aeson.Key as K
import qualified Data.Aeson.KeyMap as KM
import qualified Data.Text as T
import Data.List (isInfixOf, isPrefixOf, isSuffixOf, sort)
import System.Directory (listDirectory)
import System.Environment (lookupEnv)
import System.FilePath ((</>))
import GHC.Clock (getMonotonicTime)
import System.IO.Unsafe (unsafePerformIO)
import Test.Hspec
import Test.QuickCheck hiding (Result, generate)
import Test.QuickCheck.Monadic (PropertyM, assert, monadicIO, monitor, run)

import Support.Arbitrary (propertyCount)
import Support.Proofs (sound)
import Support.Wide
import VProf.Profile.Format.Json (requestFromJson)
import VProf.Profile.Generate
import qualified Data.Vector.Unboxed as U
import VProf.Profile.Generate.Seed (SeedFailure (..), SeedPlan (..), ladderSamples, mirror, restFrom, restWithinJerk, runInCruise, seed, seedPlan, seedVariants, throughRestBy)
import VProf.Profile.Problem (endsInMotion)
import VProf.Profile.Generate.Seed.Brake (fullJerkHolds)
import VProf.Profile.Legality (Rule (..), Violation (..), check, legalButCrawl, renderViolation)
import VProf.Profile.Request
import VProf.Profile.Sampled
import VProf.Units

cases :: Int
cases = unsafePerformIO propertyCount
{-# NOINLINE cases #-}

-- | The budget every wide request runs with: small, so that a thousand cases fit in CI, and
-- large enough for most of them to converge.
budget :: Double
budget = 0.25

-- | The budget of a fine-step request ('genFine'): its answers have up to half a million
-- samples, so a second; and one case in 'fineShare' of the wide property's count.
fineBudget :: Double
fineBudget = 1

fineShare :: Int
fineShare = 10

-- | The promise on wall time: the budget and a quarter second.
grace :: Double
grace = 0.25

withBudget :: Request -> Request
withBudget rq = rq { rqTimeBudget = Just (budget *~ second) }

-- | Generate, timing the call and forcing everything a caller reads.
timed :: Request -> IO (Result, Double)
timed rq = do
  t0 <- getMonotonicTime
  r <- generate rq
  let n = maybe 0 sampleCount (resProfile r)
  t1 <- n `seq` length (resViolations r) `seq` getMonotonicTime
  pure (r, t1 - t0)

-- | The promises on a request generated within a budget (s): within the budget and 'grace'
-- of wall time, within the cap of samples, and legal, a confirmed infeasibility, a refusal
-- the given test accepts, or NOT_CONVERGED; and at least the given share (%) of the answers
-- not NOT_CONVERGED (a requirement of coverage: a property run under 'checkCoverage' fails
-- when a generator answers NOT_CONVERGED to much more than it does now).
keepsPromises :: Double -> Double -> (Result -> Bool) -> Request -> PropertyM IO ()
keepsPromises b answered refusalOk rq0 = do
  let rq = rq0 { rqTimeBudget = Just (b *~ second) }
  (r, secs0) <- run (timed rq)
  -- wall time is the machine's too: an overrun must repeat to count (a systematic one
  -- does; a moment of preemption by another process does not)
  secs <- if secs0 <= b + grace then pure secs0 else run (snd <$> timed rq)
  monitor (tabulate "answers" [kind r])
  monitor (cover answered (not (isNotConverged r)) "answered (not NOT_CONVERGED)")
  monitor (counterexample ("answer: " ++ kind r ++ " after " ++ show secs0 ++ " s (again: " ++ show secs ++ " s); "
                           ++ show (maybe 0 sampleCount (resProfile r)) ++ " samples\n"
                           ++ unlines (map renderViolation (take 5 (resViolations r)))))
  assert (secs <= b + grace)
  assert (maybe 0 sampleCount (resProfile r) <= maxSamples)
  assert $ case resOutcome r of
    Generated -> sound rq r
    Failed (InfeasibleRequest _ _) -> sound rq r
    Failed (InvalidRequest _) -> refusalOk r
    Failed (NotConverged _) -> True

-- | The class of an answer, for the report of shares.
kind :: Result -> String
kind r = case resOutcome r of
  Generated -> "legal"
  Failed (InfeasibleRequest f _) -> "infeasible: " ++ f
  Failed (NotConverged m)
    | "time budget" `isPrefixOf` m && "first pass" `isInfixOf` m -> "not converged: budget (first pass)"
    | "time budget" `isPrefixOf` m -> "not converged: budget"
    | "iteration cap" `isPrefixOf` m -> "not converged: iteration cap"
    | otherwise -> "not converged: " ++ takeWhile (/= ':') m
  Failed (InvalidRequest es) -> "refused: " ++ unwords (map feField es)

-- | The cap's refusal: validation (or the generator after it) names route_length, or the one
-- zone that alone needs more than the cap (its speed_limits[i].velocity, "above the cap").
capRefusal :: Result -> Bool
capRefusal r = case resOutcome r of
  Failed (InvalidRequest es) -> not (null es) && all capError es
  _ -> False
  where
    capError e = feField e == "route_length"
                 || ("speed_limits[" `isPrefixOf` feField e && "].velocity" `isSuffixOf` feField e && "above the cap" `isInfixOf` feRule e)

isNotConverged :: Result -> Bool
isNotConverged r = case resOutcome r of
  Failed (NotConverged _) -> True
  _ -> False

isInfeasible :: Result -> Bool
isInfeasible r = case resOutcome r of
  Failed (InfeasibleRequest _ _) -> True
  _ -> False

durationOf :: Result -> Maybe Double
durationOf r = case (resOutcome r, resProfile r) of
  (Generated, Just p) -> Just (duration p)
  _ -> Nothing

dtOf :: Request -> Double
dtOf rq = maybe defaultTimeStep si (rqTimeStep rq)

-- | Both modes generate a profile for the request, and the default one is not slower than
-- thesis mode's by more than a time step; the default's result.
notSlowerThanThesis :: Request -> IO Result
notSlowerThanThesis rq = do
  band <- generate rq
  thesis <- generate rq { rqAlgorithm = Thesis }
  resOutcome band `shouldBe` Generated
  resOutcome thesis `shouldBe` Generated
  (durationOf band <= fmap (+ dtOf rq) (durationOf thesis)) `shouldBe` True
  pure band

-- | Generate a request and its lowered one (every zone at the lowest limit): both legal, the
-- request's no slower (within one time step). The request's result.
notFasterWhenLowered :: Request -> IO Result
notFasterWhenLowered rq = do
  Just low <- pure (lowered rq)
  asked <- generate rq
  low' <- generate low
  resOutcome asked `shouldBe` Generated
  resOutcome low' `shouldBe` Generated
  (durationOf asked <= fmap (+ dtOf rq) (durationOf low')) `shouldBe` True
  pure asked

-- | A counterexample the metamorphic property found: a 9.4 cm route at 1 cm/s, where the
-- default generator's landing used to approach the end in a staircase of slower plateaus
-- (10.76 s against thesis mode's 10.22 s).
staircase :: Request
staircase = defaultRequest
  { rqRouteLength = 0.09444 *~ meter
  , rqZones = [SpeedZone (z *~ meter) (0.01 *~ mps) | z <- [0, 9.131e-3, 3.972e-2, 4.356e-2]]
  , rqMinAcceleration = (-1.636) *~ mps2, rqMaxAcceleration = 3.542 *~ mps2
  , rqMinJerk = (-11.19) *~ mps3, rqMaxJerk = 22.1 *~ mps3
  , rqTimeStep = Just (0.02 *~ second), rqTimeBudget = Just (30 *~ second) }

-- | Counterexamples the metamorphic properties found in the wide world (seed 42, 1000 cases),
-- kept in test/data: a 16 m route with a cluster of 1 cm zones and jerk -17.19..6.564 m/s³
-- (greedy seed 30.75 s, thesis mode 30.20 s); a 13 cm route with jerk -0.0893..0.05571 m/s³
-- (14.53 s as asked, 13.78 s with every zone lowered to 1 cm/s); once those were fixed, the
-- 810th case, a 7.3 cm route ending at 0.06 m/s whose two-sided meet joined on a plateau of
-- 5.8 mm/s (8.63 s against thesis mode's 4.06 s); and then the 884th, a 7.25 m route with jerk
-- -0.4276..0.1519 m/s³ at time_step 0.25 s (every greedy seed 54.0 s or more, thesis mode
-- 52.25 s). The default generator now seeds variants of the problem and, for answers of up to
-- 2048 samples, compares thesis mode's fixed point ('bestSeed', 'viaThesis').
counterexample16m, counterexample13cm, counterexample7cm, counterexample7m, counterexample17m, counterexample87cm, weakJerk6m, movingEnd10m, dentedFine31m, liftedFine12m, runInFine12m, endLevel4m, justReachingJoin16m, justReachingRunIn3m, justReachingSoftened25m, justReachingRunInOnly91m, justReachingQuick21m, justReachingMoving3m, justReachingExact6m, justReachingHeld13m, justReachingLong23m :: IO Request
counterexample16m = loadRequest "test/data/metamorphic-cluster-16m.json"
counterexample13cm = loadRequest "test/data/metamorphic-jerk-13cm.json"
counterexample7cm = loadRequest "test/data/metamorphic-moving-end-7cm.json"
counterexample7m = loadRequest "test/data/metamorphic-weak-jerk-7m.json"
counterexample17m = loadRequest "test/data/metamorphic-budget-17m.json"
counterexample87cm = loadRequest "test/data/metamorphic-thesis-step-87cm.json"
-- | Found by bench/fuzz-requests (seed 31): converged at once, then thesis mode's fixed points
-- (77 s long against the answer's 11.3 s) took up to 20 s of its time budget ('thesisWork').
weakJerk6m = loadRequest "test/data/weak-jerk-thesis-work-6m.json"
-- | Found by bench/fuzz-requests (seed 40): converged within 1 s, then 2.5 s more on thesis
-- mode, whose run-in from rest to the moving end the first estimate of its work left out.
movingEnd10m = loadRequest "test/data/moving-end-thesis-work-10m.json"
-- | Found by bench/fuzz-requests --fine (seed 1): a 30.7 m route at 0.17 ms whose two-sided
-- meet joined a cruise with a dent the limits did not need, which the band lifted one velocity
-- step (7.45e-9 m/s) a pass (NOT_CONVERGED after 1,763 passes of a 20 s budget).
dentedFine31m = loadRequest "test/data/dented-join-fine-31m.json"
-- | That route cut to 12 m: ending at 1.3 m/s, the meet joined a 7.6 s cruise whose end fell
-- 3.1 mm short of where the band stops, and the band lifted it as a whole (NOT_CONVERGED after
-- 24,000 passes of 120 s); ending at 1 m/s, the variant through rest broke the jerk rule in its
-- run-in by 3e-9 m/s³ and was refused (11.2 s instead of 8.9 s, NOT_CONVERGED at 120 s).
liftedFine12m = loadRequest "test/data/lifted-cruise-fine-12m.json"
runInFine12m = loadRequest "test/data/run-in-margins-fine-12m.json"
-- | Found by bench/fuzz-requests --fine (seed 46), here at 2 ms: a 3.96 m route that only just
-- reaches its end velocity of 1.67 m/s, whose profile ends in a cruise at it that arrives
-- within the tolerance before its last sample; no join was counted, and it was seeded through
-- rest (5.99 s).
endLevel4m = loadRequest "test/data/end-level-crawl-4m.json"
-- | From the property of routes that only just reach their end velocity (seed 42): the
-- meet's plateau at the end velocity ends 8.1 mm past the route end, or 17 mm short, with no
-- room for a dent; through rest, 13.05 s.
justReachingJoin16m = loadRequest "test/data/just-reaching-join-16m.json"
-- | From the same property: the meet joins nothing; through rest, 7.43 s.
justReachingRunIn3m = loadRequest "test/data/just-reaching-run-in-3m.json"
-- | From the same property: half a cruise step of route left after the run-in, beyond the
-- tolerance either way; through rest, 24.13 s.
justReachingSoftened25m = loadRequest "test/data/just-reaching-softened-25m.json"
-- | From the same property (seed 1): a third of a cruise step left, which only the run-in
-- alone, narrowed until it ends on the route end, takes up; through rest, 42.16 s.
justReachingRunInOnly91m = loadRequest "test/data/just-reaching-run-in-only-91m.json"
-- | From the same property (seed 1): the meet took 5.0 s for a 10.29 s seed.
justReachingQuick21m = loadRequest "test/data/just-reaching-quick-21m.json"
-- | From the same property with moving starts (seed 1): the meet found no join, and no
-- profile through rest fits; NOT_CONVERGED without a profile.
justReachingMoving3m = loadRequest "test/data/just-reaching-moving-start-3m.json"
-- | Drawn like that property from a moving start: no join, no run-up and cruise, and the
-- exact join's programs within half the tolerance had no profile; NOT_CONVERGED without one.
justReachingExact6m = loadRequest "test/data/just-reaching-exact-join-6m.json"
-- | Drawn like it too: no join, no run-up and cruise, no narrowed run-in, 394 steps beyond the
-- exact join's programs; NOT_CONVERGED without a profile.
justReachingHeld13m = loadRequest "test/data/just-reaching-held-start-13m.json"
-- | Drawn like it too: no join, nothing through rest, and the run-up and cruise longer than
-- the quick seed allows; NOT_CONVERGED without a profile.
justReachingLong23m = loadRequest "test/data/just-reaching-long-run-up-23m.json"

-- | Generated, converged within ten passes of the rubber band, and sound by the independent
-- proofs, under a budget of 60 s.
convergesInFewPasses :: Request -> Expectation
convergesInFewPasses rq = do
  r <- generate rq { rqTimeBudget = Just (60 *~ second) }
  resOutcome r `shouldBe` Generated
  resConverged r `shouldBe` True
  resIterations r `shouldSatisfy` (<= 10)
  sound rq r `shouldBe` True

-- | A property over the wide requests that end in motion, with the seed search, of at most
-- 20,000 samples; the others are labelled and pass.
onMovingEnd :: (Problem -> Property) -> WideRequest -> Property
onMovingEnd k (WideRequest rq) = case validate rq of
  Left _ -> label "refused by validation" True
  Right pb
    | not (endsInMotion pb && pbSeedSearch pb) -> label "ends at rest, or no seed search" True
    | problemLeastSamples pb > 20000 -> label "over 20,000 samples (left out)" True
    | otherwise -> k pb

loadRequest :: FilePath -> IO Request
loadRequest f = either (error . ((f ++ ": ") ++)) withLongBudget . requestFromJson <$> BL.readFile f
  where withLongBudget rq = rq { rqTimeBudget = Just (30 *~ second) }

-- | A route from rest, or from a slower start without acceleration, that only just reaches
-- its end velocity: the least time and distance of reaching it with the acceleration back at
-- zero (the acceleration rising at j_max, held at a_max where it gets there, and falling at
-- |j_min|), and a request whose route is a little longer than that distance, one zone above
-- the end velocity, a time step of 200-4,000 steps of that time. No legal profile takes less than that least time (less two
-- steps: sampled, the acceleration of a step may be a jerk step ahead of the continuous
-- ramp's at each end), and the S-curve followed by a cruise at the end velocity is one of
-- its (continuous) profiles.
data JustReaching = JustReaching Request Double Double

instance Show JustReaching where
  show (JustReaching rq t d) = show rq ++ " (the S-curve: " ++ show t ++ " s, " ++ show d ++ " m)"

instance Arbitrary JustReaching where
  arbitrary = do
    let logu lo hi = exp <$> choose (log lo, log hi)
    j1 <- logu 0.1 10
    j2 <- logu 0.1 10
    aMax <- logu 0.1 10
    aMin <- negate <$> logu 0.1 10
    vEnd <- logu 0.05 5
    -- from rest in half the cases, else from 5-95 % of the end velocity
    f <- oneof [pure 0, choose (0.05, 0.95)]
    let v0 = f * vEnd
        dv = vEnd - v0
        w = 1 / j1 + 1 / j2
        ap = min aMax (sqrt (2 * dv / w))
        t1 = ap / j1; t2 = ap / j2
        th = max 0 (dv / ap - (t1 + t2) / 2)
        v1 = j1 * t1 * t1 / 2
        v2 = v1 + ap * th
        dS = v0 * (t1 + th + t2) + j1 * t1 ^ (3 :: Int) / 6 + v1 * th + ap * th * th / 2 + v2 * t2 + ap * t2 * t2 / 2 - j2 * t2 ^ (3 :: Int) / 6
        tS = t1 + th + t2
    extra <- logu 1e-3 0.03
    top <- logu 1e-4 2
    steps <- logu 200 4000
    let rq = defaultRequest
          { rqRouteLength = dS * (1 + extra) *~ meter
          , rqZones = [SpeedZone (0 *~ meter) (vEnd * (1 + top) *~ mps)]
          , rqMinAcceleration = aMin *~ mps2, rqMaxAcceleration = aMax *~ mps2
          , rqMinJerk = negate j2 *~ mps3, rqMaxJerk = j1 *~ mps3
          , rqStartVelocity = v0 *~ mps, rqEndVelocity = vEnd *~ mps
          , rqTimeStep = Just (tS / steps *~ second)
          , rqTimeBudget = Just (10 *~ second) }
    pure (JustReaching rq tS dS)

spec :: Spec
spec = describe "the wide world of requests" $ do
  it "a route from rest, or from a slower start, that only just reaches its end velocity (0.1-3 % longer than the S-curve to it): a legal profile (the independent proofs), no shorter than the S-curve (less two steps) and at most 1 % and three steps longer than the S-curve with a cruise at the end velocity after it; from a moving start, where no whole number of steps fits, an infeasibility the independent proofs confirm, or in at most 3 % of all cases NOT_CONVERGED (through rest, 14 % of 300 routes from rest took 5-40 % longer; with the run-in and a cruise at the full ranges, 3 %; from a moving start the meet found no join in some)" $
    withMaxSuccess (max 1 (cases `div` 5)) $ checkCoverage $ property $ \(JustReaching rq tS dS) -> monadicIO $ do
      r <- run (generate rq)
      let len = rqRouteLength rq /~ meter
          vEnd = rqEndVelocity rq /~ mps
          fromRest = rqStartVelocity rq /~ mps == 0
          dt = maybe 0 (/~ second) (rqTimeStep rq)
          sCruise = tS + (len - dS) / vEnd
      monitor (tabulate "outcome" [(if fromRest then "from rest: " else "moving start: ") ++ kind r])
      monitor (cover 97 (not (isNotConverged r)) "answered: a profile, a confirmed infeasibility or a refusal")
      case (resOutcome r, resProfile r) of
        (Generated, Just p) -> do
          let t = duration p
          monitor (counterexample ("duration " ++ show t ++ " s; the S-curve " ++ show tS ++ " s, with the cruise " ++ show sCruise ++ " s"))
          assert (sound rq r && null (resViolations r) && t >= tS - 2 * dt && t <= sCruise * 1.01 + 3 * dt)
        -- from a moving start close to the end velocity, a time step too fine for the drawn
        -- jerk: refused by validation
        (Failed (InvalidRequest _), _) | not fromRest -> pure ()
        (Failed (InfeasibleRequest _ _), _) | not fromRest -> assert (sound rq r)
        -- from a moving start the meet may find no join where the run-up and a cruise do
        -- not fit either and no proof is found (2 of 2,500 moving starts): a known
        -- limit, bounded by the coverage
        (Failed (NotConverged _), _) | not fromRest -> pure ()
        (o, _) -> do
          monitor (counterexample ("answer: " ++ show o))
          assert False

  it "a 9.4 cm route at 1 cm/s lands without a staircase of slower plateaus, no slower than thesis mode" $ do
    band <- generate staircase
    thesis <- generate staircase { rqAlgorithm = Thesis }
    resOutcome band `shouldBe` Generated
    resOutcome thesis `shouldBe` Generated
    -- cruising the route less the landing tolerance at 1 cm/s takes 8.94 s; the brake adds a few steps
    fmap duration (resProfile band) `shouldSatisfy` maybe False (<= 9.1)
    (durationOf band <= durationOf thesis) `shouldBe` True

  it "every answer is legal, a confirmed infeasibility, the cap's refusal or NOT_CONVERGED; within the cap and the budget" $
    -- the share is reported, not required: under checkCoverage QuickCheck stops as soon as the
    -- share is shown (after 200 cases here), and this property's worth is its thousand cases;
    -- the fine and tiny properties below require theirs
    withMaxSuccess cases $ property $ \(WideRequest rq0) -> monadicIO (keepsPromises budget 85 capRefusal rq0)

  it "fine time steps (0.1-1 ms, as bench/fuzz-requests --fine): every answer is legal, a confirmed infeasibility or NOT_CONVERGED (at most 35 %); within the cap and the budget" $
    withMaxSuccess (max 1 (cases `div` fineShare)) $ checkCoverage $ property $ \(FineRequest rq0) -> monadicIO (keepsPromises fineBudget 65 (const False) rq0)

  it "tiny routes (10 µm-5 cm at steps of 1 µs-10 ms): every answer is legal, a confirmed infeasibility, the cap's refusal or NOT_CONVERGED (at most 15 %); within the cap and the budget" $
    withMaxSuccess (max 1 (cases `div` fineShare)) $ checkCoverage $ property $ \(TinyRequest rq0) -> monadicIO (keepsPromises fineBudget 85 capRefusal rq0)

  it "fine time steps: thesis mode's braking of a moving start and its run-in to a moving end keep the jerk rule (the full jerk's rounding breaks it in many; jerks recomputed from the velocities)" $
    withMaxSuccess cases $ property $ \(FineRequest rq) -> case validate rq of
      Left _ -> label "refused by validation" True
      Right pb ->
        let ends = [ ("start", pb) | pbV0 pb > 0 ] ++ [ ("end", mirror pb) | endsInMotion pb ]
            brokeAtFull = or [ either (const False) (not . jerksWithin q) (restFrom q) | (_, q) <- ends ]
        in cover 10 brokeAtFull "the full jerk's braking breaks the jerk rule" $
             label (if null ends then "at rest at both ends" else "in motion") $
               conjoin [ counterexample (which ++ ": " ++ show (pbDt q, pbV0 q, pbJMin q, pbJMax q)) $
                           either (const (property True)) (property . jerksWithin q) (restWithinJerk q)
                       | (which, q) <- ends ]

  it "the infeasibility claims of bench/fuzz-requests (test/data/claims, or $VPROF_CLAIMS_DIR) are made again and confirmed by an independent proof" $ do
    dir <- maybe "test/data/claims" id <$> lookupEnv "VPROF_CLAIMS_DIR"
    files <- sort . filter (".json" `isSuffixOf`) <$> listDirectory dir
    length files `shouldSatisfy` (> 0)
    bad <- concat <$> mapM (confirmClaim . (dir </>)) files
    bad `shouldBe` []

  it "the 16 m cluster route: the default generator is not slower than thesis mode (was 30.75 s against 30.20 s)" $ do
    band <- notSlowerThanThesis =<< counterexample16m
    durationOf band `shouldSatisfy` maybe False (< 30.2)

  it "the 7 cm route ending in motion: the default generator is not slower than thesis mode (was 8.63 s against 4.06 s)" $
    () <$ (notSlowerThanThesis =<< counterexample7cm)

  it "the 7 m route with weak jerk: the default generator is not slower than thesis mode (was 54.0 s against 52.25 s)" $
    () <$ (notSlowerThanThesis =<< counterexample7m)

  it "the 87 cm route of 200 zones: the default generator is not slower than thesis mode (was 40.375 s against 39.875 s: thesis mode's fixed point was compared at the default's finer velocity step)" $ do
    band <- notSlowerThanThesis =<< counterexample87cm
    durationOf band `shouldSatisfy` maybe False (< 40.375)

  it "the 6.6 m route with weak jerk: the answer is at most 11.3 s (1131 samples, the answer once measured) and no shorter than the least-time bound, converged (thesis mode, which cannot beat it and once took 17 s of a 20 s budget, is not tried: the least-work test below)" $ do
    rq <- weakJerk6m
    r <- generate rq
    resOutcome r `shouldBe` Generated
    resConverged r `shouldBe` True
    let pb = either (error . show) id (validate rq)
    fmap sampleCount (resProfile r) `shouldSatisfy`
      maybe False (\n -> n <= 1131 && fromIntegral (n - 1) >= problemLeastSamples pb)

  it "the 30.7 m route at 0.17 ms: the meet's cruise has no dent the limits do not need, and the band converges in a few passes (was NOT_CONVERGED after 1,763 passes)" $
    convergesInFewPasses =<< dentedFine31m

  it "the 12 m route at 0.17 ms ending at 1.3 m/s: the meet's cruise is shaped as the band would leave it, and the band converges in a few passes (was NOT_CONVERGED after 24,000 passes)" $
    convergesInFewPasses =<< liftedFine12m

  it "the 3.96 m route that only just reaches its end velocity (1.67 m/s, jerk -0.29..0.45 m/s³) at 2 ms: converged, sound, at most 4.40 s where none can take less than 4.369 s (reaching 1.67 m/s from rest within the jerk range; 0.028 s of cruise follow); seeded through rest it took 5.99 s" $ do
    rq <- endLevel4m
    r <- generate rq { rqTimeBudget = Just (60 *~ second) }
    resOutcome r `shouldBe` Generated
    resConverged r `shouldBe` True
    sound rq r `shouldBe` True
    case resProfile r of
      Just p -> duration p `shouldSatisfy` (\t -> t >= 4.368 && t <= 4.40)
      Nothing -> expectationFailure "no profile"

  it "routes from rest that only just reach their end velocity: the cruise at it without a dent, within the tolerance (15.9 m at 6.3 ms: 9.322 s, was 13.054 s through rest), and the end state's run-in from rest at once with a cruise (2.8 m at 15.7 ms: 5.696 s, was 7.427 s); converged and sound" $
    forM_ [(justReachingJoin16m, 9.33), (justReachingRunIn3m, 5.70)] $ \(load, most) -> do
      rq <- load
      r <- generate rq { rqTimeBudget = Just (60 *~ second) }
      resOutcome r `shouldBe` Generated
      resConverged r `shouldBe` True
      sound rq r `shouldBe` True
      fmap duration (resProfile r) `shouldSatisfy` maybe False (<= most)

  it "routes from rest that only just reach their end velocity where no whole number of cruise steps after the run-in ends within the tolerance (half a step left on 25 m, a third on 91 m: the nearest cruise and one step more or fewer all miss): the run-in within narrower ranges and a cruise, or the run-in alone, within three steps of the S-curve and its cruise; generated, converged and sound (through rest 24.13 s and 42.16 s)" $
    forM_ [(justReachingSoftened25m, 22.4834), (justReachingRunInOnly91m, 41.3526)] $ \(load, sCruise) -> do
      rq <- load
      let pb = either (error . show) id (validate rq)
          dt = pbDt pb
          runIn = either (error . show) U.reverse (restFrom (mirror pb))
          left = (pbLength pb - U.last (trapezoidDistances dt runIn)) / (pbVEnd pb * dt)
          m0 = round left :: Int
      -- at the full ranges no cruise after the run-in is legal
      [ m | m <- [m0 - 1, m0, m0 + 1], m >= 0, legalButCrawl pb (runIn U.++ U.replicate m (pbVEnd pb)) ] `shouldBe` []
      case runInCruise pb maxSamples of
        Nothing -> expectationFailure "no run-in and cruise"
        Just v -> do
          map vRule (check pb (Profile dt v (pbA0 pb) (pbAEnd pb))) `shouldSatisfy` all (== Crawl)
          fromIntegral (U.length v - 1) * dt `shouldSatisfy` (<= sCruise + 3 * dt)
      r <- generate rq
      resOutcome r `shouldBe` Generated
      resConverged r `shouldBe` True
      sound rq r `shouldBe` True
      fmap duration (resProfile r) `shouldSatisfy` maybe False (<= sCruise + 3 * dt)

  it "a 21 m route from rest that only just reaches 3.68 m/s at 2.7 ms with a weak braking jerk: the first seed is the run-in and a cruise, within 1 % and three steps of the run-in alone (no profile can be faster), and the answer comes within a 1 s budget at 8.742 s, the S-curve and its cruise (the meet took 5.0 s for a 10.29 s seed)" $ do
    rq <- justReachingQuick21m
    let pb = either (error . show) id (validate rq)
        runIn = either (error . show) id (restFrom (mirror pb))
    case spSeed (seedPlan pb) of
      Left f -> expectationFailure ("no seed: " ++ show f)
      Right v -> do
        map vRule (check pb (Profile (pbDt pb) v (pbA0 pb) (pbAEnd pb))) `shouldSatisfy` all (== Crawl)
        U.length v `shouldSatisfy` (<= floor (fromIntegral (U.length runIn) * 1.01 :: Double) + 3)
    r <- generate rq { rqTimeBudget = Just (1 *~ second) }
    resOutcome r `shouldBe` Generated
    resConverged r `shouldBe` True
    sound rq r `shouldBe` True
    fmap duration (resProfile r) `shouldSatisfy` maybe False (<= 8.7421 + 3 * pbDt pb)

  it "a 2.6 m route from 0.53 m/s that only just reaches 2.14 m/s at 4.35 ms: the run-up from the start velocity and a cruise, within three steps of the S-curve and its cruise (1.754 s); generated, converged and sound (the meet found no join, nothing through rest fits: it was NOT_CONVERGED without a profile)" $ do
    rq <- justReachingMoving3m
    r <- generate rq
    resOutcome r `shouldBe` Generated
    resConverged r `shouldBe` True
    sound rq r `shouldBe` True
    fmap duration (resProfile r) `shouldSatisfy` maybe False (<= 1.7539 + 3 * dtOf rq)

  it "a 6.4 m route from 2.26 m/s that only just reaches 2.63 m/s at 11.6 ms: the exact join within the whole end tolerance (within half of it no profile of 220 steps ends), within a step of the S-curve and its cruise (2.551 s); generated, converged and sound (it was NOT_CONVERGED without a profile)" $ do
    rq <- justReachingExact6m
    r <- generate rq
    resOutcome r `shouldBe` Generated
    resConverged r `shouldBe` True
    sound rq r `shouldBe` True
    fmap duration (resProfile r) `shouldSatisfy` maybe False (<= 2.5511 + dtOf rq)

  it "a 12.5 m route from 3.17 m/s that only just reaches 3.84 m/s at 9.1 ms: steps held at the start velocity before the run-up, within a step of the S-curve and its cruise (3.583 s); generated, converged and sound (it was NOT_CONVERGED without a profile)" $ do
    rq <- justReachingHeld13m
    r <- generate rq
    resOutcome r `shouldBe` Generated
    resConverged r `shouldBe` True
    sound rq r `shouldBe` True
    fmap duration (resProfile r) `shouldSatisfy` maybe False (<= 3.5835 + dtOf rq)

  it "a 23.4 m route from 3.20 m/s that only just reaches 3.93 m/s with 0.12 m/s² at 17.8 ms: the run-up and cruise as the seed where the meet and the ways through rest give none, within a step of the S-curve and its cruise (6.508 s); generated, converged and sound (it was NOT_CONVERGED without a profile)" $ do
    rq <- justReachingLong23m
    r <- generate rq
    resOutcome r `shouldBe` Generated
    resConverged r `shouldBe` True
    sound rq r `shouldBe` True
    fmap duration (resProfile r) `shouldSatisfy` maybe False (<= 6.5080 + dtOf rq)

  it "the 12 m route at 0.17 ms ending at 1 m/s: the seed variant through rest plans its run-in inside the jerk range and is legal (it broke the jerk rule in 418 samples)" $ do
    pb <- either (error . show) id . validate <$> runInFine12m
    fullJerkHolds pb `shouldBe` False
    case seedVariants pb of
      viaRest : _ -> case viaRest maxSamples of
        Just w -> do
          map vRule (check pb (Profile (pbDt pb) w (pbA0 pb) (pbAEnd pb))) `shouldSatisfy` all (== Crawl)
          -- through rest it takes 8.9 s; the meet's seed took 11.2 s
          fromIntegral (U.length w - 1) * pbDt pb `shouldSatisfy` (< 9)
        Nothing -> expectationFailure "no profile through rest"
      [] -> expectationFailure "no seed variants"

  it "the 12 m route at 0.17 ms starting at 1.95 m/s: thesis mode brakes its start inside the jerk range (at the full jerk the rounding put it 7.1e-9 m/s³ beyond, and no thesis profile was legal)" $ do
    pb <- either (error . show) id . validate <$> runInFine12m
    fmap (jerksWithin pb) (restFrom pb) `shouldBe` Right False
    fmap (jerksWithin pb) (restWithinJerk pb) `shouldBe` Right True
    -- the margin costs no sample here
    fmap U.length (restWithinJerk pb) `shouldBe` fmap U.length (restFrom pb)

  it "the 12 m route at 0.17 ms ending at 1 m/s: the first seed is the meet's (shorter than the 8.9 s through rest), and every variant follows it" $ do
    pb <- either (error . show) id . validate <$> runInFine12m
    let plan = seedPlan pb
    case (spSeed plan, spVariants plan) of
      (Right v, viaRest : _) -> do
        fromIntegral (U.length v - 1) * pbDt pb `shouldSatisfy` (< 8)
        length (spVariants plan) `shouldBe` length (seedVariants pb)
        fmap U.length (viaRest maxSamples) `shouldSatisfy` maybe False (> U.length v)
      (Left f, _) -> expectationFailure ("no seed: " ++ show f)
      (_, []) -> expectationFailure "no seed variants"

  it "a moving end's first seed is the meet's, legal, or where the meet finds no join the seed through rest: never a failure to join where the seed through rest is legal" $
    withMaxSuccess cases $ property $ onMovingEnd $ \pb -> case spSeed (seedPlan pb) of
      Left (LandingFailed m) ->
        label "the meet finds no join" $ counterexample m $
          case seedVariants pb of
            viaRest : _ -> counterexample "the seed through rest is legal" (null (viaRest ladderSamples))
            [] -> property True
      Left _ -> label "proven unreachable or over the cap" True
      Right v -> label (either (const "seeded through rest: the meet finds no join") (const "seeded by the meet") (seed pb)) $
        let bad = filter ((/= Crawl) . vRule) (check pb (Profile (pbDt pb) v (pbA0 pb) (pbAEnd pb)))
        in counterexample (show (take 3 bad)) (null bad)

  it "a seed variant through rest is left out only where it cannot beat the seed (its landing's least samples, over the route less the tolerance, and its run-in are already as many): the same variant run in full finds nothing shorter" $
    withMaxSuccess cases $ property $ onMovingEnd $ \pb -> case seed pb of
      Left _ -> label "no seed" True
      Right v ->
        let limit = U.length v - 2
            shorter = maybe Nothing (\w -> if U.length w < U.length v then Just w else Nothing)
            full = shorter (throughRestBy False pb limit)
            pruned = shorter (throughRestBy True pb limit)
        in label (maybe "no shorter profile through rest" (const "a shorter profile through rest") full) $
             counterexample (show (fmap U.length full, fmap U.length pruned)) (full == pruned)

  it "the 12 m route at 0.17 ms ending at 1 m/s under a budget the meet fits in: converged, and faster than the 8.913 s profile through rest (6.954 s: with the whole route's end in the brake bound's reach the passes stopped at 11.15 m before the run-in)" $ do
    r <- generate . (\rq -> rq { rqTimeBudget = Just (60 *~ second) }) =<< runInFine12m
    resOutcome r `shouldBe` Generated
    resConverged r `shouldBe` True
    durationOf r `shouldSatisfy` maybe False (< 6.96)

  it "the 187 m route with weak jerk against a wide acceleration range: no dip below the last zone's limit, where the brake bound once put the route's end in reach 88 m early (81.215 s, 0.16 m/s at 137.5 m; now 77.953 s)" $ do
    rq <- loadRequest "test/data/weak-jerk-dip-187m.json"
    r <- generate rq { rqTimeBudget = Just (60 *~ second) }
    resOutcome r `shouldBe` Generated
    resConverged r `shouldBe` True
    sound rq r `shouldBe` True
    durationOf r `shouldSatisfy` maybe False (< 78)
    Just p <- pure (resProfile r)
    let v = prVelocities p
        s = trapezoidDistances (prDt p) v
        -- from the last zone's start (135.17 m) to 5 m before the end, where the stop begins
        inZone = [ x | (x, d) <- zip (U.toList v) (U.toList s), d >= 135.18, d <= 181 ]
    minimum inZone `shouldSatisfy` (> 2.1)

  it "thesis mode is compared where its least work to beat the answer is within its cap (test/data's cases it beat), and not where it is beyond (the 6.6 m route, and a 9.9 m route whose run-in from rest to 1.29 m/s the estimate once left out)" $ do
    let leastWorks rq = do
          let pb = either (error . show) id (validate rq)
              r = generatePure rq
          Just n0 <- pure (sampleCount <$> resProfile r)
          let own = thesisVelocityStep (pbDt pb) (pbAMin pb) (pbAMax pb) (pbJMin pb) (pbJMax pb)
          pure [ thesisLeastWork pb n0 dv | dv <- [pbDv pb, own] ]
    tried <- mapM (\load -> leastWorks =<< load) [counterexample16m, counterexample13cm, counterexample7cm, counterexample7m, counterexample87cm]
    mapM_ (\ws -> ws `shouldSatisfy` any (<= thesisWork)) tried
    skipped <- mapM (\load -> leastWorks =<< load) [weakJerk6m, movingEnd10m]
    mapM_ (\ws -> ws `shouldSatisfy` all (> thesisWork)) skipped

  it "the 13 cm route with weak jerk: lowering every zone does not make it faster (was 14.53 s against 13.78 s)" $ do
    asked <- notFasterWhenLowered =<< counterexample13cm
    durationOf asked `shouldSatisfy` maybe False (< 13.78)

  it "the 17 m route: lowering every zone does not make the full search faster (was 26.10 s within 0.25 s against 24.20 s)" $
    () <$ (notFasterWhenLowered =<< counterexample17m)

  it "the default generator is never slower than thesis mode (within one time step) when both succeed, and neither claims infeasible what the other generates" $
    withMaxSuccess cases $ property $ \(WideRequest rq0) -> monadicIO $ do
      let claim rq = do
            (band, _) <- timed rq { rqAlgorithm = Band }
            (thesis, _) <- timed rq { rqAlgorithm = Thesis }
            pure $ case (durationOf band, durationOf thesis) of
              (Just db, Just dth) -> Right (db <= dth + dtOf rq + 1e-9, "band " ++ show db ++ " s, thesis " ++ show dth ++ " s")
              -- the two modes answer one question: a legal profile in one refutes the
              -- other's claim that none exists
              (Just _, _) | isInfeasible thesis -> Right (False, "band legal, thesis " ++ kind thesis)
              (_, Just _) | isInfeasible band -> Right (False, "thesis legal, band " ++ kind band)
              _ -> Left ("band " ++ coarse band ++ ", thesis " ++ coarse thesis)
      settle claim rq0

  it "lowering every zone to the lowest limit never makes the profile faster (within one time step), nor leaves the request as asked infeasible" $
    withMaxSuccess cases $ property $ \(WideRequest rq0) -> monadicIO $
      case lowered rq0 of
        Nothing -> monitor (tabulate "settled by" ["not lowered: start or end above the lowest limit"])
        Just low0 -> do
          let claim rq = do
                let low = low0 { rqTimeBudget = rqTimeBudget rq }
                (r, _) <- timed rq
                (rl, _) <- timed low
                pure $ case (durationOf r, durationOf rl) of
                  (Just d, Just dl) -> Right (d <= dl + dtOf rq + 1e-9, "as asked " ++ show d ++ " s, lowered " ++ show dl ++ " s")
                  -- the lowered request's legal profile is legal as asked: the request as
                  -- asked cannot be infeasible
                  (_, Just _) | isInfeasible r -> Right (False, "lowered legal, as asked " ++ kind r)
                  _ -> Left ("as asked " ++ coarse r ++ ", lowered " ++ coarse rl)
          settle claim rq0

-- | A request the CLI answered infeasible (the field in its "claimed" key): generated again
-- (with the full search's budget, so that a loaded machine does not turn the answer into a
-- timeout), the answer must claim the same field and one of the independent proofs must
-- confirm it. The words of what does not hold, if anything.
confirmClaim :: FilePath -> IO [String]
confirmClaim f = do
  bytes <- BL.readFile f
  let claimed = case A.decode bytes of
        Just (A.Object o) | Just (A.String t) <- KM.lookup (K.fromString "claimed") o -> Just (T.unpack t)
        _ -> Nothing
  case requestFromJson bytes of
    Left e -> pure [f ++ ": " ++ e]
    Right rq -> do
      r <- generate rq { rqTimeBudget = Just (fullBudget *~ second) }
      pure $ case resOutcome r of
        Failed (InfeasibleRequest fld _)
          | claimed /= Just fld -> [f ++ ": claimed " ++ show claimed ++ ", now " ++ fld]
          | sound rq r -> []
          | otherwise -> [f ++ ": no independent proof confirms the claim on " ++ fld]
        _ -> [f ++ ": now answered " ++ kind r]

-- | A metamorphic claim on a request: checked on the answers within the wide budget; where
-- they break it, on the answers of the full search. The default generator's search is an
-- anytime one (it stops trying seed variants once half the budget is spent), so within a
-- tight budget its answer depends on the machine's speed and load, and only the complete
-- search's answer is the one the claim is about. A claim is broken too where one answer is
-- legal and the other claims the (no harder) request infeasible. A claim whose answers do
-- not both succeed otherwise (a refusal, NOT_CONVERGED, an infeasibility of the harder one)
-- is tabulated and passes.
settle :: (Request -> IO (Either String (Bool, String))) -> Request -> PropertyM IO ()
settle claim rq0 = do
  first <- run (claim (withBudget rq0))
  case first of
    Left answers -> monitor (tabulate "settled by" ["none: " ++ answers])
    Right (True, _) -> monitor (tabulate "settled by" ["the budgeted answers"])
    Right (False, within) -> do
      full <- run (claim rq0 { rqTimeBudget = Just (fullBudget *~ second) })
      monitor (tabulate "settled by" ["the full search"])
      monitor (counterexample ("within " ++ show budget ++ " s: " ++ within
                               ++ "; with the full search: " ++ either id snd full))
      assert (either (const False) fst full)

-- | An answer's kind without its field or reason (for the tables of unsettled claims).
coarse :: Result -> String
coarse r = takeWhile (/= ':') (kind r)

-- | The full search's budget (s): ample for every wide request to try all its seed variants.
fullBudget :: Double
fullBudget = 30

-- | The jerks of a braking v_0 .. v_N, from the start acceleration on, within the problem's
-- jerk range and the checker's slack (1e-9 relative, at least 1e-9 m/s³): recomputed here
-- from the velocities' second differences, apart from the checker.
jerksWithin :: Problem -> U.Vector Double -> Bool
jerksWithin q w = all ok js
  where
    dt = pbDt q
    accs = pbA0 q : zipWith (\a b -> (b - a) / dt) (U.toList w) (drop 1 (U.toList w))
    js = zipWith (\a b -> (b - a) / dt) accs (drop 1 accs)
    ok j = j <= pbJMax q + 1e-9 * max 1 (abs (pbJMax q)) && j >= pbJMin q - 1e-9 * max 1 (abs (pbJMin q))
