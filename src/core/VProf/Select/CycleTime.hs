-- | The time of a joint-space point-to-point move, timed by the project's own jerk-limited
-- profile generator ("VProf.Profile"): every joint starts and stops together on the straight
-- line in joint space, so the move is one 1-D profile over the path parameter.
--
-- With Δq_i the joint distances and v_i, a_i, j_i the joint limits, the parameter s runs over
-- L = max_i |Δq_i| / v_i (the seconds the slowest joint needs at full speed) with joint i at
-- q_i + Δq_i·s/L; its speed limit is then 1, its acceleration limit min_i a_i·L/|Δq_i| and its
-- jerk limit min_i j_i·L/|Δq_i| (the tightest joint binds). Limits a robot file does not give
-- follow the default rule of 'jointRates' (docs/select.md).
module VProf.Select.CycleTime
  ( JointRates (..)
  , jointRates
  , defaultJointSpeed
  , accelerationTime
  , jerkTime
  , profileTimeStep
  , moveTime
  , cycleTime
  ) where

import qualified Data.Vector.Unboxed as U

import VProf.Kinematics.Model
import VProf.Profile
import VProf.Units

-- | Per joint: speed (rad/s or m/s), acceleration (/s²) and jerk (/s³) limits.
data JointRates = JointRates
  { jrVelocity :: U.Vector Double
  , jrAcceleration :: U.Vector Double
  , jrJerk :: U.Vector Double
  }
  deriving (Eq, Show)

-- | A joint whose speed is not published: 90 °/s (0.5 m/s for a prismatic joint).
defaultJointSpeed :: JointKind -> Double
defaultJointSpeed Revolute = pi / 2
defaultJointSpeed Prismatic = 0.5

-- | Without a published acceleration, a joint reaches its full speed in this time: a = v / 0.25 s.
accelerationTime :: Double
accelerationTime = 0.25

-- | The jerk limit takes the acceleration from 0 to a in this time: j = a / 0.05 s.
jerkTime :: Double
jerkTime = 0.05

-- | The generator's time step for joint moves (s).
profileTimeStep :: Double
profileTimeStep = 1 / 32

-- | The robot file's limits, or the default rule: v from the file or 'defaultJointSpeed';
-- a from the file or v / 'accelerationTime'; j = a / 'jerkTime'.
jointRates :: Robot -> JointRates
jointRates r =
  let js = robotJoints r
      vs = [maybe (defaultJointSpeed (jointKind j)) id (jointMaxVelocity j) | j <- js]
      as = [maybe (v / accelerationTime) id (jointMaxAcceleration j) | (j, v) <- zip js vs]
  in JointRates (U.fromList vs) (U.fromList as) (U.fromList (map (/ jerkTime) as))

-- | The time of the move from a to b (s), or why the generator found no profile.
moveTime :: JointRates -> U.Vector Double -> U.Vector Double -> Either String Double
moveTime JointRates{..} a b
  | len < 1e-9 = Right 0
  | otherwise = firstLegal [min profileTimeStep (len / 16), min profileTimeStep (len / 16) / 4]
  where
    -- the grid: 'profileTimeStep', finer for a short move (at least 16 steps over its full-speed
    -- time), and once more four times finer should the generator not arrive on the first
    firstLegal [] = Left ("no profile for a move of " ++ show len ++ " s at full speed")
    firstLegal (dt : rest) =
      let rq = defaultRequest
            { rqRouteLength = len *~ meter
            , rqZones = [SpeedZone (0 *~ meter) (1 *~ mps)]
            , rqMinAcceleration = negate acc *~ mps2
            , rqMaxAcceleration = acc *~ mps2
            , rqMinJerk = negate jerk *~ mps3
            , rqMaxJerk = jerk *~ mps3
            , rqTimeStep = Just (dt *~ second)
            , rqEndTolerance = Just ((1e-3 * len) *~ meter)
            }
          res = generatePure rq
      in case (resultLegal res, resProfile res) of
           (True, Just p) -> Right (duration p)
           _ | null rest -> Left ("no profile for a move of " ++ show len ++ " s at full speed: "
                                  ++ case resOutcome res of
                                       Failed f -> renderFailure f
                                       Generated -> "the checker found violations")
             | otherwise -> firstLegal rest
    d = U.map abs (U.zipWith (-) b a)
    moving = [i | i <- [0 .. U.length d - 1], d U.! i > 1e-12]
    len = maximum (0 : [d U.! i / jrVelocity U.! i | i <- moving])
    acc = minimum [jrAcceleration U.! i * len / d U.! i | i <- moving]
    jerk = minimum [jrJerk U.! i * len / d U.! i | i <- moving]

-- | The sum of the moves through the joint vectors in order.
cycleTime :: JointRates -> [U.Vector Double] -> Either String Double
cycleTime rates qs = sum <$> sequence (zipWith (moveTime rates) qs (drop 1 qs))
