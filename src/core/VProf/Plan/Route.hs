{-# LANGUAGE BangPatterns, RecordWildCards #-}
-- | The route of a plan: the polyline through the waypoints with a circular blend at every
-- corner that has a zone (RAPID zone data: @zN@ = N mm, @fine@ = stop at the waypoint), the
-- orientation by slerp along each segment, eased from one segment's rate of turning to the
-- next's around each blend ('Spin'), and arc length s as the one coordinate. A blend is the
-- circular arc tangent to both segments whose tangent points lie at distance t = min(zone,
-- half of each adjacent segment) from the corner; it never leaves the zone's sphere around the
-- waypoint, and its deviation from the corner is t·tan(θ/4) for the turning angle θ
-- (derivation in docs/plan.md). Two waypoints at one position (closer than
-- 0.1 mm) with different orientations are a turn in place: the motion stops before and after
-- it, and s counts the arc of a point 'turnRadius' (0.1 m) from the TCP, so that the speed
-- limit and the profile apply to the turn as to a move. Positions in m, angles in rad.
module VProf.Plan.Route
  ( Zone (..)
  , zoneRadius
  , Waypoint (..)
  , waypoint
  , PieceKind (..)
  , Piece (..)
  , Route (..)
  , mkRoute
  , routeLength
  , pieceAt
  , routeAt
  , routeTfAt
  , routeTangentAt
  , routeRadiusAt
  , routeGrid
  , Spin (..)
  , Turning (..)
  , spinAt
  , minWaypointGap
  , turnRadius
  , minTurnAngle
  , minZone
  , reversalAngle
  ) where

import Data.List (intercalate)
import qualified Data.Vector as V
import qualified Data.Vector.Unboxed as U
import qualified Linear as L
import Numeric.Units.Dimensional.Prelude (Length, (*~), (/~), metre)

import VProf.Geometry.Quaternion (qangle, qconj, qexp, qlog, qmul, slerpShort)
import VProf.Geometry.Vec (P3 (..), Q4 (..), norm)
import VProf.Kinematics.Transform (Quat (..), Tf, V3 (..), fromQuat, v3Add, v3Dot, v3Norm, v3Scale, v3Sub)
import VProf.Validation

-- | RAPID zone data of a corner: stop at the waypoint, or blend within this radius.
data Zone = Fine | Blend !(Length Double)
  deriving (Eq, Show)

-- | The zone radius in m (0 for 'Fine').
zoneRadius :: Zone -> Double
zoneRadius = \case
  Fine -> 0
  Blend z -> z /~ metre

-- | One waypoint: the TCP position and orientation (a quaternion; q and −q are the same).
data Waypoint = Waypoint
  { wpPosition    :: !(L.V3 (Length Double))
  , wpOrientation :: !(L.Quaternion Double)
  } deriving (Eq, Show)

-- | A waypoint from SI numbers: position (m) and quaternion (w, x, y, z).
waypoint :: (Double, Double, Double) -> (Double, Double, Double, Double) -> Waypoint
waypoint (x, y, z) (w, a, b, c) =
  Waypoint (L.V3 (x *~ metre) (y *~ metre) (z *~ metre)) (L.Quaternion w (L.V3 a b c))

-- | A straight move, a corner's blend, or a turn in place (the position fixed, or moving less
-- than 'minWaypointGap' in a straight line, while the orientation turns).
data PieceKind = Straight | Arc | Turn
  deriving (Eq, Show)

-- | One piece of the route. A straight piece runs from 'pcA' along the unit 'pcU'; an arc has
-- centre 'pcA', radius 'pcRadius', and its point at angle φ is A + r·(cos φ·U + sin φ·W)
-- (U from the centre to the start, W the direction of travel at the start). A turn in place
-- runs from 'pcA' by the whole (tiny, possibly zero) displacement 'pcU', its length the
-- 'turnRadius' times its angle. The orientation is not a piece's: see 'Spin'.
data Piece = Piece
  { pcKind    :: !PieceKind
  , pcStart   :: !Double   -- ^ s at the start (m)
  , pcLength  :: !Double   -- ^ m
  , pcA       :: !V3
  , pcU       :: !V3
  , pcW       :: !V3
  , pcRadius  :: !Double   -- ^ m (0 for a straight piece)
  , pcIndex   :: !Int      -- ^ the segment (straight: from waypoint i to i+1) or corner (arc: waypoint i)
  } deriving (Eq, Show)

-- | How the orientation turns along one stretch of s: by slerp from one orientation to another
-- at a steady rate, or eased along a cubic Bézier curve of rotations in cumulative form (Kim,
-- Kim and Shin 1995), q(u) = q_a·exp(w₁·β₁(u))·exp(w₂·β₂(u))·exp(w₃·β₃(u)) with u the fraction
-- of the stretch, β₁ = 1 − (1 − u)³, β₂ = 3u² − 2u³, β₃ = u³; its rotation rate at its ends is
-- 3·w₁ and 3·w₃ per stretch length, in the tool's frame.
data Turning = Steady !Q4 !Q4 | Eased !Q4 !P3 !P3 !P3
  deriving (Eq, Show)

-- | One stretch of the orientation along s. Along a segment the tool turns by slerp from its
-- first waypoint's orientation to its second's, steadily in the segment's length; around a
-- blended corner it eases from the incoming segment's rate to the outgoing one's over the blend
-- and as far again on either side as the blend's tangent length (at most half the straight move
-- beside it), so that the orientation's rate along s is continuous through the corner and the
-- joints' slopes dq/ds do not step where a blend meets a straight move (docs/plan.md).
data Spin = Spin
  { spStart   :: !Double  -- ^ s at the start (m)
  , spLength  :: !Double  -- ^ (m)
  , spTurning :: !Turning
  } deriving (Eq, Show)

data Route = Route
  { rtPieces    :: !(V.Vector Piece)
  , rtStarts    :: !(U.Vector Double)  -- ^ s at the start of every piece
  , rtLength    :: !Double             -- ^ m
  , rtWaypointS :: !(U.Vector Double)  -- ^ s of each waypoint (the middle of its blend when blended)
  , rtStops     :: ![Double]           -- ^ s of the interior waypoints where the motion stops
  , rtPoints    :: ![V3]               -- ^ the waypoints' positions (m)
  , rtZones     :: !(U.Vector Double)  -- ^ per waypoint, the zone radius used (m; 0: a stop)
  , rtSpins     :: !(V.Vector Spin)    -- ^ the orientation along s, stretch by stretch
  , rtSpinStarts :: !(U.Vector Double)
  } deriving (Show)

routeLength :: Route -> Double
routeLength = rtLength

-- | Consecutive waypoints closer than this (m) are a turn in place, or refused when their
-- orientations differ by less than 'minTurnAngle' (s would not advance).
minWaypointGap :: Double
minWaypointGap = 1e-4

-- | On a turn in place, s is the arc of a point this far from the TCP (m): a turn of θ rad is
-- 0.1·θ m of route, and the TCP speed limit v holds that point to v (the tool turns at most
-- v / 0.1 rad/s: 286°/s at v500).
turnRadius :: Double
turnRadius = 0.1

-- | The least turn in place (rad): 'minWaypointGap' of route, 1e-3 rad (0.057°).
minTurnAngle :: Double
minTurnAngle = minWaypointGap / turnRadius

-- | The smallest blend radius (m; RAPID's smallest predefined zone, z0, is 0.3 mm): a corner
-- blended within less is driven no faster than a stop, and its tiny pieces cost a long plan
-- (a 0.1 µm zone took 12 s, 1 nm ran out of time). A zone is 0 (a stop) or at least this.
minZone :: Double
minZone = 1e-4

-- | A corner turning by more than this (rad) is a reversal: the motion stops there even with
-- a zone (the blend's radius would vanish).
reversalAngle :: Double
reversalAngle = pi - 1e-3

-- | The route through the waypoints, each corner with its zone (one zone a waypoint, missing
-- ones 'Fine'; the first and last are ignored: the route starts and ends at rest). Errors name the waypoint (from 0).
mkRoute :: [Zone] -> [Waypoint] -> Either [FieldError] Route
mkRoute zones wps = validated [errors] route
  where
    n = length wps
    zs = take n (zones ++ repeat Fine)
    pts = [ V3 (x /~ metre) (y /~ metre) (z /~ metre) | Waypoint (L.V3 x y z) _ <- wps ]
    qs = [ Q4 w a b c | Waypoint _ (L.Quaternion w (L.V3 a b c)) <- wps ]
    nums (V3 x y z) = [x, y, z]
    errors = concat
      [ ensure (n >= 2) (literalError "waypoints" (show n) "a route needs at least 2 waypoints")
      , concat [ [ fieldError ("waypoints[" ++ show i ++ "].position") v "m" "must be a finite number" | v <- nums p, not (finite v) ]
                 ++ take 1 [ fieldError ("waypoints[" ++ show i ++ "].position") v "m"
                               tooFarRule
                           | v <- nums p, finite v, abs v > maxCoordinate ]
               | (i, p) <- zip [0 :: Int ..] pts ]
      , concat [ ensure (all finite [w, a, b, c] && nq > 0.5 && nq < 2)
                   (fieldError ("waypoints[" ++ show i ++ "].orientation") nq ""
                      "the quaternion's norm must be about 1")
               | (i, Q4 w a b c) <- zip [0 :: Int ..] qs, let nq = sqrt (w*w + a*a + b*b + c*c) ]
      , concat [ ensure (not (all finite (nums p ++ nums p')) || d >= minWaypointGap || th >= minTurnAngle)
                   (literalError ("waypoints[" ++ show i ++ "].position")
                      ("(" ++ intercalate ", " (map showNumber (nums p)) ++ ") m")
                      ("is " ++ showNumber (fromIntegral (round (d * 1e6) :: Integer) / 1000) ++ " mm from waypoint " ++ show (i - 1)
                       ++ " and turns by " ++ showNumber (fromIntegral (round (th * 180 / pi * 1e4) :: Integer) / 1e4) ++ "° from it"
                       ++ "; consecutive waypoints must be at least " ++ showNumber (minWaypointGap * 1000)
                       ++ " mm apart, or turn by at least " ++ showNumber (fromIntegral (round (minTurnAngle * 180 / pi * 1e4) :: Integer) / 1e4)
                       ++ "° (a turn in place)"))
               | (i, (p', q'), (p, q)) <- zip3 [1 :: Int ..] (zip pts qs) (drop 1 (zip pts qs))
               , let d = v3Norm (v3Sub p p'); th = angleOf q' q ]
      , take 1 [ fieldError "zone" (z * 1000) "mm" "must be a finite number >= 0"
               | Blend zq <- zs, let z = zq /~ metre, not (finite z && z >= 0) ]
      , take 1 [ fieldError "zone" (z * 1000) "mm"
                   ("must be 0 (a stop) or at least " ++ showNumber (minZone * 1000) ++ " mm: a corner blended within less is driven no faster than a stop")
               | Blend zq <- zs, let z = zq /~ metre, finite z, z > 0, z < minZone ]
      ]
    route = buildRoute (U.fromList (map zoneRadius zs))
                       (V.fromList pts) (V.fromList (map norm4 qs))
    norm4 (Q4 w a b c) = let k = sqrt (w*w + a*a + b*b + c*c) in Q4 (w/k) (a/k) (b/k) (c/k)
    -- the angle between two orientations (rad; 0 when a quaternion is not finite or zero: its
    -- own error is named above)
    angleOf a b = let v = qangle (norm4 a) (norm4 b) in if finite v then v else 0

buildRoute :: U.Vector Double -> V.Vector V3 -> V.Vector Q4 -> Route
buildRoute zs pts qs = Route (V.fromList pieces) (U.fromList (map pcStart pieces)) total wpS stops (V.toList pts) tUsedZone
                             (V.fromList spins) (U.fromList (map spStart spins))
  where
    n = V.length pts
    nseg = n - 1
    segLen i = v3Norm (v3Sub (pts V.! (i + 1)) (pts V.! i))
    segDir i = v3Scale (1 / segLen i) (v3Sub (pts V.! (i + 1)) (pts V.! i))
    -- segment i turns in place (its waypoints at one position, validated to turn enough)
    isTurn i = i >= 0 && i < nseg && segLen i < minWaypointGap
    -- the turning angle at interior waypoint i (neither neighbour a turn in place)
    turn i = let c = max (-1) (min 1 (v3Dot (segDir (i - 1)) (segDir i))) in acos c
    -- the motion stops at a stop zone, a reversal, and before and after a turn in place
    isStop i = i > 0 && i < n - 1 && (zs U.! i <= 0 || isTurn (i - 1) || isTurn i || turn i >= reversalAngle)
    -- tangent length at each waypoint: 0 at the ends, at stops and where the path is straight
    tan' = U.generate n $ \i ->
      if i == 0 || i == n - 1 || isStop i then 0
      else let z = zs U.! i; th = turn i
           in if th < 1e-9 then 0 else minimum [z, segLen (i - 1) / 2, segLen i / 2]
    tUsedZone = tan'
    slerpSeg i u = slerpShort (qs V.! i) (qs V.! (i + 1)) u
    -- pieces, built segment by segment: the straight part of segment i, then the arc at
    -- waypoint i+1 (if any)
    go !s i acc
      | i >= nseg = (reverse acc, s)
      | isTurn i =
          let l = turnRadius * qangle (qs V.! i) (qs V.! (i + 1))
          in go (s + l) (i + 1) (Piece Turn s l (pts V.! i) (v3Sub (pts V.! (i + 1)) (pts V.! i)) (V3 0 0 0) 0 i : acc)
      | otherwise =
          let l = segLen i
              d = segDir i
              ta = tan' U.! i; tb = tan' U.! (i + 1)
              a = v3Add (pts V.! i) (v3Scale ta d)
              ls = l - ta - tb
              straight = Piece Straight s ls a d d 0 i
              s1 = s + max 0 ls
              acc1 = if ls > 1e-12 then straight : acc else acc
          in if tb > 0 && i + 1 < nseg
               then
                 let d2 = segDir (i + 1)
                     th = turn (i + 1)
                     r = tb / tan (th / 2)
                     nrm = let v = v3Sub d2 (v3Scale (v3Dot d2 d) d) in v3Scale (1 / v3Norm v) v
                     t1 = v3Sub (pts V.! (i + 1)) (v3Scale tb d)
                     c = v3Add t1 (v3Scale r nrm)
                     arc = Piece Arc s1 (r * th) c (v3Scale (-1) nrm) d r (i + 1)
                 in go (s1 + r * th) (i + 1) (arc : acc1)
               else go s1 (i + 1) acc1
    (pieces, total) = go 0 0 []
    -- the orientation, stretch by stretch (see 'Spin'): a steady slerp along each straight
    -- piece and turn, an eased stretch around each blend reaching into the straight pieces
    -- beside it by up to the corner's tangent length (half such a piece at most)
    pv = V.fromList pieces
    kindAt j = if j >= 0 && j < V.length pv then Just (pcKind (pv V.! j)) else Nothing
    reach t j = if kindAt j == Just Straight then min t (pcLength (pv V.! j) / 2) else 0
    rate i = scaleP (1 / segLen i) (qlog (qmul (qconj (qs V.! i)) (qs V.! (i + 1))))
    spins = filter ((> 1e-12) . spLength) (map spinOf [0 .. V.length pv - 1])
    spinOf j =
      let p = pv V.! j
          i = pcIndex p
      in case pcKind p of
           Turn -> Spin (pcStart p) (pcLength p) (Steady (qs V.! i) (qs V.! (i + 1)))
           Straight ->
             let l = segLen i; ta = tan' U.! i; tb = tan' U.! (i + 1)
                 e0 = if kindAt (j - 1) == Just Arc then reach ta j else 0
                 e1 = if kindAt (j + 1) == Just Arc then reach tb j else 0
             in Spin (pcStart p + e0) (pcLength p - e0 - e1)
                     (Steady (slerpSeg i ((ta + e0) / l)) (slerpSeg i ((l - tb - e1) / l)))
           Arc ->
             let t = tan' U.! i
                 e0 = reach t (j - 1); e1 = reach t (j + 1)
                 len = pcLength p + e0 + e1
                 qa = slerpSeg (i - 1) ((segLen (i - 1) - t - e0) / segLen (i - 1))
                 qb = slerpSeg i ((t + e1) / segLen i)
                 w1 = scaleP (len / 3) (rate (i - 1)); w3 = scaleP (len / 3) (rate i)
                 c1 = qmul qa (qexp w1); c2 = qmul qb (qexp (scaleP (-1) w3))
             in Spin (pcStart p - e0) len (Eased qa w1 (qlog (qmul (qconj c1) c2)) w3)
    scaleP k (P3 x y z) = P3 (k * x) (k * y) (k * z)
    -- waypoint s: the start of the route, each corner (blend middle or stop) and the end
    wpS = U.fromList (0 : [ cornerS i | i <- [1 .. n - 2] ] ++ [total | n >= 2])
    cornerS i = case [ p | p <- pieces, pcKind p == Arc, pcIndex p == i ] of
      (p : _) -> pcStart p + pcLength p / 2
      [] -> case [ p | p <- pieces, pcKind p /= Arc, pcIndex p == i ] of
              (p : _) -> pcStart p
              [] -> total
    stops = [ wpS U.! i | i <- [1 .. n - 2], isStop i ]

-- | The index of the piece holding s (the last whose start is <= s; clamped).
pieceAt :: Route -> Double -> Int
pieceAt rt = lastAtMost (rtStarts rt)

-- | The last index whose value is <= s (0 when none is; the values ascending).
lastAtMost :: U.Vector Double -> Double -> Int
lastAtMost st s = go 0 (U.length st - 1)
  where
    go lo hi
      | lo >= hi = lo
      | otherwise = let mid = (lo + hi + 1) `div` 2
                    in if st U.! mid <= s then go mid hi else go lo (mid - 1)

-- | The index of the orientation stretch holding s (the last whose start is <= s; clamped).
spinIndexAt :: Route -> Double -> Int
spinIndexAt rt = lastAtMost (rtSpinStarts rt)

-- | Position (m) and orientation at s (clamped to [0, L]).
routeAt :: Route -> Double -> (V3, Q4)
routeAt rt s0 = (pieceLocal (rtPieces rt V.! pieceAt rt s) s, spinAt (rtSpins rt V.! spinIndexAt rt s) s)
  where s = max 0 (min (rtLength rt) s0)

pieceLocal :: Piece -> Double -> V3
pieceLocal Piece{..} s =
  let x = max 0 (min pcLength (s - pcStart))
      f = if pcLength > 0 then x / pcLength else 0
  in case pcKind of
       Straight -> v3Add pcA (v3Scale x pcU)
       Turn -> v3Add pcA (v3Scale f pcU)
       Arc -> let ph = x / pcRadius
              in v3Add pcA (v3Add (v3Scale (pcRadius * cos ph) pcU) (v3Scale (pcRadius * sin ph) pcW))

-- | The orientation of a stretch at s (clamped to it).
spinAt :: Spin -> Double -> Q4
spinAt Spin{..} s =
  let x = max 0 (min spLength (s - spStart))
      f = if spLength > 0 then x / spLength else 0
      g = 1 - f
      turnBy k (P3 a b c) = qexp (P3 (k * a) (k * b) (k * c))
  in case spTurning of
       Steady qa qb -> slerpShort qa qb f
       Eased qa w1 w2 w3 -> qmul (qmul (qmul qa (turnBy (1 - g * g * g) w1)) (turnBy (f * f * (3 - 2 * f)) w2)) (turnBy (f * f * f) w3)

-- | How many times as densely in its rotation an eased stretch of the orientation is sampled:
-- its rate of turning changes within a few millimetres, and the joint path, cubic between
-- samples, follows it with an error whose third derivative shows in the TCP's jerk by forward
-- kinematics (docs/plan.md, section 2).
easedDensity :: Int
easedDensity = 4

-- | The largest rotation rate of a stretch per unit of its fraction u (rad): on an eased one
-- the rate is at most |w₁|·β₁' + |w₂|·β₂' + |w₃|·β₃', a quadratic in u maximised exactly.
spinRate :: Spin -> Double
spinRate sp = case spTurning sp of
  Steady qa qb -> qangle qa qb
  Eased _ w1 w2 w3 ->
    let a = 3 * norm w1; b = 6 * norm w2; c = 3 * norm w3
        at u = a * (1 - u) * (1 - u) + b * u * (1 - u) + c * u * u
        den = 2 * (a - b + c)
        vertex = [ u | den /= 0, let u = (2 * a - b) / den, u > 0, u < 1 ]
    in maximum (map at (0 : 1 : vertex))

-- | The pose at s as a rigid transform (the IK target).
routeTfAt :: Route -> Double -> Tf
routeTfAt rt s = let (p, Q4 w a b c) = routeAt rt s in fromQuat p (Quat w a b c)

-- | The unit tangent (direction of travel) at s; on a turn in place the direction of its
-- tiny displacement, or 0 when there is none.
routeTangentAt :: Route -> Double -> V3
routeTangentAt rt s0 =
  let s = max 0 (min (rtLength rt) s0)
      Piece{..} = rtPieces rt V.! pieceAt rt s
  in case pcKind of
       Straight -> pcU
       Turn -> let d = v3Norm pcU in if d > 0 then v3Scale (1 / d) pcU else V3 0 0 0
       Arc -> let ph = max 0 (min pcLength (s - pcStart)) / pcRadius
              in v3Add (v3Scale (negate (sin ph)) pcU) (v3Scale (cos ph) pcW)

-- | The radius of curvature at s (infinite on a straight piece).
routeRadiusAt :: Route -> Double -> Double
routeRadiusAt rt s = let p = rtPieces rt V.! pieceAt rt s in if pcKind p == Arc then pcRadius p else 1 / 0

-- | The sample positions along the route: every piece cut into equal steps of at most @ds@
-- (m), @dAngle@ (rad) of the tool's rotation at its fastest on the piece ('easedDensity' times
-- as many on an eased stretch) and, on a blend, twice @dAngle@ of the path's turn (a blend of a
-- fraction of a millimetre is sampled along its arc, not only at its two ends); piece ends are
-- samples; 0 and L included.
routeGrid :: Double -> Double -> Route -> U.Vector Double
routeGrid ds dAngle rt = U.fromList (concatMap one (V.toList (rtPieces rt)) ++ [rtLength rt])
  where
    turn p = if pcKind p == Arc && pcRadius p > 0 then pcLength p / pcRadius p else 0
    -- the fastest rotation (rad/m, the eased stretches' times their density) of the
    -- orientation's stretches that overlap [a, b]
    fastest a b =
      maximum (0 : [ dense sp * spinRate sp / spLength sp
                   | sp <- V.toList (V.slice i0 (i1 - i0 + 1) (rtSpins rt)), spLength sp > 0 ])
      where i0 = spinIndexAt rt a; i1 = max i0 (spinIndexAt rt (b - 1e-12))
    dense sp = case spTurning sp of { Eased{} -> fromIntegral easedDensity; _ -> 1 }
    one p =
      let a = pcStart p; l = pcLength p
          k = maximum [ 1, ceiling (l / ds), ceiling (fastest a (a + l) * l / dAngle)
                      , ceiling (turn p / (2 * dAngle)) ] :: Int
      in [ a + l * fromIntegral j / fromIntegral k | j <- [0 .. k - 1] ]
