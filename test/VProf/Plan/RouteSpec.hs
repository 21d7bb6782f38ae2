-- | The route: arc length, continuity of position and tangent through blends, of the
-- orientation's rate of turning at every seam but stops (finite differences), each segment's
-- steady rate with @fine@, deviation from
-- the waypoint polyline within the zone, and exact passage through the waypoints of @fine@,
-- over random waypoints and zones; turns in place (two waypoints at one position): the position
-- held, the orientation turned from one waypoint's to the next, 0.1 m of s per rad, a stop on
-- either side.
module VProf.Plan.RouteSpec (spec) where

import qualified Data.Vector as V
import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import Support.Gen (turnedBy)
import Support.PlanChecker (polylineDistance)
import VProf.Geometry.Quaternion (qangle, qconj, qlog, qmul)
import VProf.Geometry.Vec (P3 (..), Q4 (..))
import VProf.Kinematics.Transform (V3 (..), v3Dot, v3Norm, v3Sub)
import VProf.Plan
import VProf.Units
import VProf.Validation (renderFieldError)

data Case = Case [((Double, Double, Double), (Double, Double, Double, Double))] Double
  deriving (Show)

-- | 2–8 waypoints in a 1 m cube (consecutive ones at least 1 mm apart), random orientations,
-- a zone of 0 (fine) to 80 mm.
genCase :: Gen Case
genCase = do
  n <- choose (2, 8)
  ps <- vectorOf n ((,,) <$> c <*> c <*> c) `suchThat` gaps
  qs <- vectorOf n quat
  z <- oneof [pure 0, choose (0.0005, 0.08)]
  pure (Case (zip ps qs) z)
  where
    c = choose (-0.5, 0.5)
    gaps ps = and (zipWith (\a b -> dist a b >= 1e-3) ps (drop 1 ps))
    quat = do
      (w, x, y, z) <- (,,,) <$> g <*> g <*> g <*> g
      let k = sqrt (w * w + x * x + y * y + z * z)
      pure (if k < 1e-3 then (1, 0, 0, 0) else (w / k, x / k, y / k, z / k))
    g = choose (-1, 1)

-- | A case of 'genCase' with turns in place: after some waypoints a copy of its position (or one
-- moved by less than 0.1 mm) with another orientation, turned by 0.06°–180° from it.
genTurnCase :: Gen Case
genTurnCase = do
  Case wps z <- genCase
  let turnAfter (p@(x, y, zc), q) = do
        extra <- frequency [(2, pure False), (1, pure True)]
        if not extra then pure [(p, q)] else do
          shift <- oneof [pure (0, 0, 0), (,,) <$> tiny <*> tiny <*> tiny]
          q' <- rotated q
          let (dx, dy, dz) = shift
          pure [(p, q), ((x + dx, y + dy, zc + dz), q')]
  wps' <- concat <$> mapM turnAfter wps
  -- at least one turn
  wps'' <- if length wps' > length wps then pure wps' else do
             q' <- rotated (snd (head wps))
             pure (head wps : (fst (head wps), q') : tail wps)
  pure (Case wps'' z)
  where
    tiny = choose (-0.00003, 0.00003)
    -- q turned about a random axis by 0.06°–180°
    rotated (w, x, y, zq) = do
      Q4 w' x' y' z' <- turnedBy (oneof [choose (1.05e-3, 0.02), choose (0.02, pi)]) (Q4 w x y zq)
      pure (w', x', y', z')

dist :: (Double, Double, Double) -> (Double, Double, Double) -> Double
dist (a, b, c) (x, y, z) = sqrt ((a - x) ^ (2 :: Int) + (b - y) ^ (2 :: Int) + (c - z) ^ (2 :: Int))

routeOf :: Case -> Route
routeOf (Case wps z) =
  either (error . show) id (mkRoute (map (const zone) wps) [ waypoint p q | (p, q) <- wps ])
  where zone = if z == 0 then Fine else Blend (z *~ meter)

tup :: V3 -> (Double, Double, Double)
tup (V3 x y z) = (x, y, z)

-- | The step of the finite differences of the orientation's rate (m).
rateStep :: Double
rateStep = 1e-7

-- | The tool's body rate of turning (rad/m) just before and just after s, by the rotation
-- between orientations 'rateStep' apart, and how much each side's changes over the next step
-- (what the two may differ by when the rate is continuous but bends at s).
ratesAround :: Route -> Double -> ([Double], [Double], Double)
ratesAround rt s = (l1, r1, gap l1 l2 + gap r1 r2)
  where
    h = rateStep
    qAt = snd . routeAt rt
    rate a b = let P3 x y z = qlog (qmul (qconj (qAt a)) (qAt b)) in map (/ (b - a)) [x, y, z]
    l1 = rate (s - h) s; l2 = rate (s - 2 * h) (s - h)
    r1 = rate s (s + h); r2 = rate (s + h) (s + 2 * h)

gap :: [Double] -> [Double] -> Double
gap u v = sqrt (sum (zipWith (\x y -> (x - y) ^ (2 :: Int)) u v))

mag :: [Double] -> Double
mag = sqrt . sum . map (^ (2 :: Int))

spec :: Spec
spec = describe "VProf.Plan.Route" $ do
  it "has the length of its pieces, at most the polyline's, and equal to it with fine" $
    property $ forAll genCase $ \cs@(Case wps z) ->
      let rt = routeOf cs
          poly = sum (zipWith dist (map fst wps) (drop 1 (map fst wps)))
          pieces = sum (map pcLength (V.toList (rtPieces rt)))
      in counterexample (show (routeLength rt, poly, pieces)) $
           abs (pieces - routeLength rt) < 1e-9 && routeLength rt <= poly + 1e-9
             && (z > 0 || abs (routeLength rt - poly) < 1e-9)
  it "s is arc length: the chord sum over a 0.1 mm grid matches the length" $
    property $ forAll genCase $ \cs ->
      let rt = routeOf cs
          l = routeLength rt
          k = max 10 (ceiling (l / 1e-4)) :: Int
          pts = [ fst (routeAt rt (l * fromIntegral i / fromIntegral k)) | i <- [0 .. k] ]
          chord = sum (zipWith (\a b -> v3Norm (v3Sub a b)) pts (drop 1 pts))
      in counterexample (show (chord, l)) $ chord <= l + 1e-9 && chord >= l - 1e-4 * fromIntegral (V.length (rtPieces rt))
  it "is continuous in position everywhere, and in tangent except at stops" $
    property $ forAll genCase $ \cs ->
      let rt = routeOf cs
          ps = V.toList (rtPieces rt)
          -- each join with the least radius of its two pieces (infinite for straights): over the
          -- ±0.1 µm the tangents are compared across, each side turns by at most 0.1 µm / r (two
          -- blends meet where the segment between them is shorter than their zones)
          joins = [ (pcStart b, isStop, min (radius a) (radius b))
                  | (a, b) <- zip ps (drop 1 ps), let isStop = any (\x -> abs (x - pcStart b) < 1e-9) (rtStops rt) ]
          radius p = if pcKind p == Arc then pcRadius p else 1 / 0
          eps = 1e-9
          angle u v = acos (max (-1) (min 1 (v3Dot u v)))
      in conjoin [ counterexample ("at s = " ++ show s ++ " (least radius " ++ show r ++ " m)") $
                     v3Norm (v3Sub (fst (routeAt rt (s - eps))) (fst (routeAt rt (s + eps)))) < 1e-7
                     .&&. (stop || angle (routeTangentAt rt (s - 1e-7)) (routeTangentAt rt (s + 1e-7)) <= 2e-7 / r + 1e-5)
                 | (s, stop, r) <- joins ]
  it "stays within the zone of the waypoint polyline, and each blend within its waypoint's zone sphere" $
    property $ forAll genCase $ \cs@(Case wps z) ->
      let rt = routeOf cs
          l = routeLength rt
          grid = [ l * fromIntegral i / 2000 | i <- [0 .. 2000 :: Int] ]
          dev s = polylineDistance (map fst wps) (tup (fst (routeAt rt s)))
          arcs = [ (p, wp) | p <- V.toList (rtPieces rt), pcKind p == Arc, let wp = fst (wps !! pcIndex p) ]
      in conjoin [ counterexample ("s = " ++ show s ++ ": " ++ show (dev s)) (dev s <= z + 1e-9) | s <- grid ]
         .&&. conjoin [ counterexample "arc" $ dist (tup (fst (routeAt rt s))) wp <= z + 1e-9
                      | (p, wp) <- arcs, i <- [0 .. 10 :: Int], let s = pcStart p + pcLength p * fromIntegral i / 10 ]
  it "with fine passes exactly through every waypoint, in position and orientation" $
    property $ forAll genCase $ \(Case wps _) ->
      let rt = routeOf (Case wps 0)
      in conjoin [ counterexample (show i) $
                     dist (tup p) pos < 1e-9 && qangle o (Q4 w x y zq) < 1e-6
                 | (i, (pos, (w, x, y, zq))) <- zip [0 :: Int ..] wps
                 , let (p, o) = routeAt rt (rtWaypointS rt U.! i) ]
  it "turns the orientation at a rate continuous along s but at stops (finite differences on either side of every seam)" $
    property $ forAll (oneof [genCase, genTurnCase]) $ \cs ->
      let rt = routeOf cs
          isStop s = any (\x -> abs (x - s) < 1e-9) (rtStops rt)
      in conjoin [ counterexample ("seam at s = " ++ show s ++ ": rate " ++ show lr ++ " then " ++ show rr) $
                     gap lr rr <= 2 * drift + 1e-6 * (1 + mag lr)
                 | s <- U.toList (rtStarts rt) ++ U.toList (rtSpinStarts rt), s > 3 * rateStep, s < routeLength rt - 3 * rateStep, not (isStop s)
                 , let (lr, rr, drift) = ratesAround rt s ]
  it "with fine, turns along each segment at its own steady rate (the rotation between its waypoints over its length), which steps at the waypoint" $
    property $ forAll genCase $ \(Case wps _) ->
      let rt = routeOf (Case wps 0)
          toQ (w, x, y, zq) = Q4 w x y zq
          segRate i = let (pa, qa) = wps !! i; (pb, qb) = wps !! (i + 1)
                          P3 x y z = qlog (qmul (qconj (toQ qa)) (toQ qb))
                      in map (/ dist pa pb) [x, y, z]
      in conjoin [ counterexample ("waypoint " ++ show i ++ ": " ++ show (lr, rr) ++ " against " ++ show (segRate (i - 1), segRate i)) $
                     gap lr (segRate (i - 1)) <= drift + 1e-6 * (1 + mag lr) && gap rr (segRate i) <= drift + 1e-6 * (1 + mag rr)
                 | i <- [1 .. length wps - 2], let (lr, rr, drift) = ratesAround rt (rtWaypointS rt U.! i) ]
  it "turns the orientation continuously along s (no step above the grid's 0.5°)" $
    property $ forAll genCase $ \cs ->
      let rt = routeOf cs
          grid = U.toList (routeGrid 1e-3 (0.5 * pi / 180) rt)
          qs = map (snd . routeAt rt) grid
      in conjoin [ counterexample (show d) (d <= 0.5 * pi / 180 + 1e-9) | (a, b) <- zip qs (drop 1 qs), let d = qangle a b ]
  describe "turns in place" $ do
    it "hold the position, turn from one waypoint's orientation to the next's, take 0.1 m of s per rad, and stop on either side" $
      property $ forAll genTurnCase $ \cs@(Case wps _) ->
        let rt = routeOf cs
            turns = [ p | p <- V.toList (rtPieces rt), pcKind p == Turn ]
            toQ (w, x, y, zq) = Q4 w x y zq
            stopAt s = any (\x -> abs (x - s) < 1e-9) (0 : routeLength rt : rtStops rt)
        in counterexample (show (length turns) ++ " turns") (not (null turns))
           .&&. conjoin
             [ counterexample ("turn " ++ show i) $
                 let (pa, qa) = wps !! i; (pb, qb) = wps !! (i + 1)
                     th = qangle (toQ qa) (toQ qb)
                     at f = routeAt rt (pcStart p + f * pcLength p)
                     moved = dist pa pb
                 in abs (pcLength p - 0.1 * th) < 1e-12
                    .&&. conjoin [ counterexample (show f) (dist (tup (fst (at f))) pa <= moved + 1e-12) | f <- [0, 0.25, 0.5, 0.75, 1] ]
                    .&&. qangle (snd (at 0)) (toQ qa) < 1e-9 .&&. qangle (snd (at 1)) (toQ qb) < 1e-9
                    .&&. counterexample "turns on the short way at a steady rate"
                           (conjoin [ abs (qangle (snd (at f)) (toQ qa) - f * th) < 1e-6 | f <- [0.25, 0.5, 0.75] ])
                    .&&. counterexample "a stop before and after" (stopAt (pcStart p) && stopAt (pcStart p + pcLength p))
             | p <- turns, let i = pcIndex p ]
    it "with them, the route still passes every waypoint in position and orientation, stays within the zone, and turns by at most the grid's step" $
      property $ forAll genTurnCase $ \cs@(Case wps z) ->
        let rt = routeOf cs
            l = routeLength rt
            grid = U.toList (routeGrid 1e-3 (0.5 * pi / 180) rt)
            qs = map (snd . routeAt rt) grid
            fine = routeOf (Case wps 0)
        in conjoin [ counterexample ("waypoint " ++ show i) $ dist (tup p) pos < 1e-9 && qangle o (Q4 w x y zq) < 1e-6
                   | (i, (pos, (w, x, y, zq))) <- zip [0 :: Int ..] wps, let (p, o) = routeAt fine (rtWaypointS fine U.! i) ]
           .&&. conjoin [ counterexample ("s = " ++ show s) (polylineDistance (map fst wps) (tup (fst (routeAt rt s))) <= z + 1e-9)
                        | i <- [0 .. 500 :: Int], let s = l * fromIntegral i / 500 ]
           .&&. conjoin [ counterexample (show d) (d <= 0.5 * pi / 180 + 1e-9) | (a, b) <- zip qs (drop 1 qs), let d = qangle a b ]
    it "a repeated pose (a turn below 0.06°) is refused, naming the waypoint; 0.05 mm apart with a 10° turn is a turn" $ do
      let q10 = (cos (5 * pi / 180), sin (5 * pi / 180), 0, 0)
      case mkRoute [Fine, Fine] [waypoint (0.3, 0, 0.2) (1, 0, 0, 0), waypoint (0.3, 0, 0.2) (cos 2.5e-4, sin 2.5e-4, 0, 0)] of
        Left [e] -> do
          show e `shouldContain` "waypoints[1]"
          renderFieldError e `shouldContain` "is 0.0 mm from waypoint 0 and turns by 0.0286° from it"
          renderFieldError e `shouldContain` "or turn by at least 0.0573° (a turn in place)"
        r -> expectationFailure ("expected one error, got " ++ show (fmap routeLength r))
      case mkRoute [Fine, Fine] [waypoint (0.3, 0, 0.2) (1, 0, 0, 0), waypoint (0.3, 0, 0.20005) q10] of
        Right rt -> do
          map pcKind (V.toList (rtPieces rt)) `shouldBe` [Turn]
          routeLength rt `shouldSatisfy` (\l -> abs (l - 0.1 * 10 * pi / 180) < 1e-12)
        Left es -> expectationFailure (show es)
  it "refuses waypoints closer than 0.1 mm, naming the waypoint" $ do
    let r = mkRoute [Fine, Fine] [waypoint (0, 0, 0) (1, 0, 0, 0), waypoint (0, 0, 0.00005) (1, 0, 0, 0)]
    case r of
      Left [e] -> do
        show e `shouldContain` "waypoints[1]"
        -- the distance is said as a distance, the position as a position (was "position = 0.05 mm")
        renderFieldError e `shouldContain` "is 0.05 mm from waypoint 0"
        renderFieldError e `shouldContain` "(0.0, 0.0, 0.00005) m"
      _ -> expectationFailure "expected one error"
