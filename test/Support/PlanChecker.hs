-- | An independent checker of a planned joint trajectory, written apart from VProf.Plan: it
-- reads only the trajectory's samples, the robot's published limits and DH table, the waypoints
-- and the zone, and recomputes everything itself:
--
-- * every joint value within its position limits (to 1e-9);
-- * every joint speed, by forward differences of q over the time step, within its published
--   limit, with a tolerance of 0.1 %;
-- * every joint acceleration, by second differences (q_{k+1} − 2·q_k + q_{k−1}) / dt², within its
--   limit — the robot file's max_acceleration, else the documented default 2·q̇max per second —
--   with a tolerance of 1 %;
-- * the TCP, by a textbook forward kinematics ("Support.FkOracle": one 4×4 matrix a DH step),
--   within the zone of the waypoint polyline: its distance to the nearest segment at most the
--   zone radius + 0.1 mm;
-- * every part's profile legal for its zones by the profile legality checker, from and to the
--   speeds it starts and ends at; the first part starting and the last part ending at rest, the
--   motion at rest at every stop of the route, and each part starting at the speed the previous
--   one ends at (to 0.1 %);
-- * the speed limit as listed to the user ('planZoneList'): the route from 0 to its end without
--   gap or overlap, and every sample's speed within the limit at its distance (to 0.1 %);
-- * ('checkWaypointPoses') every waypoint the motion rests at with its own orientation — the
--   first, the last, and both ends of every turn in place — held by some sample: the TCP
--   within 0.1 mm of its position and 1e-4 rad of its orientation;
-- * the TCP stream itself, as a controller follows it across the parts' joins: accelerations
--   and jerks from the velocity samples alone (at rest before the first and after the last)
--   within the plan's ranges, and the acceleration column equal to those differences (to
--   'streamTolerance');
-- * ('checkTcpMotion') the TCP's own motion against what the plan was asked for, from the
--   oracle's TCP positions alone: its speed (the distance between two samples over the time
--   step) within the requested speed and every listed zone at most that speed, its acceleration
--   and jerk along the path (differences of those speeds) within the requested ones: the checks
--   above take the limits from the plan's own listing and columns.
module Support.PlanChecker
  ( checkTrajectory
  , checkTcpMotion
  , checkWaypointPoses
  , oracleTcp
  , oracleTcpMatrix
  , polylineDistance
  , speedTolerance
  , accelerationTolerance
  , jointAccelerationLimit
  , tcpTolerance
  ) where

import qualified Data.Vector.Unboxed as U

import Support.FkOracle
import Support.LegalityOracle (Verdict (..), checkerAllowance, oracleVerdict, oracleViolations)
import VProf.Kinematics.Model
import VProf.Kinematics.Transform (toRows4)
import VProf.Plan (LimitZone (..), Plan (..), Route (..), Trajectory (..), planZoneList)
import VProf.Profile (Request (..), SpeedZone (..), check, defaultRequest, renderViolation, resProfile, validate)
import VProf.Profile.Sampled (Columns (..), columns)
import VProf.Units

-- | The TCP stream's acceleration and jerk against the plan's ranges: 1e-6 relative. Two parts
-- that meet at speed ask for the same speed there and are scaled together, so the stream keeps
-- the ranges across their joins as each part's profile keeps them inside (each part was
-- stretched onto its own length before, which made the speeds step where parts met: 4 % above
-- the jerk limit at a 2 ms step). Twice the jerk, as parts joined on one sample can give, is far
-- outside it.
streamTolerance :: Double
streamTolerance = 1e-6

speedTolerance, tcpTolerance, accelerationTolerance :: Double
speedTolerance = 1e-3
accelerationTolerance = 1e-2

-- | A joint's acceleration limit: the published one, else twice its speed limit per second.
jointAccelerationLimit :: Joint -> Maybe Double
jointAccelerationLimit j = case (jointMaxAcceleration j, jointMaxVelocity j) of
  (Just a, _) -> Just a
  (Nothing, Just v) -> Just (2 * v)
  _ -> Nothing
tcpTolerance = 1e-4

-- | At rest: a speed within 1e-9 m/s of 0, the rounding slack the profile legality checker
-- allows an end velocity (a 0.66 mm turn in place ended at 2.9e-10 m/s).
restSlack :: Double
restSlack = 1e-9

-- | The TCP position (m) at joint values q by the textbook matrices.
oracleTcp :: Robot -> [Double] -> (Double, Double, Double)
oracleTcp r qs = let m = oracleTcpMatrix r qs in (m !! 0 !! 3, m !! 1 !! 3, m !! 2 !! 3)

-- | The waypoints the motion rests at with their own orientation — the first, the last, and
-- both ends of every turn in place (consecutive waypoints within 0.1 mm) — each held by some
-- sample of the trajectory: the TCP (the textbook matrices) within 'tcpTolerance' of its
-- position and 1e-4 rad of its orientation (quaternions w, x, y, z).
checkWaypointPoses :: Robot -> [((Double, Double, Double), (Double, Double, Double, Double))] -> Plan -> [String]
checkWaypointPoses r wps plan =
  [ "waypoint " ++ show i ++ " is not reached: the nearest sample is " ++ show (d * 1000) ++ " mm and "
      ++ show (a * 180 / pi) ++ "° from its pose"
  | i <- rests
  , let (p, q) = wps !! i
        near = [ (dist3 p (m !! 0 !! 3, m !! 1 !! 3, m !! 2 !! 3), rotAngle (quatMat q) m) | m <- poses ]
        (d, a) = foldr1 (\x y -> if fst x + snd x <= fst y + snd y then x else y) ((1 / 0, 1 / 0) : near)
  , d > tcpTolerance || a > 1e-4 ]
  where
    tr = planTrajectory plan
    n = trDof tr
    m = U.length (trTime tr)
    poses = [ oracleTcpMatrix r [ trQ tr U.! (k * n + j) | j <- [0 .. n - 1] ] | k <- [0 .. m - 1] ]
    nw = length wps
    turnSeg j = dist3 (fst (wps !! j)) (fst (wps !! (j + 1))) < 1e-4
    rests = [ i | i <- [0 .. nw - 1], i == 0 || i == nw - 1 || turnSeg (i - 1) || (i < nw - 1 && turnSeg i) ]
    dist3 (a, b, c) (x, y, z) = sqrt ((a - x) ^ (2 :: Int) + (b - y) ^ (2 :: Int) + (c - z) ^ (2 :: Int))
    quatMat (w, x, y, z) =
      let k = sqrt (w * w + x * x + y * y + z * z); [qw, qx, qy, qz] = map (/ k) [w, x, y, z]
      in [ [1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qz * qw), 2 * (qx * qz + qy * qw)]
         , [2 * (qx * qy + qz * qw), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qx * qw)]
         , [2 * (qx * qz - qy * qw), 2 * (qy * qz + qx * qw), 1 - 2 * (qx * qx + qy * qy)] ]
    -- the angle of R_aᵀ·R_b from its trace
    rotAngle ra mb = let t = sum [ ra !! i !! j * mb !! i !! j | i <- [0 .. 2], j <- [0 .. 2] ]
                     in acos (max (-1) (min 1 ((t - 1) / 2)))

-- | The TCP's 4×4 matrix in the world: the base, every link, then the tool, by the textbook matrices.
oracleTcpMatrix :: Robot -> [Double] -> [[Double]]
oracleTcpMatrix r qs = foldl mmul (rows4 (robotBase r)) [ linkMat l (var (linkDrive l)) | l <- robotLinks r ] `mmul` rows4 (robotTool r)
  where
    rows4 t = let xs = toRows4 t in [take 4 xs, take 4 (drop 4 xs), take 4 (drop 8 xs), drop 12 xs]
    var (Drive off terms) = off + sum [ c * (qs !! j) | (j, c) <- terms ]
    linkMat l v = case (linkGeometry l, linkJointKind l) of
      (DhStandard th d a al, Just Revolute) -> dhStd (th + v) d a al
      (DhStandard th d a al, Just Prismatic) -> dhStd th (d + v) a al
      (DhStandard th d a al, Nothing) -> dhStd th d a al
      (DhModified al a th d, Just Revolute) -> dhMod al a (th + v) d
      (DhModified al a th d, Just Prismatic) -> dhMod al a th (d + v)
      (DhModified al a th d, Nothing) -> dhMod al a th d
      (FixedTransform t, _) -> rows4 t
      (UrdfJoint {}, _) -> error "PlanChecker: URDF robots are not covered"

-- | The distance of a point to a polyline.
polylineDistance :: [(Double, Double, Double)] -> (Double, Double, Double) -> Double
polylineDistance ps p = minimum (zipWith seg ps (drop 1 ps))
  where
    seg (ax, ay, az) (bx, by, bz) =
      let (px, py, pz) = p
          (dx, dy, dz) = (bx - ax, by - ay, bz - az)
          l2 = dx * dx + dy * dy + dz * dz
          u = if l2 <= 0 then 0 else max 0 (min 1 (((px - ax) * dx + (py - ay) * dy + (pz - az) * dz) / l2))
          (cx, cy, cz) = (ax + u * dx - px, ay + u * dy - py, az + u * dz - pz)
      in sqrt (cx * cx + cy * cy + cz * cz)

-- | The TCP's motion by the oracle's forward kinematics alone, against what the plan was asked
-- for: its speed (the distance between two samples over the time step, which a motion at most
-- that fast cannot exceed) within the requested speed (m/s) and every listed zone at most that
-- speed; and its acceleration and jerk along the path, by the first and second differences of
-- those speeds (at rest before the first sample and after the last), within the requested
-- acceleration (m/s²) and jerk (m/s³), to 'fkTolerance'. The length of a step along the path is
-- the mean of its two samples' speeds over the time step, so its differences keep the requested
-- ranges; the chord between two samples is shorter than the path where it bends: by at most
-- φ²/6 of it, φ the larger of the angles the TCP turns by at the step's two samples (an arc of
-- angle θ is θ²/24 longer than its chord, and a step turns by at most twice the angle at either
-- end), and each difference gets the bends of the steps it takes as an allowance. Where the TCP
-- runs straight that allowance is nought.
checkTcpMotion :: Robot -> Double -> Double -> Double -> Double -> Plan -> [String]
checkTcpMotion r speed acc jerk dt plan =
  take 5 [ "step " ++ show k ++ ": the TCP moves " ++ show (d * dt * 1000) ++ " mm in " ++ show dt ++ " s, "
           ++ show d ++ " m/s, above the requested " ++ show speed ++ " m/s"
         | (k, d) <- zip [0 :: Int ..] speeds, d > speed * (1 + speedTolerance) + 1e-9 ]
  ++ take 1 [ "the listed zone from " ++ show (lzStart z) ++ " m allows " ++ show (lzSpeed z) ++ " m/s, above the requested "
              ++ show speed ++ " m/s" | z <- planZoneList plan, lzSpeed z > speed * (1 + 1e-9) ]
  ++ take 5 [ "step " ++ show k ++ ": the TCP's acceleration along its path (oracle FK) is " ++ show a
              ++ " m/s², above the requested " ++ show acc ++ " (allowance for its bend " ++ show sl ++ ")"
            | (k, a, sl) <- zip3 [0 :: Int ..] accs accSlack, abs a > acc * (1 + fkTolerance) + sl + 1e-6 ]
  ++ take 5 [ "sample " ++ show k ++ ": the TCP's jerk along its path (oracle FK) is " ++ show j
              ++ " m/s³, above the requested " ++ show jerk ++ " (allowance for its bend " ++ show sl ++ ")"
            | (k, j, sl) <- zip3 [0 :: Int ..] jerks jerkSlack, abs j > jerk * (1 + fkTolerance) + sl + 1e-6 ]
  where
    tr = planTrajectory plan
    n = trDof tr
    m = U.length (trTime tr)
    tcps = [ oracleTcp r [ trQ tr U.! (k * n + i) | i <- [0 .. n - 1] ] | k <- [0 .. m - 1] ]
    steps = zipWith sub3 (drop 1 tcps) tcps
    speeds = [ norm3 d / dt | d <- steps ]
    -- the angle the TCP turns by at every sample (0 at the first and the last)
    turns = [0] ++ zipWith angle steps (drop 1 steps) ++ [0]
    bends = [ v * phi * phi / 6 | (v, phi) <- zip speeds (zipWith max turns (drop 1 turns)) ]
    diffs xs = zipWith (\x y -> (y - x) / dt) xs (drop 1 xs)
    sums xs = zipWith (\x y -> (x + y) / dt) xs (drop 1 xs)
    accs = diffs ([0] ++ speeds ++ [0])
    accSlack = sums ([0] ++ bends ++ [0])
    jerks = diffs ([0] ++ accs ++ [0])
    jerkSlack = sums ([0] ++ accSlack ++ [0])
    sub3 (ax, ay, az) (bx, by, bz) = (ax - bx, ay - by, az - bz)
    norm3 (x, y, z) = sqrt (x * x + y * y + z * z)
    angle u@(ux, uy, uz) w@(wx, wy, wz) =
      let nu = norm3 u; nw = norm3 w
      in if nu == 0 || nw == 0 then pi else acos (max (-1) (min 1 ((ux * wx + uy * wy + uz * wz) / (nu * nw))))

-- | The tolerance of the acceleration and jerk found from the oracle's TCP positions: 1 %.
fkTolerance :: Double
fkTolerance = 1e-2

-- | Every problem found (empty: the trajectory passes). The zone radius in m (0 for fine).
checkTrajectory :: Robot -> [(Double, Double, Double)] -> Double -> Double -> Double -> Double -> Plan -> [String]
checkTrajectory r wps zone acc jerk dt plan = concat
  [ [ "sample " ++ show k ++ ": " ++ jointName j ++ " = " ++ show x ++ " outside [" ++ show lo ++ ", " ++ show hi ++ "]"
    | k <- [0 .. m - 1], (i, j) <- zip [0 ..] joints, let x = q k i; Limits lo hi = jointLimits j
    , x < lo - 1e-9 || x > hi + 1e-9 ]
  , take 5 [ "step " ++ show k ++ ": " ++ jointName j ++ " speed " ++ show sp ++ " above its limit " ++ show vmax
           | k <- [0 .. m - 2], (i, j) <- zip [0 ..] joints, Just vmax <- [jointMaxVelocity j]
           , let sp = abs (q (k + 1) i - q k i) / (t (k + 1) - t k)
           , sp > vmax * (1 + speedTolerance) + 1e-9 ]
  , take 5 [ "sample " ++ show k ++ ": " ++ jointName j ++ " acceleration " ++ show ac ++ " above its limit " ++ show amax
           | k <- [1 .. m - 2], (i, j) <- zip [0 ..] joints, Just amax <- [jointAccelerationLimit j]
           , let h = t (k + 1) - t k
           , let ac = abs (q (k + 1) i - 2 * q k i + q (k - 1) i) / (h * h)
           , ac > amax * (1 + accelerationTolerance) + 1e-6 ]
  , take 5 [ "sample " ++ show k ++ ": the TCP is " ++ show (d * 1000) ++ " mm from the waypoint polyline (zone "
             ++ show (zone * 1000) ++ " mm)"
           | k <- [0 .. m - 1], let d = polylineDistance wps (oracleTcp r [ q k i | i <- [0 .. n - 1] ])
           , d > zone + tcpTolerance ]
  , [ "the time step is " ++ show (t (k + 1) - t k) ++ " s at sample " ++ show k | k <- take 1 [ k | k <- [0 .. m - 2], abs (t (k + 1) - t k - dt) > 1e-9 ] ]
  , concat [ profileProblems i zs res | (i, zs, res) <- zip3 [0 :: Int ..] (planZones plan) (planProfiles plan) ]
  , [ "the first part starts at " ++ show v ++ " m/s, not at rest" | Just v <- [take1 (map fst ends)], abs v > restSlack ]
  , [ "the last part ends at " ++ show v ++ " m/s, not at rest" | Just v <- [take1 (reverse (map snd ends))], abs v > restSlack ]
  , [ "the motion does not stop at the stop " ++ show st ++ " m: " ++ show v ++ " m/s there"
    | st <- rtStops (planRoute plan), (zs, (_, v)) <- zip (planZones plan) ends, not (null zs)
    , abs (lzEnd (last zs) - st) < 1e-9, abs v > restSlack ]
  , [ "part " ++ show (i + 1) ++ " starts at " ++ show v1 ++ " m/s, part " ++ show i ++ " ends at " ++ show v0 ++ " m/s"
    | (i, (_, v0), (v1, _)) <- zip3 [0 :: Int ..] ends (drop 1 ends), abs (v1 - v0) > 1e-3 * max v0 v1 + restSlack ]
  , [ "the trajectory is empty" | m == 0 ]
    -- the listed speed limit (the plan's zones, as the CLI and the wire give them): the route
    -- from 0 to its end without gap or overlap, and every sample's speed within it where it is
  , take 1 [ "the zone listing starts at " ++ show (lzStart z) ++ " m" | z : _ <- [listed], abs (lzStart z) > 1e-9 ]
  , take 1 [ "the zone listing ends at " ++ show (lzEnd z) ++ " m of " ++ show len | z <- take 1 (reverse listed), abs (lzEnd z - len) > 1e-6 * max 1 len ]
  , take 5 [ "the zone listing jumps from " ++ show (lzEnd z0) ++ " m to " ++ show (lzStart z1) ++ " m"
           | (z0, z1) <- zip listed (drop 1 listed), abs (lzStart z1 - lzEnd z0) > 1e-9 ]
  , take 5 [ "sample " ++ show k ++ ": " ++ show v ++ " m/s at " ++ show s ++ " m, above the listed limit " ++ show lim
           | k <- [0 .. m - 1], let s = trS tr U.! k; v = trV tr U.! k
             -- on a boundary between two zones, the higher (a profile's sample there keeps the next one's)
           , let lim = maximum ((-1 / 0) : [ lzSpeed z | z <- listed, lzStart z - 1e-9 <= s, s <= lzEnd z + 1e-9 ])
           , v > lim * (1 + speedTolerance) + 1e-9 ]
    -- the TCP stream as a controller follows it, sample by sample across the parts' joins:
    -- accelerations and jerks from the velocities alone, at rest before the first sample and
    -- after the last, and the acceleration column the same as those differences
  , take 5 [ "step " ++ show k ++ ": the TCP acceleration " ++ show a ++ " m/s² is above the limit " ++ show acc
           | (k, a) <- zip [0 :: Int ..] (U.toList streamA), abs a > acc * (1 + streamTolerance) + 1e-9 ]
  , take 5 [ "sample " ++ show k ++ ": the TCP jerk " ++ show j ++ " m/s³ is above the limit " ++ show jerk
             ++ " (accelerations " ++ show a0 ++ " then " ++ show a1 ++ " m/s²)"
           | (k, a0, a1) <- zip3 [0 :: Int ..] (0 : U.toList streamA) (U.toList streamA ++ [0])
           , let j = (a1 - a0) / dt, abs j > jerk * (1 + streamTolerance) + 1e-9 ]
  , take 5 [ "step " ++ show k ++ ": the acceleration column says " ++ show c ++ " m/s², the velocities " ++ show a
           | (k, a, c) <- zip3 [0 :: Int ..] (U.toList streamA) (U.toList (trA tr)), abs (a - c) > streamTolerance * jerk * dt + 1e-9 ]
  ]
  where
    tr = planTrajectory plan
    joints = robotJoints r
    n = trDof tr
    m = U.length (trTime tr)
    q k i = trQ tr U.! (k * n + i)
    t k = trTime tr U.! k
    take1 xs = case xs of { (x : _) -> Just x; [] -> Nothing }
    listed = planZoneList plan
    len = rtLength (planRoute plan)
    streamA = let v = trV tr in if U.length v < 2 then U.empty else U.zipWith (\v0 v1 -> (v1 - v0) / dt) v (U.tail v)
    -- each part's first and last speed
    ends = [ (U.head vs, U.last vs) | res <- planProfiles plan, Just p <- [resProfile res]
                                    , let vs = colVelocity (columns p), not (U.null vs) ]
    profileProblems i zs res = case zs of
      [] -> ["stretch " ++ show i ++ " has no zones"]
      (z0 : _) ->
        let a = lzStart z0
            b = lzEnd (last zs)
            -- the end tolerance the planner asks: 1e-5 of the part's length (1 µm at most), or
            -- where that profile ends farther short, a quarter of it, up to three times: the
            -- first under which the profile breaks no rule is the one it was asked with
            rq tol = defaultRequest
              { rqRouteLength = (b - a) *~ meter
              , rqZones = [ SpeedZone ((lzStart z - a) *~ meter) (lzSpeed z *~ mps) | z <- zs ]
              , rqMinAcceleration = negate acc *~ mps2, rqMaxAcceleration = acc *~ mps2
              , rqMinJerk = negate jerk *~ mps3, rqMaxJerk = jerk *~ mps3
              , rqTimeStep = Just (dt *~ second), rqEndTolerance = Just (tol *~ meter) }
            tols = take 4 (iterate (/ 4) (min 1e-6 ((b - a) * 1e-5)))
        in case resProfile res of
             Nothing -> ["part " ++ show i ++ " has no profile"]
             Just p ->
               let vs = colVelocity (columns p)
                   asked tol = (rq tol) { rqStartVelocity = U.head vs *~ mps, rqEndVelocity = U.last vs *~ mps }
               in case map (validate . asked) tols of
                    Left es : _ -> ["part " ++ show i ++ ": its zones are not a valid request: " ++ show es]
                    vs' ->
                      let pbs = [ q | Right q <- vs' ]
                          pb = head ([ q | q <- pbs, null (check q p) ] ++ pbs)
                      in [ "part " ++ show i ++ ": " ++ renderViolation v | v <- take 5 (check pb p) ]
                         ++ [ "part " ++ show i ++ ": the independent oracle finds " ++ show (take 3 (oracleViolations checkerAllowance pb p))
                            | oracleVerdict pb p == SurelyIllegal ]
