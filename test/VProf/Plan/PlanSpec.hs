-- | Plans checked end to end by the independent checker (Support.PlanChecker): random short
-- paths of a UR5, an IRB 140 and a Panda (7 joints, numerical IK), failures that must stop with
-- their reason and distance, and a real recording compressed by the library and placed in a
-- UR5's workspace.
module VProf.Plan.PlanSpec (spec) where

import Data.List (isInfixOf, nubBy)
import qualified Data.Vector.Unboxed as U
import qualified Linear as L
import System.FilePath ((</>))
import Test.Hspec
import Test.QuickCheck

import Support.Arbitrary (shared)
import Support.Gen (turnedBy)
import Support.PlanChecker
import Support.DistanceOracle (oMesh)
import Support.RobotOracle (oracleClearance)
import Support.Recordings (loadTum)
import VProf.Compress (Compressed (..), Path (..), Settings (..), Track (..), compress, defaultSettings)
import VProf.Geometry.Quaternion (qmul, qconj)
import VProf.Geometry.Vec (P3 (..), Q4 (..), ptoList)
import VProf.Geometry.Bvh (buildBvh)
import VProf.Geometry.Format.Obj (readObj)
import VProf.Geometry.Mesh (triangles)
import VProf.Kinematics.Forward (Pose (..), forwardPose)
import VProf.Kinematics.Collision (CollisionOptions (..), collisionModel, defaultCollisionOptions)
import VProf.Kinematics.Ik (IkOptions (..), IkSolution (..), solveIk, kinematicsFor, defaultIkOptions, kinChain)
import VProf.Kinematics.Jacobian (jacobian, manipulability)
import qualified VProf.Kinematics.Transform as T
import VProf.Kinematics.Library (lookupRobot)
import VProf.Kinematics.Model
import VProf.Kinematics.Transform (Quat (..), V3 (..))
import VProf.Plan
import VProf.Units
import VProf.Validation (FieldError (..))

robot :: String -> Robot
robot name = either (error . show) id (lookupRobot name)

-- | A comfortable configuration of each robot (rad), away from limits and singularities.
comfortable :: String -> [Double]
comfortable = \case
  "ur5" -> [0, -1.4, -2.0, -1.3, 1.57, 0]
  "abb-irb140" -> [0, 0.3, -0.3, 0, 0.9, 0]
  _ -> [0, -0.6, 0, -2.2, 0, 1.7, 0.8]

-- | A random path near the comfortable configuration's TCP: 2–5 waypoints within ±6 cm of it,
-- the orientation turned by up to ±8° about random axes, a zone of 0–20 mm, a speed of
-- 100–800 mm/s.
genPlan :: String -> Gen ([Waypoint], Zone, Double)
genPlan name = do
  dq <- vectorOf (length (comfortable name)) (choose (-0.2, 0.2))
  let r = robot name
      q0 = U.fromList (zipWith (+) (comfortable name) dq)
      Pose (V3 x y z) (Quat w a b c) = forwardPose (compile r) q0
  k <- choose (2, 5)
  offs <- vectorOf k ((,,) <$> o <*> o <*> o) `suchThat` apart
  rots <- vectorOf k ((,,) <$> t <*> t <*> t)
  zone <- oneof [pure Fine, (\mm -> Blend ((mm / 1000) *~ meter)) <$> choose (1, 20)]
  v <- choose (0.1, 0.8)
  let wp (dx, dy, dz) (rx, ry, rz) =
        let Q4 qw qx qy qz = qmul (Q4 w a b c) (small rx ry rz)
        in waypoint (x + dx, y + dy, z + dz) (qw, qx, qy, qz)
  pure (zipWith wp offs rots, zone, v)
  where
    o = choose (-0.06, 0.06)
    t = choose (-0.07, 0.07)
    apart ps = and (zipWith (\(a, b, c) (d, e, f) -> (a - d) ^ (2 :: Int) + (b - e) ^ (2 :: Int) + (c - f) ^ (2 :: Int) > 1e-4) ps (drop 1 ps))
    small rx ry rz = let th = sqrt (rx * rx + ry * ry + rz * rz); s = if th < 1e-12 then 0.5 else sin (th / 2) / th
                     in Q4 (cos (th / 2)) (s * rx) (s * ry) (s * rz)

-- | A path of 'genPlan' with turns in place: after one or more waypoints, the same position
-- with the orientation turned by 0.06°–23° about a random axis.
genTurnPlan :: String -> Gen ([Waypoint], Zone, Double)
genTurnPlan name = do
  (wps, zone, v) <- genPlan name
  flags <- vectorOf (length wps) (frequency [(2, pure False), (1, pure True)]) `suchThat` or
  wps' <- concat <$> sequence [ if f then (\t -> [w, t]) <$> turned w else pure [w] | (w, f) <- zip wps flags ]
  pure (wps', zone, v)
  where
    turned (Waypoint p (L.Quaternion w (L.V3 a b c))) = do
      Q4 qw qx qy qz <- turnedBy (oneof [choose (1.1e-3, 0.01), choose (0.01, 0.4)]) (Q4 w a b c)
      pure (Waypoint p (L.Quaternion qw (L.V3 qx qy qz)))

poses :: [Waypoint] -> [((Double, Double, Double), (Double, Double, Double, Double))]
poses wps = [ ((si x, si y, si z), (w, a, b, c)) | Waypoint (L.V3 x y z) (L.Quaternion w (L.V3 a b c)) <- wps ]

positions :: [Waypoint] -> [(Double, Double, Double)]
positions wps = [ (si x, si y, si z) | Waypoint (L.V3 x y z) _ <- wps ]

planAndCheck :: Robot -> [Waypoint] -> Zone -> Double -> Property
planAndCheck = planAndCheckWith defaultAcceleration defaultJerk

planAndCheckWith :: Double -> Double -> Robot -> [Waypoint] -> Zone -> Double -> Property
planAndCheckWith acc jerk r wps zone v =
  let rq = (planRequest r wps) { prZone = zone, prSpeed = v *~ mps, prAcceleration = acc *~ mps2, prJerk = jerk *~ mps3 }
  in case planPath rq of
       Left f -> counterexample (describePlanFailure f) False
       Right plan ->
         let problems = checkTrajectory r (positions wps) (zoneRadius zone) acc jerk defaultTimeStep plan
                        ++ checkTcpMotion r v acc jerk defaultTimeStep plan
                        ++ offRoute r plan
         in counterexample (unlines problems) (null problems && planLegal plan && planDuration plan > 0)

-- | The samples whose TCP (the textbook matrices) is further from the route's position at the
-- sample's s than 1 nm when the plan says its joint values are projected onto the route, else
-- than 10 µm (the joint path's interpolation error; at most 5 named).
offRoute :: Robot -> Plan -> [String]
offRoute r plan =
  take 5 [ "sample " ++ show k ++ ": the TCP is " ++ show (d * 1e9) ++ " nm from the route at s = " ++ show s
             ++ (if planOnRoute plan then " (projected onto it)" else " (not projected)")
         | k <- [0 .. U.length (trS tr) - 1]
         , let s = trS tr U.! k
               (x, y, z) = oracleTcp r [ trQ tr U.! (k * n + i) | i <- [0 .. n - 1] ]
               V3 px py pz = fst (routeAt (planRoute plan) s)
               d = sqrt ((x - px) ^ (2 :: Int) + (y - py) ^ (2 :: Int) + (z - pz) ^ (2 :: Int))
         , d > (if planOnRoute plan then 1e-9 else 1e-5) ]
  where
    tr = planTrajectory plan
    n = trDof tr

spec :: Spec
spec = describe "VProf.Plan" $ do
  describe "random short paths pass the independent checker" $
    mapM_ (\name -> it name $ withMaxSuccess 20 $ forAll (genPlan name) $ \(wps, zone, v) -> planAndCheck (robot name) wps zone v)
      ["ur5", "abb-irb140", "franka-panda"]

  it "projects most random short paths' trajectories onto the route (at least 15 of 20 on a UR5; the rest keep the joint path's values, where projected they broke a joint limit)" $
    property $ withMaxSuccess 3 $ forAll (vectorOf 20 (genPlan "ur5")) $ \cases ->
      let rs = [ planOnRoute plan | (wps, zone, v) <- cases
               , Right plan <- [planPath ((planRequest (robot "ur5") wps) { prZone = zone, prSpeed = v *~ mps })] ]
      in counterexample (show (length (filter id rs)) ++ " of " ++ show (length rs) ++ " projected") (length (filter id rs) >= 15)

  -- at 3 m/s, 20 m/s² and 400 m/s³ the joints' speed and acceleration limits bind, not the TCP's
  describe "random fast paths keep every joint's speed and acceleration (the checker's second differences)" $
    mapM_ (\name -> it name $ withMaxSuccess 15 $ forAll (genPlan name) $ \(wps, zone, _) -> planAndCheckWith 20 400 (robot name) wps zone 3)
      ["ur5", "abb-irb140"]

  -- a turn in place is a stretch of its own, from rest to rest, its s the arc of a point 0.1 m
  -- from the TCP: the checker's limits hold on it as on a move, and it reaches its orientation
  describe "random paths with turns in place pass the independent checker and reach every turn's orientation" $
    mapM_ (\name -> it name $ withMaxSuccess 15 $ forAll (genTurnPlan name) $ \(wps, zone, v) ->
             let r = robot name
             in case planPath ((planRequest r wps) { prZone = zone, prSpeed = v *~ mps }) of
                  Left f -> counterexample (describePlanFailure f) False
                  Right plan ->
                    let problems = checkTrajectory r (positions wps) (zoneRadius zone) defaultAcceleration defaultJerk defaultTimeStep plan
                                   ++ checkWaypointPoses r (poses wps) plan ++ checkTcpMotion r v defaultAcceleration defaultJerk defaultTimeStep plan
                    in counterexample (unlines problems) (null problems && planLegal plan && planDuration plan > 0))
      ["ur5", "abb-irb140", "franka-panda"]

  it "a tool turned in place by 90° about its axis: 0.157 m of s, a plan from rest to rest that holds the position and ends at the turned orientation" $ do
    let r = robot "ur5"
        Pose (V3 x y z) (Quat w a b c) = forwardPose (compile r) (U.fromList (comfortable "ur5"))
        Q4 qw qx qy qz = qmul (Q4 w a b c) (Q4 (cos (pi / 4)) 0 0 (sin (pi / 4)))
        wps = [waypoint (x, y, z) (w, a, b, c), waypoint (x, y, z) (qw, qx, qy, qz)]
    case planPath (planRequest r wps) of
      Left f -> expectationFailure (describePlanFailure f)
      Right plan -> do
        routeLength (planRoute plan) `shouldSatisfy` (\l -> abs (l - 0.1 * pi / 2) < 1e-12)
        checkTrajectory r (positions wps) 0 defaultAcceleration defaultJerk defaultTimeStep plan `shouldBe` []
        checkWaypointPoses r (poses wps) plan `shouldBe` []
        planDuration plan `shouldSatisfy` (> 0)

  it "stops with out of reach, at the distance where the route leaves the workspace" $ do
    let r = robot "ur5"
        wps = [waypoint (0.4, 0, 0.3) (0, 1, 0, 0), waypoint (1.2, 0, 0.3) (0, 1, 0, 0)]
    case planPath (planRequest r wps) of
      Left (Stopped (PlanStop (OutOfReach _) s (V3 px _ _))) -> do
        s `shouldSatisfy` (\x -> x > 0.3 && x < 0.8)
        px `shouldSatisfy` (\x -> abs (x - (0.4 + s)) < 1e-9)
        -- the oracle: IK reaches the route 2 mm before the stop and not at it
        let kin = kinematicsFor r
            target d = (routeTfAt (either (error . show) id (mkRoute [Fine, Fine] wps))) d
        either (const False) (not . null) (solveIk defaultIkOptions kin (target (s - 0.002)) Nothing) `shouldBe` True
        either (const False) (not . null) (solveIk defaultIkOptions kin (target s) Nothing) `shouldBe` False
      Left f -> expectationFailure ("stopped otherwise: " ++ describePlanFailure f)
      Right _ -> expectationFailure "planned a path out of reach"

  it "stops at a joint limit: an IRB 140 passing behind its base runs J1 into ±180°" $ do
    let r = robot "abb-irb140"
        wps = [waypoint (-0.4, 0.3, 0.3) (0, 1, 0, 0), waypoint (-0.4, -0.3, 0.3) (0, 1, 0, 0)]
        start = U.fromList (map (* (pi / 180)) [143, 20, 30, 0, 30, 0])
    case planPath (planRequest r wps) { prStart = Just start } of
      Left (Stopped st@(PlanStop (JointLimit j _ l) s _)) -> do
        j `shouldBe` "J1"
        describeStop st `shouldSatisfy` isInfixOf "J1 reaches its limit 180.00°"
        abs l `shouldSatisfy` (\x -> abs (x - pi) < 1e-9)
        -- y crosses 0 (the base angle 180°) at s = 0.3 m
        s `shouldSatisfy` (\x -> abs (x - 0.3) <= 0.0015)
      Left f -> expectationFailure ("stopped otherwise: " ++ describePlanFailure f)
      Right _ -> expectationFailure "planned through a joint limit"

  it "the checker rejects a trajectory run faster (its speeds or its accelerations 1.5 times their peak share), and one moved off the route" $ do
    let r = robot "ur5"
        wps = [waypoint (0.4, -0.1, 0.3) (0, 1, 0, 0), waypoint (0.5, 0.1, 0.3) (0, 1, 0, 0), waypoint (0.4, 0.1, 0.25) (0, 1, 0, 0)]
        -- a TCP speed that makes joints run near their limits
        rq = (planRequest r wps) { prSpeed = 3 *~ mps, prAcceleration = 20 *~ mps2, prJerk = 400 *~ mps3 }
    case planPath rq of
      Left f -> expectationFailure (describePlanFailure f)
      Right plan -> do
        let check' = checkTrajectory r (positions wps) 0.01 20 400 defaultTimeStep
            tr = planTrajectory plan
            n = trDof tr
            m = U.length (trTime tr)
            qAt k i = trQ tr U.! (k * n + i)
            vmax = [ maybe (1 / 0) id (jointMaxVelocity j) | j <- robotJoints r ]
            amax = map (maybe (1 / 0) id . jointAccelerationLimit) (robotJoints r)
            dt = defaultTimeStep
            -- the peak joint speed and acceleration as shares of their limits, measured here
            peakV = maximum [ abs (qAt (k + 1) i - qAt k i) / dt / vm | k <- [0 .. m - 2], (i, vm) <- zip [0 .. n - 1] vmax ]
            peakA = maximum [ abs (qAt (k + 1) i - 2 * qAt k i + qAt (k - 1) i) / (dt * dt) / am
                            | k <- [1 .. m - 2], (i, am) <- zip [0 .. n - 1] amax ]
            -- time run c times as fast: speeds c times, accelerations c² times as high
            faster c = plan { planTrajectory = tr { trTime = U.map (/ c) (trTime tr) } }
            -- the first joint turned by 0.05 rad everywhere: the TCP leaves the route
            moved = plan { planTrajectory = tr { trQ = U.imap (\k x -> if k `mod` n == 0 then x + 0.05 else x) (trQ tr) } }
        check' plan `shouldBe` []
        check' (faster (1.5 / peakV)) `shouldSatisfy` any (\x -> "speed" `elem` words x)
        check' (faster (sqrt (1.5 / peakA))) `shouldSatisfy` any (\x -> "acceleration" `elem` words x)
        check' moved `shouldSatisfy` any (\m -> "polyline" `elem` words m)

  it "refuses bad input naming the field and the value" $ do
    let r = robot "ur5"
        wps = [waypoint (0.4, 0, 0.3) (0, 1, 0, 0), waypoint (0.5, 0, 0.3) (0, 1, 0, 0)]
    case planPath (planRequest r wps) { prSpeed = (-1) *~ mps, prTimeStep = 0 *~ second } of
      Left (InvalidPlan es) -> do
        map feField es `shouldContain` ["speed"]
        map feField es `shouldContain` ["dt"]
      _ -> expectationFailure "accepted a negative speed"

  it "plans a real recording (freiburg1_xyz, compressed, scaled by 0.5 and placed in front of a UR5)" $ do
    wps <- placedFreiburg
    let r = robot "ur5"
        rq = (planRequest r wps) { prSpeed = 0.25 *~ mps }
    case planPath rq of
      Left f -> expectationFailure (describePlanFailure f)
      Right plan -> do
        checkTrajectory r (positions wps) 0.01 defaultAcceleration defaultJerk defaultTimeStep plan `shouldBe` []
        planDuration plan `shouldSatisfy` (> routeLength (planRoute plan) / 0.25)

  it "a Panda path that brings J2 onto its limit stays within it between the tracked samples (the cubic used to bulge 1.6e-7 rad past -101 deg)" $ do
    let r = robot "franka-panda"
        wps = [ waypoint (-0.3, 0, 0.6) (0, 1, 0, 0), waypoint (0.3, 0, 0.6) (0, 1, 0, 0) ]
    case planPath (planRequest r wps) of
      Left f -> expectationFailure (describePlanFailure f)
      Right plan -> checkTrajectory r (positions wps) 0.01 defaultAcceleration defaultJerk defaultTimeStep plan `shouldBe` []

  it "plans the same recording at 1 m/s on a 2 ms step: the streamed speeds keep the jerk limit across every join of parts (each part stretched onto its own length made them step: 4 % above it on the README's workflow at v1000, 2 ms)" $ do
    wps <- placedFreiburg
    let r = robot "ur5"
        rq = (planRequest r wps) { prSpeed = 1 *~ mps, prTimeStep = 0.002 *~ second }
    case planPath rq of
      Left f -> expectationFailure (describePlanFailure f)
      Right plan -> do
        checkTrajectory r (positions wps) 0.01 defaultAcceleration defaultJerk 0.002 plan `shouldBe` []
        length (planStretches plan) `shouldSatisfy` (> 1)
        -- the parts are scaled together between rests: each one's samples lie where the ones
        -- before it ended, micrometres from its own profile's
        let drift = maximum [ abs (a' - a) | (a, a', _) <- planPartMaps plan ]
        drift `shouldSatisfy` (< 1e-4)

  it "plans the same recording at 3 m/s, where the joints bind and the route is timed in parts: legal by the independent checker" $ do
    wps <- placedFreiburg
    let r = robot "ur5"
        acc = 10; jerk = 200
        rq = (planRequest r wps) { prSpeed = 3 *~ mps, prAcceleration = acc *~ mps2, prJerk = jerk *~ mps3 }
    case planPath rq of
      Left f -> expectationFailure (describePlanFailure f)
      Right plan -> do
        checkTrajectory r (positions wps) 0.01 acc jerk defaultTimeStep plan `shouldBe` []
        -- a route without stops, timed in parts (docs/plan.md, steps 3, 7, 8 and 9)
        length (planStretches plan) `shouldSatisfy` (> 1)

  -- the README's workflow: freiburg1_xyz compressed, turned by 180° about z and moved over the
  -- table of cell.obj (examples/freiburg-task.yaml), planned for a UR10 holding a camera
  it "in the work cell, without a start: the most dexterous first solution that keeps the clearance, and a clear trajectory (brute force over every triangle)" $ do
    dir <- shared
    Right mesh <- readObj (dir </> "data" </> "cell" </> "cell.obj")
    rec <- loadTum "freiburg1_xyz-groundtruth.txt"
    let Right c = compress defaultSettings { sPoints = Just 40 } rec
        Path tr = oPath c
        wps = take 6 [ waypoint (1.80 - x, 0.36 - y, z - 1.10) (w', a', b', c')
                     | (P3 x y z, q) <- zip (ptoList (tPos tr)) (ptoList (tRot tr))
                     , let Q4 w' a' b' c' = qmul (Q4 0 0 0 1) q ]
        r0 = robot "ur10"
        r = r0 { robotTool = robotTool r0 `T.compose` T.fromRpy (V3 0 0 0.10) (V3 0 0 0) }
        cm = collisionModel defaultCollisionOptions { coTool = Just (Capsule (V3 0 0 (-0.10)) (V3 0 0 (-0.02)) 0.04), coSceneIgnore = [1] } r
        bvh = buildBvh mesh
        tris = oMesh [ (pt a, pt b, pt c') | (a, b, c') <- triangles mesh ]
        pt (V3 x y z) = (x, y, z)
        rq = (planRequest r wps) { prSpeed = 0.25 *~ mps, prTrack = defaultTrackOptions { toEnvironment = Just (Environment cm bvh 0.01) } }
        kin = kinematicsFor r
        ch = kinChain kin
        manip q = manipulability (U.length q) (snd (jacobian ch q))
        Waypoint (L.V3 x0 y0 z0) (L.Quaternion qw0 (L.V3 qx0 qy0 qz0)) = head wps
        target0 = T.fromQuat (V3 (si x0) (si y0) (si z0)) (Quat qw0 qx0 qy0 qz0)
        -- one solution per geometry (whole turns apart are one), each with the oracle's clearance
        sameGeometry a b = U.all (\d -> abs (d - 2 * pi * fromIntegral (round (d / (2 * pi)) :: Int)) < 1e-6) (U.zipWith (-) a b)
        sols = nubBy sameGeometry (map solJoints (either (const []) id (solveIk defaultIkOptions { ikAllSolutions = True } kin target0 Nothing)))
        clear = [ q | q <- sols, oracleClearance cm tris (U.toList q) >= 0.01 ]
    length clear `shouldSatisfy` (> 1)
    case planPath rq of
      Left f -> expectationFailure (describePlanFailure f)
      Right plan -> do
        let traj = planTrajectory plan
            q0 = trajectoryQ traj 0
            n = trajectoryCount traj
        oracleClearance cm tris (U.toList q0) `shouldSatisfy` (>= 0.01 - 1e-9)
        manip q0 `shouldSatisfy` (>= maximum (map manip clear) - 1e-9)
        mapM_ (\k -> oracleClearance cm tris (U.toList (trajectoryQ traj k)) `shouldSatisfy` (>= 0.01 - 1e-6)) [0, n `div` 10 .. n - 1]
        checkTrajectory r (positions wps) 0.01 defaultAcceleration defaultJerk defaultTimeStep plan `shouldBe` []

-- | freiburg1_xyz compressed to 40 waypoints and placed by 'placeRecording'.
placedFreiburg :: IO [Waypoint]
placedFreiburg = do
  rec <- loadTum "freiburg1_xyz-groundtruth.txt"
  let Right c = compress defaultSettings { sPoints = Just 40 } rec
      Path tr = oPath c
  pure (placeRecording (ptoList (tPos tr)) (ptoList (tRot tr)))

-- | A recording placed in the UR5's workspace: positions relative to the first sample, scaled
-- by 0.5, from (0.45, 0, 0.30) m; orientations the tool-down orientation turned by the
-- recording's rotation relative to its first sample.
placeRecording :: [P3] -> [Q4] -> [Waypoint]
placeRecording ps qs =
  [ waypoint (0.45 + 0.5 * (x - x0), 0.5 * (y - y0), 0.30 + 0.5 * (z - z0)) (w, a, b, c)
  | (P3 x y z, q) <- zip ps qs
  , let Q4 w a b c = qmul (Q4 0 1 0 0) (qmul (qconj q0) q) ]
  where
    P3 x0 y0 z0 = head ps
    q0 = head qs
