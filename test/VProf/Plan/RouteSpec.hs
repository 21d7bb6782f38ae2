-- | The route: arc length, continuity of position and tangent through blends, deviation from
-- the waypoint polyline within the zone, and exact passage through the waypoints of @fine@,
-- over random waypoints and zones.
module VProf.Plan.RouteSpec (spec) where

import qualified Data.Vector as V
import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import Support.PlanChecker (polylineDistance)
import VProf.Geometry.Quaternion (qangle)
import VProf.Geometry.Vec (Q4 (..))
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

dist :: (Double, Double, Double) -> (Double, Double, Double) -> Double
dist (a, b, c) (x, y, z) = sqrt ((a - x) ^ (2 :: Int) + (b - y) ^ (2 :: Int) + (c - z) ^ (2 :: Int))

routeOf :: Case -> Route
routeOf (Case wps z) =
  either (error . show) id (mkRoute (map (const zone) wps) [ waypoint p q | (p, q) <- wps ])
  where zone = if z == 0 then Fine else Blend (z *~ meter)

tup :: V3 -> (Double, Double, Double)
tup (V3 x y z) = (x, y, z)

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
  it "turns the orientation continuously along s (no step above the grid's 0.5°)" $
    property $ forAll genCase $ \cs ->
      let rt = routeOf cs
          grid = U.toList (routeGrid 1e-3 (0.5 * pi / 180) rt)
          qs = map (snd . routeAt rt) grid
      in conjoin [ counterexample (show d) (d <= 0.5 * pi / 180 + 1e-9) | (a, b) <- zip qs (drop 1 qs), let d = qangle a b ]
  it "refuses waypoints closer than 0.1 mm, naming the waypoint" $ do
    let r = mkRoute [Fine, Fine] [waypoint (0, 0, 0) (1, 0, 0, 0), waypoint (0, 0, 0.00005) (1, 0, 0, 0)]
    case r of
      Left [e] -> do
        show e `shouldContain` "waypoints[1]"
        -- the distance is said as a distance, the position as a position (was "position = 0.05 mm")
        renderFieldError e `shouldContain` "is 0.05 mm from waypoint 0"
        renderFieldError e `shouldContain` "(0.0, 0.0, 0.00005) m"
      _ -> expectationFailure "expected one error"
