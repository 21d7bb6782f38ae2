-- | The exact join of a short route with a moving end, where the plateau strategies of
-- the meet ("VProf.Profile.Generate.Seed.Strategy") find no plateau to join on, and the
-- proof that no profile exists.
--
-- With its number of steps N fixed, a profile's rules are linear in its velocities
-- v_0..v_N, so for each N that velocity envelopes leave open, one small linear program
-- ("VProf.Numeric.LinearProgram") either builds a profile ('exactJoin': velocities capped
-- by the lowest limit they might meet, then confirmed by the checker) or, with every rule
-- widened by the checker's slack, proves with a Farkas certificate that none exists
-- ('noProfileFits'); where the highest limit everywhere leaves a program feasible, further
-- programs keep samples out of zones they cannot be in, and the lower caps that follow
-- prove it. The method is derived in docs/profile-generator.md.
--
-- Invariant: 'exactJoin' returns only profiles the checker finds legal; 'noProfileFits'
-- claims only what verified certificates (and the bound on N) prove.
module VProf.Profile.Generate.Exact
  ( exactJoin
  , exactJoinFewer
  , compareWork
  , noProfileFits
  , proofCertificates
  , StepProof (..)
  ) where

import Data.List (sortOn)
import qualified Data.Vector.Unboxed as U
import Numeric (showFFloat)

import VProf.Profile.Generate.Seed.Brake (reachableAcc)
import VProf.Profile.Legality (legalVelocities, slack)
import VProf.Numeric.LinearProgram
import VProf.Profile.Sampled (trapezoidDistances)
import VProf.Profile.Request (Problem (..))
import VProf.Profile.SpeedLimit

-- | Velocity bounds k steps from the start and from the end, for every legal profile
-- (with the checker's slack): loF/hiF from the start, loB/hiB from the end (index = steps
-- before the end).
data Envelopes = Envelopes
  { loF, hiF, loB, hiB :: !(U.Vector Double) }

-- | How many steps the envelopes cover (and the largest N considered at all).
envCap :: Int
envCap = 4096

-- | The largest N solved as a linear program (dense; a short route's join).
lpCap :: Int
lpCap = 320

-- | The candidate step counts 'exactJoin' solves at most, fewest steps first.
joinCandidates :: Int
joinCandidates = 48

-- | The most step counts a proof certifies one by one.
proofOpenCap :: Int
proofOpenCap = 64

-- | Halvings of the bisections (the envelopes' hardest braking, the floor speed).
bisections :: Int
bisections = 60

-- | How often the caps are re-read at a solution's positions (several zones).
capRereads :: Int
capRereads = 6

-- | The margin either side of a solution's positions when its caps are re-read.
capMarginM :: Double
capMarginM = 0.01

-- | The work the exact join may spend, with a program of n steps counted as (n + 1)³ (a
-- dense simplex; measured on the 2-core VM: 11 ns a unit at 45 steps, 4 ns at 180): as the
-- meet's last resort ('exactJoin', some 2 s at most), and as the seed variant of fewer
-- steps than the best seed ('exactJoinFewer', some 0.2 s at most).
lastResortWork, compareWork :: Double
lastResortWork = 2e8
compareWork = 2e7

-- | The ways of crossing the zone boundaries 'exactJoin' tries for one step count.
assignCap :: Int
assignCap = 64

-- | How far a sample kept on one side of a zone boundary stays from it (the checker's
-- rounding).
boundaryRoomM :: Double
boundaryRoomM = 1e-6

-- | Built profiles keep this share of each range clear of its end (the checker's rounding).
narrowing :: Double
narrowing = 1e-6

-- | Extra room for the floor speed's distances: the samples may be below zero by the
-- checker's slack.
floorRoomM :: Double
floorRoomM = 1e-6

widen :: Double -> Double -> Double
widen sign x = x + sign * slack x

envelopes :: Problem -> Envelopes
envelopes pb =
  Envelopes (U.zipWith max (vel (pbV0 pb) 1 (accs (pbA0 pb) jMin)) (hardest (pbV0 pb) (pbA0 pb) aMin aMax))
            (vel (pbV0 pb) 1 (accs (pbA0 pb) jMax))
            (U.zipWith max (vel (pbVEnd pb) (-1) (accs (pbAEnd pb) (negate jMin))) (hardest (pbVEnd pb) (negate (pbAEnd pb)) (negate aMax) (negate aMin)))
            (vel (pbVEnd pb) (-1) (accs (pbAEnd pb) (negate jMax)))
  where
    dt = pbDt pb
    aMin = widen (-1) (pbAMin pb); aMax = widen 1 (pbAMax pb)
    jMin = widen (-1) (pbJMin pb); jMax = widen 1 (pbJMax pb)
    accs a0 j = U.generate envCap (\i -> max aMin (min aMax (a0 + j * fromIntegral (i + 1) * dt)))
    vel v0 sign as = U.scanl' (\v a -> v + sign * a * dt) v0 as
    -- The hardest braking from (v, a) that can still keep the velocity from going below
    -- zero later (the acceleration raised back at max_jerk must reach zero first): every
    -- legal profile from that state is at least as fast at every step. While it brakes
    -- with the least acceleration the jerk allows, no profile has less; once it rides the
    -- edge (its lowest future velocity, raising the acceleration as fast as allowed, is
    -- zero), a profile slower at some step would have both less velocity and less
    -- acceleration there, so a lowest future velocity below zero. From the end, the same
    -- on the problem mirrored in time (accelerations negated, their range flipped).
    -- This is the seed's hard brake policy ("VProf.Profile.Generate.Seed.Brake") on the
    -- ranges widened by the checker's slack: the reachable range of a step is the same
    -- function ('reachableAcc'); the acceleration on the edge is found by bisection
    -- against a floor of minus the slack, since the envelope must bound every profile
    -- the checker accepts, where the seed's closed form aims at zero exactly.
    hardest v0 a0 lo0 hi0 = U.unfoldrExactN (envCap + 1) next (v0, a0, True)
      where
        next (v, a, first)
          | first = (v, (v, a, False))
          | v <= 0 && a >= 0 = (v, (v, a, False))
          | otherwise =
              let (lo, hi) = reachableAcc dt lo0 hi0 jMin jMax a
                  x | keeps v lo = lo
                    | not (keeps v hi) = hi
                    | otherwise = bisect v lo hi bisections
                  v' = v + x * dt
              in (v', (v', x, False))
    keeps v x = go (v + x * dt) (x + jMax * dt)
      where go w y | y >= 0 = w >= negate (slack 0)
                   | otherwise = go (w + y * dt) (y + jMax * dt)
    bisect v l h n
      | n == 0 = h
      | otherwise = let m = (l + h) / 2 in if keeps v m then bisect v l m (n - 1) else bisect v m h (n - 1)

-- | The distance a lower bound covers before it first drops to u or below (all of it,
-- when it never does within the envelopes).
distanceAbove :: Double -> U.Vector Double -> Double -> Double
distanceAbove dt lo u =
  let m = maybe (U.length lo - 1) id (U.findIndex (<= u) lo)
  in U.sum (U.zipWith (\a b -> (a + b) * dt / 2) (U.take m lo) (U.slice 1 m lo))

-- | A speed every legal profile stays above at every sample, when there is one: if some
-- v_m ≤ u, then v_m's lower bound from the start is ≤ u, so the samples before m cover
-- at least the distance that bound covers before it drops to u; likewise after m from
-- the end. When those two distances exceed the route (plus tolerance), no sample is at u
-- or below. The largest such u, by bisection.
floorSpeed :: Problem -> Envelopes -> Maybe Double
floorSpeed pb env
  | not (excludes 0) = Nothing
  | otherwise = Just (go 0 (max (pbV0 pb) (pbVEnd pb)) bisections)
  where
    dt = pbDt pb
    -- (a micrometre more: the samples may be below zero by the checker's slack)
    room = pbLength pb + pbTol pb + slack (pbLength pb) + floorRoomM
    excludes u = distanceAbove dt (loF env) u + distanceAbove dt (loB env) u > room
    go lo hi n
      | n == 0 = lo
      | otherwise = let m = (lo + hi) / 2 in if excludes m then go m hi (n - 1) else go lo m (n - 1)

-- | The largest number of steps a legal profile can have, when it is bounded (given the
-- floor speed, if any).
maxSteps :: Problem -> Envelopes -> Maybe Double -> Maybe Int
maxSteps pb env fl = case [ n | Just n <- [past (loF env), past (loB env), byFloor] ] of
  [] -> Nothing
  ns -> Just (minimum ns)
  where
    dt = pbDt pb
    room = pbLength pb + pbTol pb + slack (pbLength pb)
    -- the lower bound covers more than the route after this many steps, still moving:
    -- every profile of more steps would pass the route end (or, from the end, start
    -- before the route start)
    past lo = let pos = trapezoidDistances dt lo
              in case U.findIndex (> room) pos of
                   Just n | U.all (> 0) (U.take (n + 1) lo) -> Just n
                   _ -> Nothing
    byFloor = (\u -> floor (room / (u * dt))) <$> fl

-- | The boxes of an N-step profile: lower and upper velocity bounds at each sample.
boxes :: Problem -> Envelopes -> Maybe Double -> Int -> (U.Vector Double, U.Vector Double)
boxes pb env fl n =
  ( U.generate (n + 1) (\k -> maximum [negate (slack 0), maybe 0 id fl, loF env U.! k, loB env U.! (n - k)])
  , U.generate (n + 1) (\k -> minimum [top, hiF env U.! k, hiB env U.! (n - k)]) )
  where top = widen 1 (U.maximum (pbZoneSpeeds pb))

trapezoid :: Double -> U.Vector Double -> Double
trapezoid dt = U.last . trapezoidDistances dt

-- | Can the boxes of N steps hold a profile at all?
boxFits :: Problem -> Envelopes -> Maybe Double -> Int -> Bool
boxFits pb env fl n =
  let (lo, hi) = boxes pb env fl n
      dt = pbDt pb
      len = pbLength pb
      room = pbTol pb + slack len
  in n >= 0 && U.and (U.zipWith (<=) lo hi) && trapezoid dt lo <= len + room && trapezoid dt hi >= len - room

-- | The rows of the N-step program over v_0..v_N, in this order (the tests rebuild them
-- in the same order to check a certificate): the N accelerations a_k·dt = v_{k+1} − v_k;
-- the jerk into a_0, j·dt² = v_1 − v_0 − a_start·dt; the N − 1 jerks between, v_{k+2} −
-- 2v_{k+1} + v_k; the jerk out of a_{N−1}, v_{N−1} − v_N = j·dt² − a_end·dt; and the
-- route end, s_N/dt = Σ (v_k + v_{k+1})/2. @w@ widens each range by the checker's slack
-- (proofs); without it each is narrowed by a millionth (built profiles keep clear of
-- the checker's rounding). @endRoom@ is the distance allowed either side of the route end.
joinRows :: Problem -> Bool -> Double -> Int -> [Row]
joinRows pb w endRoom n =
  [ Row [(k, -1), (k + 1, 1)] (aLo * dt) (aHi * dt) | k <- [0 .. n - 1] ]
  ++ [ Row [(0, -1), (1, 1)] ((pbA0 pb + jLo * dt) * dt) ((pbA0 pb + jHi * dt) * dt) ]
  ++ [ Row [(k, 1), (k + 1, -2), (k + 2, 1)] (jLo * dt * dt) (jHi * dt * dt) | k <- [0 .. n - 2] ]
  ++ [ Row [(n - 1, 1), (n, -1)] ((jLo * dt - pbAEnd pb) * dt) ((jHi * dt - pbAEnd pb) * dt) ]
  ++ [ Row [ (k, if k == 0 || k == n then 0.5 else 1) | k <- [0 .. n] ] ((len - endRoom) / dt) ((len + endRoom) / dt) ]
  where
    dt = pbDt pb
    len = pbLength pb
    sl sign x = if w then widen sign x else x - sign * narrowing * max 1 (abs x)
    aLo = sl (-1) (pbAMin pb); aHi = sl 1 (pbAMax pb)
    jLo = sl (-1) (pbJMin pb); jHi = sl 1 (pbJMax pb)

-- | The N-step program with per-sample caps: v_0 and v_N pinned (within the slack when
-- widened), the others within [0, cap_k]; maximising the velocities (the fastest profile
-- of that many steps).
joinLp :: Problem -> Bool -> Double -> Int -> U.Vector Double -> Lp
joinLp pb w endRoom n caps =
  Lp { lpCols = n + 1
     , lpColLo = U.generate (n + 1) (\k -> pin k (pbV0 pb - s0) (pbVEnd pb - sE) (if w then negate (slack 0) else 0))
     , lpColHi = U.generate (n + 1) (\k -> pin k (pbV0 pb + s0) (pbVEnd pb + sE) (caps U.! k))
     , lpRows = joinRows pb w endRoom n
     , lpObjective = U.replicate (n + 1) (if w then 0 else -1)
     }
  where
    s0 = if w then slack (pbV0 pb) else 0
    sE = if w then slack (pbVEnd pb) else 0
    pin k a b c | k == 0 = a
                | k == n = b
                | otherwise = c

-- | For a request the meet could not join: the first N (fewest steps first) whose program
-- gives a profile the checker finds legal, within 'lastResortWork'; first by the cheap
-- programs alone ('cheapPrograms' of each N, within 'cheapWork'), then by all of them.
--
-- Where a slow zone lies before a fast end, the screening program with the highest limit
-- everywhere is feasible for step counts far below any profile's, and each of them costs
-- all its programs (some 17, most of them ways of crossing the zone boundaries) before the
-- next N: a 105 mm part from 0.125 to 0.49999 m/s at 4 ms spent the whole budget (1.5 s)
-- on N = 81 to 90 and stopped before the 91 of its fewest profile, while the cautious
-- caps give a profile of 92 in the first 0.2 s. The programs the cheap pass solved are
-- shared with the full one (and its budget grows by their work), so that the full pass
-- reaches as far as it would alone.
exactJoin :: Problem -> Maybe (U.Vector Double)
exactJoin pb = withoutStanding pb <$> case firstWithin cheapWork (concatMap (take cheapPrograms) lists) of
  (Just v, _) -> Just v
  (Nothing, spent) -> fst (firstWithin (lastResortWork + spent) (concat lists))
  where
    (candidates, attempts) = joinPrograms pb
    lists = map attempts (take joinCandidates candidates)

-- | The programs of a step count the cheap pass of 'exactJoin' solves: with several zones
-- the screening one and the cautious caps within half the tolerance; with one zone, the
-- cautious caps within half and within the whole tolerance (all its programs).
cheapPrograms :: Int
cheapPrograms = 2

-- | The work of the cheap pass of 'exactJoin'.
cheapWork :: Double
cheapWork = lastResortWork / 4

-- | A profile of fewer than the given number of steps by the exact join, within a work
-- budget, for a seed that may be far from the fastest: the most steps first (if none of
-- them has a profile, fewer steps are not tried), then fewer by bisection on the step
-- counts the boxes leave open, the fewest found kept. Far cheaper than 'exactJoin' where
-- the seed is already the fastest (one step count's programs).
exactJoinFewer :: Double -> Int -> Problem -> Maybe (U.Vector Double)
exactJoinFewer budget below pb = case cands of
  [] -> Nothing
  _ -> case firstWithin budget (attempts (last cands)) of
    (Nothing, _) -> Nothing
    (Just v, spent) -> Just (withoutStanding pb (bisect (budget - spent) 0 (length cands - 1) v))
  where
    (candidates, attempts) = joinPrograms pb
    cands = takeWhile (< below) candidates
    -- cands !! hi has the profile best; look below it
    bisect left lo hi best
      | lo >= hi = best
      | otherwise =
          let mid = (lo + hi) `div` 2
          in case firstWithin left (attempts (cands !! mid)) of
               (Just v, spent) -> bisect (left - spent) lo mid v
               (Nothing, spent) | spent < left -> bisect (left - spent) (mid + 1) hi best
               _ -> best

-- | A profile from rest (with no start acceleration) whose program let it stand still for
-- its first steps, with those steps dropped: as many steps shorter, and still legal (the
-- checker confirms it; otherwise the profile stays as it was). The program of n steps
-- maximises the velocities' sum, which a profile of fewer steps padded with standing still
-- can do (a 30.5 m route ending at rest with -0.888 m/s²: 104 steps, the first standing,
-- where 103 are legal).
withoutStanding :: Problem -> U.Vector Double -> U.Vector Double
withoutStanding pb vs
  | pbV0 pb == 0 && pbA0 pb == 0 && standing > 0 && U.length vs - standing >= 2 && legalVelocities pb trimmed = trimmed
  | otherwise = vs
  where
    standing = U.length (U.takeWhile (<= standingSpeed) (U.drop 1 (U.take (U.length vs - 1) vs)))
    trimmed = U.cons 0 (U.drop (standing + 1) vs)

-- | A sample of a built profile at most this fast stands still (the programs' rounding).
standingSpeed :: Double
standingSpeed = 1e-12

-- | The first profile of a list of programs (each with its work) within a budget, and the
-- work spent (a program that would pass the budget is not solved).
firstWithin :: Double -> [(Double, Maybe (U.Vector Double))] -> (Maybe (U.Vector Double), Double)
firstWithin budget = go 0
  where
    go spent [] = (Nothing, spent)
    go spent ((w, r) : rest)
      | spent + w > budget = (Nothing, budget)
      | Just v <- r = (Just v, spent + w)
      | otherwise = go (spent + w) rest

-- | The step counts the boxes leave open (fewest first, at most 'lpCap'), and for each the
-- programs that may build its profile, each with its work ((n + 1)³ for n steps), in order.
joinPrograms :: Problem -> ([Int], Int -> [(Double, Maybe (U.Vector Double))])
joinPrograms pb = (candidates, attempts)
  where
    env = envelopes pb
    fl = floorSpeed pb env
    dt = pbDt pb
    len = pbLength pb
    tol = pbTol pb
    top = maybe envCap id (maxSteps pb env fl)
    candidates = [ n | n <- [1 .. min lpCap top], boxFits pb env fl n ]
    solveWith room n caps = solveRows room n caps []
    -- the program of n steps with these caps and extra rows, its distance within room of
    -- the route end: its velocities, the ends pinned and the rest clipped at zero (the
    -- solver's rounding)
    solveRows room n caps extra = case solve lp0 { lpRows = lpRows lp0 ++ extra } of
      Optimal x -> Just (U.imap (\k v -> if k == 0 then pbV0 pb else if k == n then pbVEnd pb else max 0 v) x)
      _ -> Nothing
      where lp0 = joinLp pb False room n caps
    -- half the tolerance, clear of the checker's rounding; then, where no profile of n
    -- steps ends within it, all of it but the rounding's share (a 6.39 m route from 2.26 to
    -- 2.63 m/s at 11.6 ms ends within 10 mm in 220 steps, but not within 5 mm)
    halfRoom = tol / 2
    fullRoom = tol * (1 - narrowing)
    -- the programs for n steps, each with its work, in order
    attempts n =
      let (lo, hi) = boxes pb env fl n
          w = fromIntegral (n + 1) ^ (3 :: Int) :: Double
          -- positions every legal profile of n steps keeps to: from the box sums
          -- forwards and, from the route end, backwards
          cumLo = trapezoidDistances dt lo
          cumHi = trapezoidDistances dt hi
          sLo k = max (cumLo U.! k) (len - tol - (cumHi U.! n - cumHi U.! k))
          sHi k = min (cumHi U.! k) (len + tol - (cumLo U.! n - cumLo U.! k))
          -- v_k takes part in the steps before and after it: the lowest limit anywhere
          -- either of them can lie
          cautious = U.generate (n + 1) (\k -> minLimitOn pb (max 0 (sLo (max 0 (k - 1)))) (sHi (min n (k + 1))))
          -- the caps read at the positions of a solution, a centimetre either side
          readAt vs = let s = trapezoidDistances dt vs
                          at k = s U.! max 0 (min n k)
                      in U.generate (n + 1) (\k -> minLimitOn pb (max 0 (at (k - 1) - capMarginM)) (at (k + 1) + capMarginM))
          refineIn room caps i = case solveWith room n caps of
            Just vs | legalVelocities pb vs -> Just vs
                    | i > 0 -> refineIn room (U.zipWith min caps (readAt vs)) (i - 1 :: Int)
            _ -> Nothing
          refine = refineIn halfRoom
          single = U.length (pbZoneSpeeds pb) == 1
          -- the zone boundaries a profile of n steps may reach (boundary i starts zone i)
          bounds = takeWhile (<= len + tol) (drop 1 (U.toList (pbZoneStarts pb)))
          -- the first sample at or past b: from the first that can be to the first that must be
          firstPast b = let can = head ([ k | k <- [0 .. n], sHi k >= b ] ++ [n + 1])
                            must = head ([ k | k <- [0 .. n], sLo k >= b ] ++ [n + 1])
                        in [max 1 can .. must]
          assignments = take assignCap (nondecreasing 1 (map firstPast bounds))
          assigned ms =
            let -- the zone of sample k: the boundaries at or before it
                zoneOf k = length (filter (<= k) ms)
                speeds = pbZoneSpeeds pb
                caps = U.generate (n + 1) (\k -> let z0 = zoneOf (max 0 (k - 1)); z1 = zoneOf (min n (k + 1))
                                                 in U.minimum (U.slice z0 (z1 - z0 + 1) speeds))
                far = (len + tol + 1) / dt
                row k lo hi = Row (positionTerms k) (lo / dt) (hi / dt)
                sides = concat [ [ row (m - 1) 0 (b - boundaryRoomM) | m - 1 >= 1 ] ++ [ row m (b + boundaryRoomM) far | m <= n ]
                               | (b, m) <- zip bounds ms ]
            in case solveRows halfRoom n caps sides of
                 Just vs | legalVelocities pb vs -> Just vs
                 _ -> Nothing
          highest = U.replicate (n + 1) (U.maximum (pbZoneSpeeds pb))
      -- one zone: the cautious caps are exact; several: when the cautious caps leave no
      -- solution, start from the highest limit and re-read the caps where the solution
      -- runs, a few times; then keep every sample on its side of each boundary it may
      -- cross, for the ways of crossing them that the boxes leave open
          -- then the whole tolerance, where half of it leaves no profile
          wholeTolerance = (w, refineIn fullRoom cautious 0)
                           : [ (w * fromIntegral (capRereads + 1), refineIn fullRoom highest capRereads) | not single ]
      in if single then (w, refine cautious 0) : wholeTolerance
         -- each screening program solved below counts as one solve of work, an entry
         -- without a profile
         else case solveWith halfRoom n highest of
                Just _ -> (w, Nothing) : (w, refine cautious 0) : (w * fromIntegral (capRereads + 1), refine highest capRereads)
                          : [ (w, assigned ms) | ms <- assignments ] ++ wholeTolerance
                -- no profile of n steps within half the tolerance even under the highest
                -- limit everywhere; within all of it?
                Nothing -> case solveWith fullRoom n highest of
                  -- the two screening solves, within half and within all of the tolerance
                  Nothing -> [(w, Nothing), (w, Nothing)]
                  Just _ -> (w, Nothing) : (w, Nothing) : wholeTolerance

-- | Non-decreasing choices, one from each list, each at least @lo@ (in order).
nondecreasing :: Int -> [[Int]] -> [[Int]]
nondecreasing _ [] = [[]]
nondecreasing lo (xs : rest) = [ x : ys | x <- xs, x >= lo, ys <- nondecreasing x rest ]

-- | The proof for one step count N: the exclusions (sample k lies in zone z in no profile of
-- N steps: the program with the row "s_k within zone z, widened by the slack" has this
-- certificate) and the certificate of the program whose samples are capped by the highest
-- limit of the zones left to them (by the highest limit of all where nothing is excluded).
data StepProof = StepProof
  { spExclusions :: [(Int, Int, Farkas)]   -- ^ (sample k, zone index z, certificate)
  , spFarkas     :: Farkas
  } deriving Show

-- | The most exclusion programs one proof solves (over all its step counts).
exclusionCap :: Int
exclusionCap = 4000

-- | The proof that no profile fits: N is bounded, and every N up to the bound either has
-- boxes that cannot hold a profile or a program with a verified certificate. The bound
-- and the proofs, by N (the N the boxes rule out have none).
--
-- Every sample keeps the limit of the zone it lies in, so where a sample cannot lie in the
-- faster zones its velocity is capped by the slower ones: the program with the highest
-- limit everywhere is tried first; when it is feasible, each sample is tested against the
-- zones from the fastest down, each zone it cannot lie in excluded by a certificate, and
-- the program with the caps left is tried again.
proofCertificates :: Problem -> Maybe (Int, [(Int, StepProof)])
proofCertificates pb = do
  nMax <- maxSteps pb env fl
  let open = [ n | n <- [0 .. nMax], boxFits pb env fl n ]
  -- a single sample (N = 0) has no program: it is left unproven
  if nMax > envCap || length open > proofOpenCap || any (\n -> n < 1 || n > lpCap) open then Nothing else do
    let plains = map plain open
        -- the zoned proofs only for the step counts the plain programs leave, and only as
        -- many exclusion programs as the cap allows in all
        work = sum [ (n - 1) * nz | (n, Nothing) <- zip open plains ]
    certs <- sequence [ maybe (if work <= exclusionCap then zoned n else Nothing) (Just . StepProof []) p
                      | (n, p) <- zip open plains ]
    pure (nMax, zip open certs)
  where
    env = envelopes pb
    fl = floorSpeed pb env
    top = widen 1 (U.maximum (pbZoneSpeeds pb))
    room = pbTol pb + slack (pbLength pb)
    nz = U.length (pbZoneSpeeds pb)
    certified lp = case solve lp of
      Infeasible f | certifies lp f -> Just f
      _ -> Nothing
    programWith n caps = joinLp pb True room n caps
    topProgram n = programWith n (U.replicate (n + 1) top)
    plain n = certified (topProgram n)
    -- zones from the fastest down (index, limit)
    byLimit = map snd (reverse (sortOn fst [ (lim, (z, lim)) | (z, lim) <- zip [0 ..] (U.toList (pbZoneSpeeds pb)) ]))
    zoned n
      | nz < 2 = Nothing
      | otherwise =
          let lp0 = topProgram n
              excluded k z = certified lp0 { lpRows = lpRows lp0 ++ [zoneRow pb k z] }
              perSample k = go byLimit
                where go [] = ([], 0)
                      go ((z, lim) : rest) = case excluded k z of
                        Just f -> let (es, c) = go rest in ((k, z, f) : es, c)
                        Nothing -> ([], widen 1 lim)
              tested = [ (k, perSample k) | k <- [1 .. n - 1] ]
              caps = U.generate (n + 1) (\k -> maybe top (min top . snd) (lookup k tested))
              exclusions = concatMap (fst . snd) tested
          in StepProof exclusions <$> certified (programWith n caps)

-- | The row "sample k of an N-step profile lies in zone z": s_k/dt = v_0/2 + v_1 + … +
-- v_{k−1} + v_k/2 within the zone's start and end (the next zone's start; for the last,
-- a metre past the route end and its tolerance), each widened by the checker's slack of the
-- route length.
zoneRow :: Problem -> Int -> Int -> Row
zoneRow pb k z = Row (positionTerms k) ((a - m) / dt) ((b + m) / dt)
  where
    dt = pbDt pb
    len = pbLength pb
    m = slack len
    a = pbZoneStarts pb U.! z
    b = if z + 1 < U.length (pbZoneStarts pb) then pbZoneStarts pb U.! (z + 1) else len + pbTol pb + 1

-- | The terms of sample k's position over the time step, s_k/dt = v_0/2 + v_1 + … +
-- v_{k−1} + v_k/2 (k ≥ 1).
positionTerms :: Int -> [(Int, Double)]
positionTerms k = (0, 0.5) : [ (j, 1) | j <- [1 .. k - 1] ] ++ [(k, 0.5)]

num :: Double -> String
num x = showFFloat Nothing (fromIntegral (round (x * 1e6) :: Integer) / 1e6 :: Double) ""

-- | The claim that no profile joins the start state to the end state within the route,
-- with the reason, when it can be proven ('proofCertificates').
noProfileFits :: Problem -> Maybe String
noProfileFits pb = do
  (nMax, certs) <- proofCertificates pb
  pure ("start_velocity " ++ num (pbV0 pb) ++ " m/s with start_acceleration " ++ num (pbA0 pb)
        ++ " m/s² and end_velocity " ++ num (pbVEnd pb) ++ " m/s with end_acceleration " ++ num (pbAEnd pb)
        ++ " m/s² cannot both be met within route_length " ++ num (pbLength pb) ++ " m: within min/max_acceleration "
        ++ num (pbAMin pb) ++ "/" ++ num (pbAMax pb) ++ " m/s² and min/max_jerk " ++ num (pbJMin pb) ++ "/"
        ++ num (pbJMax pb) ++ " m/s³ no profile of up to " ++ show nMax ++ " steps of " ++ num (pbDt pb)
        ++ " s covers the route (and none can have more)"
        ++ (if null certs then "" else "; for " ++ show (length certs) ++ " of these step counts a linear program proves it")
        ++ (case length [ () | (_, sp) <- certs, not (null (spExclusions sp)) ] of
              0 -> ""
              z -> ", for " ++ show z ++ " of them with the speed limits of the zones its samples cannot avoid"))
