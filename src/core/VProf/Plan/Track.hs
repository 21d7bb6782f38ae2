{-# LANGUAGE BangPatterns, RecordWildCards #-}
-- | The route in joint space: inverse kinematics at every sample of a fine grid along the route
-- (steps of at most 1 mm and 0.5° by default), on one continuous branch. The first sample takes
-- the given start configuration's nearest solution (or, without one, the solution nearest the
-- middle of the joint ranges; with an environment, the most dexterous that keeps the clearance);
-- every later sample the solution nearest the previous sample's (the closed forms' nearest
-- solution, or the numerical solver seeded there without restarts).
-- The tracking stops, naming the reason and the distance s, where the route leaves the
-- workspace, meets a joint limit, a singularity (smallest singular value of the Jacobian below
-- a threshold), the environment, or where the nearest solution jumps (a joint step above a
-- bound). Joint values in rad (m for prismatic joints), s in m.
module VProf.Plan.Track
  ( TrackOptions (..)
  , defaultTrackOptions
  , Environment (..)
  , StopReason (..)
  , PlanStop (..)
  , describeStop
  , Tracked (..)
  , trackedCount
  , trackedQ
  , trackedAt
  , JointPath (..)
  , jointPath
  , lagrangeWeights
  , jointPathAt
  , withJointLimits
  , stepBounds
  , trackRoute
  , smallestSingularValue
  ) where

import Data.List (minimumBy, sort, sortOn)
import Data.Ord (comparing)
import qualified Data.Vector.Unboxed as U
import Numeric (showFFloat)

import VProf.Geometry.Bvh (Bvh)
import VProf.Kinematics.Collision (Clearance (..), CollisionModel, robotClearance, robotClearanceAtLeast)
import VProf.Kinematics.Ik
import qualified VProf.Kinematics.ClosedForm as CF
import VProf.Kinematics.Forward (forward)
import VProf.Kinematics.Jacobian (jacobian, manipulability, singularValues, smallestSingularValueAbove)
import VProf.Kinematics.Model
import VProf.Kinematics.Transform (V3 (..), toRows4)
import VProf.Plan.Route

data TrackOptions = TrackOptions
  { toStepLength   :: !Double   -- ^ largest step between samples along the route (m)
  , toStepAngle    :: !Double   -- ^ largest rotation of the tool between samples (rad)
  , toMaxJointStep :: !Double   -- ^ a joint moving more than this between samples is a jump (rad or m)
  , toFineJointStep :: !Double  -- ^ a joint moving more than this between samples gets a sample between
                                --   them (rad or m), so that the joint path between samples is smooth
  , toMinSigma     :: !Double   -- ^ singular below this smallest singular value of the Jacobian
  , toEnvironment  :: !(Maybe Environment)
  }

-- | 1 mm, 0.5°, a jump above 0.25 rad (14°) between samples, samples added between two whose
-- joints move more than 0.01 rad (0.57°), singular below σ_min = 1e-3 (there a TCP speed of
-- 1 mm/s asks about 1 rad/s of some joint).
defaultTrackOptions :: TrackOptions
defaultTrackOptions = TrackOptions 1e-3 (0.5 * pi / 180) 0.25 0.01 1e-3 Nothing

-- | The scene the robot must keep clear of, with the least clearance (m).
data Environment = Environment
  { envModel     :: CollisionModel
  , envBvh       :: Bvh
  , envClearance :: !Double
  }

data StopReason
  = OutOfReach String            -- ^ the IK's explanation
  | JointLimit String JointKind Double -- ^ the joint, its kind and its limit (rad or m)
  | Singularity Double           -- ^ the smallest singular value
  | Jump String JointKind Double -- ^ the joint, its kind and its step (rad or m)
  | Collision String Double Double -- ^ the body, its clearance and the least asked (m)
  | NoSolution String            -- ^ any other IK failure
  deriving (Eq, Show)

-- | Where and why the tracking stopped: s (m) and the TCP position there (m).
data PlanStop = PlanStop
  { stopReason   :: !StopReason
  , stopS        :: !Double
  , stopPosition :: !V3
  } deriving (Eq, Show)

describeStop :: PlanStop -> String
describeStop (PlanStop r s (V3 x y z)) =
  what ++ " at s = " ++ mm s ++ " (TCP at " ++ mm x ++ ", " ++ mm y ++ ", " ++ mm z ++ ")"
  where
    mm v = showFFloat (Just 1) (v * 1000) "" ++ " mm"
    what = case r of
      OutOfReach m -> "out of reach: " ++ m
      JointLimit j k l -> "joint limit: " ++ j ++ " reaches its limit " ++ joint k l
      Singularity sv -> "singularity: the Jacobian's smallest singular value is " ++ showFFloat (Just 6) sv ""
      Jump j k d -> "jump: " ++ j ++ " would move " ++ joint k d ++ " between two samples"
      Collision b c need -> "collision: " ++ b ++ " at " ++ showFFloat (Just 2) (c * 1000) "" ++ " mm from the environment (at least "
                            ++ showFFloat (Just 2) (need * 1000) "" ++ " mm asked)"
      NoSolution m -> "no IK solution: " ++ m

-- | A joint value in the unit a person reads: degrees for a revolute joint, mm for a prismatic one.
joint :: JointKind -> Double -> String
joint Revolute x = showFFloat (Just 2) (x * 180 / pi) "°"
joint Prismatic x = showFFloat (Just 1) (x * 1000) " mm"

-- | The tracked route: the grid s_0..s_N and the joint vectors there (row k of n values).
data Tracked = Tracked
  { tkS     :: !(U.Vector Double)
  , tkQ     :: !(U.Vector Double)   -- ^ (N+1)·n, row-major
  , tkDof   :: !Int
  } deriving (Show)

trackedCount :: Tracked -> Int
trackedCount = U.length . tkS

trackedQ :: Tracked -> Int -> U.Vector Double
trackedQ t k = U.slice (k * tkDof t) (tkDof t) (tkQ t)

-- | The joint vector at s by linear interpolation between the grid's samples.
trackedAt :: Tracked -> Double -> U.Vector Double
trackedAt t s
  | s <= U.head ss = trackedQ t 0
  | s >= U.last ss = trackedQ t (U.length ss - 1)
  | otherwise =
      let k = seg 0 (U.length ss - 1)
          a = ss U.! k; b = ss U.! (k + 1)
          f = if b > a then (s - a) / (b - a) else 0
      in U.zipWith (\x y -> x + f * (y - x)) (trackedQ t k) (trackedQ t (k + 1))
  where
    ss = tkS t
    seg lo hi
      | hi - lo <= 1 = lo
      | otherwise = let m = (lo + hi) `div` 2 in if ss U.! m <= s then seg m hi else seg lo m

-- | The smooth joint path q(s) through the tracked samples: on every step the cubic Hermite
-- interpolant of the two samples with slopes dq/ds there, so q(s) is continuous with a continuous
-- slope (its second derivative only jumps, and stays bounded, at the samples). A sample's slope
-- is the derivative there of the polynomial through it and its four nearest samples (two either
-- side where there are; fewer where a stretch has fewer than five): right to O(h⁴) on steps of
-- length h, where the parabola through three samples is right to O(h²) only, and one-sided at
-- the ends to O(h), so that the cubics' second derivatives jumped by O(h) at the samples, which a
-- controller sees as the TCP's acceleration stepping. At the ends of the route and at its stops
-- (given as s, where the route may turn without a blend and the profile is at rest) the samples
-- are taken from one side only, so the path keeps its corner there.
data JointPath = JointPath
  { jpTracked :: !Tracked
  , jpLeft    :: !(U.Vector Double)   -- ^ (N+1)·n: the slope at each sample, seen from the step before it
  , jpRight   :: !(U.Vector Double)   -- ^ (N+1)·n: the slope at each sample, seen from the step after it
  , jpLo      :: !(U.Vector Double)   -- ^ n: the joint limits the curve is held within (empty: none)
  , jpHi      :: !(U.Vector Double)
  }

-- | The path held within joint limits: the tracked samples are within them, but the cubic
-- between two samples near a limit may bulge past it by a fraction of a microradian.
withJointLimits :: U.Vector Double -> U.Vector Double -> JointPath -> JointPath
withJointLimits lo hi jp = jp { jpLo = lo, jpHi = hi }

jointPath :: [Double] -> Tracked -> JointPath
jointPath stops tk = JointPath tk (slopes True) (slopes False) U.empty U.empty
  where
    ss = tkS tk
    nS = U.length ss
    n = tkDof tk
    q k i = tkQ tk U.! (k * n + i)
    -- the samples where the path may keep a corner: the ends and the stops, in order
    bounds = U.fromList (0 : marked (sort stops) 1 ++ [nS - 1 | nS > 1])
    marked xs@(x : rest) k
      | k > nS - 2 = []
      | x < ss U.! k - 1e-9 = marked rest k
      | x < ss U.! k + 1e-9 = k : marked xs (k + 1)
      | otherwise = marked xs (k + 1)
    marked [] _ = []
    -- the stretch [lo, hi] of samples a slope at k is taken from: at a stop, the one before it
    -- (seen from the step before) or after it
    stretch fromLeft k =
      let j = lastBound k  -- bounds ! j <= k < bounds ! (j + 1), or k the last sample
          atBound = bounds U.! j == k
          lo0 = if atBound then (if j > 0 then bounds U.! (j - 1) else k) else bounds U.! j
          hi0 = if j + 1 < U.length bounds then bounds U.! (j + 1) else k
      in if atBound then (if fromLeft then (lo0, k) else (k, hi0)) else (lo0, hi0)
    -- the last bound at or before sample k (bounds start at 0)
    lastBound k = go 0 (U.length bounds - 1)
      where go lo hi | lo >= hi = lo
                     | otherwise = let mid = (lo + hi + 1) `div` 2
                                   in if bounds U.! mid <= k then go mid hi else go lo (mid - 1)
    -- the samples a slope at k is taken from, with their weights: the same for every joint
    weightsAt fromLeft k =
      let (lo0, hi0) = stretch fromLeft k
          -- an end of the route seen from outside: its one stretch
          (lo, hi) = if lo0 == hi0 then stretch (not fromLeft) k else (lo0, hi0)
          first = max lo (min (k - 2) (hi - 4))
          nodes = [first .. min hi (first + 4)]
      in if nS < 2 || hi <= lo then [] else zip nodes (lagrangeWeights (map (ss U.!) nodes) (ss U.! k))
    slopes fromLeft =
      let ws = map (weightsAt fromLeft) [0 .. nS - 1]
      in U.concat [ U.generate n (\i -> sum [ c * q j i | (j, c) <- w ]) | w <- ws ]

-- | The weights of the derivative at x of the polynomial through points at the distinct xs (x
-- one of them): the slope there is Σ_j w_j·y_j, w_j = ℓ_j'(x) for the Lagrange basis ℓ_j.
lagrangeWeights :: [Double] -> Double -> [Double]
lagrangeWeights xs x = map basis (zip [0 :: Int ..] xs)
  where
    others j = [ xm | (m, xm) <- zip [0 ..] xs, m /= j ]
    basis (j, xj)
      | xj == x = sum [ 1 / (x - xm) | xm <- others j ]
      | otherwise = product [ x - xm | xm <- others j, xm /= x ] / product [ xj - xm | xm <- others j ]

-- | The joint vector at s on the smooth path.
jointPathAt :: JointPath -> Double -> U.Vector Double
jointPathAt (JointPath t ml mr lo hi) s
  | s <= U.head ss = trackedQ t 0
  | s >= U.last ss = trackedQ t (U.length ss - 1)
  | otherwise =
      let k = seg 0 (U.length ss - 1)
          a = ss U.! k; b = ss U.! (k + 1)
          hk = b - a
          u = if hk > 0 then (s - a) / hk else 0
          h00 = (2 * u - 3) * u * u + 1
          h10 = ((u - 2) * u + 1) * u
          h01 = (3 - 2 * u) * u * u
          h11 = (u - 1) * u * u
      in U.generate n $ \i ->
           within i (h00 * q k i + h10 * hk * mr U.! (k * n + i) + h01 * q (k + 1) i + h11 * hk * ml U.! ((k + 1) * n + i))
  where
    within i x
      | U.null lo = x
      | otherwise = max (lo U.! i) (min (hi U.! i) x)
    ss = tkS t
    n = tkDof t
    q k i = tkQ t U.! (k * n + i)
    seg lo hi
      | hi - lo <= 1 = lo
      | otherwise = let m = (lo + hi) `div` 2 in if ss U.! m <= s then seg m hi else seg lo m

-- | On step k (0 ≤ k < N), joint i: the largest |dq/ds| and the largest |d²q/ds²| of the cubic,
-- exactly (its second derivative is linear on the step, its slope a parabola).
stepBounds :: JointPath -> Int -> Int -> (Double, Double)
stepBounds (JointPath t ml mr _ _) k i
  | hk <= 0 = (0, 0)
  | otherwise = (maximum (abs m0 : abs m1 : vertex), max (abs c0) (abs c1))
  where
    ss = tkS t
    n = tkDof t
    hk = ss U.! (k + 1) - ss U.! k
    dlt = (tkQ t U.! ((k + 1) * n + i) - tkQ t U.! (k * n + i)) / hk
    m0 = mr U.! (k * n + i)
    m1 = ml U.! ((k + 1) * n + i)
    c0 = (6 * dlt - 4 * m0 - 2 * m1) / hk
    c1 = (2 * m0 + 4 * m1 - 6 * dlt) / hk
    -- the slope's extremum where the second derivative crosses zero inside the step
    vertex = [ m0 + 0.5 * c0 * u | c0 * c1 < 0, let u = hk * c0 / (c0 - c1) ]

smallestSingularValue :: Chain -> U.Vector Double -> Double
smallestSingularValue ch q = case singularValues (chainDof ch) (snd (jacobian ch q)) of
  [] -> 0
  svs -> minimum svs

-- | Track the route from the start configuration (or mid-limits).
trackRoute :: TrackOptions -> Kinematics -> Route -> Maybe (U.Vector Double) -> Either PlanStop Tracked
trackRoute TrackOptions{..} kin rt start = do
  q0 <- solveAt 0 (pickStart <$> solveIk defaultIkOptions kin (routeTfAt rt 0) start) Nothing Nothing
  checkAt 0 q0
  go 0 q0 Nothing [q0] [0] (drop 1 (U.toList grid))
  where
    ch = kinChain kin
    n = chainDof ch
    joints = robotJoints (chainRobot ch)
    grid = routeGrid toStepLength toStepAngle rt
    -- the shortest step the tracking halves down to
    minFineStep = 1e-6
    contOpts = defaultIkOptions { ikMaxRestarts = 0 }
    posAt s = fst (routeAt rt s)
    stop :: Double -> StopReason -> Either PlanStop a
    stop s r = Left (PlanStop r s (posAt s))

    -- without a start configuration: the solution nearest the middle of the joint ranges, each
    -- joint's distance in halves of its range (a turn for an unbounded joint); with an
    -- environment, of the solutions that keep the clearance the most dexterous (largest
    -- manipulability), as robot selection picks a first target's, the nearest mid-limits among
    -- equals (whole turns apart)
    pickStart sols = case start of
      Just _ -> sols
      Nothing -> take 1 (sortOn (\sol -> (startRank (solJoints sol), U.sum (U.imap normSq (solJoints sol)))) sols)
    startRank q = case toEnvironment of
      Nothing -> (False, 0)
      Just Environment{..} ->
        ( not (robotClearanceAtLeast envModel envBvh q envClearance)
        , negate (fromIntegral (round (1e9 * manipulability n (snd (jacobian ch q))) :: Integer) :: Double) )
    normSq i x =
      let lo = chainLo ch U.! i; hi = chainHi ch U.! i
          (mid, half) = if isInfinite lo || isInfinite hi then (0, pi) else (0.5 * (lo + hi), 0.5 * (hi - lo))
          d = (x - mid) / max 1e-9 half
      in d * d

    -- every grid sample in turn, and between two whose joints move more than toFineJointStep
    -- (near a singularity the wrists turn fast) the sample halfway, down to 'minFineStep'
    go !sPrev prev trend qs ss pending = case pending of
      [] -> Right (Tracked (U.fromList (reverse ss)) (U.concat (reverse qs)) n)
      s : rest -> do
        q <- solveAt s (continueIk (routeTfAt rt s) prev) (Just prev) trend
        let steps = U.zipWith (\a b -> abs (a - b)) q prev
            j = U.maxIndex steps
        if steps U.! j > toMaxJointStep
          then stop s (maybe (Jump (jointName (joints !! j)) (jointKind (joints !! j)) (steps U.! j)) (\(nm, kd, l) -> JointLimit nm kd l) (nearLimit prev trend))
          else if steps U.! j > toFineJointStep && s - sPrev > minFineStep
            then go sPrev prev trend qs ss (0.5 * (sPrev + s) : s : rest)
            else do
              checkAt s q
              go s q (Just (U.zipWith (-) q prev)) (q : qs) (s : ss) rest

    -- the solution nearest the previous sample's: for the six-axis closed forms, each branch's
    -- principal solution with every joint turned by whole turns to lie nearest the previous
    -- value (within the limits), nearest first, checked by forward kinematics (lazily: the
    -- tracking takes the first that passes, so usually one check a sample instead of eight);
    -- else the facade, seeded
    continueIk target prev = case kinMethod kin of
      ClosedFormSixAxis solver
        | Just pose <- CF.poseFromRowMajor (toRows4 target)
        , Right principal <- CF.solvePrincipal solver pose
        , sols@(_ : _) <- [ IkSolution q pe re d Nothing
                          | (d, q) <- sortOn fst [ (seedDistance q prev, q) | p <- principal
                                                 , Just q <- [nearestTurns prev (CF.solQ p)] ]
                          , let (pe, re) = residual (forward ch q) target
                          , pe <= ikTolPosition defaultIkOptions, re <= ikTolRotation defaultIkOptions ]
        -> Right sols
      -- to 1e-10 m and rad where the solver gets there (its default 1e-6 leaves samples up to
      -- a micrometre off the route, noise the TCP's jerk shows), else to the default
      _ -> case solveIk contOpts { ikTolPosition = 1e-10, ikTolRotation = 1e-10 } kin target (Just prev) of
             r@(Right (_ : _)) -> r
             _ -> solveIk contOpts kin target (Just prev)
    nearestTurns prev q = fmap U.fromList $ sequence $ flip map [0 .. n - 1] $ \i ->
      let x = q U.! i; p = prev U.! i
          lo = chainLo ch U.! i; hi = chainHi ch U.! i
          y = x + 2 * pi * fromIntegral (round ((p - x) / (2 * pi)) :: Int)
          cands = [ c | c <- [y, y - 2 * pi, y + 2 * pi], c >= lo - 1e-12, c <= hi + 1e-12 ]
      in if null cands then Nothing else Just (max lo (min hi (minimumBy (comparing (\c -> abs (c - p))) cands)))

    -- the solution nearest the seed, or the reason there is none
    solveAt s res prev trend = case res of
      Right (sol : _) -> Right (solJoints sol)
      Right [] -> stop s (NoSolution "no solution within the joint limits")
      Left f -> case f of
        BeyondReach {} -> stop s (OutOfReach (describeFailure f))
        InsideReach {} -> stop s (OutOfReach (describeFailure f))
        Unreachable {} -> stop s (OutOfReach (describeFailure f))
        OutsideLimits sols -> case [ (nm, kd, l) | (nm, by) : _ <- sols, let (kd, l) = limitOf nm by ] of
          ((nm, kd, l) : _) -> stop s (JointLimit nm kd l)
          [] -> stop s (NoSolution (describeFailure f))
        _ -> case prev >>= \p -> nearLimit p trend of
          Just (nm, kd, l) -> stop s (JointLimit nm kd l)
          Nothing
            | Just p <- prev, smallestSingularValue ch p < 10 * toMinSigma -> stop s (Singularity (smallestSingularValue ch p))
            | otherwise -> stop s (NoSolution (describeFailure f))

    limitOf nm by = case [ jt | jt <- joints, jointName jt == nm ] of
      (jt : _) -> let Limits lo hi = jointLimits jt in (jointKind jt, if by < 0 then lo else hi)
      [] -> (Revolute, 0)

    -- a joint within one jump bound of a finite limit and moving toward it (by the last step's
    -- direction): the one nearest its limit
    nearLimit q trend =
      let toward i dirSign = case trend of
            Nothing -> True
            Just t -> signum (t U.! i) == dirSign
          cands = [ (d, (jointName jt, jointKind jt, l))
                  | (i, jt) <- zip [0 ..] joints
                  , let x = q U.! i; Limits lo hi = jointLimits jt
                  , (l, d, sg) <- [(lo, x - lo, -1), (hi, hi - x, 1)]
                  , not (isInfinite l), d <= toMaxJointStep, toward i sg ]
      in if null cands then Nothing else Just (snd (minimumBy (comparing fst) cands))

    -- singular below toMinSigma (the Cholesky test of "VProf.Kinematics.Jacobian"; the SVD only
    -- to report the value), then the clearance
    checkAt s q = do
      if smallestSingularValueAbove n (snd (jacobian ch q)) toMinSigma then Right ()
        else let sg = smallestSingularValue ch q in if sg < toMinSigma then stop s (Singularity sg) else Right ()
      case toEnvironment of
        Nothing -> Right ()
        Just Environment{..}
          | robotClearanceAtLeast envModel envBvh q envClearance -> Right ()
          | otherwise -> case robotClearance envModel envBvh q of
              Just c -> stop s (Collision (clrBodyName c) (clrDistance c) envClearance)
              Nothing -> Right ()
