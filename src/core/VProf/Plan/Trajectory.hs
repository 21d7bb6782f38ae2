{-# LANGUAGE RecordWildCards #-}
-- | The plan, end to end: the route through the waypoints ("VProf.Plan.Route"), tracked in joint
-- space ("VProf.Plan.Track"), its speed limits as zones ("VProf.Plan.Limits"), and the timing by
-- the velocity-profile generator: one profile request per part of the route (the stretches
-- between stops, some cut at their slow corners, and parts cut again where their profiles
-- cruise), with the TCP's jerk range at the controller's
-- time step and an acceleration range chosen per part: by the joints' acceleration rule, then
-- faster variants admitted only by the check of the sampled joint motion ('jointsKeepLimits'):
-- boosts, braking and speeding up raised apart, zones flattened where the joints turn fast and
-- lifted where the rule is too strict (docs/plan.md, section 3). The generator's samples s(t) give the joint values q(t) on the smooth
-- joint path through the tracked samples (cubic Hermite, 'jointPathAt'; 1 mm apart by default)
-- and the joint speeds by central differences in time. Request and result are plain records, SI
-- inside and units at the boundary, so that a wire layer can convert them.
module VProf.Plan.Trajectory
  ( PlanRequest (..)
  , planRequest
  , defaultTimeStep
  , defaultAcceleration
  , defaultJerk
  , defaultEndTolerance
  , defaultPlanBudget
  , Trajectory (..)
  , trajectoryCount
  , trajectoryQ
  , trajectoryQd
  , Plan (..)
  , planDuration
  , planZoneList
  , PlanFailure (..)
  , describePlanFailure
  , planPath
  , limitOptionsFor
  ) where

import Data.List (group, sort)
import GHC.Conc (par)
import Numeric (showGFloat)
import qualified Data.Vector as V
import qualified Data.Vector.Unboxed as U

import VProf.Kinematics.Ik (kinematicsFor)
import VProf.Kinematics.Ik.Numeric (reachBound, refineOnto)
import VProf.Kinematics.Transform (V3 (..), v3Norm, v3Sub)
import qualified Linear as L
import VProf.Kinematics.Model
import VProf.Plan.Limits
import VProf.Plan.Route
import VProf.Plan.Track
import VProf.Profile (Request (..), Result (..), SpeedZone (..), Outcome (..), defaultRequest, generatePure, resultLegal, renderFailure)
import VProf.Profile.Request (leastStepLimit, maxSamples)
import VProf.Profile.Sampled (Columns (..), columns, duration, trapezoidDistances)
import VProf.Profile.Legality (slack)
import VProf.Units
import VProf.Validation

data PlanRequest = PlanRequest
  { prWaypoints    :: ![Waypoint]
  , prZone         :: !Zone                    -- ^ every corner's zone
  , prRobot        :: !Robot                   -- ^ with its base and tool
  , prStart        :: !(Maybe (U.Vector Double)) -- ^ start configuration (rad, m); default: nearest mid-limits
  , prSpeed        :: !(Velocity Double)       -- ^ the TCP speed limit
  , prAcceleration :: !(Acceleration Double)   -- ^ the TCP acceleration range ±a
  , prJerk         :: !(Jerk Double)           -- ^ the TCP jerk range ±j
  , prTimeStep     :: !(Time Double)           -- ^ the controller's time step
  , prEndTolerance :: !(Length Double)         -- ^ how close each stretch's profile ends to its end
  , prTrack        :: !TrackOptions
  }

-- | 4 ms, the interpolation period of common robot controllers.
defaultTimeStep :: Double
defaultTimeStep = 0.004

defaultAcceleration, defaultJerk, defaultEndTolerance :: Double
defaultAcceleration = 2     -- m/s²
defaultJerk = 20            -- m/s³
defaultEndTolerance = 1e-6  -- m: the parts of a stretch cut at its corners meet at a speed, and
                            -- their stretch factors, so the speeds where they meet, agree to
                            -- about this over the part's length

-- | Seconds a plan may take without a budget of its own (@vprof plan@ without @--time-budget@,
-- a 'PlanRequest' with @time_budget@ 0): the same on the command line and in the daemon, so
-- that both answer alike. A long route takes seconds (the README's 9 m recording about 9 s at
-- the defaults on a 2-core VM), a 0.6 m square at a time step of 0.25 ms about 45 s.
defaultPlanBudget :: Double
defaultPlanBudget = 60

-- | A request with the defaults: v500 (500 mm/s), z10 (10 mm), 2 m/s², 20 m/s³, 4 ms.
planRequest :: Robot -> [Waypoint] -> PlanRequest
planRequest r wps = PlanRequest
  { prWaypoints = wps, prZone = Blend (0.01 *~ meter), prRobot = r, prStart = Nothing
  , prSpeed = 0.5 *~ mps, prAcceleration = defaultAcceleration *~ mps2, prJerk = defaultJerk *~ mps3
  , prTimeStep = defaultTimeStep *~ second, prEndTolerance = defaultEndTolerance *~ meter
  , prTrack = defaultTrackOptions }

-- | The timed joint trajectory: per sample the profile's t, s, v, a, j and the joint values and
-- speeds (rows of n, row-major).
data Trajectory = Trajectory
  { trTime, trS, trV, trA, trJ :: !(U.Vector Double)
  , trQ   :: !(U.Vector Double)
  , trQd  :: !(U.Vector Double)
  , trDof :: !Int
  } deriving (Show)

trajectoryCount :: Trajectory -> Int
trajectoryCount = U.length . trTime

trajectoryQ, trajectoryQd :: Trajectory -> Int -> U.Vector Double
trajectoryQ t k = U.slice (k * trDof t) (trDof t) (trQ t)
trajectoryQd t k = U.slice (k * trDof t) (trDof t) (trQd t)

data Plan = Plan
  { planRoute      :: !Route
  , planTracked    :: !Tracked
  , planSteps      :: !StepLimits
  , planStretches  :: ![(Double, Double)]   -- ^ the parts [a, b] timed one by one (m): the
                                             --   stretches between stops, some cut at slow corners
  , planZones      :: ![[LimitZone]]         -- ^ per part, in route coordinates
  , planPartMaps   :: ![(Double, Double, Double)]
                                             -- ^ per part (a, a', k): a route distance x of the
                                             --   part [a, b] is at a' + k·(x − a) in the
                                             --   trajectory's distances (the parts joined and
                                             --   scaled between rests: 'assemble')
  , planAccelerations :: ![(Double, Double)] -- ^ per part, the TCP acceleration range used: the
                                             --   braking and the speeding-up magnitude (m/s²)
  , planProfiles   :: ![Result]              -- ^ per part
  , planTrajectory :: !Trajectory
  , planLegal      :: !Bool                  -- ^ every part's profile legal by the checker
  , planOnRoute    :: !Bool                  -- ^ the trajectory's joint values projected onto the
                                             --   route (its TCP there to rounding); False: the
                                             --   joint path's own, whose TCP is off the route by
                                             --   its interpolation error (projected, they broke
                                             --   a joint's speed or acceleration limit)
  }

planDuration :: Plan -> Double
planDuration p = let t = trTime (planTrajectory p) in if U.null t then 0 else U.last t

-- | The speed limit along the whole route, the parts' zones in turn, without gaps: a join
-- moved a step ('timeParts') leaves the sliver [u, u + v·dt] (or [u − v·dt, u]) to neither
-- part; the motion crosses it at the join's speed v, which the zones either side both allow,
-- and the lower of them is stretched over it.
planZoneList :: Plan -> [LimitZone]
planZoneList p = go (zipWith mapped (planPartMaps p) (planZones p))
  where
    -- the part's zones where its samples are ('planPartMaps')
    mapped (a, a', k) zs = [ z { lzStart = a' + k * (lzStart z - a), lzEnd = a' + k * (lzEnd z - a) } | z <- zs ]
    go (zs0@(_ : _) : zs1@(z1 : more) : rest)
      | lzStart z1 - lzEnd z0 > 1e-9 =
          if lzSpeed z0 <= lzSpeed z1
            then init zs0 ++ z0 { lzEnd = lzStart z1 } : go (zs1 : rest)
            else zs0 ++ go ((z1 { lzStart = lzEnd z0 } : more) : rest)
      where z0 = last zs0
    go (zs : rest) = zs ++ go rest
    go [] = []

data PlanFailure
  = InvalidPlan [FieldError]
  | Stopped PlanStop
  | ProfileFailed Int (Double, Double) String   -- ^ stretch, its [a, b] (m), the generator's failure

describePlanFailure :: PlanFailure -> String
describePlanFailure = \case
  InvalidPlan es -> unlines (map renderFieldError es)
  Stopped st -> "the plan stops: " ++ describeStop st
  ProfileFailed i (a, b) m -> "no legal profile for stretch " ++ show i ++ " (s from " ++ showNumber a ++ " to "
                              ++ showNumber b ++ " m): " ++ m

-- | The limits of a robot: its joints' speeds and accelerations ('defaultJointAcceleration').
limitOptionsFor :: PlanRequest -> LimitOptions
limitOptionsFor PlanRequest{..} = LimitOptions
  { loTcpSpeed = si prSpeed
  , loTcpAcceleration = si prAcceleration
  , loJointSpeed = U.fromList [ maybe (1 / 0) id (jointMaxVelocity j) | j <- robotJoints prRobot ]
  , loJointAcceleration = U.fromList (map defaultJointAcceleration (robotJoints prRobot))
  }

-- | The stretch accelerations tried, as fractions of the joints' ceiling ('tangentialCeiling'):
-- a larger one accelerates harder on the straights and leaves less of the joints' acceleration
-- for the corners. The search starts at 'startFraction'.
accelerationFractions :: [Double]
accelerationFractions = [0.2, 0.35, 0.5, 0.65, 0.8, 0.9, 0.95]

-- | The boost phase: accelerations beyond the rule's, as fractions of the ceiling, and the
-- share of the acceleration the corner zones assume.
boostFractions, boostBetas :: [Double]
boostFractions = [1, 1.25, 1.5, 2, 2.5, 3]
boostBetas = [0, 0.5]

startFraction :: Int
startFraction = 4

-- | What a part's request keeps below the plan's speeds, acceleration and jerk: the scale of
-- the joined parts ('assemble') is at most 1 / (1 − 1e-5), each part ending within 1e-5 of
-- its length.
partMargin :: Double
partMargin = 1 - 1e-5

-- | The factor that stretches a profile's columns (distance, speed, acceleration, jerk) for a
-- part of length l to end exactly on l (the generator ends within its end tolerance of it).
stretchFactor :: Double -> Columns -> Double
stretchFactor l c =
  let e = if U.null (colDistance c) then 0 else U.last (colDistance c)
  in if e > 0 then l / e else 1

-- | The distance along the route of a profile's samples for the part [a, b]: its own distance
-- stretched to end exactly on b.
stretchedS :: Double -> Double -> Columns -> U.Vector Double
stretchedS a b c = let f = stretchFactor (b - a) c in U.map (\x -> a + f * x) (colDistance c)

-- | The sampled joint motion at the route distances ss (one every dt) keeps the joints' limits:
-- joint speeds by forward differences within q̇max_i, joint accelerations by second differences
-- within q̈max_i; with rest ends, the one-sided second difference at each end within q̈max_i / 2,
-- so that the difference across the junction with the next stretch (their sum) keeps the limit.
jointsKeepLimits :: LimitOptions -> JointPath -> Double -> Bool -> U.Vector Double -> Bool
jointsKeepLimits lo jp dt restEnds ss = null (jointViolations lo jp dt restEnds ss)

-- | The samples (indices into ss) at which the sampled joint motion breaks a limit as
-- 'jointsKeepLimits' measures it, in order (lazy: the first costs only the samples before it).
jointViolations :: LimitOptions -> JointPath -> Double -> Bool -> U.Vector Double -> [Int]
jointViolations lo jp dt restEnds ss = sampledViolations lo dt restEnds (U.length ss) (tkDof (jpTracked jp)) (\k i -> qs V.! k U.! i)
  where qs = V.generate (U.length ss) (\k -> jointPathAt jp (ss U.! k))

-- | 'jointViolations' of m samples of n joint values each, given as q k i.
sampledViolations :: LimitOptions -> Double -> Bool -> Int -> Int -> (Int -> Int -> Double) -> [Int]
sampledViolations LimitOptions{..} dt restEnds m n q
  | m < 2 = []
  | otherwise = [ k | k <- [0 .. m - 1], not (speedOk k && accOk k && endsOk k) ]
  where
    speedOk k = k > m - 2 || and [ abs (q (k + 1) i - q k i) <= loJointSpeed U.! i * dt | i <- [0 .. n - 1] ]
    accOk k = k < 1 || k > m - 2 || and [ abs (q (k + 1) i - 2 * q k i + q (k - 1) i) <= loJointAcceleration U.! i * dt * dt | i <- [0 .. n - 1] ]
    endsOk k
      | not restEnds = True
      | k == 0 = endOk 0 1
      | k == m - 1 = endOk (m - 1) (m - 2)
      | otherwise = True
    endOk k k' = and [ abs (q k' i - q k i) <= 0.5 * loJointAcceleration U.! i * dt * dt | i <- [0 .. n - 1] ]

-- | The zones with the speed on [x0, x1] capped at v (zones split at x0 and x1 where needed):
-- speeds only go down.
capZones :: Double -> Double -> Double -> [LimitZone] -> [LimitZone]
capZones x0 x1 v = concatMap cap
  where
    cap z
      | lzEnd z <= x0 || lzStart z >= x1 || lzSpeed z <= v = [z]
      | otherwise = filter (\w -> lzEnd w > lzStart w)
          [ z { lzEnd = max (lzStart z) x0 }
          , z { lzStart = max (lzStart z) x0, lzEnd = min (lzEnd z) x1, lzSpeed = v }
          , z { lzStart = min (lzEnd z) x1 } ]

-- | The list, with f of every element sparked for parallel evaluation (the parts and stretches
-- of a plan are timed independently of each other).
sparkEach :: (a -> Double) -> [a] -> [a]
sparkEach f xs = foldr (\x r -> f x `par` r) xs xs

-- | Sorted, without repeats.
nubSorted :: [Double] -> [Double]
nubSorted xs = map head (group (sort xs))

-- | Descend along the ladder from 'startFraction' while the next rung is strictly faster (the
-- duration is close to unimodal in the fraction: about three profiles a stretch instead of
-- seven); the fastest rung seen wins. Durations are looked at through @timeOf@ (infinite for an
-- illegal profile), so a stretch with no legal profile keeps the start rung and its failure.
descend :: (a -> Double) -> [a] -> a
descend timeOf xs = xs !! descendIndex timeOf xs

descendIndex :: (a -> Double) -> [a] -> Int
descendIndex timeOf xs = go (min startFraction (n - 1))
  where
    n = length xs
    t i = timeOf (xs !! i)
    -- the next rungs either way are sparked while this one is computed (with -N, on another core)
    ahead js r = foldr (\j acc -> if j >= 0 && j < n then t j `par` acc else acc) r js
    go i = ahead [i + 1, i - 1] $
      if i + 1 < n && t (i + 1) < t i then up (i + 1)
      else if i > 0 && t (i - 1) < t i then down (i - 1)
      else i
    up i = ahead [i + 1] (if i + 1 < n && t (i + 1) < t i then up (i + 1) else i)
    down i = ahead [i - 1] (if i > 0 && t (i - 1) < t i then down (i - 1) else i)

-- | The fastest admitted rung found by 'descend' with the rungs @ok@ refuses counted as
-- infinitely slow (the climb stops at the first refused rung: a higher acceleration seldom
-- makes the joints' motion gentler); when the start rung and its neighbours are all refused,
-- the first rung below it that @ok@ admits (a lower acceleration), else the start rung.
descendAdmitted :: (a -> Double) -> (a -> Bool) -> [a] -> a
descendAdmitted timeOf ok xs =
  let i = descendIndex (\x -> if ok x then timeOf x else 1 / 0) xs
  in head ([ x | x <- reverse (take (i + 1) xs), ok x ] ++ [xs !! i])

validateRequest :: PlanRequest -> [FieldError]
validateRequest PlanRequest{..} = concat
  [ positive "speed" (si prSpeed) "m/s"
  , positive "acceleration" (si prAcceleration) "m/s²" `orElse` weak "acceleration" (si prAcceleration) "m/s²" "dt" 1
  , positive "jerk" (si prJerk) "m/s³" `orElse` weak "jerk" (si prJerk) "m/s³" "dt²" 2
  , ensureFinite "dt" dt "s" $ ensure (dt >= minTimeStep && dt <= maxTimeStep) (fieldError "dt" dt "s" timeStepRule)
  , positive "end_tolerance" (si prEndTolerance) "m"
  , case prStart of
      Nothing -> []
      Just q | not (U.length q == dof prRobot && U.all finite q) ->
                 [literalError "start" (show (U.toList q))
                    ("must be " ++ show (dof prRobot) ++ " finite joint values for " ++ robotName prRobot)]
             -- a start outside a joint's range is no configuration of the robot (and radians
             -- given as degrees, 90 for 90°, would silently pick another branch)
             | otherwise -> concat [ outside i j x | (i, j, x) <- zip3 [0 :: Int ..] (robotJoints prRobot) (U.toList q) ]
  , ensure (dof prRobot > 0) (literalError "robot" (robotName prRobot) "has no joints")
  ]
  where
    dt = si prTimeStep
    positive f x u = ensureFinite f x u (ensure (x > 0) (fieldError f x u "must be > 0"))
    orElse es more = if null es then more else es
    sig v = showGFloat (Just 2) v ""
    -- a range whose step changes the speed by no more than the checker's resolution would
    -- be refused by the generator for every stretch, under its own field names; the
    -- stretches run at fractions of the acceleration down to a fifth ('accelerationFractions'):
    -- 'planResolutionMargin' times the generator's least
    weak f x u by order
      | finite dt && dt >= minTimeStep && dt <= maxTimeStep && x <= planResolutionMargin * leastStepLimit order dt =
          [fieldError f x u ("is too weak for dt " ++ showNumber dt ++ " s: a step at it would change the speed by "
                              ++ sig (x * dt ^ order) ++ " m/s (" ++ f ++ "·" ++ by ++ "); it must be above "
                              ++ sig (planResolutionMargin * leastStepLimit order dt) ++ " " ++ u ++ " at this dt")]
      | otherwise = []
    outside i j x =
      let Limits lo hi = jointLimits j
          slack = 1e-9 * max 1 (abs x)
          rev = jointKind j == Revolute
          -- rounded for reading, but a huge value as it is (rounding 1e308 overflowed to Infinity)
          rounded k v = if abs v < 1e9 then showNumber (fromIntegral (round (v * k) :: Integer) / k) else showNumber v
          deg v = rounded 1000 (v * 180 / pi)
          shown v = rounded 1e6 v ++ (if rev then " rad (" ++ deg v ++ "°)" else " m")
      in ensure (x >= lo - slack && x <= hi + slack)
           (literalError ("start[" ++ show i ++ "]") (shown x)
              ("joint " ++ jointName j ++ " is outside its limits " ++ shown lo ++ " to " ++ shown hi))

-- | How many times the generator's least acceleration and jerk (a step at them changes the
-- speed by more than 'speedResolution') a plan's ranges must be: its stretches run at
-- fractions of the acceleration down to a fifth, each scaled to its part's length.
planResolutionMargin :: Double
planResolutionMargin = 10

planPath :: PlanRequest -> Either PlanFailure Plan
planPath rq@PlanRequest{..} = do
  route <- either (Left . InvalidPlan . (validateRequest rq ++)) Right
             (mkRoute (map (const prZone) prWaypoints) prWaypoints)
  case validateRequest rq of
    [] -> Right ()
    es -> Left (InvalidPlan es)
  -- each stretch between stops is one profile, which holds at most maxSamples samples: at the
  -- speed asked for, the longest one must fit (else the generator's refusal would name its own
  -- route_length and time_step, not the plan's speed)
  let stops = 0 : rtStops route ++ [rtLength route]
      longest = maximum (zipWith (-) (drop 1 stops) stops)
      least = longest / si prSpeed / si prTimeStep
      -- a waypoint beyond the arm's reach makes such a stretch more often than a slow speed:
      -- the first is named (a waypoint 1000 km away was blamed on the speed alone)
      (shoulder, reach) = reachBound (compile prRobot)
      beyond = [ (k, d) | (k, w) <- zip [0 :: Int ..] prWaypoints
                        , let L.V3 x y z = fmap si (wpPosition w); d = v3Norm (v3Sub (V3 x y z) shoulder), d > reach + 1e-9 ]
      misplaced = case beyond of
        (k, d) : _ -> "; waypoint " ++ show k ++ " is " ++ showNumber (roundSignificantTo 6 d) ++ " m from the robot's shoulder, beyond its reach of "
                      ++ showNumber (roundSignificantTo 6 reach) ++ " m: is it misplaced, or in another unit?"
        [] -> ""
  if least > fromIntegral maxSamples
    then Left (InvalidPlan [fieldError "speed" (si prSpeed) "m/s"
                 ("is too slow for this path: its longest stretch between stops, " ++ showNumber longest ++ " m, would take at least "
                  ++ (if least < 1e15 then show (ceiling least :: Integer) else showNumber least) ++ " samples at dt " ++ showNumber (si prTimeStep)
                  ++ " s, above the cap of " ++ show maxSamples ++ " samples of one profile; raise the speed or dt" ++ misplaced)])
    else Right ()
  tracked <- either (Left . Stopped) Right (trackRoute prTrack (kinematicsFor prRobot) route prStart)
  let lo = limitOptionsFor rq
      ch = compile prRobot
      jp = withJointLimits (chainLo ch) (chainHi ch) (jointPath (rtStops route) tracked)
      pb = pathBounds jp
      cuts = 0 : rtStops route ++ [rtLength route]
      top = si prSpeed
      grid = tkS tracked
      -- a part [a, b] of the route from speed va to speed vb (m/s; the acceleration 0 at both):
      -- the profile at each acceleration of the ladder (computed when looked at), its zones by
      -- the rule (safe by construction)
      tries (a, b) va vb =
        let ceil' = tangentialCeiling lo pb a b
        in [ candidate (a, b) va vb acc acc | f <- accelerationFractions, let acc = min (si prAcceleration) (f * ceil') ]
      sym acc = (acc, acc)
      -- the profile at acceleration A whose corner zones assume the acceleration ac ≤ A there
      candidate (a, b) va vb acc ac =
        let st = stepLimitsAt lo route pb ac a b in timed (a, b) va vb (sym acc) st (limitZones top st a b)
      -- the profile of a part at the acceleration range (braking, speeding up) under the zones zs
      -- (of its steps st)
      timed (a, b) va vb acc st zs = ((a, b), acc, st, zs, endingWithin a b (\tol -> generatePure (profileRequest tol a b acc zs va vb)))
      timeOf (_, _, _, _, r) = if resultLegal r then maybe (1 / 0) duration (resProfile r) else 1 / 0
      samplesOf ((a, b), _, _, _, r) = maybe U.empty (stretchedS a b . columns) (resProfile r)
      -- a candidate's duration when its sampled joint motion keeps the limits ('jointsKeepLimits'),
      -- else infinite
      score restEnds c = if timeOf c < 1 / 0 && jointsKeepLimits lo jp dt restEnds (samplesOf c) then timeOf c else 1 / 0
      -- from the rule's choice, faster ones that only the joints' own check admits: corner zones
      -- that assume less acceleration there (β·A, β = 0 then 0.5), and more acceleration on the
      -- way (up the boost ladder while each rung is faster and admitted)
      boost restEnds va vb safe@((a, b), acc0, _, _, _) =
        let ceil' = tangentialCeiling lo pb a b
            ladder = snd acc0 : [ acc | f <- boostFractions, let acc = min (si prAcceleration) (f * ceil'), acc > snd acc0 ]
            -- up the ladder while each rung keeps the limits and is strictly faster
            climb beta (best, t) (acc : rest) =
              let c = candidate (a, b) va vb acc (beta * acc)
              in if timeOf c < t && score restEnds c < 1 / 0 then climb beta (c, timeOf c) rest else (best, t)
            climb _ bt [] = bt
        in fst (foldl (\bt beta -> climb beta bt ladder) (safe, timeOf safe) boostBetas)
      -- a stretch between stops, timed whole; or cut at its slow corners (under half the
      -- stretch's fastest zone), so that every part between two such corners takes its own
      -- acceleration, when that is faster and the joined parts keep the joints' limits. A corner
      -- is cut in the middle of its blend, or (tried too) at its slowest step, within the blend
      -- and a blend's length either side, where the orientation turns. The parts' corner zones
      -- assume no acceleration there (so they do not depend on the part's acceleration, and
      -- neither does the speed at a cut: the lower of the two parts' zones there); each part's
      -- acceleration is the fastest on the ladder whose joint motion keeps the limits
      planStretch (a, b) =
        let boosted = boost True 0 0 (descend timeOf (tries (a, b) 0 0))
            whole = let ((x, y), _, _, _, _) = boosted
                    in if score True boosted < 1 / 0
                         then refine ((< 1 / 0) . score True) (timed (x, y) 0 0) (accelerationCap (x, y)) boosted
                         else boosted
            (_, _, _, zs0, _) = whole
            fastest = if null zs0 then 0 else maximum (map lzSpeed zs0)
            slow c = minimum (fastest : [ lzSpeed z | z <- zs0, lzStart z <= c, c <= lzEnd z ]) < 0.5 * fastest
            arcs = [ pc | pc <- V.toList (rtPieces route), pcKind pc == Arc ]
            middles = [ c | pc <- arcs, Just c <- [nearestSample (pcStart pc + 0.5 * pcLength pc) a b], slow c ]
            slowest = [ c | pc <- arcs
                          , let x0 = max a (pcStart pc - pcLength pc); x1 = min b (pcStart pc + 2 * pcLength pc)
                          , x1 > x0
                          , let st = stepLimitsAt lo route pb 0 x0 x1
                          , not (U.null (slLimit st))
                          , Just c <- [nearestSample (slS st U.! U.minIndex (slLimit st)) a b], slow c ]
            -- the part bounds of [x, y] for a list of cuts: those at least minPartLength after the
            -- previous one and before y (on a shorter part the profile's margin for its end
            -- tolerance, 1 µm over the part's length, would show as a step in speed where it meets
            -- its neighbours)
            boundsIn x y cuts = x : spaced (filter (<= y - minPartLength) (nubSorted cuts)) ++ [y]
              where
                spaced = go x
                go _ [] = []
                go prev (c : cs) = if c - prev >= minPartLength then c : go c cs else go prev cs
            boundsFor = boundsIn a b
            -- the parts between the bounds, each timed ('part') from and to the speed at its cuts:
            -- the lower of the two parts' zones there and of @cap@ at the cut; vx and vy at the ends.
            -- Also whether every part has zones.
            --
            -- Each part's profile assumes no acceleration just past its end and just before its
            -- start; joined on one sample, a part braking into a cut and the next speeding up out
            -- of it can jump from one acceleration to the other, up to twice the jerk. Where the
            -- streamed speeds across such a join break the jerk limit ('joinKeepsJerk'), the join
            -- is moved by one time step: the part after the cut (speed v) starts at u + v·dt, or
            -- the part before it ends at u − v·dt, whichever makes the parts faster, and the step
            -- between is driven at v with no acceleration, as both profiles assume ('assemble'
            -- keeps both samples). Where the next part's first zone at u + v·dt is below v, the
            -- cut's speed is lowered to it for that way; a way that would leave a part shorter
            -- than half 'minPartLength' (or, ending early, below its zone) is not taken. The joins
            -- that keep the limit on one sample stay so: a moved part is one time step shorter
            -- only on average (its samples fall elsewhere; its first step no longer holds the
            -- corner, so its acceleration can differ), and moving every join cost the README's
            -- workflow 1.2 s of 28.1 (4 %). Moving a join re-times a part, which can change the
            -- speeds at its other end, so the joins are checked again, one at a time, until none
            -- breaks the limit.
            timeParts bounds vx vy cap =
              let -- a part's steps and zones: those of the route's grid samples around it, the zones
                  -- cut to the part (a part moved by a time step starts or ends between samples;
                  -- from the samples inside it alone, its zones missed the sliver beyond them, and
                  -- its profile then ran a length other than its zones')
                  spanned (x, y) =
                    let gx = maybe (U.last grid) (\k -> grid U.! max 0 (k - 1)) (U.findIndex (> x + 1e-12) grid)
                        gy = maybe (U.last grid) (grid U.!) (U.findIndex (>= y - 1e-12) grid)
                        st = stepLimitsAt lo route pb 0 gx gy
                    in ((x, y), st, [ z { lzStart = max x (lzStart z), lzEnd = min y (lzEnd z) }
                                    | z <- limitZones top st gx gy, lzEnd z > x, lzStart z < y ])
                  parts0 = map spanned (zip bounds (drop 1 bounds))
                  speeds = vx : [ minimum (cap u : map lzSpeed (take 1 (reverse zl) ++ take 1 zr))
                                | ((_, _, zl), ((u, _), _, zr)) <- zip parts0 (drop 1 parts0) ] ++ [vy]
                  -- (its steps and zones are those of [u, y], on the route's grid, the zones cut at
                  -- the new start)
                  shiftAt p0@((u, y), st, zs0) v = case [ (p1, w) | w <- [v, lowered], w > 0, Just p1 <- [at w] ] of
                    (p1, w) : _ -> (p1, w)
                    [] -> (p0, v)
                    where
                      at w = let u' = u + w * dt
                             in case dropWhile (\z -> lzEnd z <= u') zs0 of
                                  z : rest | u' <= y - 0.5 * minPartLength, lzSpeed z >= w -> Just ((u', y), st, z { lzStart = u' } : rest)
                                  _ -> Nothing
                      lowered = case dropWhile (\z -> lzEnd z <= u + v * dt) zs0 of
                        z : _ -> min v (lzSpeed z)
                        [] -> 0
                  -- join j (between parts j and j+1, j = 0 … n−2), moved one way: part j+1 starts
                  -- one time step later (and the speed at the cut)
                  shiftedAll = zipWith shiftAt (drop 1 parts0) (drop 1 (init speeds))
                  nParts = length parts0
                  lowers = [ j | (j, (_, w), v) <- zip3 [0 :: Int ..] shiftedAll (drop 1 speeds), w < v ]
                  -- or the other way: part j ends one time step before the cut, at u − v·dt (its
                  -- zones cut there), where its zone there keeps v and it keeps half a part's length
                  endEarly ((x, u), st, zs0) v =
                    let u' = u - v * dt
                        keep = [ z | z <- zs0, lzStart z < u' ]
                    in case reverse keep of
                         zl : _ | u' >= x + 0.5 * minPartLength, lzSpeed zl >= v -> Just ((x, u'), st, init keep ++ [zl { lzEnd = u' }])
                         _ -> Nothing
                  -- part i with its start moved or not, and its end as cut (0), at the moved
                  -- join's lowered speed (1) or one step early (2): each variant timed once (lazily)
                  geometryOf i sh e =
                    let (p, vStart) = if sh && i > 0 then shiftedAll !! (i - 1) else (parts0 !! i, speeds !! i)
                    in case e of
                         0 -> Just (p, vStart, speeds !! (i + 1))
                         1 -> Just (p, vStart, snd (shiftedAll !! i))
                         _ -> (\p' -> (p', vStart, speeds !! (i + 1))) <$> endEarly p (speeds !! (i + 1))
                  table = [ [ [ (\(p, va, vb) -> part p va vb) <$> geometryOf i sh e | e <- [0, 1, 2 :: Int] ] | sh <- [False, True] ]
                          | i <- [0 .. nParts - 1] ]
                  -- the joins moved so far: True when the part after starts later, False when the
                  -- part before ends early
                  choice m i = ( i > 0 && lookup (i - 1) m == Just True
                               , case lookup i m of
                                   Just True | i `elem` lowers -> 1
                                   Just False -> 2
                                   _ -> 0 )
                  layout m = sequence [ let (sh, e) = choice m i in table !! i !! fromEnum sh !! e | i <- [0 .. nParts - 1] ]
                  -- the first join that breaks the jerk limit is moved the way that makes the
                  -- parts faster; again until none breaks it
                  settle m rs = case [ j | (j, (r1, r2)) <- zip [0 :: Int ..] (zip rs (drop 1 rs)), j `notElem` map fst m, not (joinKeepsJerk r1 r2) ] of
                    [] -> (m, rs)
                    j : _ -> case [ (sum (map timeOf rs'), (m', rs')) | way <- [True | startMoves j] ++ [False], let m' = (j, way) : m, Just rs' <- [layout m'] ] of
                      [] -> (m, rs)
                      opts -> uncurry settle (snd (foldr1 (\a b -> if fst a <= fst b then a else b) opts))
                  startMoves j = let (((a', _), _, _), _) = shiftedAll !! j; ((a, _), _, _) = parts0 !! (j + 1) in a' /= a
                  (moved, results) = case layout [] of
                    Just rs0 -> settle [] (sparkEach (score False) rs0)
                    Nothing -> ([], [])
                  parts = [ maybe p (\(g, _, _) -> g) (let (sh, e) = choice moved i in geometryOf i sh e) | (i, p) <- zip [0 :: Int ..] parts0 ]
              in (all (\(_, _, zs) -> not (null zs)) parts, results)
            -- two parts joined on one sample (the first's last dropped, the second's first kept:
            -- both at the cut's speed) keep the jerk limit in the streamed speeds: the second
            -- differences (v⁺ − 2v + v⁻)/dt² at the samples either side of the join within the
            -- parts' jerk range (the TCP jerk less 'partMargin', which the scale of 'assemble'
            -- takes at most)
            joinKeepsJerk r1 r2 = case (streamedSpeeds r1, streamedSpeeds r2) of
              (v1, v2) | U.length v1 >= 2, U.length v2 >= 2 ->
                let n1 = U.length v1
                    within x = abs x <= partMargin * si prJerk * dt * dt * (1 + 1e-9)
                in within (v2 U.! 1 - 2 * U.head v2 + v1 U.! (n1 - 2))
                   && (n1 < 3 || within (U.head v2 - 2 * v1 U.! (n1 - 2) + v1 U.! (n1 - 3)))
              _ -> True
            streamedSpeeds (_, _, _, _, r) = maybe U.empty (colVelocity . columns) (resProfile r)
            splitAt' bounds = snd (timeParts bounds 0 0 (const (1 / 0)))
            -- a part's acceleration: the fastest rung of the ladder whose joint motion keeps the
            -- limits, then refined ('refine')
            part ((x, y), st, zs) vx vy =
              let ceil' = tangentialCeiling lo pb x y
                  ok = (< 1 / 0) . score False
                  rung = descendAdmitted timeOf ok
                           [ timed (x, y) vx vy (sym acc) st zs
                           | f <- accelerationFractions ++ boostFractions, let acc = min (si prAcceleration) (f * ceil') ]
              in if ok rung then lift (x, y) vx vy st (flatten (x, y) vx vy st (refine ok (timed (x, y) vx vy) (accelerationCap (x, y)) rung)) else rung
            -- a part at a higher acceleration than it keeps the joints' limits with, its zones
            -- lowered where the sampled joint motion breaks them: over each run of breaking
            -- samples (and 'flattenMargin' either side) to the lowest speed the profile had
            -- there, so that the next profile crosses it without accelerating (the tangential
            -- part |q'|·a is then 0 where |q'| is large: the joints turning fast just after a
            -- corner, where the orientation turns); again up to 'flattenRounds' times. The
            -- fastest admitted profile wins; zones only go down.
            flatten (x, y) vx vy st c0 =
              let (_, (br0, up0), _, zs0', _) = c0
                  a0 = max br0 up0
                  hiA = accelerationCap (x, y)
                  accs = [ acc | f <- [2, 1.4], let acc = min hiA (f * a0), acc > 1.05 * a0 ]
                  -- each run capped at the lowest speed the profile had on it (±margin), never
                  -- below the speed the part starts or ends at when the run reaches its start or end
                  capRuns c ss runs zs =
                    let vs = maybe U.empty (colVelocity . columns) (let (_, _, _, _, r) = c in resProfile r)
                        caps = [ (s0 - flattenMargin, s1 + flattenMargin, vcap)
                               | (s0, s1) <- runs
                               , let inR = U.findIndices (\u -> u >= s0 - flattenMargin && u <= s1 + flattenMargin) ss
                               , not (U.null inR)
                               , let vmin = U.minimum (U.map (vs U.!) inR)
                               , let vcap = maximum (vmin : [ vx | s0 - flattenMargin <= x ] ++ [ vy | s1 + flattenMargin >= y ]) ]
                    in if any (\(_, _, v) -> v < 1e-3) caps then Nothing
                       else Just (foldr (\(s0, s1, v) -> capZones s0 s1 v) zs caps)
              in fastestOf c0 [ repairZones (timed (x, y) vx vy (acc, acc) st) capRuns zs0' | acc <- accs ]
            -- the zones a joint's acceleration binds (the rule takes |q'|·A + |q''|·v² with the
            -- largest slope and curvature of each step and both parts at full size, while the two
            -- parts often differ in sign: braking into a corner lowers a joint's acceleration
            -- there) raised by 1.5, else 1.2 times, never above the speed bounds (joint speeds,
            -- TCP speed, centripetal) of any step they cover; where the sampled joint motion
            -- breaks the limits, the zones over each run of breaking samples (±'flattenMargin')
            -- go back to their speeds, up to 'flattenRounds' times. The fastest admitted
            -- profile wins
            lift (x, y) vx vy st c0 =
              let (_, acc, _, zs0', _) = c0
                  hard = stepLimitsAt lo { loJointAcceleration = U.map (const (1 / 0)) (loJointAcceleration lo) } route pb 0 x y
                  hardOn z = U.minimum (U.cons (1 / 0) (U.ifilter (\k _ -> slS hard U.! (k + 1) > lzStart z && slS hard U.! k < lzEnd z) (slLimit hard)))
                  byJointAcceleration z = case lzBinding z of { ByJointAcceleration _ -> True; _ -> False }
                  lifted f = [ if byJointAcceleration z then z { lzSpeed = max (lzSpeed z) (min (hardOn z) (f * lzSpeed z)) } else z
                             | z <- zs0' ]
                  restoreRuns _ _ runs zs =
                    let near z = or [ lzEnd z > s0 - flattenMargin && lzStart z < s1 + flattenMargin | (s0, s1) <- runs ]
                        back = [ if near z then z0 else z | (z, z0) <- zip zs zs0' ]
                    in if back == zs then Nothing else Just back
              in if any byJointAcceleration zs0'
                   then fastestOf c0 [ repairZones (timed (x, y) vx vy acc st) restoreRuns (lifted f) | f <- [1.5, 1.2] ]
                   else c0
            -- The profile under the zones zs, and while its sampled joint motion breaks the limits
            -- the zones adjusted over the runs of breaking samples (@adjust@ the profile, its
            -- samples, the runs, the zones; Nothing gives up), up to 'flattenRounds' times: the
            -- first profile that keeps the limits, if any.
            repairZones mk adjust = go flattenRounds
              where
                go k zs =
                  let c = mk zs
                      ss = samplesOf c
                  in if timeOf c == 1 / 0 then Nothing
                     else case runsOf ss (jointViolations lo jp dt False ss) of
                       [] -> Just c
                       runs | k <= (0 :: Int) -> Nothing
                            | otherwise -> adjust c ss runs zs >>= go (k - 1)
            fastestOf c0 cs = foldl (\c d -> if timeOf d < timeOf c then d else c) c0 [ c | Just c <- cs ]
            -- runs of breaking samples (indices into ss) no more than 2 margins apart, as [s0, s1]
            runsOf ss = foldr join [] . map (\k -> (ss U.! k, ss U.! k))
              where
                join (s0, s1) ((t0, t1) : rest) | t0 - s1 <= 2 * flattenMargin = (s0, t1) : rest
                join r rest = r : rest
            -- the parts' time as 'assemble' joins them: a part that starts one time step after
            -- the previous one ends ('timeParts') adds that step
            total ps = sum (map (score False) ps) + dt * fromIntegral (length [ () | (p, q) <- zip ps (drop 1 ps), snd (spanOf p) /= fst (spanOf q) ])
            -- the parts' samples as 'assemble' joins them: a part that starts where the previous
            -- one ends (the same sample) without its first
            joined ps = U.concat (take 1 (map samplesOf ps) ++ zipWith (\p q -> let (_, b) = spanOf p; (a', _) = spanOf q
                                                                               in (if a' == b then U.drop 1 else id) (samplesOf q)) ps (drop 1 ps))
            spanOf ((x, y), _, _, _, _) = (x, y)
            -- (cuts that leave one part would only time the whole stretch again, and the two
            -- kinds of cut often give the same parts)
            splitBounds = [ bs | (i, bs) <- zip [0 :: Int ..] candidatesB, length bs > 2, bs `notElem` take i candidatesB ]
              where candidatesB = map boundsFor [middles, slowest]
            splits = [ ps | bounds <- splitBounds
                          , let ps = splitAt' bounds
                          , all (\(_, _, _, zs, _) -> not (null zs)) ps, total ps < timeOf whole
                          , jointsKeepLimits lo jp dt True (joined ps) ]
            chosen0 = case splits of
              [] -> [whole]
              _ -> foldr1 (\x y -> if total x <= total y then x else y) splits
            -- each part cut again in the middle of every run of three or more samples where its
            -- profile cruises (a = 0: the pieces meet there at the profile's speed and with no
            -- acceleration, as the part's own profile does), so that every piece takes its own
            -- acceleration: one acceleration a part is set by its worst sample. A part's pieces
            -- are kept when together faster than the part, and all of them when the stretch's
            -- pieces, joined, keep the joints' limits.
            pieces c@((x, y), _, _, _, r) = case resProfile r of
              Nothing -> [c]
              Just prof ->
                let ss = samplesOf c
                    as = colAcceleration (columns prof)
                    runs = sampleRuns (U.length ss) (\k -> abs (as U.! k) < 1e-9)
                    mids = [ c' | k <- [ (k0 + k1) `div` 2 | (k0, k1) <- runs, k1 - k0 >= 2 ]
                                , Just c' <- [nearestSample (ss U.! k) x y] ]
                in recut (const id) c prof mids
            -- each piece cut again where its joints' ceiling (tangentialCeiling) rises out of a
            -- slow corner: a part's one acceleration is set by its worst step, often the few
            -- millimetres next to a corner where a wrist still turns fast. The cut goes to the
            -- first grid sample after which the ceiling of the rest is 'exitRise' times the
            -- part's, when that is within the first third of the part (and likewise from its
            -- end), so that the rest takes its own acceleration. The pieces meet at 'exitSpeed'
            -- times the part's own speed there, with no acceleration.
            exits c@((x, y), _, _, _, r) = case resProfile r of
              Nothing -> [c]
              Just prof ->
                let t0 = tangentialCeiling lo pb x y
                    inner = U.filter (\g -> g >= x + minPartLength && g <= y - minPartLength) grid
                    ni = U.length inner
                    rises g = tangentialCeiling lo pb g y >= exitRise * t0      -- false, then true as g grows
                    holds g = tangentialCeiling lo pb x g >= exitRise * t0      -- true, then false as g grows
                    -- the least index in [lo', hi') where p turns true (hi' when it never does)
                    firstTrue p lo' hi'
                      | lo' >= hi' = lo'
                      | otherwise = let md = (lo' + hi') `div` 2
                                    in if p (inner U.! md) then firstTrue p lo' md else firstTrue p (md + 1) hi'
                    iStart = firstTrue rises 0 ni
                    iEnd = firstTrue (not . holds) 0 ni - 1
                    third = (y - x) / 3
                    cutsAt = [ g | ni > 0, iStart < ni, let g = inner U.! iStart, g - x <= third ]
                             ++ [ g | ni > 0, iEnd >= 0, let g = inner U.! iEnd, y - g <= third ]
                in if isInfinite t0 || null cutsAt then [c] else recut (const (exitSpeed *)) c prof cutsAt
            -- a part cut at the given places into pieces, each timed as a part ('timeParts'),
            -- meeting at @speed u v@ at a cut u where the part's own speed is v, with no
            -- acceleration; the pieces when together faster than the part, else the part
            recut speed c@((x, y), _, _, _, _) prof cutsAt =
              let ss = samplesOf c
                  vs = colVelocity (columns prof)
                  -- the profile's speed at route distance u (linear between its samples)
                  speedAt u = case U.findIndex (>= u) ss of
                    Nothing -> U.last vs
                    Just 0 -> U.head vs
                    Just k -> let s0 = ss U.! (k - 1); s1 = ss U.! k
                                  w = if s1 > s0 then (u - s0) / (s1 - s0) else 1
                              in (1 - w) * vs U.! (k - 1) + w * vs U.! k
                  bounds = boundsIn x y cutsAt
                  (zoned, timedSubs) = timeParts bounds (U.head vs / partMargin)
                                                        (U.last vs / partMargin) (\u -> speed u (speedAt u))
              in if length bounds <= 2 || not zoned || total timedSubs >= score False c
                   then [c] else timedSubs
            -- the runs (first, last) of consecutive samples 1 .. m−2 of a profile of m samples
            -- where p holds
            sampleRuns m p = go 1
              where
                go k | k >= m - 1 = []
                     | p k = let e = until (\j -> j >= m - 1 || not (p j)) (+ 1) k in (k, e - 1) : go e
                     | otherwise = go (k + 1)
            -- the parts with each one's pieces by @cut@ (a part re-cut on its own), when faster
            -- and the joints' limits kept; where a part's first or last piece meets its
            -- neighbour on one sample and the join breaks the jerk limit ('joinKeepsJerk', as
            -- 'timeParts' checks its own), the two parts stay whole (again until every join
            -- keeps it: whole parts met well before)
            keepIfFaster before cut =
              let -- (whether the part is whole, its pieces)
                  recut0 = [ (False, cut b) | b <- before ]
                  settleCuts cs =
                    let bad = [ i | (i, ((w1, x), (w2, y))) <- zip [0 :: Int ..] (zip cs (drop 1 cs))
                                  , not (w1 && w2)
                                  , let p = last x; q = head y
                                  , snd (spanOf p) == fst (spanOf q), not (joinKeepsJerk p q) ]
                    in case bad of
                         [] -> cs
                         i : _ -> settleCuts [ if j == i || j == i + 1 then (True, [b]) else c | (j, b, c) <- zip3 [0 ..] before cs ]
                  after = concatMap snd (settleCuts recut0)
              in if length after > length before && total after < total before
                   && jointsKeepLimits lo jp dt True (joined after)
                then after else before
            chosen1 = keepIfFaster chosen0 pieces
            exitRounds k ps = if k <= (0 :: Int) then ps
                              else let ps' = keepIfFaster ps exits
                                   in if length ps' == length ps then ps else exitRounds (k - 1) ps'
            chosen2 = exitRounds exitRoundsMax chosen1
            -- a long speed-up (20 samples or more) whose first half has a ceiling 'riseRatio'
            -- times its second half's cut in the middle, the pieces meeting at the speed the
            -- first half reaches from the run's start at a share ('speedUpShares') of its
            -- ceiling, never below the part's own speed there; a long braking likewise,
            -- mirrored. Each share is timed, the faster pieces kept.
            speedUps c@((x, y), _, _, _, r) = case resProfile r of
              Nothing -> [c]
              Just prof ->
                let ss = samplesOf c
                    vs = colVelocity (columns prof)
                    as = colAcceleration (columns prof)
                    runsWhere = sampleRuns (U.length ss)
                    -- (the cut, (its distance from the run's end it is reached from, the speed at
                    -- that end, the ceiling between them)): speeding up forward from a run's
                    -- start, braking backward from its end
                    cands = [ (g, (d, v0, t1))
                            | (k0, k1) <- runsWhere (\k -> as U.! k > 1e-9), k1 - k0 >= 20
                            , let s0 = ss U.! k0; s1 = ss U.! k1
                            , Just g <- [nearestSample (0.5 * (s0 + s1)) x y]
                            , let t1 = tangentialCeiling lo pb s0 g; t2 = tangentialCeiling lo pb g s1
                            , t1 >= riseRatio * t2
                            , let v0 = vs U.! k0; d = g - s0 ]
                         ++ [ (g, (d, v1, t2))
                            | (k0, k1) <- runsWhere (\k -> as U.! k < -1e-9), k1 - k0 >= 20
                            , let s0 = ss U.! k0; s1 = ss U.! (k1 + 1)
                            , Just g <- [nearestSample (0.5 * (s0 + s1)) x y]
                            , let t1 = tangentialCeiling lo pb s0 g; t2 = tangentialCeiling lo pb g s1
                            , t2 >= riseRatio * t1
                            , let v1 = vs U.! (k1 + 1); d = s1 - g ]
                    -- at a share f of the ceiling over the distance d from the run's end
                    speed f u v = case [ e | (g, e) <- cands, g == u ] of
                      ((d, ve, t) : _) -> max v (sqrt (ve * ve + 2 * min (si prAcceleration) (f * t) * d))
                      [] -> v
                    tries = [ recut (speed f) c prof (map fst cands) | f <- speedUpShares ]
                in if null cands then [c] else foldr1 (\p q -> if total p <= total q then p else q) tries
        in keepIfFaster chosen2 speedUps
      -- A part's acceleration range beyond its rung: the speeding-up magnitude, then the braking
      -- one, each raised on its own by bisection between its rung and 1.6 times it (at most hi)
      -- while the sampled joint motion keeps the limits (@ok@), keeping the fastest profile. The
      -- joints that bind while a part speeds up (leaving a corner) are seldom the ones that bind
      -- while it brakes into the next.
      refine ok mk hi c0 = foldl raise c0 [(snd, \x (br, _) -> (br, x)), (fst, \x (_, up) -> (x, up))]
        where
          (_, _, st, zs, _) = c0
          raise c (get, set) =
            let (_, acc, _, _, _) = c
                go best l h k
                  | k <= (0 :: Int) || h <= l * 1.02 = best
                  | otherwise =
                      let x = 0.5 * (l + h)
                          cx = mk (set x acc) st zs
                      in if ok cx then go (if timeOf cx < timeOf best then cx else best) x h (k - 1)
                                  else go best l x (k - 1)
            in go c (get acc) (min hi (1.6 * get acc)) (3 :: Int)
      -- the most acceleration a part's search tries: three times its tangential ceiling, at
      -- most the TCP's
      accelerationCap (x, y) = min (si prAcceleration) (3 * tangentialCeiling lo pb x y)
      minPartLength = 0.01
      exitRise = 1.5
      exitSpeed = 0.97
      exitRoundsMax = 3
      riseRatio = 1.3
      speedUpShares = [0.4, 0.6]
      flattenRounds = 4
      flattenMargin = 1e-3
      -- the grid sample nearest s, strictly inside (a, b)
      nearestSample x a b = do
        k <- U.findIndex (>= x) grid
        let c = grid U.! k
        if c > a + 1e-9 && c < b - 1e-9 then Just c else Nothing
      chosen = concat (sparkEach (sum . map timeOf) (map planStretch (zip cuts (drop 1 cuts))))
      stretches = [ ab | (ab, _, _, _, _) <- chosen ]
      accs = [ acc | (_, acc, _, _, _) <- chosen ]
      zoness = [ zs | (_, _, _, zs, _) <- chosen ]
      results = [ r | (_, _, _, _, r) <- chosen ]
      steps = joinSteps [ st | (_, _, st, _, _) <- chosen ]
  case [ (i, ab, r) | (i, ab, r) <- zip3 [0 ..] stretches results, not (resultLegal r) ] of
    ((i, ab, r) : _) -> Left (ProfileFailed i ab (case resOutcome r of
                                                   Failed f -> renderFailure f
                                                   Generated -> "the profile is not legal"))
    [] -> Right ()
  let (traj, maps, onRoute) = assemble lo ch route jp (zip stretches results)
  pure (Plan route tracked steps stretches zoness maps accs results traj True onRoute)
  where
    -- the stretches' grids joined (each begins where the previous one ends)
    joinSteps sts = StepLimits (U.concat (take 1 (map slS sts) ++ map (U.drop 1 . slS) (drop 1 sts)))
                               (U.concat (map slLimit sts)) (V.concat (map slBinding sts))
    -- Each part's request: its speeds, acceleration and jerk lowered by 'partMargin', its end
    -- tolerance 1e-5 of its length at most (so that the scale of 'assemble' keeps the plan's
    -- limits); the two parts at a cut ask for the same speed there.
    profileRequest tol a b (brake, speedUp) zs va vb = defaultRequest
      { rqRouteLength = (b - a) *~ meter
      , rqStartVelocity = (partMargin * va) *~ mps
      , rqEndVelocity = (partMargin * vb) *~ mps
      , rqZones = [ SpeedZone ((lzStart z - a) *~ meter) ((partMargin * lzSpeed z) *~ mps) | z <- zs ]
      , rqMinAcceleration = negate (partMargin * brake) *~ mps2
      , rqMaxAcceleration = (partMargin * speedUp) *~ mps2
      , rqMinJerk = negate (partMargin * si prJerk) *~ mps3
      , rqMaxJerk = (partMargin * si prJerk) *~ mps3
      , rqTimeStep = Just prTimeStep
      , rqEndTolerance = Just (tol *~ meter)
        -- the planner searches over its parts' accelerations itself and keeps the fastest
        -- profile whose joint motion keeps the limits: the generator's greedy seed alone
      , rqSeedSearch = False
      }
    dt = si prTimeStep
    -- The profile of the part [a, b] that ends at most 1e-5 of its length short of b, which
    -- 'assemble' needs: asked with that tolerance, the generator may still end short by the
    -- checker's slack more (1e-9 m, above 1e-5 of a part under 0.1 mm: a turn in place of
    -- 1.3 mrad, 0.22 mm, ended 1.26e-5 short, and the scale of 'assemble' took its jerk 2.6e-6
    -- above the limit); such a profile is asked again with a quarter of the tolerance, up to
    -- three times.
    endingWithin a b gen = go (3 :: Int) (min (si prEndTolerance) ((b - a) * 1e-5))
      where
        go k tol =
          let r = gen tol
              short = case resProfile r of
                Just p | resultLegal r, let ds = colDistance (columns p), not (U.null ds) -> (b - a) - U.last ds > (b - a) * 1e-5
                _ -> False
          in if short && k > 0 then go (k - 1) (tol / 4) else r
    -- The generator ends each part within its end tolerance of the part's end, not on it. The
    -- parts are joined as they are and scaled together between the places where the motion
    -- rests (the route's ends and its stops): their distances, speeds, accelerations and jerks
    -- by F = (the length between the rests) / (the distance the joined speeds cover), so that
    -- the motion ends exactly on each rest and its distances are the trapezoid sums of its
    -- speeds. Two parts at a cut at speed ask for the same speed there, so the streamed speeds
    -- meet without a step (each part scaled to its own length met with a step of up to 1e-5
    -- of the speed, which at 2 ms broke the jerk limit by 4 %: v1000 on the README's
    -- workflow). Each part ends within 1e-5 of its length, so F ≤ 1 / (1 − 1e-5), which the
    -- requests' 'partMargin' takes: the joined motion keeps the zones, acceleration and jerk.
    -- A part's samples then lie up to the parts' summed end errors (micrometres) from where its
    -- own profile put them; the zones listed to the user follow them ('planPartMaps').
    -- A part that ends at speed ends on the next one's first row (the same sample and speed),
    -- which is dropped once; a part that ends at a stop keeps its last row, so the motion rests
    -- one sample there (acceleration 0) and the jerk into the stop and out of it stays within
    -- range (joined without it, the step from braking to speeding up doubled the jerk); a part
    -- after a cut at speed that starts one time step past it keeps its first row too (see
    -- 'timeParts').
    assemble lo ch route jp parts =
      let cols = [ ((a, b), columns p) | ((a, b), r) <- parts, Just p <- [resProfile r] ]
          nParts = length cols
          nextStarts = map (fst . fst) (drop 1 cols) ++ [1 / 0]
          -- at rest: the generator ends a part asked to stop within the legality slack of 0
          -- (1e-9 m/s; a 0.66 mm turn in place ended at 2.9e-10 m/s)
          atRest c = not (U.null (colVelocity c)) && abs (U.last (colVelocity c)) <= slack 0
          dropLast c = Columns (U.init (colTime c)) (U.init (colDistance c)) (U.init (colVelocity c))
                               (U.init (colAcceleration c)) (U.init (colJerk c))
          -- (each with its profile's own stretch onto its length, for its map)
          trimmed = [ ((ab, stretchFactor (b - a) c), if i < nParts - 1 && not (atRest c) && a' == b then dropLast c else c, atRest c || i == nParts - 1)
                    | (i, (ab@(a, b), c), a') <- zip3 [0 :: Int ..] cols nextStarts ]
          -- the parts between rests: runs that end with a part at rest (or the last)
          groups [] = []
          groups ps = let (run, rest) = break (\(_, _, r) -> r) ps
                      in case rest of
                           p : more -> (run ++ [p]) : groups more
                           [] -> [run]
          -- a group's samples: its distances (from its start), speeds, accelerations and
          -- jerks scaled by F, and each part's map from its route distance to the samples'
          scaled grp =
            let vs0 = U.concat [ colVelocity c | (_, c, _) <- grp ]
                cum = trapezoidDistances dt vs0
                x0 = fst (fst (fst3 (head grp)))
                x1 = snd (fst (fst3 (last grp)))
                total = U.last cum
                f = if total > 0 then (x1 - x0) / total else 1
                starts = scanl (+) 0 [ U.length (colVelocity c) | (_, c, _) <- grp ]
                maps = [ (a, x0 + f * (cum U.! k), f / fi) | ((((a, _), fi), _, _), k) <- zip grp starts ]
                cat g = U.map (* f) (U.concat [ g c | (_, c, _) <- grp ])
            in (U.map (\d -> x0 + f * d) cum, cat colVelocity, cat colAcceleration, cat colJerk, maps)
          fst3 (x, _, _) = x
          gs = map scaled (groups trimmed)
          m = sum [ U.length (colTime c) | (_, c, _) <- trimmed ]
          ts = U.generate m (\k -> fromIntegral k * dt)
          ss = U.concat [ x | (x, _, _, _, _) <- gs ]
          vs = U.concat [ x | (_, x, _, _, _) <- gs ]
          as = U.concat [ x | (_, _, x, _, _) <- gs ]
          js = U.concat [ x | (_, _, _, x, _) <- gs ]
          n = tkDof (jpTracked jp)
          -- each sample's joint values projected onto the route's pose at its s: the joint path
          -- is cubic between IK samples, and its error there (up to micrometres of the TCP),
          -- small as it is, shows in the TCP's jerk by third differences at dt; kept when the
          -- projected joint motion still keeps the joints' limits as the search checked the
          -- path's (the projection follows the route's steps of curvature more sharply),
          -- else the path's own values
          onPath = U.concat [ jointPathAt jp (ss U.! k) | k <- [0 .. m - 1] ]
          projected = U.concat [ ontoRoute (ss U.! k) (U.slice (k * n) n onPath) | k <- [0 .. m - 1] ]
          ontoRoute x q = U.izipWith (\i a b -> max a (min (chainHi ch U.! i) b)) (chainLo ch)
                                     (refineOnto ch (routeTfAt route x) q)
          onRoute = null (sampledViolations lo dt True m n (\k i -> projected U.! (k * n + i)))
          qs = if onRoute then projected else onPath
          qAt k i = qs U.! (k * n + i)
          qd k i
            | m < 2 = 0
            | k == 0 = (qAt 1 i - qAt 0 i) / dt
            | k == m - 1 = (qAt k i - qAt (k - 1) i) / dt
            | otherwise = (qAt (k + 1) i - qAt (k - 1) i) / (2 * dt)
          qds = U.generate (m * n) (\x -> let (k, i) = x `divMod` n in qd k i)
      in (Trajectory ts ss vs as js qs qds n, concat [ x | (_, _, _, _, x) <- gs ], onRoute)

