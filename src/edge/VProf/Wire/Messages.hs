{-# LANGUAGE DataKinds #-}
{-# LANGUAGE DeriveGeneric #-}
-- | The Haskell side of @proto/vprof/v1/vprof.proto@, as records of Debian's @protobuf@
-- package. Field numbers and types mirror the schema one to one; every proto3 scalar is
-- 'Optional' (proto3 omits defaults, so an absent field means 0 / false / ""), repeated
-- scalars are 'Packed'. Records list their fields in field-number order, which is the
-- order the encoder writes them in, as protoc-generated code does.
--
-- Nothing here knows about units: "VProf.Wire.Profile" turns these records into the
-- @dimensional@ domain types and back (the thesis's "message handler").
module VProf.Wire.Messages
  ( -- * Velocity profiles
    SpeedLimitMsg (..)
  , ProfileRequestMsg (..)
  , ErrorMsg (..)
  , ViolationMsg (..)
  , ProfileResponseMsg (..)
  , AlgorithmEnum (..)
  , ErrorCodeEnum (..)
    -- * Path compression
  , PosesMsg (..)
  , CompressRequestMsg (..)
  , CompressMetricsMsg (..)
  , CompressedPathMsg (..)
  , CompressMethodEnum (..)
    -- * Robot kinematics
  , RobotMsg (..)
  , PoseMsg (..)
  , FkRequestMsg (..)
  , FkResponseMsg (..)
  , MeshMsg (..)
  , IkRequestMsg (..)
  , IkSolutionMsg (..)
  , IkResponseMsg (..)
    -- * Robot selection
  , CapsuleMsg (..)
  , SelectRequestMsg (..)
  , SelectFailureEnum (..)
  , SelectTargetMsg (..)
  , SelectSegmentMsg (..)
  , SelectRobotResultMsg (..)
  , SelectResponseMsg (..)
    -- * Path planning
  , PlanZoneMsg (..)
  , PlanRequestMsg (..)
  , PlanStatusEnum (..)
  , PlanResponseMsg (..)
    -- * Daemon envelope
  , PingMsg (..)
  , PongMsg (..)
  , RequestMsg (..)
  , ResponseMsg (..)
    -- * Encoding helpers
  , encodeBare
  , decodeBare
  , nonDefault
  , orDefault
  , Monoid' (..)
  , enumField
  , getEnum
  ) where

import Data.ByteString (ByteString)
import Data.Int (Int32)
import Data.ProtocolBuffers
import Data.Serialize (runGet, runPut)
import Data.Text (Text)
import Data.Word (Word32, Word64)
import GHC.Generics (Generic)

-- | Encode one bare message (no length prefix).
encodeBare :: Encode a => a -> ByteString
encodeBare = runPut . encodeMessage

-- | Decode one bare message (no length prefix).
decodeBare :: Decode a => ByteString -> Either String a
decodeBare = runGet decodeMessage

-- | proto3 writes a scalar only when it is not the default; so do we, so that
-- our bytes equal protoc's.
nonDefault :: (Eq a, Monoid' a) => a -> Maybe a
nonDefault x = if isZero' x then Nothing else Just x

-- | An absent proto3 scalar is its default.
orDefault :: Monoid' a => Maybe a -> a
orDefault = maybe zero' id

-- | The defaults of proto3 scalars.
class Eq a => Monoid' a where
  zero' :: a
  -- | Is this the value proto3 leaves out? For doubles, -0.0 is not: protoc writes it.
  isZero' :: a -> Bool
  isZero' = (== zero')
instance Monoid' Double where
  zero' = 0
  isZero' x = x == 0 && not (isNegativeZero x)
instance Monoid' Word32 where zero' = 0
instance Monoid' Word64 where zero' = 0
instance Monoid' Int32 where zero' = 0
instance Monoid' Bool where zero' = False
instance Monoid' Text where zero' = mempty

-- | An enum field: absent when it is the zero value, as proto3 writes it.
enumField :: (Enum e) => e -> Maybe e
enumField e = if fromEnum e == 0 then Nothing else Just e

-- | Read an enum field; absent means the zero value.
getEnum :: (Enum e) => Maybe e -> e
getEnum = maybe (toEnum 0) id

----------------------------------------------------------------------------- enums
-- Constructors are in wire-number order starting at 0, so 'fromEnum' is the wire number.
-- In a response, a number this version does not know decodes to the catch-all (see each
-- 'Enum'); in a request (algorithm, method) it is kept, so that the service refuses it
-- naming the field instead of running the default.

data AlgorithmEnum = AlgorithmDefault | AlgorithmBand | AlgorithmThesis | AlgorithmUnknown !Int
  deriving (Eq, Show)

instance Enum AlgorithmEnum where
  fromEnum AlgorithmDefault = 0
  fromEnum AlgorithmBand = 1
  fromEnum AlgorithmThesis = 2
  fromEnum (AlgorithmUnknown n) = n
  toEnum 0 = AlgorithmDefault
  toEnum 1 = AlgorithmBand
  toEnum 2 = AlgorithmThesis
  toEnum n = AlgorithmUnknown n

data ErrorCodeEnum
  = ErrUnspecified | ErrInvalidArgument | ErrInfeasible | ErrNotConverged
  | ErrMalformed | ErrFrameTooLarge | ErrUnsupported | ErrInternal
  deriving (Eq, Show, Bounded, Enum)

data CompressMethodEnum = CompressDefault | CompressThesis | CompressRdp | CompressKnots | CompressUnknown !Int
  deriving (Eq, Show)

instance Enum CompressMethodEnum where
  fromEnum CompressDefault = 0
  fromEnum CompressThesis = 1
  fromEnum CompressRdp = 2
  fromEnum CompressKnots = 3
  fromEnum (CompressUnknown n) = n
  toEnum 0 = CompressDefault
  toEnum 1 = CompressThesis
  toEnum 2 = CompressRdp
  toEnum 3 = CompressKnots
  toEnum n = CompressUnknown n

----------------------------------------------------------------------------- profiles

data SpeedLimitMsg = SpeedLimitMsg
  { slStartDistance :: Optional 1 (Value Double)
  , slVelocity      :: Optional 2 (Value Double)
  } deriving (Generic, Show, Eq)
instance Encode SpeedLimitMsg
instance Decode SpeedLimitMsg

data ProfileRequestMsg = ProfileRequestMsg
  { prqRequestId         :: Optional 1 (Value Word64)
  , prqRouteLength       :: Optional 2 (Value Double)
  , prqSpeedLimits       :: Repeated 3 (Message SpeedLimitMsg)
  , prqMinAcceleration   :: Optional 4 (Value Double)
  , prqMaxAcceleration   :: Optional 5 (Value Double)
  , prqMinJerk           :: Optional 6 (Value Double)
  , prqMaxJerk           :: Optional 7 (Value Double)
  , prqStartVelocity     :: Optional 8 (Value Double)
  , prqStartAcceleration :: Optional 9 (Value Double)
  , prqEndVelocity       :: Optional 10 (Value Double)
  , prqEndAcceleration   :: Optional 11 (Value Double)
  , prqTimeStep          :: Optional 12 (Value Double)
  , prqVelocityStep      :: Optional 13 (Value Double)
  , prqMaxIterations     :: Optional 14 (Value Word32)
  , prqTimeBudget        :: Optional 15 (Value Double)
  , prqEndTolerance      :: Optional 16 (Value Double)
  , prqAlgorithm         :: Optional 17 (Enumeration AlgorithmEnum)
  } deriving (Generic, Show, Eq)
instance Encode ProfileRequestMsg
instance Decode ProfileRequestMsg

data ErrorMsg = ErrorMsg
  { errCode    :: Optional 1 (Enumeration ErrorCodeEnum)
  , errField   :: Optional 2 (Value Text)
  , errMessage :: Optional 3 (Value Text)
  } deriving (Generic, Show, Eq)
instance Encode ErrorMsg
instance Decode ErrorMsg

data ViolationMsg = ViolationMsg
  { vioRule    :: Optional 1 (Value Text)
  , vioSample  :: Optional 2 (Value Word32)
  , vioValue   :: Optional 3 (Value Double)
  , vioLimit   :: Optional 4 (Value Double)
  , vioMessage :: Optional 5 (Value Text)
  } deriving (Generic, Show, Eq)
instance Encode ViolationMsg
instance Decode ViolationMsg

data ProfileResponseMsg = ProfileResponseMsg
  { prsRequestId    :: Optional 1 (Value Word64)
  , prsTimeStep     :: Optional 2 (Value Double)
  , prsVelocityStep :: Optional 3 (Value Double)
  , prsTime         :: Packed 4 (Value Double)
  , prsDistance     :: Packed 5 (Value Double)
  , prsVelocity     :: Packed 6 (Value Double)
  , prsAcceleration :: Packed 7 (Value Double)
  , prsJerk         :: Packed 8 (Value Double)
  , prsIterations   :: Optional 9 (Value Word32)
  , prsConverged    :: Optional 10 (Value Bool)
  , prsLegal        :: Optional 11 (Value Bool)
  , prsComputeTime  :: Optional 12 (Value Double)
  , prsViolations   :: Repeated 13 (Message ViolationMsg)
  , prsError        :: Optional 14 (Message ErrorMsg)
  , prsErrors       :: Repeated 15 (Message ErrorMsg)
  , prsDuration     :: Optional 16 (Value Double)
  , prsAlgorithm    :: Optional 17 (Enumeration AlgorithmEnum)
  } deriving (Generic, Show, Eq)
instance Encode ProfileResponseMsg
instance Decode ProfileResponseMsg

----------------------------------------------------------------------------- compression

data PosesMsg = PosesMsg
  { posTime :: Packed 1 (Value Double)
  , posX    :: Packed 2 (Value Double)
  , posY    :: Packed 3 (Value Double)
  , posZ    :: Packed 4 (Value Double)
  , posQw   :: Packed 5 (Value Double)
  , posQx   :: Packed 6 (Value Double)
  , posQy   :: Packed 7 (Value Double)
  , posQz   :: Packed 8 (Value Double)
  } deriving (Generic, Show, Eq)
instance Encode PosesMsg
instance Decode PosesMsg

data CompressRequestMsg = CompressRequestMsg
  { crqRequestId         :: Optional 1 (Value Word64)
  , crqRecording         :: Optional 2 (Message PosesMsg)
  , crqMethod            :: Optional 3 (Enumeration CompressMethodEnum)
  , crqPoints            :: Optional 4 (Value Word32)
  , crqMargin            :: Optional 5 (Value Double)
  , crqTolerance         :: Optional 6 (Value Double)
  , crqWeightPosition    :: Optional 7 (Value Double)
  , crqWeightOrientation :: Optional 8 (Value Double)
  , crqWeightVelocity    :: Optional 9 (Value Double)
  , crqSearchRounds      :: Optional 10 (Value Word32)
  , crqFreeEnds          :: Optional 11 (Value Bool)
  , crqLeastSquaresOnly  :: Optional 12 (Value Bool)
  } deriving (Generic, Show, Eq)
instance Encode CompressRequestMsg
instance Decode CompressRequestMsg

data CompressMetricsMsg = CompressMetricsMsg
  { cmPositionSse      :: Optional 1 (Value Double)
  , cmPositionRmse     :: Optional 2 (Value Double)
  , cmPositionMean     :: Optional 3 (Value Double)
  , cmPositionMax      :: Optional 4 (Value Double)
  , cmOrientationRmse  :: Optional 5 (Value Double)
  , cmOrientationMean  :: Optional 6 (Value Double)
  , cmOrientationMax   :: Optional 7 (Value Double)
  , cmVelocityRmse     :: Optional 8 (Value Double)
  , cmVelocityMean     :: Optional 9 (Value Double)
  , cmVelocityMax      :: Optional 10 (Value Double)
  , cmGeometricRmse    :: Optional 11 (Value Double)
  , cmGeometricMax     :: Optional 12 (Value Double)
  , cmLengthRatio      :: Optional 13 (Value Double)
  , cmOrientationRatio :: Optional 14 (Value Double)
  , cmPoints           :: Optional 15 (Value Word32)
  , cmSamples          :: Optional 16 (Value Word32)
  , cmReduction        :: Optional 17 (Value Double)
  } deriving (Generic, Show, Eq)
instance Encode CompressMetricsMsg
instance Decode CompressMetricsMsg

data CompressedPathMsg = CompressedPathMsg
  { cpRequestId   :: Optional 1 (Value Word64)
  , cpPath        :: Optional 2 (Message PosesMsg)
  , cpMetrics     :: Optional 3 (Message CompressMetricsMsg)
  , cpComputeTime :: Optional 4 (Value Double)
  , cpError       :: Optional 5 (Message ErrorMsg)
  , cpWarnings    :: Repeated 6 (Value Text)
  } deriving (Generic, Show, Eq)
instance Encode CompressedPathMsg
instance Decode CompressedPathMsg

----------------------------------------------------------------------------- kinematics

data RobotMsg = RobotMsg
  { robName      :: Optional 1 (Value Text)
  , robRobotFile :: Optional 2 (Value Text)
  , robUrdf      :: Optional 3 (Value Text)
  , robBaseLink  :: Optional 4 (Value Text)
  , robTipLink   :: Optional 5 (Value Text)
  } deriving (Generic, Show, Eq)
instance Encode RobotMsg
instance Decode RobotMsg

data PoseMsg = PoseMsg
  { poseX  :: Optional 1 (Value Double)
  , poseY  :: Optional 2 (Value Double)
  , poseZ  :: Optional 3 (Value Double)
  , poseQw :: Optional 4 (Value Double)
  , poseQx :: Optional 5 (Value Double)
  , poseQy :: Optional 6 (Value Double)
  , poseQz :: Optional 7 (Value Double)
  } deriving (Generic, Show, Eq)
instance Encode PoseMsg
instance Decode PoseMsg

data FkRequestMsg = FkRequestMsg
  { fkqRequestId  :: Optional 1 (Value Word64)
  , fkqRobot      :: Optional 2 (Message RobotMsg)
  , fkqJoints     :: Packed 3 (Value Double)
  , fkqLinkFrames :: Optional 4 (Value Bool)
  } deriving (Generic, Show, Eq)
instance Encode FkRequestMsg
instance Decode FkRequestMsg

data FkResponseMsg = FkResponseMsg
  { fksRequestId       :: Optional 1 (Value Word64)
  , fksTool            :: Optional 2 (Message PoseMsg)
  , fksLinkFrames      :: Repeated 3 (Message PoseMsg)
  , fksJacobian        :: Packed 4 (Value Double)
  , fksManipulability  :: Optional 5 (Value Double)
  , fksConditionNumber :: Optional 6 (Value Double)
  , fksComputeTime     :: Optional 7 (Value Double)
  , fksError           :: Optional 8 (Message ErrorMsg)
  , fksDof             :: Optional 9 (Value Word32)
  } deriving (Generic, Show, Eq)
instance Encode FkResponseMsg
instance Decode FkResponseMsg

data MeshMsg = MeshMsg
  { meshVertices  :: Packed 1 (Value Double)
  , meshTriangles :: Packed 2 (Value Word32)
  , meshScale     :: Optional 3 (Value Double)
  , meshPose      :: Optional 4 (Message PoseMsg)
  } deriving (Generic, Show, Eq)
instance Encode MeshMsg
instance Decode MeshMsg

data IkRequestMsg = IkRequestMsg
  { ikqRequestId         :: Optional 1 (Value Word64)
  , ikqRobot             :: Optional 2 (Message RobotMsg)
  , ikqTarget            :: Optional 3 (Message PoseMsg)
  , ikqSeed              :: Packed 4 (Value Double)
  , ikqAllSolutions      :: Optional 5 (Value Bool)
  , ikqPositionTolerance :: Optional 6 (Value Double)
  , ikqRotationTolerance :: Optional 7 (Value Double)
  , ikqTimeBudget        :: Optional 8 (Value Double)
  , ikqEnvironment       :: Repeated 9 (Message MeshMsg)
  , ikqClearance         :: Optional 10 (Value Double)
  , ikqIgnoreBodies      :: Packed 11 (Value Word32)
  } deriving (Generic, Show, Eq)
instance Encode IkRequestMsg
instance Decode IkRequestMsg

data IkSolutionMsg = IkSolutionMsg
  { iksJoints         :: Packed 1 (Value Double)
  , iksPositionError  :: Optional 2 (Value Double)
  , iksRotationError  :: Optional 3 (Value Double)
  , iksBranch         :: Optional 4 (Value Text)
  , iksManipulability :: Optional 5 (Value Double)
  , iksClearance      :: Optional 6 (Value Double)
  , iksSeedDistance   :: Optional 7 (Value Double)
  } deriving (Generic, Show, Eq)
instance Encode IkSolutionMsg
instance Decode IkSolutionMsg

data IkResponseMsg = IkResponseMsg
  { ikrRequestId   :: Optional 1 (Value Word64)
  , ikrSolutions   :: Repeated 2 (Message IkSolutionMsg)
  , ikrSolver      :: Optional 3 (Value Text)
  , ikrComputeTime :: Optional 4 (Value Double)
  , ikrError       :: Optional 5 (Message ErrorMsg)
  , ikrDof         :: Optional 6 (Value Word32)
  } deriving (Generic, Show, Eq)
instance Encode IkResponseMsg
instance Decode IkResponseMsg

----------------------------------------------------------------------------- selection

data CapsuleMsg = CapsuleMsg
  { cslMsgAx     :: Optional 1 (Value Double)
  , cslMsgAy     :: Optional 2 (Value Double)
  , cslMsgAz     :: Optional 3 (Value Double)
  , cslMsgBx     :: Optional 4 (Value Double)
  , cslMsgBy     :: Optional 5 (Value Double)
  , cslMsgBz     :: Optional 6 (Value Double)
  , cslMsgRadius :: Optional 7 (Value Double)
  } deriving (Generic, Show, Eq)
instance Encode CapsuleMsg
instance Decode CapsuleMsg

data SelectRequestMsg = SelectRequestMsg
  { slqRequestId    :: Optional 1 (Value Word64)
  , slqEnvironment  :: Repeated 2 (Message MeshMsg)
  , slqBase         :: Optional 3 (Message PoseMsg)
  , slqTool         :: Optional 4 (Message PoseMsg)
  , slqToolCapsule  :: Optional 5 (Message CapsuleMsg)
  , slqPayload      :: Optional 6 (Value Double)
  , slqClearance    :: Optional 7 (Value Double)
  , slqTargets      :: Repeated 8 (Message PoseMsg)
  , slqPath         :: Optional 9 (Value Bool)
  , slqPathStep     :: Optional 10 (Value Double)
  , slqRobots       :: Repeated 11 (Message RobotMsg)
  , slqIgnoreBodies :: Packed 12 (Value Word32)
  } deriving (Generic, Show, Eq)
instance Encode SelectRequestMsg
instance Decode SelectRequestMsg

-- | Constructors in wire-number order; an unknown number decodes to 'SelectFailureOther'.
data SelectFailureEnum
  = SelectFailureNone | SelectFailureReach | SelectFailureJointLimits | SelectFailureOrientation
  | SelectFailureCollision | SelectFailureSingular | SelectFailureBudget | SelectFailurePath
  | SelectFailureOther
  deriving (Eq, Show, Bounded)

instance Enum SelectFailureEnum where
  fromEnum = \case
    SelectFailureNone -> 0
    SelectFailureReach -> 1
    SelectFailureJointLimits -> 2
    SelectFailureOrientation -> 3
    SelectFailureCollision -> 4
    SelectFailureSingular -> 5
    SelectFailureBudget -> 6
    SelectFailurePath -> 7
    SelectFailureOther -> 8
  toEnum = \case
    0 -> SelectFailureNone
    1 -> SelectFailureReach
    2 -> SelectFailureJointLimits
    3 -> SelectFailureOrientation
    4 -> SelectFailureCollision
    5 -> SelectFailureSingular
    6 -> SelectFailureBudget
    7 -> SelectFailurePath
    _ -> SelectFailureOther

data SelectTargetMsg = SelectTargetMsg
  { stLabel          :: Optional 1 (Value Text)
  , stReached        :: Optional 2 (Value Bool)
  , stJoints         :: Packed 3 (Value Double)
  , stBranch         :: Optional 4 (Value Text)
  , stClearance      :: Optional 5 (Value Double)
  , stClearanceBody  :: Optional 6 (Value Text)
  , stManipulability :: Optional 7 (Value Double)
  , stFailure        :: Optional 8 (Value Text)
  , stFailureCode    :: Optional 9 (Enumeration SelectFailureEnum)
  } deriving (Generic, Show, Eq)
instance Encode SelectTargetMsg
instance Decode SelectTargetMsg

data SelectSegmentMsg = SelectSegmentMsg
  { ssFrom    :: Optional 1 (Value Word32)
  , ssTo      :: Optional 2 (Value Word32)
  , ssSamples :: Optional 3 (Value Word32)
  , ssFailure :: Optional 4 (Value Text)
  } deriving (Generic, Show, Eq)
instance Encode SelectSegmentMsg
instance Decode SelectSegmentMsg

data SelectRobotResultMsg = SelectRobotResultMsg
  { srRobot             :: Optional 1 (Value Text)
  , srName              :: Optional 2 (Value Text)
  , srRank              :: Optional 3 (Value Word32)
  , srRejected          :: Optional 4 (Value Text)
  , srTargets           :: Repeated 5 (Message SelectTargetMsg)
  , srSegments          :: Repeated 6 (Message SelectSegmentMsg)
  , srReached           :: Optional 7 (Value Word32)
  , srTotal             :: Optional 8 (Value Word32)
  , srComplete          :: Optional 9 (Value Bool)
  , srMinClearance      :: Optional 10 (Value Double)
  , srMinClearanceBody  :: Optional 11 (Value Text)
  , srMinManipulability :: Optional 12 (Value Double)
  , srCycleTime         :: Optional 13 (Value Double)
  , srCycleTimeNote     :: Optional 14 (Value Text)
  , srScore             :: Optional 15 (Value Double)
  , srDof               :: Optional 16 (Value Word32)
  } deriving (Generic, Show, Eq)
instance Encode SelectRobotResultMsg
instance Decode SelectRobotResultMsg

data SelectResponseMsg = SelectResponseMsg
  { slrRequestId   :: Optional 1 (Value Word64)
  , slrRobots      :: Repeated 2 (Message SelectRobotResultMsg)
  , slrComputeTime :: Optional 3 (Value Double)
  , slrError       :: Optional 4 (Message ErrorMsg)
  , slrErrors      :: Repeated 5 (Message ErrorMsg)
  } deriving (Generic, Show, Eq)
instance Encode SelectResponseMsg
instance Decode SelectResponseMsg

----------------------------------------------------------------------------- planning

data PlanZoneMsg = PlanZoneMsg
  { pzStartDistance :: Optional 1 (Value Double)
  , pzVelocity      :: Optional 2 (Value Double)
  , pzEndDistance   :: Optional 3 (Value Double)
  , pzBinding       :: Optional 4 (Value Text)
  } deriving (Generic, Show, Eq)
instance Encode PlanZoneMsg
instance Decode PlanZoneMsg

data PlanRequestMsg = PlanRequestMsg
  { plqRequestId    :: Optional 1 (Value Word64)
  , plqWaypoints    :: Optional 2 (Message PosesMsg)
  , plqRobot        :: Optional 3 (Message RobotMsg)
  , plqBase         :: Optional 4 (Message PoseMsg)
  , plqTool         :: Optional 5 (Message PoseMsg)
  , plqEnvironment  :: Repeated 6 (Message MeshMsg)
  , plqClearance    :: Optional 7 (Value Double)
  , plqIgnoreBodies :: Packed 8 (Value Word32)
  , plqSpeed        :: Optional 9 (Value Double)
  , plqAcceleration :: Optional 10 (Value Double)
  , plqJerk         :: Optional 11 (Value Double)
  , plqZone         :: Optional 12 (Value Double)
  , plqTimeStep     :: Optional 13 (Value Double)
  , plqStart        :: Packed 14 (Value Double)
  , plqTimeBudget   :: Optional 15 (Value Double)
  } deriving (Generic, Show, Eq)
instance Encode PlanRequestMsg
instance Decode PlanRequestMsg

-- | Constructors in wire-number order; an unknown number decodes to 'PlanStatusUnspecified'.
data PlanStatusEnum
  = PlanStatusUnspecified | PlanStatusOk | PlanStatusInvalidArgument | PlanStatusOutOfReach
  | PlanStatusJointLimit | PlanStatusSingularity | PlanStatusJump | PlanStatusCollision
  | PlanStatusNoSolution | PlanStatusNoProfile | PlanStatusBudget | PlanStatusInternal
  deriving (Eq, Show, Bounded)

instance Enum PlanStatusEnum where
  fromEnum = \case
    PlanStatusUnspecified -> 0
    PlanStatusOk -> 1
    PlanStatusInvalidArgument -> 2
    PlanStatusOutOfReach -> 3
    PlanStatusJointLimit -> 4
    PlanStatusSingularity -> 5
    PlanStatusJump -> 6
    PlanStatusCollision -> 7
    PlanStatusNoSolution -> 8
    PlanStatusNoProfile -> 9
    PlanStatusBudget -> 10
    PlanStatusInternal -> 11
  toEnum = \case
    1 -> PlanStatusOk
    2 -> PlanStatusInvalidArgument
    3 -> PlanStatusOutOfReach
    4 -> PlanStatusJointLimit
    5 -> PlanStatusSingularity
    6 -> PlanStatusJump
    7 -> PlanStatusCollision
    8 -> PlanStatusNoSolution
    9 -> PlanStatusNoProfile
    10 -> PlanStatusBudget
    11 -> PlanStatusInternal
    _ -> PlanStatusUnspecified

data PlanResponseMsg = PlanResponseMsg
  { plrRequestId    :: Optional 1 (Value Word64)
  , plrStatus       :: Optional 2 (Enumeration PlanStatusEnum)
  , plrDof          :: Optional 3 (Value Word32)
  , plrTimeStep     :: Optional 4 (Value Double)
  , plrTime         :: Packed 5 (Value Double)
  , plrDistance     :: Packed 6 (Value Double)
  , plrVelocity     :: Packed 7 (Value Double)
  , plrAcceleration :: Packed 8 (Value Double)
  , plrJerk         :: Packed 9 (Value Double)
  , plrQ            :: Packed 10 (Value Double)
  , plrQd           :: Packed 11 (Value Double)
  , plrDuration     :: Optional 12 (Value Double)
  , plrRouteLength  :: Optional 13 (Value Double)
  , plrStops        :: Packed 14 (Value Double)
  , plrZones        :: Repeated 15 (Message PlanZoneMsg)
  , plrStopDistance :: Optional 16 (Value Double)
  , plrStopPose     :: Optional 17 (Message PoseMsg)
  , plrStopJoint    :: Optional 18 (Value Text)
  , plrStopBody     :: Optional 19 (Value Text)
  , plrStopValue    :: Optional 20 (Value Double)
  , plrComputeTime  :: Optional 21 (Value Double)
  , plrError        :: Optional 22 (Message ErrorMsg)
  , plrErrors       :: Repeated 23 (Message ErrorMsg)
  } deriving (Generic, Show, Eq)
instance Encode PlanResponseMsg
instance Decode PlanResponseMsg

----------------------------------------------------------------------------- envelope

data PingMsg = PingMsg
  { pingPayload :: Optional 1 (Value Text)
  } deriving (Generic, Show, Eq)
instance Encode PingMsg
instance Decode PingMsg

data PongMsg = PongMsg
  { pongPayload :: Optional 1 (Value Text)
  , pongVersion :: Optional 2 (Value Text)
  } deriving (Generic, Show, Eq)
instance Encode PongMsg
instance Decode PongMsg

-- | @oneof body@ is, on the wire, a set of optional fields of which at most one is present;
-- the Haskell package has no oneof, so the envelope keeps them as optional fields and
-- "VProf.Wire.Envelope" enforces "exactly one".
data RequestMsg = RequestMsg
  { reqRequestId :: Optional 1 (Value Word64)
  , reqProfile   :: Optional 2 (Message ProfileRequestMsg)
  , reqCompress  :: Optional 3 (Message CompressRequestMsg)
  , reqPing      :: Optional 4 (Message PingMsg)
  , reqFk        :: Optional 5 (Message FkRequestMsg)
  , reqIk        :: Optional 6 (Message IkRequestMsg)
  , reqSelect    :: Optional 7 (Message SelectRequestMsg)
  , reqPlan      :: Optional 8 (Message PlanRequestMsg)
  } deriving (Generic, Show, Eq)
instance Encode RequestMsg
instance Decode RequestMsg

data ResponseMsg = ResponseMsg
  { rspRequestId  :: Optional 1 (Value Word64)
  , rspProfile    :: Optional 2 (Message ProfileResponseMsg)
  , rspCompressed :: Optional 3 (Message CompressedPathMsg)
  , rspPong       :: Optional 4 (Message PongMsg)
  , rspError      :: Optional 5 (Message ErrorMsg)
  , rspFk         :: Optional 6 (Message FkResponseMsg)
  , rspIk         :: Optional 7 (Message IkResponseMsg)
  , rspSelect     :: Optional 8 (Message SelectResponseMsg)
  , rspPlan       :: Optional 9 (Message PlanResponseMsg)
  } deriving (Generic, Show, Eq)
instance Encode ResponseMsg
instance Decode ResponseMsg
