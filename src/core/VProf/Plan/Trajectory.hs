{-# LANGUAGE RecordWildCards #-}
-- | The plan, end to end: the route through the waypoints ("VProf.Plan.Route"), tracked in joint
-- space ("VProf.Plan.Track"), its speed limits as zones ("VProf.Plan.Limits"), and the timing by
-- the velocity-profile generator: one profile request per stretch between stops (the route's
-- end points and its @fine@ waypoints), each from rest to rest with the TCP's acceleration and
-- jerk ranges at the controller's time step. The stretch's TCP acceleration bound A shares each
-- joint's acceleration limit with its speed limits in the corners ("VProf.Plan.Limits"): a few
-- values of A below the joints' ceiling are tried and the fastest legal profile is kept. The generator's samples s(t) give the joint values q(t) on the smooth
-- joint path through the tracked samples (cubic Hermite, 'jointPathAt'; 1 mm apart by default)
-- and the joint speeds by central differences in time. Request and result are plain records, SI inside and
-- units at the boundary, so that a wire layer can convert them.
module VProf.Plan.Trajectory
  ( PlanRequest (..)
  , planRequest
  , defaultTimeStep
  , defaultAcceleration
  , defaultJerk
  , defaultEndTolerance
  , Trajectory (..)
  , trajectoryCount
  , trajectoryQ
  , trajectoryQd
  , Plan (..)
  , planDuration
  , PlanFailure (..)
  , describePlanFailure
  , planPath
  , limitOptionsFor
  ) where

import qualified Data.Vector as V
import qualified Data.Vector.Unboxed as U

import VProf.Kinematics.Ik (kinematicsFor)
import VProf.Kinematics.Model
import VProf.Plan.Limits
import VProf.Plan.Route
import VProf.Plan.Track
import VProf.Profile (Request (..), Result (..), SpeedZone (..), Outcome (..), defaultRequest, generatePure, resultLegal, renderFailure)
import VProf.Profile.Sampled (Columns (..), columns, duration)
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
defaultEndTolerance = 1e-4  -- m

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
  , planStretches  :: ![(Double, Double)]   -- ^ [a, b] between stops (m)
  , planZones      :: ![[LimitZone]]         -- ^ per stretch, in route coordinates
  , planAccelerations :: ![Double]           -- ^ per stretch, the TCP acceleration range ±a used (m/s²)
  , planProfiles   :: ![Result]              -- ^ per stretch
  , planTrajectory :: !Trajectory
  , planLegal      :: !Bool                  -- ^ every stretch's profile legal by the checker
  }

planDuration :: Plan -> Double
planDuration p = let t = trTime (planTrajectory p) in if U.null t then 0 else U.last t

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

startFraction :: Int
startFraction = 4

-- | Descend along the ladder from 'startFraction' while the next rung is strictly faster (the
-- duration is close to unimodal in the fraction: about three profiles a stretch instead of
-- seven); the fastest rung seen wins. Durations are looked at through @timeOf@ (infinite for an
-- illegal profile), so a stretch with no legal profile keeps the start rung and its failure.
descend :: (a -> Double) -> [a] -> a
descend timeOf xs = go startFraction
  where
    n = length xs
    t i = timeOf (xs !! i)
    go i
      | i + 1 < n && t (i + 1) < t i = up (i + 1)
      | i > 0 && t (i - 1) < t i = down (i - 1)
      | otherwise = xs !! i
    up i = if i + 1 < n && t (i + 1) < t i then up (i + 1) else xs !! i
    down i = if i > 0 && t (i - 1) < t i then down (i - 1) else xs !! i

validateRequest :: PlanRequest -> [FieldError]
validateRequest PlanRequest{..} = concat
  [ positive "speed" (si prSpeed) "m/s"
  , positive "acceleration" (si prAcceleration) "m/s²"
  , positive "jerk" (si prJerk) "m/s³"
  , ensureFinite "dt" dt "s" $ ensure (dt > 0 && dt <= 1) (fieldError "dt" dt "s" "must be > 0 and at most 1 s")
  , positive "end_tolerance" (si prEndTolerance) "m"
  , case prStart of
      Nothing -> []
      Just q -> ensure (U.length q == dof prRobot && U.all finite q)
                  (literalError "start" (show (U.toList q))
                     ("must be " ++ show (dof prRobot) ++ " finite joint values for " ++ robotName prRobot))
  , ensure (dof prRobot > 0) (literalError "robot" (robotName prRobot) "has no joints")
  ]
  where
    dt = si prTimeStep
    positive f x u = ensureFinite f x u (ensure (x > 0) (fieldError f x u "must be > 0"))

planPath :: PlanRequest -> Either PlanFailure Plan
planPath rq@PlanRequest{..} = do
  route <- either (Left . InvalidPlan . (validateRequest rq ++)) Right
             (mkRoute (map (const prZone) prWaypoints) prWaypoints)
  case validateRequest rq of
    [] -> Right ()
    es -> Left (InvalidPlan es)
  tracked <- either (Left . Stopped) Right (trackRoute prTrack (kinematicsFor prRobot) route prStart)
  let lo = limitOptionsFor rq
      jp = jointPath (rtStops route) tracked
      pb = pathBounds jp
      cuts = 0 : rtStops route ++ [rtLength route]
      top = si prSpeed
      -- per stretch: the profile at each acceleration of the ladder (computed when looked at)
      tries (a, b) =
        let ceil' = tangentialCeiling lo pb a b
        in [ ((a, b), acc, st, zs, generatePure (profileRequest a b acc zs))
           | f <- accelerationFractions
           , let acc = min (si prAcceleration) (f * ceil')
           , let st = stepLimitsAt lo route pb acc a b, let zs = limitZones top st a b ]
      timeOf (_, _, _, _, r) = if resultLegal r then maybe (1 / 0) duration (resProfile r) else 1 / 0
      chosen = map (descend timeOf . tries) (zip cuts (drop 1 cuts))
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
  let traj = assemble jp (zip stretches results)
  pure (Plan route tracked steps stretches zoness accs results traj True)
  where
    -- the stretches' grids joined (each begins where the previous one ends)
    joinSteps sts = StepLimits (U.concat (take 1 (map slS sts) ++ map (U.drop 1 . slS) (drop 1 sts)))
                               (U.concat (map slLimit sts)) (V.concat (map slBinding sts))
    -- The generator ends within the end tolerance of the stretch's end, not on it; the
    -- trajectory stretches each profile's s by f = (b − a) / s_end so that it stops exactly there
    -- (a jump to the end would be a joint acceleration spike). f ≤ 1 + tolerance / (b − a), so
    -- the request asks for speeds, acceleration and jerk lowered by that factor: once stretched,
    -- the profile keeps the zones, acceleration and jerk of the plan.
    margin a b = 1 / (1 + si prEndTolerance / (b - a))
    profileRequest a b acc zs = defaultRequest
      { rqRouteLength = (b - a) *~ meter
      , rqZones = [ SpeedZone ((lzStart z - a) *~ meter) ((margin a b * lzSpeed z) *~ mps) | z <- zs ]
      , rqMinAcceleration = negate (margin a b * acc) *~ mps2
      , rqMaxAcceleration = (margin a b * acc) *~ mps2
      , rqMinJerk = negate (margin a b * si prJerk) *~ mps3
      , rqMaxJerk = (margin a b * si prJerk) *~ mps3
      , rqTimeStep = Just prTimeStep
      , rqEndTolerance = Just prEndTolerance
      }
    dt = si prTimeStep
    assemble jp parts =
      let cols = [ (a, stretchTo (b - a) (columns p)) | ((a, b), r) <- parts, Just p <- [resProfile r] ]
          stretchTo l c =
            let e = if U.null (colDistance c) then 0 else U.last (colDistance c)
                f = if e > 0 then l / e else 1
            in c { colDistance = U.map (* f) (colDistance c), colVelocity = U.map (* f) (colVelocity c)
                 , colAcceleration = U.map (* f) (colAcceleration c), colJerk = U.map (* f) (colJerk c) }
          nParts = length cols
          -- the last row of every stretch but the last is the next one's first (both at rest)
          trimmed = [ (a, if i < nParts - 1 then dropLast c else c) | (i, (a, c)) <- zip [0 :: Int ..] cols ]
          dropLast c = Columns (U.init (colTime c)) (U.init (colDistance c)) (U.init (colVelocity c))
                               (U.init (colAcceleration c)) (U.init (colJerk c))
          offsets = scanl (+) 0 [ fromIntegral (U.length (colTime c)) * dt | (_, c) <- trimmed ]
          ts = U.concat [ U.map (+ o) (colTime c) | ((_, c), o) <- zip trimmed offsets ]
          ss = U.concat [ U.map (+ a) (colDistance c) | (a, c) <- trimmed ]
          vs = U.concat [ colVelocity c | (_, c) <- trimmed ]
          as = U.concat [ colAcceleration c | (_, c) <- trimmed ]
          js = U.concat [ colJerk c | (_, c) <- trimmed ]
          n = tkDof (jpTracked jp)
          m = U.length ts
          qs = U.concat [ jointPathAt jp (ss U.! k) | k <- [0 .. m - 1] ]
          qAt k i = qs U.! (k * n + i)
          qd k i
            | m < 2 = 0
            | k == 0 = (qAt 1 i - qAt 0 i) / dt
            | k == m - 1 = (qAt k i - qAt (k - 1) i) / dt
            | otherwise = (qAt (k + 1) i - qAt (k - 1) i) / (2 * dt)
          qds = U.generate (m * n) (\x -> let (k, i) = x `divMod` n in qd k i)
      in Trajectory ts ss vs as js qs qds n
