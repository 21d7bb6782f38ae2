-- | The join strategies of the two-sided meet, in the order they are tried.
--
-- Each 'Strategy' is a name and a function from the shared 'MeetContext' to the legal
-- profiles it finds, lazily and best first, so that it can be run, tested and timed on
-- its own. 'strategies' is the order of the meet: the plateau at a speed limit both
-- passes already cruise at, the plateau at the start or end velocity where the envelope's
-- top is hardly above it, then plateaus below the envelope's top, and, for the short
-- routes where those are too short for their dent, the tuned, end-level, softened and
-- valley plateaus, and last the exact join ("VProf.Profile.Generate.Exact"). The method
-- behind each is in docs/profile-generator.md.
--
-- Invariant: every profile a strategy returns has passed the checker, a crawl aside
-- ('VProf.Profile.Legality.legalButCrawl': the generator cuts a profile at its arrival); a
-- strategy never claims infeasibility.
module VProf.Profile.Generate.Seed.Strategy
  ( Strategy (..)
  , strategies
    -- * The strategies
  , limitCruise
  , peakPlateau
  , tunedPlateau
  , topEndLevel
  , endLevelPlateau
  , softenedPlateau
  , valleyPlateau
  , exactLp
    -- * The peak plateau's search
  , probeLevel
  , closestJoin
    -- * Constants
  , peakLevelDrops
  , peakBandWork
  , peakCloseSteps
  , tunedSpan
  , tunedSteps
  , softenedLevelDrops
  , softenSteps
  , softenScaleStep
  , valleyFractions
  ) where

import Data.List (group, sortBy)
import Data.Ord (comparing)
import qualified Data.Vector.Unboxed as U

import VProf.Profile.Generate.Exact (exactJoin)
import VProf.Profile.Generate.Seed.Join
import VProf.Profile.Problem (Problem (..))
import VProf.Profile.Problem.Transform (scaleRanges)
import VProf.Profile.SpeedLimit (limitAt, minLimitOn)

-- | A named way to join the forward and the backward pass.
data Strategy = Strategy
  { strategyName  :: String
  , strategyJoins :: MeetContext -> [U.Vector Double]  -- ^ legal profiles, best first
  }

-- | The meet's strategies, in the order it tries them.
strategies :: [Strategy]
strategies = [limitCruise, topEndLevel, peakPlateau, tunedPlateau, endLevelPlateau, softenedPlateau, valleyPlateau, exactLp]

-- | The plateau levels below the envelope's top, as fractions of it taken off: the
-- highest first (a lower level gives a longer plateau and a gentler dent).
peakLevelDrops :: [Double]
peakLevelDrops = [0.001, 0.003, 0.01, 0.02, 0.04, 0.07, 0.12, 0.2, 0.3, 0.45, 0.6, 0.75, 0.9]

-- | A stretch where both passes cruise at one speed limit counts with at least this many
-- samples; one of 'longRunSamples' or more is tried before the shorter ones; at most
-- 'runsTried' stretches are tried.
shortRunSamples, longRunSamples, runsTried :: Int
shortRunSamples = 4
longRunSamples = 16
runsTried = 4

-- | The envelope is at the speed limit where it is within this share of it (at least of
-- 1 m/s).
atLimitTolerance :: Double
atLimitTolerance = 1e-9

-- | The tuned plateau's grid: 'tunedSteps' + 1 levels from the top down to (1 −
-- 'tunedSpan') of it, fine enough to see the overshoot change sign between neighbours.
tunedSpan :: Double
tunedSpan = 0.7

tunedSteps :: Int
tunedSteps = 32

-- | The softened plateau's levels below the top (as fractions taken off), besides the
-- start and end velocities.
softenedLevelDrops :: [Double]
softenedLevelDrops = [0.02, 0.1, 0.3]

-- | The softened plateau's range scales: 'softenSteps' of them from 1 down by
-- 'softenScaleStep' each (1, 0.96, …, 0.4).
softenSteps :: Int
softenSteps = 16

softenScaleStep :: Double
softenScaleStep = 0.04

-- | The valley levels, as fractions of the top.
valleyFractions :: [Double]
valleyFractions = [0.5, 0.25, 0.1, 0.03]

-- | How often a valley level is lowered to the lowest limit on its stretch, and how far
-- below that limit it then goes (as a share of it).
valleyLowerings :: Int
valleyLowerings = 3

valleyBelowLimit :: Double
valleyBelowLimit = 1e-6

-- | Stretches where both passes cruise at the same speed limit: the lower envelope is
-- already flat there, so the plateau costs nothing but the dent. Long stretches first,
-- the last of them first (the backward pass then has the least to do again, and the
-- forward one resumes from nearly all of its uncapped run).
limitCruise :: Strategy
limitCruise = Strategy "limit cruise" $ \c ->
  let pb = mcPb c
      h = mcEnvelope c
      fS = mcFS c
      atCap k = abs (h U.! k - limitAt pb (fS U.! k)) <= atLimitTolerance * max 1 (h U.! k)
      runs = sortBy (comparing (\(a, b) -> (b - a < longRunSamples, negate b)))
               [ (head ks, last ks) | ks <- groupRuns [ k | k <- [0 .. U.length h - 1], atCap k ], length ks >= shortRunSamples ]
      flat = [ (v, fS U.! a, fS U.! b) | (a, b) <- take runsTried runs, let v = h U.! a ]
  in plateausAt c flat

-- | Plateaus just below the envelope's top, over the stretch where the envelope is above
-- them, from the highest level down. The rubber band raises a plateau one velocity step a
-- pass, and at a fine time step the levels are far apart in steps (0.1 % of 3.5 m/s is a
-- million steps of 3.7e-9 m/s at 0.2 ms; such a request spent its 20 s budget 2,000
-- passes into them). So where raising the first level that joins to the one above it that
-- does not (the top itself for the first) would take the band more than 'peakBandWork'
-- (its steps times the samples), it is raised to within 'peakCloseSteps' steps of a level
-- that does not join ('closestJoin').
peakPlateau :: Strategy
peakPlateau = Strategy "peak plateau" $ \c ->
  let top = mcTop c
      dv = pbDv (mcPb c)
      work vNo vOk = (vNo - vOk) / dv * fromIntegral (U.length (mcEnvelope c))
      down _ [] = []
      down above (v : vs) = case probeLevel c v of
        (m, p : _) | work above v <= peakBandWork -> p : rest
                   | otherwise -> let (_, _, q) = closestJoin c (above, Nothing) (v, m) p in q : rest
        _ -> down v vs
        where rest = concatMap (snd . probeLevel c) vs
  in down top [ v | d <- peakLevelDrops, let v = top * (1 - d), v > 0 ]

-- | A level's plateau join over the stretch around the peak, if any, and the join margin of
-- its capped passes ('joinMargin'; none where the passes cannot be capped there).
probeLevel :: MeetContext -> Double -> (Maybe Double, [U.Vector Double])
probeLevel c v = case around c v of
  Just (alpha, beta) | Just cp <- capped c v alpha beta -> (Just (joinMargin c v cp), maybe [] pure (plateau c v cp))
  _ -> (Nothing, [])

-- | The join at the highest level between vNo, which does not join, and vOk, which joins
-- (as p), to within 'peakCloseSteps' velocity steps of a level that does not, with that
-- level and the one that does not join (vNo itself, where none between does): a bisection
-- on whether a level joins, whose probes are guided by the join margin ('joinMargin').
-- Every answer is still the plain predicate's: a level counts as joining only where its
-- join is found. Each probe runs two capped passes (some 0.15 s on a 44 m route at
-- 0.112 ms), and a bisection takes 10-20 of them.
--
-- * Where the margins at both ends are known, the one at or above zero and the other below,
--   the next probe is where the straight line between them crosses zero, a quarter of the
--   wanted width past it towards the further end (so that the probe after it can close the
--   bracket from the other side); never nearer than a 64th of the bracket to its ends.
-- * Otherwise, and after two guided probes in a row that did not halve the bracket (the
--   margin jumps where a capped pass takes a step more, and a join's boundary can lie at
--   such a jump, or where a dent stops being legal), the bracket is halved.
closestJoin :: MeetContext -> (Double, Maybe Double) -> (Double, Maybe Double) -> U.Vector Double
            -> (Double, Double, U.Vector Double)
closestJoin c no0 ok0 p0 = go (0 :: Int) 0 Nothing no0 ok0 p0
  where
    near = peakCloseSteps * pbDv (mcPb c)
    -- weak: the guided probes in a row that did not halve the bracket; guided: the
    -- bracket's width before the last probe, when that was a guided one
    go n weak0 guided (vNo, mNo) (vOk, mOk) p
      | w <= near || n >= joinBisections = (vOk, vNo, p)
      | otherwise = case probeLevel c m of
          (mm, q : _) -> go (n + 1) weak wasGuided (vNo, mNo) (m, mm) q
          (mm, []) -> go (n + 1) weak wasGuided (m, mm) (vOk, mOk) p
      where
        w = vNo - vOk
        weak = case guided of
          Just w0 | w > w0 / 2 -> weak0 + 1
          _ -> 0 :: Int
        estimate = case (mOk, mNo) of
          (Just fo, Just fn) | fo >= 0, fn < 0, weak < 2 -> Just (vOk + w * fo / (fo - fn))
          _ -> Nothing
        (m, wasGuided) = case estimate of
          Just r -> let aim = if r - vOk <= vNo - r then r + near / 4 else r - near / 4
                    in (max (vOk + w / 64) (min (vNo - w / 64) aim), Just w)
          Nothing -> ((vNo + vOk) / 2, Nothing)

-- | The peak plateau's level is raised where the rubber band would need more than
-- 'peakBandWork' velocity steps times samples (some ten seconds of passes at 40–80 ns a
-- sample) to raise it to a level that does not join, until it is within 'peakCloseSteps'
-- steps of one. (Not where the band can do it in time: from a lower plateau it has room to
-- reshape the ramps around it and may end shorter; a 3 s request at 1 ms, which the band
-- finished in 4,074 passes of 3,000 samples, ended 4 ms longer from a plateau raised to
-- within 64 steps.)
peakBandWork, peakCloseSteps :: Double
peakBandWork = 2e8
peakCloseSteps = 64

-- | Between two levels the distance the cruise must cover changes continuously with the
-- level, while each cruise step covers v·dt: for a fixed number of cruise steps the
-- overshoot changes sign between levels where that number fits the one and not the
-- other, and a bisection on the level finds where no dent is needed at all. Each pair of
-- neighbouring levels is tried over the stretch around the peak and over the widest one.
tunedPlateau :: Strategy
tunedPlateau = Strategy "tuned plateau" $ \c ->
  let top = mcTop c
      levels = map head (group (sortBy (flip compare)
                 ([ top * (1 - tunedSpan * fromIntegral i / fromIntegral tunedSteps) | i <- [0 .. tunedSteps] ] ++ endLevels c)))
  in [ p | (v1, v2) <- zip levels (drop 1 levels), v2 > 0, stretch <- [around c, wide c]
         , Just (alpha, beta) <- [stretch v2], Just p <- [tune c v1 v2 alpha beta] ]

-- | The plateau at the start or the end velocity: a profile that only speeds up (or only
-- slows down) on a short route has its plateau at one of them.
endLevelPlateau :: Strategy
endLevelPlateau = Strategy "end-level plateau" $ \c -> endLevelJoins c (const True)

-- | The plateau joins at the start or end velocity that pass a test, over the widest stretch.
endLevelJoins :: MeetContext -> (Double -> Bool) -> [U.Vector Double]
endLevelJoins c ok = plateausAt c [ (v, alpha, beta) | v <- endLevels c, ok v, Just (alpha, beta) <- [wide c v] ]

-- | The end-level plateau where the envelope's top is at most 'topEndShare' above the start
-- or end velocity (the route only just reaches it): every level the peak plateau tries
-- is then below that velocity, and no plateau can be much above it, so it goes before
-- them (each of their levels costs two capped passes: on a 3.96 m route from rest to
-- 1.67 m/s at 0.13 ms, whose top is 7e-5 above the end velocity, the meet took 1.03 s with
-- the end-level plateau after the peak and tuned plateaus, 0.23 s with it first).
topEndLevel :: Strategy
topEndLevel = Strategy "end-level plateau at the top" $ \c -> endLevelJoins c (\v -> mcTop c <= v * (1 + topEndShare))

-- | How far above the start or end velocity the envelope's top may be for 'topEndLevel':
-- the peak plateau's highest level ('peakLevelDrops') is that far below the top.
topEndShare :: Double
topEndShare = head peakLevelDrops

-- | The plateau at v with both passes run within a fraction of the acceleration and jerk
-- ranges (still legal for the problem): their ramps then take longer, continuously with
-- the fraction, so that the overshoot left over moves through zero. The passes start
-- afresh (the uncapped ones were made with the full ranges).
softenedPlateau :: Strategy
softenedPlateau = Strategy "softened plateau" $ \c ->
  [ p | v <- endLevels c ++ [ mcTop c * (1 - d) | d <- softenedLevelDrops ], Just (alpha, beta) <- [wide c v]
      , Just p <- [soften c v alpha beta] ]

soften :: MeetContext -> Double -> Double -> Double -> Maybe (U.Vector Double)
soften c v alpha beta =
  let at phi = cappedOn c (scaleRanges phi (mcPb c)) (scaleRanges phi (mcMirror c)) [] [] v alpha beta
      dt = ctxDt c
      r = leftOver dt v
      grid = [ (phi, cp) | i <- [0 .. softenSteps - 1], let phi = 1 - softenScaleStep * fromIntegral i, Just cp <- [at phi] ]
      -- a sign change between neighbours with a small step is a root; a step of nearly a
      -- cruise step's distance is a wrap (a pass took a step more)
      roots = [ p | ((p1, c1), (p2, c2)) <- zip grid (drop 1 grid), r c1 * r c2 <= 0
                  , abs (r c1 - r c2) < v * dt / wrapDivisor, Just p <- [bisectJoin c at (const v) p1 p2 (signum (r c1)) joinBisections] ]
  in case roots of
       (p : _) -> Just p
       [] -> Nothing

-- | A level low enough that both ends can brake to it with room to spare, over the whole
-- stretch between (below every limit there), so the plateau is long and its dent gentle;
-- slow, but the rubber band raises it afterwards.
valleyPlateau :: Strategy
valleyPlateau = Strategy "valley plateau" $ \c ->
  plateausAt c [ (v, alpha, beta) | f <- valleyFractions, Just (v, alpha, beta) <- [lowPlateau c (mcTop c * f) valleyLowerings] ]

lowPlateau :: MeetContext -> Double -> Int -> Maybe (Double, Double, Double)
lowPlateau c v n
  | v <= 0 || n <= 0 = Nothing
  | otherwise = do
      (alpha, beta) <- wide c v
      let lim = minLimitOn (mcPb c) (max 0 alpha) (min (ctxLength c) beta)
      if lim >= v then Just (v, alpha, beta) else lowPlateau c (lim * (1 - valleyBelowLimit)) (n - 1)

-- | The join solved exactly, as a linear program over the number of steps.
exactLp :: Strategy
exactLp = Strategy "exact join" $ \c -> maybe [] pure (exactJoin (mcPb c))

-- | The plateau joins at the given levels and stretches, in order.
plateausAt :: MeetContext -> [(Double, Double, Double)] -> [U.Vector Double]
plateausAt c lvs = [ p | (v, alpha, beta) <- lvs, Just cp <- [capped c v alpha beta], Just p <- [plateau c v cp] ]

-- | The start and end velocities, where they lie strictly between zero and the top.
endLevels :: MeetContext -> [Double]
endLevels c = let pb = mcPb c in [ x | x <- [pbVEnd pb, pbV0 pb], x > 0, x < mcTop c ]

-- | Runs of consecutive integers.
groupRuns :: [Int] -> [[Int]]
groupRuns [] = []
groupRuns (k : ks) = let (run, rest) = go k ks in (k : run) : groupRuns rest
  where go p (x : xs) | x == p + 1 = let (r, t) = go x xs in (x : r, t)
        go _ xs = ([], xs)
