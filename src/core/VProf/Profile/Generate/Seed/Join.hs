-- | The plateau join of the two-sided meet, and the context every join strategy shares.
--
-- The forward pass from the start state and the same pass on the 'mirror' (from the end
-- state, backwards in time) are run once ('meetContext'); the profile follows the lower
-- of the two ('mcEnvelope'). A /plateau join/ at level V runs both passes again with
-- every limit capped at V over a stretch [alpha, beta] ('capped'), each until its first
-- cruise sample at V, and fills the gap between them with a cruise at V whose length
-- covers the distance; a sin² dent (or bump) in the cruise takes out the fraction of a
-- step left over where it is more than half the end tolerance, or where the cruise
-- without it is not legal ('plateau', 'joinAt'); the join kept is then shaped as the
-- rubber band would leave it ('bandShaped'). The strategies of
-- "VProf.Profile.Generate.Seed.Strategy" choose the levels and stretches.
--
-- Invariant: a join only ever returns velocities the checker finds legal for the
-- problem but for a crawl ('legalButCrawl': the generator cuts a profile at its arrival,
-- and cut here the join's end would lie short again, for the band to lift once more);
-- every other outcome is 'Nothing'.
module VProf.Profile.Generate.Seed.Join
  ( -- * The shared context
    MeetContext (..)
  , meetContext
  , ctxLength
  , ctxTol
  , ctxDt
    -- * Passes capped at a level
  , Capped
  , capped
  , cappedOn
    -- * Joins
  , plateau
  , joinMargin
  , tune
  , leftOver
  , bisectJoin
    -- * Stretches
  , around
  , wide
    -- * Constants
  , joinBisections
  , wrapDivisor
  ) where

import Data.List (sortBy)
import Data.Ord (comparing)
import qualified Data.Vector.Unboxed as U

import VProf.Profile.Generate.Seed.Brake
import VProf.Profile.Generate.Seed.Explain
import VProf.Profile.Generate.Seed.Greedy (passCapMessage, passFrom, passStepCap)
import VProf.Profile.Legality (legalButCrawl)
import VProf.Profile.Problem (Problem (..))
import VProf.Profile.Problem.Transform (capOn, mirror)

-- | What every join strategy works from: the problem and its mirror, the start state and
-- the end state (on the mirror), their pass environments, the two uncapped passes, and
-- their lower envelope at the forward pass's samples with its highest point.
data MeetContext = MeetContext
  { mcPb       :: !Problem
  , mcMirror   :: !Problem
  , mcStart    :: !St
  , mcEnd      :: !St                -- ^ the end state, as the start of the mirror
  , mcFEnv     :: !SeedEnv
  , mcBEnv     :: !SeedEnv
  , mcFAll     :: Pass               -- ^ the forward pass, from the start state on
  , mcBAll     :: Pass               -- ^ the backward pass (on the mirror), from the end state on
  , mcFS       :: U.Vector Double    -- ^ the forward pass's positions
  , mcEnvelope :: U.Vector Double    -- ^ the lower envelope at those positions, up to the route end
  , mcPeak     :: Int                -- ^ the index of the envelope's highest point
  , mcTop      :: Double             -- ^ the envelope's highest point
  , mcScheduled :: Bool              -- ^ the passes probe long brakings only now and then
  , mcJudge    :: !Problem           -- ^ what a joined profile must be legal for: the request's
                                     --   problem, also where the passes plan inside its jerk range
  }

-- | A pass's states, unboxed (velocity, acceleration, position): a boxed list of them
-- would take some 100 bytes a state, and the uncapped passes are kept for all the joins.
type Pass = U.Vector (Double, Double, Double)

toPass :: [St] -> Pass
toPass sts = U.fromList [ (v, a, s) | St v a s <- sts ]

-- | The states of a pass, from the given one on, as a lazy list (made again for each use).
statesFrom :: Int -> Pass -> [St]
statesFrom k p = [ St v a s | (v, a, s) <- U.toList (U.drop k p) ]

ctxLength, ctxTol, ctxDt :: MeetContext -> Double
ctxLength = pbLength . mcPb
ctxTol = pbTol . mcPb
ctxDt = pbDt . mcPb

-- | A capped pass runs this far past the route end, so that the cap holds to its end.
capPastEnd :: Double
capPastEnd = 1

-- | A state cruises at v when its velocity is within this share of v (at least of
-- 1 m/s) and its acceleration within this of zero.
cruiseTolerance :: Double
cruiseTolerance = 1e-9

-- | A capped pass shares the uncapped pass's states while the cap lies further ahead
-- than this many braking reaches plus 'resumeMarginM'.
resumeReaches, resumeMarginM :: Double
resumeReaches = 2
resumeMarginM = 1

-- | A cruise goes without its dent when its overshoot is within the tolerance over this
-- divisor (half the end tolerance): the rubber band raises only while the route end stays
-- within half the tolerance, so a cruise without its dent is what the band would make of
-- the dented one, one velocity step a pass.
undentedDivisor :: Double
undentedDivisor = 2

-- | A bisected join stops at an overshoot within the tolerance over this divisor.
joinPrecisionDivisor :: Double
joinPrecisionDivisor = 100

-- | The halvings a bisected join (on a level or a range scale) takes at most.
joinBisections :: Int
joinBisections = 48

-- | Two overshoots whose difference is below a cruise step's distance over this divisor
-- changed sign at a root; a larger jump is a wrap (a pass took a step more).
wrapDivisor :: Double
wrapDivisor = 2

-- | A stretch for a level starts this many cruise steps (plus the tolerance) past where
-- the end can brake to it.
stretchMarginSteps :: Double
stretchMarginSteps = 2

-- | The two passes of the meet and their lower envelope, or why an end state cannot be
-- passed at all; with @scheduled@ every pass of the meet probes long brakings only now and
-- then ('VProf.Profile.Generate.Seed.Greedy.scheduledSteps'). The passes run on @pb@; a
-- joined profile is judged on @judge@, the request's own problem, which is @pb@ itself or
-- @pb@ with the jerk range widened back (a profile the rounding puts a hair beyond the
-- narrowed range is still legal for the request's).
meetContext :: Bool -> Problem -> Problem -> Either SeedFailure MeetContext
meetContext scheduled judge pb = do
  let rv = mirror pb
      rt0 = St (pbVEnd pb) (pbA0 rv) 0
      st0 = St (pbV0 pb) (pbA0 pb) 0
      len = pbLength pb
      fTerm = forwardTerm pb
      bTerm = backwardTerm pb
  if sinksBelowZero rv then Left (endAccFailure pb) else Right ()
  fEnv <- either (Left . startInfeasible pb (seedEnv pb fTerm True)) Right (policyFor pb fTerm st0)
  bEnv <- either (Left . endInfeasible pb (seedEnv rv bTerm True)) Right (policyFor rv bTerm rt0)
  let fAll = toPass (st0 : passFrom scheduled fEnv passStepCap (\st -> stS st >= len) st0)
      bAll = toPass (rt0 : passFrom scheduled bEnv passStepCap (\st -> stS st >= len) rt0)
      (fV, _, fS) = U.unzip3 fAll
      (bV, _, bS) = U.unzip3 bAll
      unfinished ss = U.length ss > passStepCap && U.last ss < len
  if unfinished fS then Left (OverCap (passCapMessage pb "forward" (U.last fS))) else Right ()
  if unfinished bS then Left (OverCap (passCapMessage pb "backward" (U.last bS))) else Right ()
  let bX = U.reverse (U.map (len -) bS)
      bW = U.reverse bV
      -- the lower envelope at the forward pass's samples up to the route end
      h = U.generate (U.length (U.takeWhile (<= len) fS)) (\k -> min (fV U.! k) (lerpAt bX bW (fS U.! k)))
      kStar = U.maxIndex h
  pure MeetContext
    { mcPb = pb, mcMirror = rv, mcStart = st0, mcEnd = rt0, mcFEnv = fEnv, mcBEnv = bEnv
    , mcFAll = fAll, mcBAll = bAll, mcFS = fS, mcEnvelope = h, mcPeak = kStar, mcTop = h U.! kStar
    , mcScheduled = scheduled, mcJudge = judge }

-- | The start pass must be able to come down to the end velocity by the route end; the
-- end pass (backwards) to the start velocity by the route start.
forwardTerm, backwardTerm :: Problem -> Term
forwardTerm pb = Term (pbLength pb + pbTol pb) (pbVEnd pb)
backwardTerm pb = Term (pbLength pb + pbTol pb) (pbV0 pb)

-- | Linear interpolation of ys over ascending xs, clamped at both ends.
lerpAt :: U.Vector Double -> U.Vector Double -> Double -> Double
lerpAt xs ys x
  | n == 0 = 0
  | x <= U.head xs = U.head ys
  | x >= U.last xs = U.last ys
  | otherwise =
      let i = go 0 (n - 1)
          x0 = xs U.! i; x1 = xs U.! (i + 1)
          w = if x1 > x0 then (x - x0) / (x1 - x0) else 0
      in ys U.! i + w * (ys U.! (i + 1) - ys U.! i)
  where
    n = U.length xs
    -- invariant: xs[lo] <= x < xs[hi]
    go lo hi
      | hi - lo <= 1 = lo
      | otherwise = let mid = (lo + hi) `div` 2 in if xs U.! mid <= x then go mid hi else go lo mid

-- | Two capped passes of the meet (the states after the start and after the end), their
-- cruise velocities and the distance left between them.
data Capped = Capped [St] [St] !Double !Double !Double

cruising :: Double -> St -> Bool
cruising v st = abs (stV st - v) <= cruiseTolerance * max 1 v && abs (stA st) <= cruiseTolerance

-- | The two passes capped at v over [alpha, beta], each up to its first cruise sample at
-- v, and the distance the cruise between them must cover; the uncapped passes' states
-- are reused as far as the cap cannot have changed them.
capped :: MeetContext -> Double -> Double -> Double -> Maybe Capped
capped c = cappedOn c (mcPb c) (mcMirror c) (statesFrom 1 (mcFAll c)) (statesFrom 1 (mcBAll c))

-- | 'capped' on a problem and mirror of one's own (the same route and states), reusing
-- the given uncapped states.
cappedOn :: MeetContext -> Problem -> Problem -> [St] -> [St] -> Double -> Double -> Double -> Maybe Capped
cappedOn c base rv fFree bFree v alpha beta = do
  -- the forward pass capped at v from alpha on, until it cruises at v
  let len = ctxLength c
      st0 = mcStart c
      rt0 = mcEnd c
      pF = capOn alpha (len + capPastEnd) v base
      pB = capOn (len - beta) (len + capPastEnd) v rv
  fE <- either (const Nothing) Just (policyFor pF (forwardTerm (mcPb c)) st0)
  bE <- either (const Nothing) Just (policyFor pB (backwardTerm (mcPb c)) rt0)
  let fRun = resume (mcScheduled c) (mcFEnv c) fE fFree alpha st0 (\st -> stS st > beta || stS st >= alpha && cruising v st)
      bRun = resume (mcScheduled c) (mcBEnv c) bE bFree (len - beta) rt0 (\st -> stS st > len - alpha || stS st >= len - beta && cruising v st)
  fi <- lastMaybe fRun
  bm <- lastMaybe bRun
  guardM (cruising v fi && cruising v bm)
  pure (Capped fRun bRun (stV fi) (stV bm) (len - stS bm - stS fi))

-- | A capped pass follows the uncapped one for as long as the cap lies beyond the reach
-- of every brake test it makes (twice the braking reach, plus a metre): it resumes from
-- there rather than from the start.
resume :: Bool -> SeedEnv -> SeedEnv -> [St] -> Double -> St -> (St -> Bool) -> [St]
resume scheduled e0 e1 free cut start stop =
  let shared = if eHard e0 /= eHard e1 then []
               else takeWhile (\st -> let (d, _) = brakeBound e0 st in stS st + resumeReaches * d + resumeMarginM < cut) free
      from = if null shared then start else last shared
  in shared ++ passFrom scheduled e1 passStepCap stop from

-- | k steps at the plateau level, from the forward pass's cruise sample to the backward
-- pass's, cover this much more than the gap.
overBy :: Double -> Double -> Capped -> Int -> Double
overBy dt v (Capped _ _ vi vm gap) k = dt * (vi + vm) / 2 + dt * v * fromIntegral (k - 1) - gap

kUpOf :: Double -> Double -> Capped -> Int
kUpOf dt v (Capped _ _ vi vm gap) = 1 + max 0 (ceiling ((gap / dt - (vi + vm) / 2) / v - roundingSlack)) :: Int

-- | How much longer the gap between two capped passes is than the shortest a plateau
-- join can close: one cruise step, less half the end tolerance ('plateau' joins with a
-- single step when its overshoot, 'overBy' one step, is within that). Below zero the
-- passes overlap too far to join; above it a join fails only where its dent or bump is
-- not legal. It falls as the level rises towards the envelope's top, smoothly but for
-- jumps of about a step's distance where a capped pass takes a step more.
joinMargin :: MeetContext -> Double -> Capped -> Double
joinMargin c v cp = ctxTol c / undentedDivisor - overBy (ctxDt c) v cp 1

-- | The plateau join at v: one step more than the gap (a dent takes the rest out) or one
-- fewer (a bump adds it, where the limits leave room above the plateau), the smaller
-- overshoot first.
plateau :: MeetContext -> Double -> Capped -> Maybe (U.Vector Double)
plateau c v cp =
  let dt = ctxDt c
      kUp = kUpOf dt v cp
      ks = sortBy (comparing (abs . overBy dt v cp)) (kUp : [ kUp - 1 | kUp > 1 ])
  in joinAt c v cp ks

-- | The profile of the capped passes joined by a cruise of k steps at v, for the first k
-- that gives a legal one: without a dent first where the overshoot is within half the end
-- tolerance, then with the dent (the route end met exactly). Legal but for a crawl counts:
-- a cruise at the end velocity into the route end (the end-level plateau) arrives within
-- the tolerance before its last sample whenever a step is shorter than the tolerance, and
-- refused so, a 3.96 m route from rest to 1.67 m/s with jerk -0.29..0.45 m/s³ found no
-- join at 4, 2 or 0.13 ms and was seeded through rest (5.99 s at 2 ms, where the plateau gives
-- 4.40 s). The dent's depth is some
-- 8·V/(|j|·dt·T) velocity steps of the rubber band for a cruise of T seconds, which the
-- band fills one step a pass: thousands of passes at a 0.5 ms step (moving-start-end
-- at 0.5 ms spent a 30 s budget on them; undented, it converges in one pass).
joinAt :: MeetContext -> Double -> Capped -> [Int] -> Maybe (U.Vector Double)
joinAt c v cp@(Capped fRun bRun _ _ _) ks =
  let pb = mcPb c
      judge = mcJudge c
      dt = ctxDt c
      tol = ctxTol c
      over = overBy dt v cp
      -- the distance a dent of depth 1 takes out of a cruise of k steps
      perDepth k = dt * fromIntegral k / 2
      depth k = if k > 1 then over k / perDepth k else 0
      -- the cruise with a dent of depth d (a bump where d < 0); the passes and the dent's
      -- shape made once (unboxed: a join at a fine step has some 10⁵ samples, and the
      -- bisection in 'bandShaped' makes a profile of it up to 60 times)
      fV = U.fromList (pbV0 pb : map stV fRun)
      bV = U.fromList (reverse (pbVEnd pb : map stV bRun))
      profileAt k =
        let bump = U.generate (max 0 (k - 1)) (\i -> let x = sin (pi * fromIntegral (i + 1) / fromIntegral k) in x * x)
        in \d -> U.concat [fV, U.map (\b -> v - d * b) bump, bV]
      legal = legalButCrawl judge
      -- last, without a dent, an end within the tolerance but more than half of it from the
      -- route end (the checker's rule): where the cruise is too short for its dent or bump
      -- (a 15.9 m route from rest that only just reaches its end velocity of 3.99 m/s at
      -- 6.3 ms: 8.1 mm past the end with a cruise of eight 25 mm steps, 17 mm short with one
      -- step fewer, and no join at all: through rest it took 13.05 s, where the plateau at the
      -- end velocity takes 9.33 s)
      tries = [ (k, 0) | k <- ks, k > 1, abs (over k) <= tol / undentedDivisor ]
              ++ [ (k, depth k) | k <- ks, k > 1 || abs (over k) <= tol / undentedDivisor ]
              ++ [ (k, 0) | k <- ks, k > 1, abs (over k) > tol / undentedDivisor, abs (over k) <= tol * (1 - 1e-6) ]
  in case [ (k, d, vs) | (k, d) <- tries, let vs = profileAt k d, legal vs ] of
       -- lazily: only the profile a strategy keeps is shaped
       (k, d, vs) : _ | k > 1 -> Just (bandShaped legal (pbDv judge) ((over k - tol / undentedDivisor * (1 - 1e-6)) / perDepth k) d (profileAt k) vs)
                      | otherwise -> Just vs
       [] -> Nothing

-- | The cruise shaped as the rubber band would leave it: the band raises a sample while
-- the route end stays within half the tolerance past it and no later sample is pushed
-- into a lower zone, one velocity step a pass, so a cruise whose end lies short of that
-- costs it one pass a step: a dent of 2.5e-4 m/s in steps of 7.45e-9 m/s (a 30.7 m route
-- at 0.17 ms: NOT_CONVERGED after 1,763 passes of a 20 s budget), or an undented cruise
-- of 7.6 s at 1.3 m/s whose end fell short by up to half the tolerance, which the band
-- lifted as a whole (5.7e-8 m a pass: NOT_CONVERGED after 24,000 passes of 120 s). The
-- depth @target@ puts the end just inside half the tolerance past the route end (a bump
-- where it is negative); when that profile is illegal, a bisection between it and the
-- legal depth @d0@ (the join's own) finds the legal one nearest to it, to within two
-- velocity steps.
bandShaped :: (U.Vector Double -> Bool) -> Double -> Double -> Double -> (Double -> U.Vector Double) -> U.Vector Double -> U.Vector Double
bandShaped legal dv target d0 at own
  | abs (target - d0) <= 2 * dv = own
  | legal first = first
  | otherwise = go d0 target own (0 :: Int)
  where
    first = at target
    -- ok: legal (its profile is best); bad: not legal
    go ok bad best n
      | abs (bad - ok) <= 2 * dv || n >= 60 = best
      | otherwise =
          let mid = (ok + bad) / 2
              vs = at mid
          in if legal vs then go mid bad vs (n + 1) else go ok mid best (n + 1)

-- | The tuned plateau between levels v1 > v2 over the same stretch: for each cruise
-- length whose overshoot changes sign between them, bisect the level down to an
-- overshoot of a hundredth of the tolerance.
tune :: MeetContext -> Double -> Double -> Double -> Double -> Maybe (U.Vector Double)
tune c v1 v2 alpha beta = do
  c1 <- capped c v1 alpha beta
  c2 <- capped c v2 alpha beta
  let r1 = leftOver (ctxDt c) v1 c1; r2 = leftOver (ctxDt c) v2 c2
  guardM (r1 * r2 <= 0 && abs (r1 - r2) < v2 * ctxDt c / wrapDivisor)
  bisectJoin c (\x -> capped c x alpha beta) id v1 v2 (signum r1) joinBisections

-- | The cruise length nearest to the gap at level v, and the overshoot it leaves: that
-- changes sign where one of them fits exactly, or where it wraps round (by a step's
-- distance) when one of the passes takes a step more; a bisection tells them apart.
nearestK :: Double -> Double -> Capped -> Int
nearestK dt v cp = let k0 = kUpOf dt v cp in minimumOn (abs . overBy dt v cp) [ k | k <- [k0 - 1, k0], k >= 1 ]

leftOver :: Double -> Double -> Capped -> Double
leftOver dt v cp = overBy dt v cp (nearestK dt v cp)

-- | Bisect a parameter x from a, where the overshoot of the passes made at x (with the
-- plateau at level x) has sign sa, towards b, where it has the other, down to an
-- overshoot of a hundredth of the tolerance; then join there.
bisectJoin :: MeetContext -> (Double -> Maybe Capped) -> (Double -> Double) -> Double -> Double -> Double -> Int -> Maybe (U.Vector Double)
bisectJoin c at level a b sa n
  | n <= 0 = Nothing
  | otherwise = do
      let mid = (a + b) / 2
          v = level mid
          dt = ctxDt c
      cm <- at mid
      let o = leftOver dt v cm
      if abs o <= ctxTol c / joinPrecisionDivisor then joinAt c v cm [nearestK dt v cm]
        else if signum o == sa then bisectJoin c at level mid b sa (n - 1) else bisectJoin c at level a mid sa (n - 1)

-- | The stretch around the envelope's peak where the envelope is above v (from where the
-- start, or the end, can brake to v when the envelope does not come down to it).
around :: MeetContext -> Double -> Maybe (Double, Double)
around c v =
  let h = mcEnvelope c
      fS = mcFS c
      kStar = mcPeak c
      n = U.length h
      len = ctxLength c
      kl = last (-1 : [ k | k <- [0 .. kStar - 1], h U.! k <= v ])
      kr = head ([ k | k <- [kStar + 1 .. n - 1], h U.! k <= v ] ++ [n])
      margin = stretchMarginSteps * v * ctxDt c + ctxTol c
      alpha = if kl < 0 then brakeDistanceTo (mcPb c) (mcStart c) v + margin else fS U.! kl
      beta = if kr >= n then len - brakeDistanceTo (mcMirror c) (mcEnd c) v - margin else fS U.! kr
  in if alpha < beta then Just (alpha, beta) else Nothing

-- | The widest stretch for level v: from where the start no longer needs to brake to be
-- at v to where the end does (a state that needs no braking to be at v caps from where
-- it is).
wide :: MeetContext -> Double -> Maybe (Double, Double)
wide c v =
  let margin = stretchMarginSteps * v * ctxDt c + ctxTol c
      reach q st = let d = brakeDistanceTo q st v in if d > 0 then d + margin else 0
      alpha = reach (mcPb c) (mcStart c)
      beta = ctxLength c - reach (mcMirror c) (mcEnd c)
  in if alpha < beta then Just (alpha, beta) else Nothing

lastMaybe :: [a] -> Maybe a
lastMaybe xs = if null xs then Nothing else Just (last xs)

minimumOn :: Ord b => (a -> b) -> [a] -> a
minimumOn f = head . sortBy (comparing f)

guardM :: Bool -> Maybe ()
guardM b = if b then Just () else Nothing
