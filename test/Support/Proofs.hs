-- | Independent proofs of the generator's infeasibility claims, written apart from the
-- generator from the checker's rules: bounds on every legal profile (hardest braking,
-- hardest accelerating, a floor speed), the mirrored problem, and a check of the
-- generator's Farkas certificates against rows built here. A claim the generator makes
-- is accepted by the tests only when one of these confirms it ('sound').
module Support.Proofs
  ( startInfeasibleProof
  , hardestBrakeStep
  , endInfeasibleProof
  , stateGapProof
  , floorBound
  , certificateHolds
  , certificateHoldsIn
  , certificateTerms
  , certificateTermsIn
  , zoneRowOf
  , stepProofHolds
  , mirrored
  , startAccProof
  , sound
  ) where

import qualified Data.Vector.Unboxed as U

import VProf.Numeric.LinearProgram (Farkas (..))
import VProf.Profile.Generate
import VProf.Profile.Generate.Exact (StepProof (..), proofCertificates)
import VProf.Profile.Legality
import VProf.Profile.Request
import VProf.Profile.Sampled

import Support.LegalityOracle (Verdict (..), oracleVerdict)

-- | An independent proof that a start state cannot obey the limits: the velocity of any
-- profile is, at every time, at least that of the hardest braking (jerk at its minimum
-- until the acceleration is at its minimum, then held), which ignores that the
-- acceleration must come back to zero before the velocity reaches zero, so it is a lower
-- bound. A profile reaches each position no sooner than... the bound reaches it no later
-- than any profile could: so if the bound's velocity is above a zone's limit all the way
-- until the bound's position reaches the zone (and the bound is still moving), every
-- profile enters that zone too fast. Likewise for stopping before the route end.
startInfeasibleProof :: Problem -> Bool
startInfeasibleProof pb =
  any zoneProof boundaries || any dwellProof spans || tooFastSomewhere || any crossedTooLate (map fst (drop 1 zones)) || endProof
  where
    dt = pbDt pb
    len = pbLength pb
    zones = zip (U.toList (pbZoneStarts pb)) (U.toList (pbZoneSpeeds pb))
    -- a step that crosses a zone boundary touches both zones: the lower limit holds
    boundaries = [ (z, min l0 l1) | ((_, l0), (z, l1)) <- zip zones (drop 1 zones) ]
    highestOn a b = maximum [ lim | ((st, lim), next) <- zip zones (map (Just . fst) (drop 1 zones) ++ [Nothing])
                                  , st <= b, maybe True (> a) next ]
    -- hardest braking: a lower bound on every profile's velocity and position at every
    -- step (clamped at rest; only its part before rest is used)
    lower = let (moving, rest) = span (\(a, v, _) -> v > 0 || a > 0) (iterate brake (pbA0 pb, pbV0 pb, 0))
            in moving ++ take 1 rest
    brake = hardestBrakeStep pb
    -- hardest accelerating: an upper bound on position
    upper = iterate (\(a, v, s) -> let a' = min (pbAMax pb) (a + pbJMax pb * dt); v' = v + a' * dt
                                    in (a', v', s + (v + v') * dt / 2)) (pbA0 pb, pbV0 pb, 0)
    lowerArr = take 2000000 lower
    vL = U.fromList [ v | (_, v, _) <- lowerArr ]
    sL = U.fromList [ s | (_, _, s) <- lowerArr ]
    firstIndex p xs = case filter (p . snd) (zip [0 :: Int ..] xs) of ((i, _) : _) -> Just i; [] -> Nothing
    -- a profile's step that touches zone start z ends at a step k+1 >= tU (it is at most
    -- as far as the upper bound) and starts at k < tB (it is at least as far as the lower
    -- bound): its top velocity is at least the lower bound's least velocity on [tU, tB]
    -- Before a profile reaches z all its samples lie before z, so its velocity is also at
    -- most the highest limit there: the upper bound on position, capped so.
    cappedUpper z = let cap = highestOn 0 z
                        vs = [ min cap v | (_, v, _) <- take 2000000 upper ]
                    in scanl (+) 0 (zipWith (\a b -> (a + b) * dt / 2) vs (drop 1 vs))
    zoneProof (z, lim) = case (firstIndex (>= z) (cappedUpper z), firstIndex (>= z) (U.toList sL)) of
      (Just tU, Just tB) | tU <= tB -> minimum [ max (vL U.! max 0 (m - 1)) (vL U.! m + extra z m) | m <- [tU .. tB] ] > lim
      _ -> False
    -- A profile that first reaches zone [z, z2) at sample m (m within [tU, tB] as above)
    -- is inside it for a while: each step that starts in the zone keeps to its limit, so
    -- it covers at most lim·dt, and the samples m−1 .. m+D all keep to the limit, with
    -- D = ⌊(z2 − z)/(lim·dt)⌋ (samples m .. m+D−1 are still before z2). The profile has
    -- them all: it ends at L − tolerance or beyond, so z2 is taken no further than that.
    -- If for every such m one of them is, by the lower bound, above the limit, no profile
    -- gets through the zone.
    spans = [ (z, min z2 (len - pbTol pb - 1e-9 * len), lim) | ((z, lim), z2) <- zip (drop 1 zones) (map fst (drop 2 zones) ++ [len]) ]
    dwellProof (z, z2, lim) = case (firstIndex (>= z) (cappedUpper z), firstIndex (>= z) (U.toList sL)) of
      (Just tU, Just tB) | tU <= tB && z2 > z ->
        let limS = lim + 1e-9 * max 1 lim
            d = floor ((z2 - z) / (limS * dt)) :: Int
            over k = k < U.length vL && vL U.! k > limS
        in all (\m -> any over [max 0 (m - 1) .. m + d]) [tU .. tB]
      _ -> False
    -- While the bound's accelerations are the least any profile can have (each step at
    -- max(a_min, previous + min_jerk·dt)), every profile's lead in velocity over it, d_k,
    -- never shrinks; so a profile that is at z at sample m, where the bound is at
    -- sL_m < z, has d_m·m·dt >= z − sL_m: it is faster there by at least that.
    leastSoFar = U.fromList (scanl (&&) True (zipWith (\(a, _, _) (a', _, _) -> a' == max (pbAMin pb) (a + pbJMin pb * dt)) lowerArr (drop 1 lowerArr)))
    extra z m
      | m > 0 && m < U.length leastSoFar && leastSoFar U.! m && sL U.! m < z = (z - sL U.! m) / (fromIntegral m * dt)
      | otherwise = 0
    -- every profile is, at step k, somewhere in [sL_k, sU_k] at a velocity of at least vL_k
    tooFastSomewhere = or [ v > highestOn s (min su len) | ((_, v, s), (_, _, su)) <- zip lowerArr upper, s <= len ]
    -- A zone start z: until a profile first reaches z (at sample m), each of its steps
    -- touches a zone before z, so v_0..v_m are at most the highest limit before z. If
    -- every profile is faster than that from sample k on (the lower bound), it must have
    -- reached z by sample k−1; but moving no faster than those limits (and the upper
    -- bound), it cannot be at z by then.
    crossedTooLate z =
      let capBefore = maximum [ lim | (st, lim) <- zones, st < z ]
          reach = scanl (+) 0 (zipWith (\a b -> (a + b) * dt / 2) capped (drop 1 capped))
          capSlack = capBefore + 1e-9 * max 1 capBefore
          capped = [ min capSlack v | (_, v, _) <- take 2000000 upper ]
      in case U.findIndex (> capSlack) vL of
           Just k | k >= 1 -> reach !! (k - 1) < z
           _ -> False
    -- the route end: no sample may pass L + tol, and the last one must be at the end velocity
    endProof = case (firstIndex (> len + pbTol pb) (U.toList sL)) of
      Just tB -> let tU = maybe 0 id (firstIndex (>= len - pbTol pb) [ s | (_, _, s) <- take 2000000 upper ])
                 in tU <= tB && U.minimum (U.slice tU (tB - tU + 1) vL) > pbVEnd pb
      Nothing -> False

-- | One step of the hardest braking that a profile can do without its velocity going
-- below zero later: the acceleration must come back to zero (at most max_jerk per step)
-- before the velocity does, so every profile's velocity stays above this one's.
-- (acceleration, velocity, position) to the next.
hardestBrakeStep :: Problem -> (Double, Double, Double) -> (Double, Double, Double)
hardestBrakeStep pb (a, v, s) =
  let dt = pbDt pb
      lo = max (pbAMin pb) (a + pbJMin pb * dt)
      hi = min (pbAMax pb) (a + pbJMax pb * dt)
      keepsPositive x = v + x * dt + dt * sum (takeWhile (< 0) [ x + fromIntegral i * pbJMax pb * dt | i <- [1 :: Int ..] ]) >= 0
      bisect l h n = if n == (0 :: Int) then h else let m = (l + h) / 2 in if keepsPositive m then bisect l m (n - 1) else bisect m h (n - 1)
      a' | keepsPositive lo = lo
         | not (keepsPositive hi) = hi
         | otherwise = bisect lo hi 60
      v' = v + a' * dt
  in (a', max 0 v', s + (v + max 0 v') * dt / 2)

-- | Independent check of the end-state claims: coming into (v_end, a_end) the
-- accelerations before the end are bounded by the jerk; with a_end > 0 the velocity
-- before the end is at most v_end − Σ positive lower bounds; if that is negative, no
-- profile reaches the end state.
endInfeasibleProof :: Problem -> Bool
endInfeasibleProof pb
  | pbAEnd pb > 0 =
      let j = pbJMax pb * dt
          lows = takeWhile (> 0) [ pbAEnd pb - fromIntegral k * j | k <- [1 :: Int ..] ]
      in pbVEnd pb - dt * sum lows < -1e-9
  | pbAEnd pb < 0 =
      -- a_end < 0: the last step's velocity v_{N-1} >= v_end + |a_{N-1}| dt with
      -- a_{N-1} <= a_end - j_min dt < 0; the step [s_{N-1}, s_N] touches the route end
      let aLast = pbAEnd pb - pbJMin pb * dt
          vPrev = pbVEnd pb - aLast * dt
          limEnd = U.last (pbZoneSpeeds pb)
      in aLast < 0 && vPrev > limEnd * (1 + 1e-9)
  | otherwise = False
  where dt = pbDt pb

-- | Independent check of a claim that the start and end states cannot both be met: for
-- every number of steps N, each legal profile's accelerations are boxed by the jerk
-- limits from both ends (a_k within a_start + (k+1)·dt·[j_min, j_max] and a_{N-1-i}
-- within a_end − (i+1)·dt·[j_max, j_min], clipped to [a_min, a_max], each widened by the
-- checker's slack), so its velocities lie in boxes whose sums bound the route end. N is
-- bounded: by the step at which the lowest velocities from the start already carry a
-- sample past L + tolerance (the overshoot rule), the same from the end (on the mirrored
-- problem), or by a speed every profile stays above ('floorBound'). Every N up to the
-- bound must have an empty box or a route end out of reach of the box sums, or else a
-- certificate from the generator ('proofCertificates') that this test checks against
-- rows of its own ('certificateHolds'): then no profile exists.
stateGapProof :: Problem -> Bool
stateGapProof pb = case bound of
  Just nB -> all (\n -> not (feasibleWith n) || certified n) [0 .. nB]
  Nothing -> False
  where
    dt = pbDt pb
    len = pbLength pb
    eps x = 1e-9 * max 1 (abs x)
    lo = pbAMin pb - eps (pbAMin pb)
    hi = pbAMax pb + eps (pbAMax pb)
    jLo = pbJMin pb - eps (pbJMin pb)
    jHi = pbJMax pb + eps (pbJMax pb)
    clip x = min hi (max lo x)
    limitTop = let m = U.maximum (pbZoneSpeeds pb) in m + eps m
    room = len + pbTol pb + eps len
    -- velocity bounds m steps from the start (forwards) and from the end (backwards)
    fwd j m = pbV0 pb + dt * sum [ clip (pbA0 pb + fromIntegral i * j * dt) | i <- [1 .. m] ]
    bwd j m = pbVEnd pb - dt * sum [ clip (pbAEnd pb - fromIntegral i * j * dt) | i <- [1 .. m] ]
    nCap = 4096 :: Int
    -- the lower ones also no lower than the hardest braking that keeps the velocity
    -- from going below zero later (from the end: on the mirrored problem)
    braking q = U.fromList (take (nCap + 1) ([ v | (_, v, _) <- takeWhile (\(a, v, _) -> v > 0 || a < 0) (iterate (hardestBrakeStep q) (pbA0 q, pbV0 q, 0)) ] ++ repeat 0))
    vFwdLo = U.zipWith max (U.generate (nCap + 1) (fwd jLo)) (braking pb)
    vFwdHi = U.generate (nCap + 1) (fwd jHi)
    vBwdHi = U.generate (nCap + 1) (bwd jHi)
    vBwdLo = U.zipWith max (U.generate (nCap + 1) (bwd jLo)) (braking (mirrored pb))
    firstPast v =
      let pos = U.scanl' (+) 0 (U.zipWith (\a b -> (a + b) * dt / 2) v (U.tail v))
      in case U.findIndex (> room) pos of
           Just n | U.all (> 0) (U.take (n + 1) v) -> Just n
           _ -> Nothing
    fl = floorBound dt room vFwdLo vBwdLo
    bound = case [ n | Just n <- [firstPast vFwdLo, firstPast vBwdLo, (\u -> floor (room / (u * dt))) <$> fl] ] of
      [] -> Nothing
      ns -> Just (minimum ns)
    feasibleWith n =
      let lower = U.generate (n + 1) (\k -> maximum [negate (eps 0), maybe 0 id fl, vFwdLo U.! k, vBwdLo U.! (n - k)])
          upper = U.generate (n + 1) (\k -> minimum [limitTop, vFwdHi U.! k, vBwdHi U.! (n - k)])
          dist v = U.sum (U.zipWith (\a b -> (a + b) * dt / 2) v (U.drop 1 v))
      in U.and (U.zipWith (<=) lower upper) && dist lower <= len + pbTol pb + eps len && dist upper >= len - pbTol pb - eps len
    certs = maybe [] snd (proofCertificates pb)
    certified n = n >= 1 && maybe False (stepProofHolds pb n) (lookup n certs)

-- | A speed u > 0 that every legal profile stays above, if the lower velocity bounds
-- show one: a sample at u or below would be reached no sooner than the lower bound from
-- the start drops to u, and left no later than the one from the end does, so the profile
-- would cover at least both of their distances down to u; when those exceed the route,
-- no sample is that slow. Those distances only shrink as u grows: the largest such u by
-- bisection.
floorBound :: Double -> Double -> U.Vector Double -> U.Vector Double -> Maybe Double
floorBound dt room fromStart fromEnd
  | excludes 0 = Just (bisect 0 (max (U.head fromStart) (U.head fromEnd)) (60 :: Int))
  | otherwise = Nothing
  where
    above v u = let m = maybe (U.length v - 1) id (U.findIndex (<= u) v)
                in sum [ (v U.! k + v U.! (k + 1)) * dt / 2 | k <- [0 .. m - 1] ]
    excludes u = above fromStart u + above fromEnd u > room + 1e-6
    bisect a _ 0 = a
    bisect a b i = let m = (a + b) / 2 in if excludes m then bisect m b (i - 1) else bisect a m (i - 1)

-- | A Farkas certificate for the N-step problem, checked against the checker's rules
-- written out here as linear rows over v_0..v_N, each widened by the checker's slack:
-- combining the rows with the multipliers y (y_i > 0 on a row's upper side, y_i < 0 on
-- its lower) gives r·v ≤ B for every legal profile; if the least r·v can be over the
-- velocities' box (start and end pinned, the others within [0, the highest limit]) is
-- still above B, beyond a rounding margin, no legal profile has N steps. The rows, in
-- the order the generator documents: accelerations, the jerk into a_0, the jerks
-- between, the jerk out of a_{N-1}, the route end.
certificateHolds :: Problem -> Int -> U.Vector Double -> Bool
certificateHolds pb n = certificateHoldsIn pb n [] (const Nothing)

-- | The same for the rows with some more appended (zone rows, 'zoneRowOf') and the boxes'
-- upper ends capped where @cap k@ says (else the highest limit).
certificateHoldsIn :: Problem -> Int -> [([(Int, Double)], Double, Double)] -> (Int -> Maybe Double) -> U.Vector Double -> Bool
certificateHoldsIn pb n extra cap y = case certificateTermsIn pb n extra cap y of
  Just (least, _, combined, margin) -> least - combined > margin
  Nothing -> False

-- | The parts of that check: the least of r·v over the box, r, the combined bound B and
-- the rounding margin (Nothing for a multiplier vector of the wrong length or one on an
-- infinite side).
certificateTerms :: Problem -> Int -> U.Vector Double -> Maybe (Double, U.Vector Double, Double, Double)
certificateTerms pb n = certificateTermsIn pb n [] (const Nothing)

-- | The row "sample k lies in zone z" of an N-step profile: its position over dt,
-- v_0/2 + v_1 + … + v_{k−1} + v_k/2, between the zone's start and its end (the next zone's
-- start; for the last zone a metre past the route end and its tolerance), each widened by
-- 1e-9 of the route length.
zoneRowOf :: Problem -> Int -> Int -> ([(Int, Double)], Double, Double)
zoneRowOf pb k z = ((0, 0.5) : [ (j, 1) | j <- [1 .. k - 1] ] ++ [(k, 0.5)], (a - m) / dt, (b + m) / dt)
  where
    dt = pbDt pb
    len = pbLength pb
    m = 1e-9 * max 1 len
    starts = U.toList (pbZoneStarts pb)
    a = starts !! z
    b = if z + 1 < length starts then starts !! (z + 1) else len + pbTol pb + 1

-- | A proof of the generator for one step count, checked: every exclusion's certificate
-- holds for the rows with its zone row appended (so in no profile of N steps does sample k
-- lie in zone z), and the main certificate holds with every sample capped by the highest
-- limit of the zones not excluded for it (a sample keeps the limit of the zone it lies in).
stepProofHolds :: Problem -> Int -> StepProof -> Bool
stepProofHolds pb n (StepProof excl (Farkas y)) =
  and [ k >= 1 && k <= n - 1 && z >= 0 && z < nz && certificateHoldsIn pb n [zoneRowOf pb k z] (const Nothing) yz
      | (k, z, Farkas yz) <- excl ]
  && certificateHoldsIn pb n [] capOf y
  where
    nz = U.length (pbZoneSpeeds pb)
    eps x = 1e-9 * max 1 (abs x)
    capOf k = case [ z | (k', z, _) <- excl, k' == k ] of
      [] -> Nothing
      out -> Just (maximum (0 : [ lim + eps lim | (z, lim) <- zip [0 ..] (U.toList (pbZoneSpeeds pb)), z `notElem` out ]))

certificateTermsIn :: Problem -> Int -> [([(Int, Double)], Double, Double)] -> (Int -> Maybe Double)
                   -> U.Vector Double -> Maybe (Double, U.Vector Double, Double, Double)
certificateTermsIn pb n extra cap y
  | U.length y == length rows && all finiteSide (zip (U.toList y) rows) = Just (least, r, combined, margin)
  | otherwise = Nothing
  where
    dt = pbDt pb
    eps x = 1e-9 * max 1 (abs x)
    wide x = (x - eps x, x + eps x)
    (aLo, _) = wide (pbAMin pb); (_, aHi) = wide (pbAMax pb)
    (jLo, _) = wide (pbJMin pb); (_, jHi) = wide (pbJMax pb)
    accRow k = ([(k + 1, 1 / dt), (k, -1 / dt)], aLo, aHi)
    rows = [ scale dt (accRow k) | k <- [0 .. n - 1] ]
           ++ [ ([(1, 1), (0, -1)], (pbA0 pb + jLo * dt) * dt, (pbA0 pb + jHi * dt) * dt) ]
           ++ [ ([(k + 2, 1), (k + 1, -2), (k, 1)], jLo * dt * dt, jHi * dt * dt) | k <- [0 .. n - 2] ]
           -- the jerk out: (a_end − a_{N−1})/dt within [j_min, j_max], times −dt² and
           -- moved over: v_{N−1} − v_N within [j_min·dt² − a_end·dt, j_max·dt² − a_end·dt]
           ++ [ ([(n - 1, 1), (n, -1)], jLo * dt * dt - pbAEnd pb * dt, jHi * dt * dt - pbAEnd pb * dt) ]
           ++ [ ([ (k, if k == 0 || k == n then 0.5 else 1) | k <- [0 .. n] ]
                , (pbLength pb - pbTol pb - eps (pbLength pb)) / dt, (pbLength pb + pbTol pb + eps (pbLength pb)) / dt) ]
           ++ extra
    scale c (ts, l, h) = ([ (i, c * x) | (i, x) <- ts ], c * l, c * h)
    top = let m = U.maximum (pbZoneSpeeds pb) in m + eps m
    boxOf k | k == 0 = wide (pbV0 pb)
            | k == n = wide (pbVEnd pb)
            | otherwise = (negate (eps 0), maybe top (min top) (cap k))
    r = U.accum (+) (U.replicate (n + 1) 0) [ (i, yi * x) | (yi, (ts, _, _)) <- zip (U.toList y) rows, (i, x) <- ts ]
    combined = sum [ if yi > 0 then yi * h else yi * l | (yi, (_, l, h)) <- zip (U.toList y) rows ]
    least = sum [ min (rk * l) (rk * h) | (k, rk) <- zip [0 ..] (U.toList r), let (l, h) = boxOf k ]
    finiteSide (yi, (_, l, h)) = not (isInfinite l || isInfinite h) || yi == 0
    -- rounding: a few ulps of every product summed above
    margin = 1e-9 * (1 + sum [ abs yi * (max (abs l) (abs h) + sum [ abs x * top | (_, x) <- ts ]) | (yi, (ts, l, h)) <- zip (U.toList y) rows ])

-- | The problem backwards in time, written here independently of the generator's own:
-- a profile's samples reversed keep their velocities and jerks and negate their
-- accelerations; positions are measured from the route end; start and end swap. Any
-- proof that no profile exists for the mirror proves it for the problem.
mirrored :: Problem -> Problem
mirrored pb =
  let len = pbLength pb
      starts = U.toList (pbZoneStarts pb)
      ends = drop 1 starts ++ [len]
  in pb { pbZoneStarts = U.fromList (reverse [ len - e | e <- ends ])
        , pbZoneSpeeds = U.fromList (reverse (U.toList (pbZoneSpeeds pb)))
        , pbAMin = negate (pbAMax pb), pbAMax = negate (pbAMin pb)
        , pbV0 = pbVEnd pb, pbA0 = negate (pbAEnd pb), pbVEnd = pbV0 pb, pbAEnd = negate (pbA0 pb) }

-- | A result is sound when it is a legal profile or a confirmed infeasibility. The end is
-- within the tolerance up to the same rounding slack (1e-9 of the route) as every other
-- bound here: 28.19 m less 28.18 m is 0.010000000000001563 in doubles, an end exactly at
-- a 1 cm tolerance (seed 7 of the coarse-step property).
sound :: Request -> Result -> Bool
sound rq r = case (validate rq, resOutcome r, resProfile r) of
  -- legal by the product's checker (the generator's own test of done) and not illegal by the
  -- independent oracle ("Support.LegalityOracle"; borderline at rounding is the checker's call)
  (Right pb, Generated, Just p) -> null (check pb p) && oracleVerdict pb p /= SurelyIllegal
                                   && abs (finalDistance p - pbLength pb) <= pbTol pb + 1e-9 * max 1 (pbLength pb) && resConverged r
  (Right pb, Failed (InfeasibleRequest f _), _) -> case f of
    "start_velocity" -> startInfeasibleProof pb || stateGapProof pb
    "start_acceleration" -> startAccProof pb
    -- the end state seen as the start of the mirrored problem
    "end_velocity" -> startInfeasibleProof (mirrored pb) || stateGapProof pb
    "end_acceleration" -> endInfeasibleProof pb || startAccProof (mirrored pb)
    _ -> False
  _ -> False

startAccProof :: Problem -> Bool
startAccProof pb =
  let dt = pbDt pb
      accs = takeWhile (< 0) [ max (pbAMin pb) (pbA0 pb + fromIntegral k * pbJMax pb * dt) | k <- [1 :: Int ..] ]
  in pbV0 pb + dt * sum accs < 0
