-- | Validation of robot models and joint vectors: every problem at once, each naming the field
-- (@joints[2].limits.max@), the offending value, its unit and the rule it breaks.
--
-- Invariant: a model for which 'validateRobot' returns no error can be compiled and used by
-- forward kinematics, the Jacobian and IK without producing NaN from its own data; a joint vector
-- for which 'checkJointVector' returns no error has the right length and finite entries.
module VProf.Kinematics.Validate
  ( FieldError (..)
  , renderFieldError
  , validateRobot
  , validateRobotIn
  , ShowUnits (..)
  , siUnits
  , checkJointVector
  , jointsOutsideLimits
  ) where

import qualified Data.Set as Set
import qualified Data.Vector.Unboxed as U

import VProf.Kinematics.Model
import VProf.Validation
import VProf.Kinematics.Transform

-- | An error with the value as text (as the model holds it, in its SI unit).
fe :: String -> String -> String -> String -> FieldError
fe f v = FieldError f (Literal v)

-- | The units a model's values are shown in by 'validateRobotIn': a length in SI is divided by
-- the length scale and named by its name, an angle likewise (a robot file's @units@: a value typed
-- in degrees is reported in degrees, not in the radians the model holds).
data ShowUnits = ShowUnits
  { suLength :: !Double, suLengthName :: String   -- ^ metres per unit, e.g. 0.001 "mm"
  , suAngle :: !Double, suAngleName :: String     -- ^ radians per unit, e.g. π/180 "deg"
  }

-- | The model's own units: m and rad.
siUnits :: ShowUnits
siUnits = ShowUnits 1 "m" 1 "rad"

-- | A value in its SI unit ("m", "m/s", "m/s^2", "rad", "rad/s", "rad/s^2"; any other unit is
-- shown as it is) as text in the shown units, with its unit's name. A converted value is rounded
-- to 12 significant digits (165° read and shown again is not 165.00000000000003°).
showIn :: ShowUnits -> String -> Double -> (String, String)
showIn ShowUnits{..} u v = case u of
  "m" -> len ""
  "m/s" -> len "/s"
  "m/s^2" -> len "/s^2"
  "rad" -> ang ""
  "rad/s" -> ang "/s"
  "rad/s^2" -> ang "/s^2"
  _ -> (show v, u)
  where
    len suffix = conv suLength (suLengthName ++ suffix)
    ang suffix = conv suAngle (suAngleName ++ suffix)
    conv scale name
      | scale == 1 = (show v, name)
      | otherwise = (showNumber (roundSignificant (v / scale)), name)

-- | A finite length (unit "m") beyond 'maxCoordinate' or angle (unit "rad") beyond
-- 'maxAngleDeg': taken for a wrong unit (a link of 1e200 m made every IK residual infinite
-- or NaN; the sine of 1e300 rad is noise).
tooLarge :: ShowUnits -> String -> Double -> String -> [FieldError]
tooLarge su f v u
  | u == "m", abs v > maxCoordinate = [feIn su f v u tooLongRule]
  | u == "rad", abs v > maxAngleDeg * pi / 180 = [feIn su f v u tooWideRule]
  | otherwise = []

-- | An error on a value held in SI unit u, shown in the given units.
feIn :: ShowUnits -> String -> Double -> String -> String -> FieldError
feIn su f v u = let (t, u') = showIn su u v in fe f t u'

-- | The largest coupling of a link to a joint (a drive coefficient, a URDF mimic multiplier):
-- gearings and linkages couple by ratios of a few; 1e300 froze the joint (its limits shrank
-- to ±1e-300) and made the Jacobian's entries 1e300.
maxCoupling :: Double
maxCoupling = 1e6

-- | The joint speeds and accelerations taken (SI, with the words for them): a value outside is
-- a wrong number or unit. A speed of 1e308 made every cycle time 0 s, one of 1e-300 left the
-- planner a TCP acceleration of 1e-303 m/s², too weak for any time step.
data Range = Range !Double !Double String

speedRange, accelerationRange :: JointKind -> Range
speedRange Revolute = Range (1e-3 * pi / 180) (1e6 * pi / 180) "0.001 to 1e6 degrees a second"
speedRange Prismatic = Range 1e-6 1e3 "1e-6 to 1000 m/s"
accelerationRange Revolute = Range (1e-3 * pi / 180) (1e8 * pi / 180) "0.001 to 1e8 degrees a second squared"
accelerationRange Prismatic = Range 1e-6 1e6 "1e-6 to 1e6 m/s²"

outsideRange :: Range -> Double -> Maybe String
outsideRange (Range lo hi words') x
  | x < lo * (1 - 1e-12) || x > hi * (1 + 1e-12) = Just ("must be from " ++ words' ++ " (is the unit right?)")
  | otherwise = Nothing

unitOf :: JointKind -> (String, String, String)
unitOf Revolute = ("rad", "rad/s", "rad/s^2")
unitOf Prismatic = ("m", "m/s", "m/s^2")

-- | Every problem of a model, values in its SI units.
validateRobot :: Robot -> [FieldError]
validateRobot = validateRobotIn siUnits

-- | Every problem of a model, each value shown in the given units (those its file was typed in).
validateRobotIn :: ShowUnits -> Robot -> [FieldError]
validateRobotIn su Robot{..} =
  [fe "name" (show robotName) "" "must not be empty" | null robotName]
    ++ [fe "joints" "[]" "" "a robot needs at least one actuated joint" | null robotJoints]
    ++ [ fe ("joints[" ++ show i ++ "].name") (show (jointName j)) "" "duplicate joint name"
       | (i, j, seen) <- zip3 [0 :: Int ..] robotJoints (scanl (flip Set.insert) Set.empty (map jointName robotJoints))
       , jointName j `Set.member` seen ]
    ++ concat (zipWith jointErrs [0 ..] robotJoints)
    ++ concat (zipWith linkErrs [0 ..] robotLinks)
    ++ [ fe ("joints[" ++ show k ++ "]") (show (jointName (robotJoints !! k))) "" "drives no link"
       | k <- [0 .. n - 1], not (k `Set.member` drivenSet) ]
    ++ tfErrs "base" robotBase
    ++ tfErrs "tool" robotTool
    ++ [fe "payload" (show p) "kg" "must be a finite number ≥ 0" | Just p <- [robotPayload], not (finite p && p >= 0)]
    ++ [feIn su "reach" r "m" "must be a finite number > 0" | Just r <- [robotReach], not (finite r && r > 0)]
  where
    n = length robotJoints
    driven = [k | l <- robotLinks, linkJointKind l /= Nothing, (k, _) <- driveTerms (linkDrive l)]
    drivenSet = Set.fromList driven
    jointErrs :: Int -> Joint -> [FieldError]
    jointErrs i Joint{..} =
      let p = "joints[" ++ show i ++ "]"
          (u, uv, ua) = unitOf jointKind
          Limits lo hi = jointLimits
          shown = fst . showIn su u
      in [feIn su (p ++ ".limits.min") lo u "must be a number (−∞ only for a continuous joint)" | isNaN lo || lo == 1 / 0]
           ++ [feIn su (p ++ ".limits.max") hi u "must be a number (+∞ only for a continuous joint)" | isNaN hi || hi == -1 / 0]
           ++ [feIn su (p ++ ".limits.max") hi u ("must be above limits.min (" ++ shown lo ++ ")") | not (isNaN lo || isNaN hi), hi <= lo]
           ++ [fe (p ++ ".limits") (shown lo ++ ".." ++ shown hi) (snd (showIn su u lo)) "a prismatic joint needs finite limits" | jointKind == Prismatic, isInfinite lo || isInfinite hi]
           ++ [feIn su (p ++ ".max_velocity") v uv "must be a finite number > 0 (or absent)" | Just v <- [jointMaxVelocity], not (finite v && v > 0)]
           ++ [feIn su (p ++ ".max_acceleration") a ua "must be a finite number > 0 (or absent)" | Just a <- [jointMaxAcceleration], not (finite a && a > 0)]
           ++ [feIn su (p ++ ".max_velocity") v uv rule | Just v <- [jointMaxVelocity], finite v, v > 0, Just rule <- [outsideRange (speedRange jointKind) v]]
           ++ [feIn su (p ++ ".max_acceleration") a ua rule | Just a <- [jointMaxAcceleration], finite a, a > 0, Just rule <- [outsideRange (accelerationRange jointKind) a]]
    linkErrs :: Int -> Link -> [FieldError]
    linkErrs i Link{..} =
      let p = "links[" ++ show i ++ "]"
          geo = case linkGeometry of
            DhStandard a b c d -> nums [("dh.theta", a, "rad"), ("dh.d", b, "m"), ("dh.a", c, "m"), ("dh.alpha", d, "rad")]
            DhModified a b c d -> nums [("dh.alpha", a, "rad"), ("dh.a", b, "m"), ("dh.theta", c, "rad"), ("dh.d", d, "m")]
            UrdfJoint o (V3 x y z) ->
              tfErrs (p ++ ".origin") o
                ++ [fe (p ++ ".axis") (show [x, y, z]) "" "must be a finite, non-zero vector" | not (all finite [x, y, z]) || v3Norm (V3 x y z) < 1e-12]
            FixedTransform t -> tfErrs (p ++ ".transform") t
          nums xs = [feIn su (p ++ "." ++ f) v u "must be a finite number" | (f, v, u) <- xs, not (finite v)]
                    ++ concat [ tooLarge su (p ++ "." ++ f) v u | (f, v, u) <- xs, finite v ]
          drive = case linkJointKind of
            Nothing -> []
            Just _ ->
              [fe (p ++ ".drive") "[]" "" "a moving link needs at least one driving joint" | null (driveTerms linkDrive)]
                ++ [fe (p ++ ".drive.offset") (show (driveOffset linkDrive)) "" "must be a finite number" | not (finite (driveOffset linkDrive))]
                ++ [ fe (p ++ ".drive[" ++ show t ++ "].joint") (show k) "" ("must name one of the " ++ show n ++ " joints (0-based)")
                   | (t, (k, _)) <- zip [0 :: Int ..] (driveTerms linkDrive), k < 0 || k >= n ]
                ++ [ fe (p ++ ".drive[" ++ show t ++ "].coefficient") (show c) "" "must be a finite, non-zero number"
                   | (t, (_, c)) <- zip [0 :: Int ..] (driveTerms linkDrive), not (finite c) || c == 0 ]
                ++ [ fe (p ++ ".drive[" ++ show t ++ "].coefficient") (show c) "" ("must be at most " ++ showBound maxCoupling ++ " in magnitude (a ratio of a million is taken for a wrong value)")
                   | (t, (_, c)) <- zip [0 :: Int ..] (driveTerms linkDrive), finite c, abs c > maxCoupling ]
          caps = concat
            [ [feIn su (p ++ ".capsules[" ++ show c ++ "].radius") capRadius "m" "must be a finite number > 0 (a link without a body gives capsules: [])" | not (finite capRadius && capRadius > 0)]
                ++ (if finite capRadius then tooLarge su (p ++ ".capsules[" ++ show c ++ "].radius") capRadius "m" else [])
                ++ [fe (p ++ ".capsules[" ++ show c ++ "]") "" (suLengthName su) "endpoints must be finite" | not (all finite [ax, ay, az, bx, by, bz])]
                ++ take 1 (concat [ tooLarge su (p ++ ".capsules[" ++ show c ++ "]") v "m" | v <- [ax, ay, az, bx, by, bz], finite v ])
            | (c, Capsule{..}) <- zip [0 :: Int ..] linkCapsules, let V3 ax ay az = capA; V3 bx by bz = capB ]
      in geo ++ drive ++ caps
    tfErrs f t
      | not (all finite (toRows t)) = [fe f (show (toRows t)) "" "every entry must be a finite number"]
      | e : _ <- concat [ tooLarge su (f ++ ".xyz") v "m" | (k, v) <- zip [0 :: Int ..] (toRows t), k `mod` 4 == 3 ] = [e]
      | not (isRigid 1e-6 t) = [fe (f ++ ".rotation") (show (take 3 (toRows t))) "" "must be orthonormal with determinant +1"]
      | otherwise = []

-- | A joint vector for a robot of n joints: length, finite entries and (when asked) limits.
checkJointVector :: Bool -> Robot -> U.Vector Double -> [FieldError]
checkJointVector limits Robot{..} q =
  [ fe "q" (show (U.length q) ++ " values") "" ("the robot has " ++ show (length robotJoints) ++ " joints") | U.length q /= length robotJoints ]
    ++ [ fe ("q[" ++ show i ++ "]") (show x) u "must be a finite number"
       | (i, x, j) <- zip3 [0 :: Int ..] (U.toList q) robotJoints, not (finite x), let (u, _, _) = unitOf (jointKind j) ]
    -- a value beyond any robot's travel (1e9 m, a million degrees) gives no pose but noise:
    -- 1e308 m on a prismatic joint made the manipulability NaN
    ++ [ fe ("q[" ++ show i ++ "]") (show x) u (if jointKind j == Revolute then tooWideRule else tooLongRule)
       | (i, x, j) <- zip3 [0 :: Int ..] (U.toList q) robotJoints, finite x
       , let (u, _, _) = unitOf (jointKind j)
       , abs x > (if jointKind j == Revolute then maxAngleDeg * pi / 180 else maxCoordinate) ]
    ++ (if limits then jointsOutsideLimits "q" Robot{..} q else [])

-- | The entries of a joint vector outside their joints' limits, each naming @field[i]@, the
-- value and the limits in rad (revolute, with degrees beside them) or m (prismatic).
jointsOutsideLimits :: String -> Robot -> U.Vector Double -> [FieldError]
jointsOutsideLimits field r q =
  [ FieldError (field ++ "[" ++ show i ++ "]") (Number x) u
      ("is outside the limits of joint " ++ jointName j ++ ", [" ++ showNumber lo ++ ", " ++ showNumber hi ++ "] " ++ u
       ++ (if jointKind j == Revolute then " (" ++ deg x ++ " in [" ++ deg lo ++ ", " ++ deg hi ++ "] degrees)" else ""))
  | (i, x, j) <- zip3 [0 :: Int ..] (U.toList q) (robotJoints r), finite x
  , let Limits lo hi = jointLimits j
        (u, _, _) = unitOf (jointKind j)
  , x < lo - 1e-12 || x > hi + 1e-12 ]
  where deg v = showNumber (fromIntegral (round (v * 180 / pi * 1000) :: Integer) / 1000)
