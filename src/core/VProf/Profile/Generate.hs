-- | The velocity-profile generator: validation, the rubber band iterations, convergence,
-- and the verdict of the independent checker, as a 'Result'.
--
-- The iteration itself is pure ('iterations' is a lazy list of snapshots); 'generate'
-- walks it with the wall clock to honour the time budget, 'generatePure' with the
-- iteration cap only. Either way the result never passes an illegal profile off as
-- success: 'Generated' carries a profile the checker found legal, anything else is a
-- 'Failed' with the reason and, where there is one, the best profile and its violations.
module VProf.Profile.Generate
  ( module VProf.Profile.Result
  , generate
  , generatePure
  , generateProblem
  , generateWithPlan
  , iterations
  , Snapshot (..)
  , thesisHorizon
  , thesisLeastWork
  , thesisWork
  ) where

import qualified Data.Vector.Unboxed as U
import GHC.Clock (getMonotonicTime)
import System.Timeout (timeout)
import Control.Exception (evaluate)
import Data.IORef (IORef, newIORef, readIORef, writeIORef)
import Data.List (sortOn)

import VProf.Profile.Generate.RubberBand
import VProf.Profile.Generate.Seed
import VProf.Profile.Generate.Thesis
import VProf.Profile.Legality
import VProf.Profile.Sampled
import VProf.Profile.Problem (endsInMotion)
import VProf.Profile.Request
import VProf.Profile.Result
import VProf.Validation (FieldValue (..))

-- | The state after each pass.
data Snapshot = Snapshot
  { snVel       :: !(U.Vector Double)
  , snIteration :: !Int
  , snChanged   :: !Int
  , snDone      :: !Bool    -- ^ fixed point: a raising pass changed nothing
  }

-- | The passes of the rubber band for a problem: the starting profile (iteration 0)
-- and the profile after each pass (in thesis mode after each chunk of passes), ending at
-- the fixed point or going on until the iteration cap. Raising passes only ever raise,
-- so the sequence is monotone and cannot cycle.
iterations :: Problem -> Either Failure [Snapshot]
iterations pb = case pbAlgorithm pb of
  Band -> case bestSeed pb of
    Left f -> Left (seedFailure pb f)
    Right v0 -> Right (bandFrom pb v0)
  Thesis -> case thesisStages pb of
    -- the thesis mode's start and run-in fail where the request may be infeasible: the
    -- default generator's analysis says whether it is (and why)
    Left tf -> Left (case seed pb of
                       Left f@(Unattainable _ _) -> seedFailure pb f
                       Left f@(OverCap _) -> seedFailure pb f
                       _ -> NotConverged ("thesis mode: " ++ seedMessage tf))
    Right stages -> Right [ Snapshot (stgVel st) (stgPasses st) (stgChanged st) (stgDone st) | st <- stages ]
  where
    seedMessage = \case
      Unattainable _ m -> m
      LandingFailed m -> m
      OverCap m -> m

seedFailure :: Problem -> SeedFailure -> Failure
seedFailure pb = \case
  Unattainable f m -> InfeasibleRequest f m
  LandingFailed m -> NotConverged ("seed: " ++ m)
  OverCap m -> InvalidRequest [FieldError "route_length" (Number (pbLength pb)) "m" m]

-- | The default generator's passes from a seed: the seed (iteration 0) and the profile
-- after each raising pass, up to the fixed point.
bandFrom :: Problem -> U.Vector Double -> [Snapshot]
bandFrom pb v0 = Snapshot v0 0 0 False : go 1 v0
  where
    go !i v =
      let PassResult v' changed = pass pb v
          done = changed == 0
      in Snapshot v' i changed done : if done then [] else go (i + 1) v'

-- | The verdict on the last snapshot.
finish :: Problem -> Double -> Int -> Bool -> Maybe String -> U.Vector Double -> Result
finish pb secs iters done stopReason v
  | sampleCount prof > maxSamples =
      Result (Failed (InvalidRequest [overCap])) Nothing [] iters False (pbAlgorithm pb) (pbDt pb) (pbDv pb) secs
  | otherwise = finishWithin pb secs iters done stopReason prof vs
  where
    (prof, vs) = arrived pb (Profile (pbDt pb) v (pbA0 pb) (pbAEnd pb))
    overCap = FieldError "route_length" (Number (pbLength pb)) "m"
      ("the profile needs " ++ show (sampleCount prof) ++ " samples at time_step " ++ show (pbDt pb)
       ++ " s, above the cap of " ++ show maxSamples ++ " samples; split the route or raise time_step")

-- | The result of a profile within the sample cap, given the checker's verdict on it.
finishWithin :: Problem -> Double -> Int -> Bool -> Maybe String -> Profile -> [Violation] -> Result
finishWithin pb secs iters done stopReason prof vs =
  let outcome
        | null vs && done = Generated
        | null vs = Failed (NotConverged (maybe "stopped before the fixed point" id stopReason
                                          ++ "; the best profile so far is legal"))
        | otherwise = Failed (NotConverged (maybe "the fixed point of the iteration breaks limits: "
                                                  (++ "; the best profile breaks limits: ") stopReason
                                           ++ summarise vs ++ standingHint))
  in Result outcome (Just prof) vs iters done (pbAlgorithm pb) (pbDt pb) (pbDv pb) secs
  where
    summarise vs = show (length vs) ++ " violation(s), first " ++ renderViolation (head vs)
    -- the thesis mode raises whole velocity steps: on a route shorter than one step covers, its
    -- profile never leaves the start
    standingHint
      | pbAlgorithm pb == Thesis, sampleCount prof <= 2, any (\v -> vRule v == RouteEnd) vs =
          " (the thesis mode moves in velocity steps of " ++ show (pbDv pb) ++ " m/s per time_step of " ++ show (pbDt pb)
          ++ " s, more than this route takes: the band algorithm, or a smaller time_step, reaches it)"
      | otherwise = ""

-- | The profile ends at the first sample at which it has arrived (the checker's @crawl@
-- rule): whatever follows, creeping or standing at the end, is cut off. With the checker's
-- verdict on the profile it ends: the verdict already made when nothing is cut (one pass of
-- the checker, not two, on up to 2²⁰ samples; it is also what a timeout waits for).
arrived :: Problem -> Profile -> (Profile, [Violation])
arrived pb p = case [ k | Violation Crawl k _ _ <- vs0 ] of
  k : _ -> let p' = p { prVelocities = U.take (k + 1) (prVelocities p) } in (p', check pb p')
  [] -> (p, vs0)
  where vs0 = check pb p

-- | Generate with the iteration cap only (no clock): a pure function of the problem.
generatePure :: Request -> Result
generatePure rq = case validate rq of
  Left es -> invalid rq es
  Right pb -> case iterations pb of
    Left f -> failed pb f
    Right snaps ->
      let capped = take (pbMaxIter pb + 1) snaps
          lastSnap = last capped
          reason = if snDone lastSnap then Nothing else Just (capReason pb)
      in finish pb 0 (snIteration lastSnap) (snDone lastSnap) reason (snVel lastSnap)

capReason :: Problem -> String
capReason pb = "iteration cap of " ++ show (pbMaxIter pb) ++ " reached"

invalid :: Request -> [FieldError] -> Result
invalid rq es = Result (Failed (InvalidRequest es)) Nothing [] 0 False (rqAlgorithm rq) 0 0 0

failed :: Problem -> Failure -> Result
failed pb f = Result (Failed f) Nothing [] 0 False (pbAlgorithm pb) (pbDt pb) (pbDv pb) 0

-- | Generate with the iteration cap and the wall-clock budget.
generate :: Request -> IO Result
generate rq = case validate rq of
  Left es -> pure (invalid rq es)
  Right pb -> generateProblem pb

-- | The wall-clock budget binds the whole generation: iterations are checked between
-- passes, and a stage (the seed, a seed variant, a pass) still running at the hard limit
-- ('hardLimit': about the budget) is stopped by a timeout. The answer is then NOT_CONVERGED, naming the stage that ran out,
-- with the last profile a finished stage left (the best seed so far, or the profile of the
-- last finished pass) and the checker's verdict on it; before the seed has finished there
-- is no profile to give.
generateProblem :: Problem -> IO Result
generateProblem pb = generateWithPlan pb (seedPlan pb)

-- | 'generateProblem' with the seed plan given: the problem's own ('seedPlan') in the
-- generator; the tests give one whose variants they control.
generateWithPlan :: Problem -> SeedPlan -> IO Result
generateWithPlan pb plan = do
  t0 <- getMonotonicTime
  latest <- newIORef (Nothing, seedStage pb)
  r <- timeout (ceiling (hardLimit pb * 1e6)) (generateWithin pb plan t0 latest)
  case r of
    Just res -> pure res
    Nothing -> do
      (best, stage) <- readIORef latest
      let spent = "time budget of " ++ show (pbBudget pb) ++ " s spent "
      res <- case best of
        Nothing -> pure (failed pb (NotConverged (spent ++ stage ++ ", before the first pass finished" ++ roomHint pb)))
        Just (sn, kept) -> do
          -- (a fixed point reached just before the limit: only its verdict ran out of time)
          let reason | snDone sn = Nothing
                     | otherwise = Just (spent ++ stage ++ "; the profile is " ++ kept)
              r0 = finish pb 0 (snIteration sn) (snDone sn) reason (snVel sn)
          _ <- evaluate (length (resViolations r0))
          pure r0
      t1 <- getMonotonicTime
      pure res { resSeconds = t1 - t0 }

-- | What a budget spent before the first profile suggests, with the fewest samples the route
-- needs: a seed costs up to some microseconds a sample, and a fine time step makes hundreds of
-- thousands of them (at 0.1-1 ms 3 and 2 of the 30 random routes of 1-300 m of
-- bench/fuzz-requests --fine's seeds 5 and 6 are still seeding after 1 s, the default budget;
-- all 120 of its seeds 1, 2, 5 and 6 are answered within 20 s).
roomHint :: Problem -> String
roomHint pb =
  "; the profile needs at least " ++ show (ceiling (problemLeastSamples pb) :: Int) ++ " samples at time_step "
  ++ show (pbDt pb) ++ " s: give time_budget more room, or use a coarser time_step"

-- | The wall-clock time after which a running stage is stopped (s): the budget and a
-- twentieth of it (10-50 ms), less the time a long answer's verdict, garbage collection
-- and exit may take (up to 0.15 s for an answer of 2²⁰ samples, by the fewest samples the
-- route needs; at most half the budget), so that the whole run stays within the budget and
-- a quarter second.
hardLimit :: Problem -> Double
hardLimit pb = pbBudget pb + min 0.05 (max 0.01 (pbBudget pb / 20)) - reserve
  where
    reserve = min (pbBudget pb / 2) (0.15 * least / fromIntegral maxSamples)
    least = problemLeastSamples pb

-- | What a generation does before its first profile: the words for a timeout then.
seedStage :: Problem -> String
seedStage pb = case pbAlgorithm pb of
  Band -> "in the greedy seed"
  Thesis -> "in thesis mode's first stage"

-- | The last profile a finished stage left, with the words for it, and the stage running
-- now: what a timeout answers with.
type Latest = IORef (Maybe (Snapshot, String), String)

-- | The default generator's seed within the wall-clock budget, in 'seedPlan''s order: the
-- greedy seed, then the variants one after the other while less than half the budget is
-- spent (each at most a pass of the seed's length); the best so far is the latest
-- snapshot. A variant still running at 'variantShare' of the budget is given up and the
-- rubber band starts from the best seed so far, so that a variant which cannot finish
-- does not take the band's time with it. The same seed as 'bestSeed' when the budget does
-- not run out.
seedWithin :: Problem -> SeedPlan -> IO Double -> Latest -> IO (Either Failure [Snapshot])
seedWithin pb plan elapsed latest =
  case spSeed plan of
    Left f -> pure (Left (seedFailure pb f))
    Right v0 -> do
      _ <- evaluate v0
      let variants = spVariants plan
          compareWith _ best [] = pure best
          compareWith k best (q : qs) = do
            secs <- elapsed
            if secs > pbBudget pb / 2
              then pure best
              else do
                writeIORef latest (Just (Snapshot best 0 0 False, "the best seed so far")
                                  , "in seed variant " ++ show k ++ " of " ++ show (length variants))
                let left = variantShare * pbBudget pb - secs
                done <- timeout (ceiling (left * 1e6)) (evaluate (improveSeed pb best q))
                case done of
                  Just best' -> compareWith (k + 1 :: Int) best' qs
                  Nothing -> pure best
      best <- if variantsApply pb v0 then compareWith 1 v0 variants else pure v0
      pure (Right (bandFrom pb best))

-- | The share of the time budget after which a seed variant still running is given up.
-- The rest is the rubber band's and the verdict's: from a greedy seed the band mostly
-- needs a few passes, each some tens of nanoseconds a sample, and the seeds compared with
-- variants have at most 'ladderSamples' samples. (With a 1 s budget at 0.1 ms, routes of
-- 72,716 and 104,733 samples seeded in 0.33 s and 0.36 s and their first variant took
-- 0.63 s and 0.92 s: the timeout stopped it and the answer was NOT_CONVERGED with the seed;
-- the band's two passes from that seed then take 6 ms.)
variantShare :: Double
variantShare = 0.75

generateWithin :: Problem -> SeedPlan -> Double -> Latest -> IO Result
generateWithin pb plan t0 latest = do
  let elapsed = do t <- getMonotonicTime; pure (t - t0)
  snapshots <- case pbAlgorithm pb of
    Band -> seedWithin pb plan elapsed latest
    Thesis -> pure (iterations pb)
  case snapshots of
    Left f -> do
      _ <- evaluate f
      secs <- elapsed
      pure (failed pb f) { resSeconds = secs }
    Right snaps -> do
      let walk (sn : rest) = do
            _ <- evaluate (snVel sn)
            writeIORef latest (Just (sn, if snIteration sn == 0 then "the seed" else "that of pass " ++ show (snIteration sn))
                              , "during pass " ++ show (snIteration sn + 1))
            secs <- elapsed
            if snDone sn
              then pure (sn, Nothing)
              else if snIteration sn >= pbMaxIter pb
                then pure (sn, Just (capReason pb))
                else if secs > pbBudget pb
                  then pure (sn, Just ("time budget of " ++ show (pbBudget pb) ++ " s spent after "
                                       ++ show (snIteration sn) ++ " iterations"))
                  else case rest of
                    [] -> pure (sn, Nothing)
                    _ -> walk rest
          walk [] = error "iterations: empty"
      (sn, reason) <- walk snaps
      let r0 = finish pb 0 (snIteration sn) (snDone sn) reason (snVel sn)
      _ <- evaluate (length (resViolations r0))
      r <- if pbAlgorithm pb == Band && pbSeedSearch pb && resOutcome r0 == Generated && U.length (snVel sn) <= thesisVariantSamples
             then viaThesis pb elapsed r0
             else pure r0
      secs <- elapsed
      pure r { resSeconds = secs }

-- | A converged answer of at most this many samples is compared with thesis mode's
-- ('viaThesis'): thesis mode costs many passes a sample, so beyond it the comparison would
-- cost more than the answer.
thesisVariantSamples :: Int
thesisVariantSamples = 2048

-- | The work thesis mode may spend in 'viaThesis', in passes times the answer's samples
-- (on a 2-core EPYC VM a unit costs 32 ns with 9 zones, 67 ns with 152: some 0.3-0.7 s a
-- velocity step): a velocity step whose least work ('thesisLeastWork') is beyond it is not
-- tried, a run's passes are capped at it over the answer's samples, and a run whose stages'
-- passes times samples pass it is given up (the answer stands). A 6.6 m route of 1,131
-- samples at 10 ms with a jerk of 0.17 m/s³ spent 17 s of a 20 s budget (the whole of any
-- budget below that) on thesis mode's fixed points, 77 s long against the answer's 11.3 s;
-- the requests of test/data it was made for take at most 3·10⁶.
thesisWork :: Double
thesisWork = 1e7

-- | The least work (passes times the answer's samples) thesis mode needs at velocity step
-- @dv@ to be shorter than an answer of @n0@ samples. Its profile is the start braked to
-- rest, its band grown from rest by at most @dv@ a pass, and, for a moving end, the end
-- state's run-in from rest (fixed): to beat the answer, the band must pass the pace that
-- covers the rest of the route in the samples left (nothing to pass where the start is
-- already that fast: 0). Infinite where thesis mode cannot run in to the end state at all,
-- or the run-in alone takes as many samples as the answer.
thesisLeastWork :: Problem -> Int -> Double -> Double
thesisLeastWork pb n0 dv = case runIn of
  Just (nT, dE) | nT < n0 ->
    let pace = (pbLength pb - dE) / (fromIntegral (n0 - nT) * pbDt pb)
    in if pace > pbV0 pb then pace / dv * fromIntegral n0 else 0
  _ -> 1 / 0
  where
    runIn
      | endsInMotion pb =
          either (const Nothing) (\t -> Just (U.length t, U.last (trapezoidDistances (pbDt pb) t))) (restWithinJerk (mirror pb))
      | otherwise = Just (0, 0)

-- | The last variant of the default generator's seed, with what is left of the budget:
-- thesis mode's fixed point ("VProf.Profile.Generate.Thesis"), grown from rest. Where the
-- greedy seeds all brake too late (weak jerk against a strong one, many zones), its gentle
-- growth can arrive sooner. When it reaches its fixed point within the budget, is legal
-- and shorter than the converged answer, the default generator's passes run from it to
-- their own fixed point; if any of that runs out of the budget or of 'thesisWork', the
-- converged answer stands.
viaThesis :: Problem -> IO Double -> Result -> IO Result
viaThesis pb elapsed r0 = do
  secs <- elapsed
  let left = pbBudget pb - secs
      n0 = maybe maxBound sampleCount (resProfile r0)
      -- at most 'thesisWork' passes times the answer's samples (thesis mode checks its
      -- stages only every few thousand passes on a long horizon)
      thPb = pb { pbAlgorithm = Thesis
                , pbMaxIter = min (max (pbMaxIter pb) (defaultMaxIterations Thesis)) (ceiling (thesisWork / fromIntegral n0)) }
      -- thesis mode's own velocity step is coarser than the default generator's, and its
      -- pace (a step a sample a pass) sets how gently it brakes: with either step it can be
      -- the faster (0.87 m, 200 zones: 39.875 s with its own, 40.375 s with the default's)
      dvs = let own = thesisVelocityStep (pbDt pb) (pbAMin pb) (pbAMax pb) (pbJMin pb) (pbJMax pb)
            in pbDv pb : [ own | own > pbDv pb ]
      fixedPoint dv
        | thesisLeastWork pb n0 dv > thesisWork = Nothing
        | otherwise = case thesisStages thPb { pbDv = dv } of
            Left _ -> Nothing
            Right stages -> within 0 0 stages
      -- the stages while their passes times their samples stay within 'thesisWork'
      within _ _ [] = Nothing
      within work p (st : rest)
        | stgDone st = Just (stgVel st)
        | work' > thesisWork = Nothing
        | otherwise = within work' (stgPasses st) rest
        where work' = work + fromIntegral (stgPasses st - p) * fromIntegral (U.length (stgVel st))
      legalLength v = let (prof, vs) = arrived pb (Profile (pbDt pb) v (pbA0 pb) (pbAEnd pb))
                      in if null vs then Just (sampleCount prof) else Nothing
      shortest = case sortOn fst [ (m, v) | dv <- dvs, Just v <- [fixedPoint dv], Just m <- [legalLength v] ] of
        (m, v) : _ | m < n0 -> Just v
        _ -> Nothing
      attempt = case shortest of
        Just v ->
          let snaps = bandFrom pb v
              final = last (take (pbMaxIter pb + 1) snaps)
          in if snDone final
               then let r = finish pb 0 (snIteration final) True Nothing (snVel final)
                    in if resOutcome r == Generated && maybe False ((< n0) . sampleCount) (resProfile r)
                         then Just r else Nothing
               else Nothing
        _ -> Nothing
  if left <= 0
    then pure r0
    else do
      res <- timeout (ceiling (left * 1e6)) (evaluate (forceResult attempt))
      pure (maybe r0 (maybe r0 id) res)
  where
    forceResult m = case m of
      Just r -> length (resViolations r) `seq` maybe () (\p -> U.sum (prVelocities p) `seq` ()) (resProfile r) `seq` m
      Nothing -> m
