-- | A robot-selection task: where the cell's meshes are, where the robot stands, what it carries
-- and holds, how far it must stay from the cell, and the poses (or the path) it must reach.
--
-- Plain records in SI units (m, kg, rad), so that a file reader ("VProf.Select.Format.Task") or a
-- wire layer can build one; 'checkTask' names every bad field with its value. With 'taskPath' the
-- straight segments between consecutive targets, sampled every 'taskPathStep', must be followed
-- on one branch without collision, not only the targets themselves (see docs/select.md).
module VProf.Select.Task
  ( Task (..)
  , MeshPlacement (..)
  , Target (..)
  , defaultPathStep
  , minPathStep
  , minPathStepRule
  , checkTask
  , placeRobot
  , segmentSamples
  , segmentSampleCount
  ) where

import VProf.Geometry.Quaternion (slerpShort)
import VProf.Geometry.Vec (Q4 (..))
import VProf.Kinematics.Model (Capsule (..), Robot (..))
import VProf.Kinematics.Transform
import VProf.Validation

-- | One mesh of the cell: an OBJ file, its uniform scale (0.001 for millimetres) and its pose in
-- the world (m).
data MeshPlacement = MeshPlacement
  { mpFile :: FilePath
  , mpScale :: Double
  , mpPose :: Tf
  }
  deriving (Eq, Show)

-- | A pose the tool frame must reach, in the world, with where it came from (for messages).
data Target = Target
  { tgLabel :: String   -- ^ e.g. "targets[2]" or "path.mod line 14"
  , tgPose :: Tf
  }
  deriving (Eq, Show)

data Task = Task
  { taskEnvironment :: [MeshPlacement]
  , taskBase :: Tf                     -- ^ the robot's base frame in the world
  , taskTool :: Tf                     -- ^ tool frame in the robot's flange frame
  , taskToolCapsule :: Maybe Capsule   -- ^ in the tool frame
  , taskPayload :: Double              -- ^ kg (the tool and the part)
  , taskClearance :: Double            -- ^ m, least distance between the robot and the cell
  , taskIgnoreBodies :: [Int]          -- ^ bodies left out of the cell check (1: the first link)
  , taskTargets :: [Target]
  , taskPath :: Bool                   -- ^ the segments between targets must be followed too
  , taskPathStep :: Double             -- ^ m, the sampling of those segments
  }
  deriving (Eq, Show)

-- | 5 mm.
defaultPathStep :: Double
defaultPathStep = 0.005

-- | The finest sampling of a path's segments (m): every step is an IK solution and a clearance
-- check, so a step of 1e-7 m ran for minutes.
minPathStep :: Double
minPathStep = 1e-4

minPathStepRule :: String
minPathStepRule = "must be at least 0.0001 m (0.1 mm): every step is an IK solution and a clearance check"

-- | Every problem of a task's numbers, each naming its field and value (m, kg).
checkTask :: Task -> [FieldError]
checkTask Task{..} = concat
  [ ensureFinite "payload" taskPayload "kg" (ensure (taskPayload >= 0) (fieldError "payload" taskPayload "kg" "must be >= 0"))
  , ensureFinite "clearance" taskClearance "m" (ensure (taskClearance >= 0) (fieldError "clearance" taskClearance "m" "must be >= 0"))
  , ensureFinite "path_step" taskPathStep "m" (ensure (taskPathStep >= minPathStep) (fieldError "path_step" taskPathStep "m" minPathStepRule))
  , concat [ ensureFinite ("environment[" ++ show i ++ "].scale") (mpScale m) ""
               (ensure (mpScale m > 0) (fieldError ("environment[" ++ show i ++ "].scale") (mpScale m) "" "must be > 0"))
           | (i, m) <- zip [0 :: Int ..] taskEnvironment ]
  , concat [ ensure (r > 0) (fieldError "tool_capsule.radius" r "m" "must be > 0")
             ++ ensure (r <= maxCoordinate) (fieldError "tool_capsule.radius" r "m" tooLongRule)
           | Just (Capsule _ _ r) <- [taskToolCapsule] ]
  , ensure (not (finite taskClearance) || taskClearance <= maxCoordinate)
      (fieldError "clearance" taskClearance "m" tooLongRule)
  , [ literalError "targets" "[]" "at least one target is needed" | null taskTargets ]
  , [ literalError "ignore_bodies" (show b) "body numbers are >= 1" | b <- taskIgnoreBodies, b < 1 ]
  ]

-- | The robot at the task's base, holding the task's tool.
placeRobot :: Task -> Robot -> Robot
placeRobot t r = r {robotBase = taskBase t `compose` robotBase r, robotTool = robotTool r `compose` taskTool t}

-- | The poses along the straight segment from a to b (excluded) to b (included): the position
-- interpolated linearly, the orientation by slerp the short way, at most step apart (m); a pure
-- rotation is sampled every step radians of turn (5 mm ↔ 0.005 rad, about 0.3°).
segmentSamples :: Double -> Tf -> Tf -> [Tf]
segmentSamples step a b =
  let pa = translation a; pb = translation b
      qa = toQ (toQuat a); qb = toQ (toQuat b)
      n = segmentSampleCount step a b
      at k = let s = fromIntegral k / fromIntegral n
                 Q4 w x y z = slerpShort qa qb s
             in fromQuat (v3Add pa (v3Scale s (v3Sub pb pa))) (Quat w x y z)
  in map at [1 .. n]
  where
    toQ (Quat w x y z) = Q4 w x y z

-- | How many poses 'segmentSamples' gives, without making them (a segment to a target 10^8 m
-- away has 2·10^10: counting the list's length made them all, and a path task ran until its
-- time was up where its walk stops at the first sample out of reach).
segmentSampleCount :: Double -> Tf -> Tf -> Int
segmentSampleCount step a b =
  let len = max (v3Norm (v3Sub (translation b) (translation a))) (rotationAngle (inverse a `compose` b))
  in max 1 (ceiling (len / step))
