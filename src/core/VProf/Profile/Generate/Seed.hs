-- | The seed profile: a profile legal by construction and close to time-optimal, from
-- which the rubber band starts.
--
-- A route that ends at rest is seeded by one greedy pass ("VProf.Profile.Generate.Seed.Greedy")
-- that brakes to a standstill on the route end and creeps onto it; a route that ends in
-- motion by the two-sided meet ("VProf.Profile.Generate.Seed.Meet"). Both stand on the
-- brake policy and its oracle ("VProf.Profile.Generate.Seed.Brake"); when the start (or
-- end) state fails the oracle, the first step is searched ("VProf.Profile.Generate.Seed.LeadIn");
-- the failures are worded in "VProf.Profile.Generate.Seed.Explain". The method is
-- described in docs/profile-generator.md.
--
-- Invariant: a seed is legal for its problem (the checker's rules; a crawl aside, which the
-- generator cuts at the arrival); an 'Unattainable' failure is a claim about the request, a
-- 'LandingFailed' one only about the generator.
module VProf.Profile.Generate.Seed
  ( seed
  , seedWithLeadIn
  , bestSeed
  , SeedPlan (..)
  , seedPlan
  , variantsApply
  , ladderSamples
  , seedVariants
  , throughRestBy
  , runInCruise
  , improveSeed
  , Variant
  , SeedFailure (..)
  , brakeStopDistance
  , mirror
  , restFrom
  , restWithinJerk
  ) where

import Data.List (foldl')
import qualified Data.Vector.Unboxed as U

import VProf.Profile.Generate.Exact (compareWork, exactJoinFewer)
import VProf.Profile.Generate.Seed.Brake
import VProf.Profile.Generate.Seed.Explain
import VProf.Profile.Generate.Seed.Greedy (forwardMarked, passCapMessage, passStepCap)
import VProf.Profile.Generate.Seed.LeadIn (leadIn, leadInMayHelp)
import VProf.Profile.Generate.Seed.Meet (meet)
import VProf.Profile.Legality (Rule (..), Violation (..), check, legalButCrawl)
import VProf.Profile.Problem (Problem (..), endsInMotion)
import VProf.Profile.Sampled (Profile (..), trapezoidDistances)
import VProf.Profile.Problem.Transform (mirror, scaleJerk, scaleRanges)
import VProf.Profile.Request (maxSamples, problemLeastSamples)

-- | Levels of lead-in: a first step, and one more within the rest.
leadInDepth :: Int
leadInDepth = 2

-- | The seed profile's velocities v_0..v_N.
seed :: Problem -> Either SeedFailure (U.Vector Double)
seed = seedWithLeadIn leadInDepth

-- | The seed with up to @depth@ levels of lead-in: when the start state is stuck (by
-- little enough for a first step to matter, 'leadInMayHelp'), the lead-in on the
-- problem; when the end state is, the lead-in on its mirror, reversed.
seedWithLeadIn :: Int -> Problem -> Either SeedFailure (U.Vector Double)
seedWithLeadIn depth pb = case seedFrom pb of
  Left f@(Unattainable "start_velocity" _) | depth > 0, leadInMayHelp moving pb -> either (Left . maybe f id) Right (leadIn seedWithLeadIn depth pb)
  Left f@(Unattainable "end_velocity" _) | depth > 0, leadInMayHelp True (mirror pb) -> case leadIn seedWithLeadIn depth (mirror pb) of
    Right vs -> Right (U.reverse vs)
    Left (Just (LandingFailed m)) -> Left (LandingFailed ("seen from the end, backwards in time: " ++ m))
    Left _ -> Left f
  r -> r
  where moving = endsInMotion pb

-- | The seed without a lead-in: a start acceleration that sinks the velocity is refused,
-- a moving end is met from both sides, and an end at rest is landed by one pass.
seedFrom :: Problem -> Either SeedFailure (U.Vector Double)
seedFrom pb
  | sinksBelowZero pb = Left (startSinks pb)
  | endsInMotion pb = meet pb
  | otherwise = landing passStepCap pb

-- | Ending at rest: the pass brakes to a standstill on the route end; near rest it
-- creeps, so it lands within the tolerance. At most @limit@ steps: a pass that has not
-- landed by then fails.
landing :: Int -> Problem -> Either SeedFailure (U.Vector Double)
landing limit pb = either (\f -> maybe (Left f) Right (overrun pb)) Right (landingOnEnd limit pb)

-- | A start too fast to stop by the route end may still stop within its end tolerance past
-- it (the checker's rule is |s_N - L| <= end_tolerance): the hardest braking to rest, when
-- it keeps the limits with its terminal there and comes to rest within the tolerance of
-- the end.
overrun :: Problem -> Maybe (U.Vector Double)
overrun pb = case brakeCheck e st0 of
  Left _ -> Nothing
  Right () ->
    let sts = take maxSamples (hardBraking e st0)
        sEnd = if null sts then 0 else stS (last sts)
    in if not (null sts) && abs (sEnd - pbLength pb) <= pbTol pb
         then Just (U.fromList (pbV0 pb : map stV sts)) else Nothing
  where
    e = seedEnv pb (Term (pbLength pb + pbTol pb) 0) True
    st0 = St (pbV0 pb) (pbA0 pb) 0

-- | The states of the hard brake policy from a state until it is at rest.
hardBraking :: SeedEnv -> St -> [St]
hardBraking e st
  | atRest e st = []
  | otherwise = let st' = stepTo e st (brakeAcc e st) in st' : hardBraking e st'

-- | 'landing' with the terminal on the route end, the first legal one of: the pass that
-- probes long manoeuvres only now and then ('forward'); when that one lands but breaks the
-- jerk rule alone, the same planning every step a little inside the jerk range, with wider
-- margins while it still does ('jerkPlanMargins': at a 1 ms step the rounding of the
-- velocities can put a ramp at the full jerk 1e-9 to 8e-8 m/s³ beyond it; where that
-- rounding alone is beyond the checker's slack, 'roundingJerk', the margins come first);
-- when the schedule skipped a probe and the pass did not just run out of its @limit@
-- steps, the pass that probes at every step, and it with the margins when it too lands but
-- breaks the jerk rule alone. Else the answer of the last kind of pass at the full jerk.
-- (A scheduled pass that skipped no probe is the every-step pass: every pass at a coarse
-- step. One that ran out of steps is most often a seed variant cut off once it is no
-- shorter than the best ('improveSeed'), which the every-step pass, at most a few steps
-- faster, would rarely beat: it is not worth a second pass.)
landingOnEnd :: Int -> Problem -> Either SeedFailure (U.Vector Double)
landingOnEnd limit pb =
  case [ v | (Right v, Legal) <- tries ] of
    v : _ -> Right v
    [] -> fst (if retry then failedAs False everyLadder else failedAs True schedLadder)
  where
    -- where the rounding of the fastest velocity alone is beyond the checker's slack in jerk,
    -- a full-jerk ramp breaks the rule at once: the margins from the start
    fullJerk = fullJerkHolds pb
    margins = [ 0 | fullJerk ] ++ jerkPlanMargins pb
    landed s m = landingBy s m limit pb
    -- a landing's answer and the checker's verdict on it (a pass that did not land: broken)
    verdict l = let r = lResult l in (r, either (const Broken) (verdictOf pb) r)
    -- lazily: a legal first landing costs one pass; each landing is run and checked once
    firstSched = landed True (head margins)
    Landing _ skipped ranOut = firstSched
    retry = skipped && not ranOut
    -- each wider margin only while the landing before it lands and breaks the jerk rule
    -- alone, which a margin may cure (a variant's landing that stepped to rest at
    -- -293 m/s², beyond the acceleration range, was landed three more times, each with the
    -- same violation)
    ladder s l0 = go l0 (drop 1 margins)
      where go l ms = let r = verdict l
                      in r : (if snd r == JerkOnly then case ms of { m : rest -> go (landed s m) rest; [] -> [] } else [])
    schedLadder = ladder True firstSched
    everyLadder = ladder False (landed False (head margins))
    tries = schedLadder ++ (if retry then everyLadder else [])
    -- when none is legal: the landing at the full jerk (a narrowed problem's failure, such as a
    -- start it cannot save, is no claim about this one)
    failedAs s lad = if fullJerk then head lad else verdict (landed s 0)
-- | The checker's verdict on velocities for a problem, a crawl aside (the generator cuts a
-- profile at its arrival): legal; broken in the jerk rule alone, which planning a little
-- inside the jerk range may cure (the velocities' rounding); or broken otherwise.
data Verdict = Legal | JerkOnly | Broken
  deriving (Eq, Show)

verdictOf :: Problem -> U.Vector Double -> Verdict
verdictOf pb v = case [ r | x <- check pb (Profile (pbDt pb) v (pbA0 pb) (pbAEnd pb)), let r = vRule x, r /= Crawl ] of
  [] -> Legal
  rs | all (== JerkRule) rs -> JerkOnly
     | otherwise -> Broken

-- | A landing pass's answer, whether its schedule skipped a probe, and whether it ran out of
-- its steps.
data Landing = Landing
  { lResult :: Either SeedFailure (U.Vector Double)
  , _lSkipped :: Bool
  , _lRanOut :: Bool
  }

-- | The landing pass, probing on the schedule or not, planning with a jerk margin or not.
landingBy :: Bool -> Double -> Int -> Problem -> Landing
landingBy scheduled margin limit pb = case policyWith margin pb term st0 of
  Left bad -> Landing (Left (startInfeasible pb (seedEnv pb term True) bad)) False False
  Right e0 ->
    -- the pass unboxed as it is made (a boxed list of states takes some 100 bytes a state)
    let (vs, as, ss, marks) = U.unzip4 (U.fromList [ (v, a, s, k) | (St v a s, k) <- forwardMarked scheduled e0 landTol limit st0 ])
        sEnd = if U.null ss then 0 else U.last ss
        aRest = if U.null as then pbA0 pb else U.last as
        -- at rest with an acceleration that cannot return to zero in one jerk step:
        -- stand still for one more sample
        settle = let j = negate aRest / dt in if j >= pbJMin pb && j <= pbJMax pb then [] else [0]
        -- the pass aims at half the tolerance; one that ends outside that but within the
        -- tolerance the checker allows (|s_N - L| <= end_tolerance) is kept (at a 1 s step a
        -- 32.741 m route was missed by 5.0 mm of a 10 mm tolerance and answered NOT_CONVERGED)
        landed
          | abs (sEnd - pbLength pb) <= landTol || U.null vs && pbLength pb <= landTol
              || not (U.null vs) && abs (sEnd - pbLength pb) <= pbTol pb
              = Right (U.concat [U.singleton (pbV0 pb), vs, U.fromList settle])
          | U.length vs >= passStepCap = Left (OverCap (passCapMessage pb "forward" sEnd))
          | otherwise = Left (LandingFailed ("the forward pass stopped at " ++ num sEnd ++ " m, aiming at " ++ num (pbLength pb) ++ " m"))
    in Landing landed (U.or marks) (U.length vs >= limit)
  where
    dt = pbDt pb
    st0 = St (pbV0 pb) (pbA0 pb) 0
    term = Term (pbLength pb) 0
    landTol = pbTol pb / 2

-- | A seed of at most this many samples is compared with the seeds of the variants of
-- its problem ('bestSeed'); a longer one is kept as it is (the variants would
-- cost up to five more greedy passes of its length).
ladderSamples :: Int
ladderSamples = 131072

-- | Does the seed get compared with the variants' ('bestSeed')? Only a seed of at most
-- 'ladderSamples' samples.
variantsApply :: Problem -> U.Vector Double -> Bool
variantsApply pb v0 = pbSeedSearch pb && U.length v0 <= ladderSamples

-- | A variant's seed, given the most steps it may take (beyond them it cannot be shorter).
type Variant = Int -> Maybe (U.Vector Double)

-- | The default generator's seed: 'seed', or a shorter one from a variant of the problem
-- ('seedVariants') when one is legal for the problem.
--
-- The greedy pass is not time-optimal. It speeds up into every higher zone it can reach,
-- and where the jerk that ends a braking is much weaker than the one that starts it
-- (asymmetric ranges), the braking before the next lower zone, begun at the last moment,
-- sinks far below that zone's limit while its acceleration slowly returns to zero: in a
-- cluster of short zones the profile nearly stops before each low one. The same pass with
-- symmetric ranges (the weaker side's magnitude both ways) starts braking earlier and
-- gentler and, there, arrives seconds sooner; with every zone lowered to the lowest limit
-- a steady plateau can beat a chain of such dips. And the two-sided meet of a route that
-- ends in motion may join its passes only on a plateau far below the limits, where
-- stopping once and running in to the end state (thesis mode's way) is faster. So the
-- greedy pass also runs on each variant, each stopped once it is no shorter than the best
-- so far ('improveSeed'), and the shortest seed wins. Each variant's limits are at most
-- the problem's and its ranges inside the problem's, so its seed is legal for the problem
-- too (the checker confirms it, crawl aside: the generator cuts a profile at its
-- arrival). Because the lowered problem's own variants are among them, lowering the
-- limits never makes the default generator's profile faster.
bestSeed :: Problem -> Either SeedFailure (U.Vector Double)
bestSeed pb = do
  let plan = seedPlan pb
  v0 <- spSeed plan
  pure $ if variantsApply pb v0 then foldl' (improveSeed pb) v0 (spVariants plan) else v0

-- | The order in which 'bestSeed' finds its seed, which the wall-clock generator walks
-- with a snapshot after each step: 'seed' first (the two-sided meet, or the landing of a
-- route that ends at rest), then the variants. Where the meet of a route that ends in
-- motion finds no join, the seed through rest (the head of its variants) is the first seed
-- when it is legal, and the variants follow without it.
--
-- (Long routes ending in motion were once seeded through rest first, the meet after it,
-- because the meet could cost many greedy passes: 5-12 s against 1.5-2 s on a 12 m route
-- at 0.17 ms. That cost was 'brakeBound''s, which put the route's end in reach far too
-- early; with its triangle the meet takes 0.7 s there and the seed through rest 0.9 s, and
-- the order only spent a pass before the meet: without it the 12 m routes of test/data
-- converge to 6.954 s and 6.798 s within 1 s, where they gave 8.783 s and 8.803 s, and
-- dented-join-fine-31m to 16.853 s within 3 s, where it gave 18.408 s. Figures in
-- docs/profile-generator.md, "The seed through rest as a fallback".)
data SeedPlan = SeedPlan
  { spSeed :: Either SeedFailure (U.Vector Double)
    -- ^ 'seed', or where the meet finds no join the seed through rest
  , spVariants :: [Variant]
  }

-- | 'bestSeed''s order for a problem (lazy: each part is computed when it is used). A start
-- at rest (or slower than the end) whose route only just reaches its end velocity is seeded
-- by its run-in and cruise ('quickRunIn') without the meet.
seedPlan :: Problem -> SeedPlan
seedPlan pb
  | Just v <- quickRunIn pb = SeedPlan (Right v) (seedVariants pb)
  | otherwise = uncurry SeedPlan $ case seed pb of
  -- the head of a moving end's variants is the seed through rest ('seedVariants'), here of
  -- any length; what it returns the checker has found legal for the problem, a crawl aside.
  -- A proof that the end state cannot be reached is kept: no profile can be legal.
  -- Where nothing through rest fits either, a start slower than the end takes its run-up
  -- and cruise with any number of steps (a 23.4 m route from 3.20 to 3.93 m/s at 17.8 ms
  -- took 367 samples, more than 'quickRunIn' allows, and was NOT_CONVERGED without one).
  Left f@(LandingFailed _) | endsInMotion pb && pbSeedSearch pb, _viaRest : rest <- variants ->
    case throughRestBy False pb ladderSamples of
      Just r -> (Right r, rest)
      Nothing | runsUp pb, Just r <- runInCruise pb ladderSamples -> (Right r, variants)
      Nothing -> (Left f, variants)
  r -> (r, variants)
  where variants = seedVariants pb

-- | The variants of a problem whose seeds 'bestSeed' compares: the problem with symmetric
-- jerk ranges, with symmetric acceleration and jerk ranges, and the same three with every
-- zone lowered to the lowest limit (when the start and end velocities fit under it), each
-- only once. A route that ends at rest lands each (but the problem itself) by one greedy
-- pass; a route that ends in motion lands each (the problem itself too) at rest where the
-- end state's run-in begins, and then runs in, and also takes the lowered problem's own
-- seed (its two-sided meet) and, last, the exact join of fewer steps than the best so far,
-- of the problem and of the lowered one ('exactJoinFewer').
seedVariants :: Problem -> [Variant]
seedVariants pb
  | moving = map throughRest (dedupe [] problems) ++ [ runInCruise pb | runsUp pb ]
             ++ [ loweredSeed | lowerable, lowered /= pb ]
             ++ [ fewerSteps q | q <- pb : [ lowered | lowerable, lowered /= pb ] ]
  | otherwise = map landed (dedupe [pb] problems)
  where
    moving = endsInMotion pb
    vLow = U.minimum (pbZoneSpeeds pb)
    lowerable = pbV0 pb <= vLow && pbVEnd pb <= vLow
    problems = [ t q | q <- pb : [ lowered | lowerable ], t <- [id, symJerk, symJerk . symAcc] ]
    -- a moving end: the lowered problem's own seed (its two-sided meet) too, which its
    -- variants do not give (a 0.70 m route to 0.136 m/s took 4.5 s as asked and 4.0 s with
    -- its zones lowered: the meet of the lowered one joins on a plateau the other's misses)
    loweredSeed limit = case seed lowered of
      Right v | U.length v <= limit + 1 -> Just v
      _ -> Nothing
    lowered = pb { pbZoneStarts = U.singleton 0, pbZoneSpeeds = U.singleton vLow }
    -- a moving end: the exact join of fewer steps than the best seed so far, if any. The
    -- meet's plateau can lie far below the fastest profile on a short route, even stop on
    -- it, and a stop is a fixed point of the rubber band: a 10 m route from rest behind a
    -- 0.953 m/s zone (1.19 m) took 8.625 s ending at 3 m/s, stopping at 5.73 m; the exact
    -- join's profile takes 5.25 s.
    fewerSteps q limit = exactJoinFewer compareWork (limit + 1) q
    symJerk q = let m = min (negate (pbJMin q)) (pbJMax q) in q { pbJMin = negate m, pbJMax = m }
    symAcc q = let m = min (negate (pbAMin q)) (pbAMax q) in q { pbAMin = negate m, pbAMax = m }
    dedupe _ [] = []
    dedupe seen (q : qs) | q `elem` seen = dedupe seen qs
                         | otherwise = q : dedupe (q : seen) qs
    landed q limit
      | sinksBelowZero q = Nothing
      | otherwise = either (const Nothing) Just (landing limit q)
-- | Thesis mode's way to a moving end ("VProf.Profile.Generate.Thesis") as a seed variant:
-- at rest where the hardest braking from the end state, backwards in time, begins; two
-- samples at rest there, so that the acceleration is zero between the landing and the
-- run-in. The run-in brakes at the full jerk; where the rounding of the velocities puts
-- that beyond the jerk rule (a fine step, 'fullJerkHolds'), it is planned a little inside
-- the jerk range, with the margins in turn while the profile breaks only the jerk rule (a
-- 12 m route at 0.17 ms: the run-in of 9,072 samples broke it by 3e-9 m/s³ in 418
-- samples, and the 8.9 s profile through rest lost to the meet's 11.2 s).
throughRest :: Problem -> Variant
throughRest = throughRestBy True

-- | 'throughRest' for a seed variant (True: only a profile shorter than @limit@ + 2 samples
-- counts, and a landing that cannot give one is not run, 'stopCannotWin'), or as the seed
-- when the meet found none (False: any length, the landing up to its @limit@ steps, or a
-- start too fast to stop braked past the route end within its tolerance).
throughRestBy :: Bool -> Problem -> Variant
throughRestBy shorterOnly q limit = firstLegal (jerkPlanLadder q)
  where
    firstLegal [] = Nothing
    firstLegal (tq : rest) = case throughRestWith tq of
      Nothing -> Nothing
      Just w -> case verdictOf q w of
        Legal -> Just w
        JerkOnly -> firstLegal rest
        Broken -> Nothing
    throughRestWith tq = do
      tailV <- runInFromRest tq
      let dE = U.last (trapezoidDistances (pbDt q) tailV)
          restPb = q { pbLength = pbLength q - dE, pbVEnd = 0, pbAEnd = 0 }
      if pbLength restPb <= 0 || sinksBelowZero restPb then Nothing else Just ()
      -- no landing shorter than the least time allows, so none that could win: then the
      -- pass, up to the limit, is not run
      if shorterOnly && stopCannotWin restPb (U.length tailV) limit then Nothing else Just ()
      v <- either (const Nothing) Just (landing (limit - U.length tailV) restPb)
      pure (v U.++ tailV)

-- | A start at rest (or in motion below the end velocity, without acceleration): the end
-- state's run-in from rest at once (the hardest braking from the end state, backwards in
-- time, as in 'throughRest'; from a moving start lifted by its velocity, 'runUp'), then a
-- cruise at the end velocity over the rest of the route. Where the route only just reaches
-- the end velocity, this is the fastest profile there is but for the rounding to whole
-- steps, and the two-sided meet may find no plateau (its forward pass, which brakes its
-- acceleration by the policy's margins, can need more room to settle at the end velocity
-- than the run-in does): a 2.8 m route from rest to 1.12 m/s at 15.7 ms took 7.43 s through
-- rest, 5.70 s run in and cruising (test/data/just-reaching-run-in-3m.json); a 2.6 m route
-- from 0.53 to 2.14 m/s had no profile, now 1.749 s (just-reaching-moving-start-3m.json).
-- The cruise's steps are the nearest to the distance left, or one more or fewer; where none
-- of them ends within the tolerance, the run-in is narrowed until one does (below); the
-- run-in is planned inside the jerk range where the full jerk breaks the rule
-- ('jerkPlanLadder'); the first profile legal but for a crawl wins.
runInCruise :: Problem -> Variant
runInCruise q limit = case [ v | r <- runUps, v <- cruiseAfter r ] ++ held ++ softened of
  v : _ -> Just v
  [] -> Nothing
  where
    ladder = jerkPlanLadder q
    -- each rung of the ladder with its run-up (where it has one)
    rungs = [ (tq, r) | tq <- ladder, Just r <- [runUp tq] ]
    runUps = map snd rungs
    dt = pbDt q
    vEnd = pbVEnd q
    step = vEnd * dt
    -- the distance left after a run-in, in cruise steps
    stepsLeft runIn = (pbLength q - U.last (trapezoidDistances dt runIn)) / step
    room runIn = limit + 1 - U.length runIn
    -- (the steps counted before a profile is made: a long route at a slow end velocity
    -- would need more than the limit, or than an Int holds)
    cruiseAfter runIn =
      let steps = stepsLeft runIn
          m0 = round steps :: Int
      in [ v | steps <= fromIntegral (room runIn), m <- [m0, m0 + 1, m0 - 1], m <= room runIn
             , Just v <- [profileWith runIn m] ]
    -- From a moving start, k steps held at the start velocity before the run-up and m
    -- cruising after it: T = k + m steps cover T cruise steps less k times the velocities'
    -- difference, so for each T the distances are spaced by (v_end - v_0)·dt, which where it
    -- is below twice the tolerance leaves one within it; the fewest T first (a 12.5 m route
    -- from 3.17 to 3.84 m/s at 9.1 ms, 394 steps beyond the exact join's programs, left
    -- 1.54 cruise steps after its run-up and was NOT_CONVERGED without a profile)
    held = [ v | v0 > 0, v0 < vEnd, r <- runUps, v <- take 1 (holdsAround r) ]
    holdsAround runIn =
      let x = stepsLeft runIn
          ratio = (vEnd - v0) / vEnd
          t0 = max 0 (ceiling (x - pbTol q / step)) :: Int
      in [ v | x <= fromIntegral (room runIn), t <- [t0, t0 + 1, t0 + 2], t <= room runIn
             , let k = max 0 (min t (round ((fromIntegral t - x) / ratio))), k > 0
             , Just v <- [heldWith k runIn (t - k)] ]
    v0 = pbV0 q
    -- Where no whole number of cruise steps ends within the tolerance (a cruise of a few
    -- steps, too short for a dent), the run-in within narrower ranges ('scaleRanges'): it
    -- takes longer and covers more of the route, continuously with the scale, so the
    -- distance left falls through a whole number of cruise steps. Its offset from the
    -- nearest whole number falls with the scale and wraps from -1/2 to 1/2 where a step is
    -- lost; a sign change between neighbouring scales with less than half a step between
    -- them is a root, and so is the last scale whose run-in fits (within half a step of the
    -- end) before one that does not, the run-in alone then ending on the route end; each
    -- bisected until the profile is legal. The scales are spaced by a quarter of one over
    -- the run-in's steps (an eighth to a quarter of a step of run-in time each), for
    -- 'softRunInScales' of them.
    softened = [ v | (tq, r1) <- rungs, stepsLeft r1 <= fromIntegral (room r1) + softRunInReach
                   , v <- take 1 (softRoots tq r1) ]
    -- a run-in and the cruise steps left after it, where they fit
    fitting r = let x = stepsLeft r in if x > fromIntegral (room r) then Nothing else Just (x, r)
    softRoots tq r1 =
      let at phi = runUp (scaleRanges phi tq) >>= fitting
          dphi = 1 / (4 * fromIntegral (max 1 (U.length r1)))
          grid = (1, fitting r1) : [ (phi, at phi) | i <- [1 .. softRunInScales], let phi = 1 - dphi * fromIntegral i, phi > softRunInLeast ]
          tries (p1, a1) (p2, a2) = case (a1, a2) of
            (Just (x1, _), Just (x2, r2)) ->
              [ v | abs (offset x2) * step <= pbTol q, Just v <- [profileAt r2] ]
              ++ [ v | offset x1 * offset x2 <= 0, abs (offset x1 - offset x2) < 0.5, Just v <- [bisectScale at p1 p2 (signum (offset x1)) softRunInBisections] ]
            (Just (x1, _), Nothing) | x1 >= 0, x1 < 0.5 -> maybe [] pure (bisectScale at p1 p2 1 softRunInBisections)
            _ -> []
      in concat (zipWith tries grid (drop 1 grid))
    offset x = x - fromIntegral (round x :: Int)
    -- a legal profile at a scale between hi (its offset of sign s) and lo (a run-in that
    -- does not fit counts as below zero)
    bisectScale at hi lo s n
      | n <= 0 = Nothing
      | otherwise =
          let mid = (hi + lo) / 2
              towardsLo = bisectScale at mid lo s (n - 1)
              towardsHi = bisectScale at hi mid s (n - 1)
          in case at mid of
               Nothing -> if s > 0 then towardsHi else towardsLo
               Just (x, r) -> case profileAt r of
                 Just v -> Just v
                 Nothing -> if signum (offset x) == s then towardsLo else towardsHi
    -- the run-in and the nearest whole number of cruise steps, when legal
    profileAt r = profileWith r (max 0 (round (stepsLeft r)))
    -- the run-in and m cruise steps, when legal
    profileWith = heldWith 0
    -- k steps at the start velocity, the run-in and m cruise steps, when legal
    heldWith k r m
      | m < 0 = Nothing
      | otherwise = let v = U.replicate k v0 U.++ r U.++ U.replicate m vEnd in if legalButCrawl q v then Just v else Nothing

-- | How many narrower run-ins 'runInCruise' tries, the least scale of its ranges, and the
-- halvings of its bisection.
softRunInScales, softRunInBisections :: Int
softRunInScales = 40
softRunInBisections = 40

softRunInLeast :: Double
softRunInLeast = 0.5

-- | The most cruise steps a narrower run-in is looked for to take off: where more are left
-- than the profile may have, none is run.
softRunInReach :: Double
softRunInReach = 16

-- | A start at rest (or slower than the end, 'runsUp') whose route only just reaches its end
-- velocity: the run-in and the cruise ('runInCruise') when they take at most 'quickShare'
-- and 'quickSteps' more than the run-in at the full ranges, which no legal profile can beat
-- (it is the fastest way from the start to the end state), so that the meet could not gain
-- more. The meet can cost seconds where it finds no plateau: a 21 m route from rest to
-- 3.68 m/s at 2.7 ms (jerk -0.10..6.2 m/s^3) took 5.0 s for a 3,760-sample seed, the run-in
-- and cruise 0.3 ms for 3,195 samples (8.741 s, the S-curve and its cruise 8.742 s), and
-- with the budget's half spent by the meet under load no variant ran and the answer was
-- 10.29 s.
quickRunIn :: Problem -> Maybe (U.Vector Double)
quickRunIn pb
  | runsUp pb, pbSeedSearch pb, Just r1 <- runUp pb =
      runInCruise pb (floor (fromIntegral (U.length r1) * (1 + quickShare)) + quickSteps)
  | otherwise = Nothing

quickShare :: Double
quickShare = 0.01

quickSteps :: Int
quickSteps = 3

-- | A start at rest or in motion, without acceleration, below the end velocity: 'runUp'
-- reaches the end state from it.
runsUp :: Problem -> Bool
runsUp pb = endsInMotion pb && pbA0 pb == 0 && pbV0 pb < pbVEnd pb

-- | The fastest run from the start velocity (acceleration zero) up to the end state,
-- forwards in time: the end state's run-in from rest ('runInFromRest') with every velocity
-- less the start velocity, lifted by it (the jerk and acceleration of a profile do not
-- change with a constant added to its velocities; the speed limits are lowered by it, and
-- the run's distance is the shifted one's and the start velocity's cruise: the caller
-- checks the profile against the problem). None where a speed limit is at or below the
-- start velocity: the run only speeds up.
runUp :: Problem -> Maybe (U.Vector Double)
runUp q
  | v0 == 0 = runInFromRest q
  | U.any (<= v0) (pbZoneSpeeds q) = Nothing
  | otherwise = U.map (+ v0) <$> runInFromRest q { pbV0 = 0, pbVEnd = pbVEnd q - v0, pbZoneSpeeds = U.map (subtract v0) (pbZoneSpeeds q) }
  where v0 = pbV0 q

-- | The end state's run-in from rest, forwards in time (0 .. v_end): the hardest braking from
-- the end state on the mirror, reversed.
runInFromRest :: Problem -> Maybe (U.Vector Double)
runInFromRest q = either (const Nothing) (Just . U.reverse) (restFrom (mirror q))

-- | A profile through rest whose landing is on this problem (it ends at rest) and whose
-- run-in has this many samples cannot be shorter than @limit@ + 2 samples, the best seed's
-- length ('improveSeed'): the landing takes at least 'problemLeastSamples' steps (a bound
-- on every legal profile of its problem), so its samples and the run-in's are at least that
-- and one more. A landing that has no chance so is not run: on a 44 m route at 0.112 ms
-- ending at 4 m/s (bench/fuzz-requests --fine seed 5, request 13), stopping before the
-- run-in of 34,496 samples needs at least 126,124 samples where the best seed has 85,097,
-- and the six variants through rest each ran a pass of some 0.45 s to find that out.
stopCannotWin :: Problem -> Int -> Int -> Bool
stopCannotWin restPb tailSamples limit =
  problemLeastSamples restPb + fromIntegral tailSamples + 1 >= fromIntegral limit + 2

-- | The problems a braking is planned on in turn while it breaks the jerk rule alone: the
-- problem itself, then its jerk range narrowed by each of the 'jerkPlanMargins'; where the
-- full jerk cannot hold ('fullJerkHolds'), the narrowed ones first and the problem last.
jerkPlanLadder :: Problem -> [Problem]
jerkPlanLadder q
  | fullJerkHolds q = q : narrowed
  | otherwise = narrowed ++ [q]
  where narrowed = [ scaleJerk (1 - m) q | m <- jerkPlanMargins q ]

-- | The better of a seed and a variant's: the variant's when it is shorter and legal for
-- the problem. The variant's pass stops once it is no shorter, so it costs at most a pass
-- of the seed's length.
improveSeed :: Problem -> U.Vector Double -> Variant -> U.Vector Double
improveSeed pb best variant = case variant (U.length best - 2) of
  Just v | U.length v < U.length best, legalButCrawl pb v -> v
  _ -> best

-- | 'restFrom' for thesis mode, whose braking of a moving start and run-in to a moving end
-- are the profile's own: planned a little inside the jerk range, with the margins in turn
-- ('jerkPlanMargins'), while the braking breaks the problem's jerk rule (the rounding of
-- the velocities at a fine step: a 12 m route at 0.17 ms braked its start from 1.95 m/s
-- 7.1e-9 m/s³ beyond the limit, 925 samples of its thesis-mode profile broke the jerk rule,
-- and thesis mode had no legal profile to give).
-- The full jerk first where it can hold ('fullJerkHolds'), last where it cannot; when no
-- braking keeps the rule, the full jerk's answer.
restWithinJerk :: Problem -> Either SeedFailure (U.Vector Double)
restWithinJerk q = firstKeeping (map restFrom (jerkPlanLadder q))
  where
    firstKeeping [] = restFrom q
    firstKeeping (r : rest) = case r of
      Right w | keepsJerk w -> r
      _ -> firstKeeping rest
    -- the braking's own jerks, from the start acceleration on (it ends with its own last
    -- acceleration: how it goes on is the caller's)
    keepsJerk w =
      let aLast = if U.length w >= 2 then (U.last w - w U.! (U.length w - 2)) / pbDt q else pbA0 q
      in null [ x | x <- check q (Profile (pbDt q) w (pbA0 q) aLast), vRule x == JerkRule ]

-- | The hardest legal braking from the start state to a standstill within the route,
-- v_0 .. 0 (just v_0 when the start is at rest): the thesis mode's way into its band,
-- which grows from rest (see "VProf.Profile.Generate.Thesis").
restFrom :: Problem -> Either SeedFailure (U.Vector Double)
restFrom pb
  | sinksBelowZero pb = Left (startSinks pb)
  | otherwise = case brakeCheck e st0 of
      Left bad -> Left (startInfeasible pb e bad)
      Right () -> Right (U.fromList (pbV0 pb : map stV (take maxSamples (hardBraking e st0))))
  where
    e = seedEnv pb (Term (pbLength pb) 0) True
    st0 = St (pbV0 pb) (pbA0 pb) 0
