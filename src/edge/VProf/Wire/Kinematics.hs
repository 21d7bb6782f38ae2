{-# LANGUAGE OverloadedStrings #-}
-- | Robot kinematics on the wire: 'FkRequestMsg' and 'IkRequestMsg' to the core's robot, joint
-- vectors, target pose and collision scene, with validation errors that name the proto field and
-- the value in its unit (@joints[2] = NaN rad@, @target: the quaternion (1, 0, 0, 0.5) has norm
-- 1.118@), and the core's results back to 'FkResponseMsg' / 'IkResponseMsg'.
--
-- A robot is a library name (its model compiled once per process and kept), or an inline robot
-- file (YAML/JSON) or URDF, read by the same readers as files are. Joint values are SI (rad, m);
-- a field left at 0 takes its default, as proto3 omits it.
module VProf.Wire.Kinematics
  ( -- * Requests
    FkQuery (..)
  , IkQuery (..)
  , fkFromMsg
  , ikFromMsg
  , robotFromMsg
  , poseFromMsg
  , jointsFromMsg
  , meshFromMsg
  , withoutEnvironment
    -- * Responses
  , fkToMsg
  , ikToMsg
  , ikFailureToError
  , solverName
  , poseToMsg
  , fkError
  , ikError
  , mkError
  ) where

import Data.Char (isAlphaNum, toLower)
import Data.List (intercalate)
import qualified Data.Map.Strict as Map
import Data.Maybe (fromMaybe)
import Data.ProtocolBuffers (getField, putField)
import qualified Data.ByteString.Lazy as BL
import qualified Data.Text as T
import qualified Data.Text.Encoding as TE
import qualified Data.Vector.Unboxed as U
import Data.Word (Word32, Word64)

import VProf.Geometry.Bvh (Bvh, buildBvh)
import VProf.Geometry.Mesh (Mesh, ScenePart (..), composeScene, fromTriangles)
import VProf.Kinematics
import VProf.Kinematics.Collision (CollisionModel, CollisionOptions (..), collisionModel, defaultCollisionOptions, unknownBody)
import VProf.Kinematics.Format.RobotFile (readRobotYaml)
import VProf.Kinematics.Format.Urdf (UrdfOptions (..), readUrdf)
import VProf.Kinematics.Library (libraryRobots, lookupRobot)
import VProf.Select.Ik (SelectIkFailure (..), SelectIkOptions (..), describeSelectIkFailure)
import VProf.Validation (FieldValue (..), finite, literalError, maxCoordinate, showBound, tooFarRule)
import VProf.Wire.Messages

-- | A validated FK request.
data FkQuery = FkQuery
  { fqRobot :: Robot
  , fqKinematics :: Kinematics
  , fqJoints :: U.Vector Double
  , fqLinkFrames :: Bool
  }

-- | A validated IK request. 'iqScene' is the environment with its collision model, when given.
data IkQuery = IkQuery
  { iqRobot :: Robot
  , iqKinematics :: Kinematics
  , iqTarget :: Tf
  , iqSeed :: Maybe (U.Vector Double)
  , iqOptions :: IkOptions
  , iqBudget :: Double
  , iqScene :: Maybe (Bvh, CollisionModel, SelectIkOptions)
  }

------------------------------------------------------------------------------ robots

-- | Library robots compiled once (lazily, per robot), by their normalised key and name.
libraryCache :: Map.Map String (Robot, Kinematics)
libraryCache = Map.fromList $ concat
  [ [(norm key, entry), (norm (robotName r), entry)]
  | (key, Right r) <- libraryRobots, let entry = (r, kinematicsFor r) ]

norm :: String -> String
norm = map toLower . filter isAlphaNum

err :: String -> String -> String -> FieldError
err f v rule = literalError f v rule

-- | The robot of a request: a library name, or an inline robot file or URDF. Errors name
-- @robot@, @robot.name@, @robot.robot_file@ or @robot.urdf@.
robotFromMsg :: Maybe RobotMsg -> Either [FieldError] (Robot, Kinematics)
robotFromMsg Nothing = Left [err "robot" "" "is missing: give a library name, a robot file or a URDF"]
robotFromMsg (Just m) = case [ k | (k, True) <- [("name", has name), ("robot_file", has file), ("urdf", has urdf)] ] of
  [k] | k /= "urdf", links@(_ : _) <- filter (has . snd) [("base_link", baseLink), ("tip_link", tipLink)] ->
    Left [ err ("robot." ++ f) (show (T.unpack t)) ("is for a URDF only; the robot is given by " ++ k ++ ", whose chain is fixed")
         | (f, t) <- links ]
  ["name"] -> case Map.lookup (norm (T.unpack name)) libraryCache of
    Just e -> Right e
    Nothing -> Left [err "robot.name" (show (T.unpack name)) (either id (const "is not in the library") (lookupRobot (T.unpack name)))]
  ["robot_file"] -> case readRobotYaml (TE.encodeUtf8 file) of
    Left es -> Left [err "robot.robot_file" "" (intercalate "; " es)]
    Right r -> Right (r, kinematicsFor r)
  ["urdf"] ->
    let opts = UrdfOptions (nonEmpty baseLink) (nonEmpty tipLink)
    in case readUrdf opts (BL.fromStrict (TE.encodeUtf8 urdf)) of
         Left es -> Left [err "robot.urdf" "" (intercalate "; " es)]
         Right r -> Right (r {robotSources = ["URDF sent in the request"]}, kinematicsFor r {robotSources = ["URDF sent in the request"]})
  [] -> Left [err "robot" "" "is empty: set one of name, robot_file, urdf"]
  ks -> Left [err "robot" "" ("sets " ++ intercalate ", " ks ++ ": set exactly one of name, robot_file, urdf")]
  where
    name = orDefault (getField (robName m)) :: T.Text
    file = orDefault (getField (robRobotFile m)) :: T.Text
    urdf = orDefault (getField (robUrdf m)) :: T.Text
    baseLink = orDefault (getField (robBaseLink m)) :: T.Text
    tipLink = orDefault (getField (robTipLink m)) :: T.Text
    has = not . T.null . T.strip
    nonEmpty t = if T.null t then Nothing else Just (T.unpack t)

------------------------------------------------------------------------------ values

-- | A pose (position m, unit quaternion) to a rigid transform; errors name @prefix.x@ … or
-- @prefix@ for a quaternion that is not of unit norm (within 1e-6).
poseFromMsg :: String -> PoseMsg -> Either [FieldError] Tf
poseFromMsg prefix p
  | not (null bad) = Left bad
  | abs (nrm - 1) > 1e-6 =
      Left [FieldError prefix (Literal ("quaternion (" ++ intercalate ", " (map show [w, a, b, c]) ++ ")")) ""
              ("has norm " ++ show nrm ++ ": must be a unit quaternion (norm 1 within 1e-6)")]
  | otherwise = Right (fromQuat (V3 x y z) (Quat w a b c))
  where
    [x, y, z, w, a, b, c] = map orDefault [ getField (poseX p), getField (poseY p), getField (poseZ p)
                                          , getField (poseQw p), getField (poseQx p), getField (poseQy p)
                                          , getField (poseQz p) ] :: [Double]
    nrm = sqrt (w * w + a * a + b * b + c * c)
    bad = [ FieldError (prefix ++ "." ++ k) (Number v) u "must be a finite number"
          | (k, v, u) <- zip3 ["x", "y", "z", "qw", "qx", "qy", "qz"] [x, y, z, w, a, b, c] ["m", "m", "m", "", "", "", ""]
          , not (finite v) ]
          ++ [ FieldError (prefix ++ "." ++ k) (Number v) "m" tooFarRule
             | (k, v) <- zip ["x", "y", "z"] [x, y, z], finite v, abs v > maxCoordinate ]

-- | A joint vector of the robot's length with finite entries, in rad (revolute) and m (prismatic).
jointsFromMsg :: String -> Robot -> [Double] -> Either [FieldError] (U.Vector Double)
jointsFromMsg field r qs
  | length qs /= n = Left [err field (show (length qs) ++ " values") ("the robot " ++ robotName r ++ " has " ++ show n ++ " joints")]
  | not (null bad) = Left bad
  | otherwise = Right (U.fromList qs)
  where
    n = dof r
    bad = [ FieldError (field ++ "[" ++ show i ++ "]") (Number x) (unit j) "must be a finite number"
          | (i, x, j) <- zip3 [0 :: Int ..] qs (robotJoints r), not (finite x) ]
    unit j = if jointKind j == Revolute then "rad" else "m"

-- | A request's clearance and ignore_bodies act on its environment: sent without one, they
-- would go unused without a word, so they are errors naming the field.
withoutEnvironment :: Bool -> Double -> [Word32] -> [FieldError]
withoutEnvironment hasEnv c ignores =
  [ FieldError "clearance" (Number c) "m" "is given without an environment: send the cell's meshes in environment, or leave clearance 0"
  | not hasEnv, finite c, c > 0 ]
  ++ [ err "ignore_bodies" (show ignores) "is given without an environment: the bodies are left out of the check against the environment only"
     | not hasEnv, not (null ignores) ]

-- | A non-negative finite option; 0 (absent) takes the default.
positiveOr :: String -> String -> Double -> Double -> Either [FieldError] Double
positiveOr field unit def v
  | not (finite v) || v < 0 = Left [FieldError field (Number v) unit "must be a finite number >= 0 (0 means the default)"]
  | v == 0 = Right def
  | otherwise = Right v

collect :: [Either [FieldError] a] -> Either [FieldError] [a]
collect es = case concat [ e | Left e <- es ] of
  [] -> Right [ a | Right a <- es ]
  errs -> Left errs

------------------------------------------------------------------------------ requests

fkFromMsg :: FkRequestMsg -> Either [FieldError] FkQuery
fkFromMsg m = do
  (r, k) <- robotFromMsg (getField (fkqRobot m))
  q <- jointsFromMsg "joints" r (getField (fkqJoints m))
  -- the contract asks joints within the limits: a pose of a configuration the robot cannot
  -- take is refused, not answered as if it could (90 meant as degrees is 90 rad)
  case jointsOutsideLimits "joints" r q of
    [] -> pure (FkQuery r k q (orDefault (getField (fkqLinkFrames m))))
    es -> Left es

ikFromMsg :: IkRequestMsg -> Either [FieldError] IkQuery
ikFromMsg m = do
  (r, k) <- robotFromMsg (getField (ikqRobot m))
  let seedList = getField (ikqSeed m)
      target = maybe (Left [err "target" "" "is missing: the tool pose wanted (position m, unit quaternion)"])
                     (poseFromMsg "target") (getField (ikqTarget m))
      seed = if null seedList then Right Nothing else Just <$> jointsFromMsg "seed" r seedList
      tolP = positiveOr "position_tolerance" "m" (ikTolPosition defaultIkOptions) (orDefault (getField (ikqPositionTolerance m)))
      tolR = positiveOr "rotation_tolerance" "rad" (ikTolRotation defaultIkOptions) (orDefault (getField (ikqRotationTolerance m)))
      budget = positiveOr "time_budget" "s" 1 (orDefault (getField (ikqTimeBudget m))) >>= \b ->
        if b > 3600 then Left [FieldError "time_budget" (Number b) "s" "must be at most 3600"] else Right b
      envs = getField (ikqEnvironment m)
      clearance = let c = orDefault (getField (ikqClearance m)) :: Double in
        if finite c && c >= 0 then Right c else Left [FieldError "clearance" (Number c) "m" "must be a finite number >= 0"]
      unused = withoutEnvironment (not (null envs)) (orDefault (getField (ikqClearance m))) (getField (ikqIgnoreBodies m))
      ignores = [ if b == 0 then Left [FieldError ("ignore_bodies[" ++ show i ++ "]") (Literal "0") "" "bodies count from 1"]
                  else maybe (Right (fromIntegral b :: Int)) (\e -> Left [FieldError ("ignore_bodies[" ++ show i ++ "]") (Literal (show b)) "" e])
                             (unknownBody r False (fromIntegral b))
                | (i, b) <- zip [0 :: Int ..] (getField (ikqIgnoreBodies m)) ]
      meshes = collect [ meshFromMsg ("environment[" ++ show i ++ "]") e | (i, e) <- zip [0 :: Int ..] envs ]
  -- every problem at once
  case concat [ either id (const []) target, either id (const []) seed, either id (const []) tolP
              , either id (const []) tolR, either id (const []) budget, either id (const []) clearance
              , concat [ e | Left e <- ignores ], either id (const []) meshes, unused ] of
    errs@(_ : _) -> Left errs
    [] -> do
      t <- target; s <- seed; tp <- tolP; tr <- tolR; b <- budget; c <- clearance; parts <- meshes
      is <- collect ignores
      let opts = defaultIkOptions { ikTolPosition = tp, ikTolRotation = tr
                                  , ikAllSolutions = orDefault (getField (ikqAllSolutions m)) }
          scene | null parts = Nothing
                | otherwise = Just ( buildBvh (composeScene parts)
                                   , collisionModel defaultCollisionOptions { coSceneIgnore = is } r
                                   , defaultSelectIkOptions' opts c )
      pure (IkQuery r k t s opts b scene)
  where
    defaultSelectIkOptions' opts c = SelectIkOptions { siIk = opts, siClearance = c, siSelfMargin = 0 }

-- | One environment mesh: vertices (x y z each, times scale = m), triangles (three vertex
-- indices each), scale (0 means 1), pose (absent means identity).
meshFromMsg :: String -> MeshMsg -> Either [FieldError] ScenePart
meshFromMsg prefix m = do
  let vs = getField (meshVertices m)
      ts = getField (meshTriangles m)
      nv = length vs `div` 3
      sc = orDefault (getField (meshScale m)) :: Double
      e1 = [ err (prefix ++ ".vertices") (show (length vs) ++ " numbers") "must hold x y z per vertex (a multiple of 3)" | length vs `mod` 3 /= 0 ]
        ++ [ FieldError (prefix ++ ".vertices[" ++ show i ++ "]") (Number v) "" "must be a finite number" | (i, v) <- take 1 [ iv | iv@(_, v) <- zip [0 :: Int ..] vs, not (finite v) ] ]
        ++ [ err (prefix ++ ".triangles") (show (length ts) ++ " indices") "must hold three vertex indices per triangle (a multiple of 3, at least one triangle)"
           | length ts `mod` 3 /= 0 || null ts ]
        ++ [ err (prefix ++ ".triangles[" ++ show i ++ "]") (show t) ("is not a vertex index: the mesh has " ++ show nv ++ " vertices (indices from 0)")
           | (i, t) <- take 1 [ it | it@(_, t) <- zip [0 :: Int ..] ts, fromIntegral t >= nv ] ]
        ++ [ FieldError (prefix ++ ".scale") (Number sc) "" "must be a finite number >= 0 (0 means 1)" | not (finite sc) || sc < 0 ]
        -- a scale that puts a vertex beyond the bound of every coordinate is a wrong unit (1e308
        -- made the vertices infinite and every IK solution 'collide')
        ++ [ FieldError (prefix ++ ".scale") (Number sc) ""
               ("puts vertex " ++ show (i `div` 3) ++ " more than " ++ showBound maxCoordinate ++ " m from the origin (is the unit right?)")
           | finite sc, sc > 0, i <- take 1 [ j | (j, v) <- zip [0 :: Int ..] vs, finite v, abs (v * sc) > maxCoordinate ] ]
        ++ [ FieldError (prefix ++ ".vertices[" ++ show i ++ "]") (Number v) "" ("is more than " ++ showBound maxCoordinate ++ " from the origin (is the unit right?)")
           | (i, v) <- take 1 [ iv | iv@(_, v) <- zip [0 :: Int ..] vs, finite v, abs v > maxCoordinate ] ]
      pose = maybe (Right identity) (poseFromMsg (prefix ++ ".pose")) (getField (meshPose m))
  case e1 ++ either id (const []) pose of
    errs@(_ : _) -> Left errs
    [] -> do
      tf <- pose
      let vx = U.fromList vs
          vert i = let j = 3 * fromIntegral (i :: Word32) in V3 (vx U.! j) (vx U.! (j + 1)) (vx U.! (j + 2))
          tris = triples ts
          mesh = fromTriangles [ (vert a, vert b, vert c) | (a, b, c) <- tris ] :: Mesh
      pure (ScenePart mesh (if sc == 0 then 1 else sc) tf)
  where
    triples (a : b : c : rest) = (a, b, c) : triples rest
    triples _ = []

------------------------------------------------------------------------------ responses

mkError :: ErrorCodeEnum -> String -> String -> ErrorMsg
mkError code field msg = ErrorMsg
  { errCode = putField (enumField code)
  , errField = putField (nonDefault (T.pack field))
  , errMessage = putField (nonDefault (T.pack msg))
  }

poseToMsg :: Tf -> PoseMsg
poseToMsg t = PoseMsg (f x) (f y) (f z) (f w) (f a) (f b) (f c)
  where
    Pose (V3 x y z) (Quat w a b c) = poseFromTf t
    f v = putField (nonDefault v)

solverName :: Kinematics -> String
solverName k = case kinMethod k of
  ClosedFormDobot _ -> "closed-form dobot"
  ClosedFormSixAxis _ -> "closed-form six-axis"
  NumericLM -> "numerical"

-- | An FK response (no error).
fkToMsg :: Word64 -> Double -> FkQuery -> FkResponseMsg
fkToMsg rid secs FkQuery{..} = FkResponseMsg
  { fksRequestId = putField (nonDefault rid)
  , fksTool = putField (Just (poseToMsg tool))
  , fksLinkFrames = putField (if fqLinkFrames then map poseToMsg (linkFrames ch fqJoints) else [])
  , fksJacobian = putField (concat (jacobianRows n jac))
  , fksManipulability = putField (nonDefault (manipulability n jac))
  , fksConditionNumber = putField (nonDefault (conditionNumber n jac))
  , fksComputeTime = putField (nonDefault secs)
  , fksError = putField Nothing
  , fksDof = putField (nonDefault (fromIntegral n))
  }
  where
    ch = kinChain fqKinematics
    n = chainDof ch
    (tool, jac) = jacobian ch fqJoints

-- | An FK response carrying only an error.
fkError :: Word64 -> Double -> ErrorCodeEnum -> String -> String -> FkResponseMsg
fkError rid secs code field msg = FkResponseMsg
  { fksRequestId = putField (nonDefault rid), fksTool = putField Nothing, fksLinkFrames = putField []
  , fksJacobian = putField [], fksManipulability = putField Nothing, fksConditionNumber = putField Nothing
  , fksComputeTime = putField (nonDefault secs), fksError = putField (Just (mkError code field msg))
  , fksDof = putField Nothing }

-- | An IK response with solutions (each with its clearance when there is an environment).
ikToMsg :: Word64 -> Double -> IkQuery -> [(IkSolution, Maybe Double)] -> IkResponseMsg
ikToMsg rid secs IkQuery{..} sols = IkResponseMsg
  { ikrRequestId = putField (nonDefault rid)
  , ikrSolutions = putField (map sol sols)
  , ikrSolver = putField (Just (T.pack (solverName iqKinematics)))
  , ikrComputeTime = putField (nonDefault secs)
  , ikrError = putField Nothing
  , ikrDof = putField (nonDefault (fromIntegral n))
  }
  where
    ch = kinChain iqKinematics
    n = chainDof ch
    sol (s, clr) = IkSolutionMsg
      { iksJoints = putField (U.toList (solJoints s))
      , iksPositionError = putField (nonDefault (solPositionError s))
      , iksRotationError = putField (nonDefault (solRotationError s))
      , iksBranch = putField (nonDefault (T.pack (fromMaybe "" (solBranch s))))
      , iksManipulability = putField (nonDefault (manipulability n (snd (jacobian ch (solJoints s)))))
      , iksClearance = putField (clr >>= nonDefault)
      , iksSeedDistance = putField (nonDefault (solSeedDistance s))
      }

-- | An IK response carrying only an error.
ikError :: Word64 -> Double -> Maybe Kinematics -> ErrorCodeEnum -> String -> String -> IkResponseMsg
ikError rid secs k code field msg = IkResponseMsg
  { ikrRequestId = putField (nonDefault rid), ikrSolutions = putField []
  , ikrSolver = putField (T.pack . solverName <$> k)
  , ikrComputeTime = putField (nonDefault secs), ikrError = putField (Just (mkError code field msg))
  , ikrDof = putField (nonDefault . fromIntegral . chainDof . kinChain =<< k) }

-- | Why there is no solution, as (code, field, message): a bad request is INVALID_ARGUMENT naming
-- @target@ or @seed@; a budget run out NOT_CONVERGED; anything else (reach, limits, orientation,
-- collisions) INFEASIBLE.
ikFailureToError :: Robot -> Maybe SelectIkOptions -> SelectIkFailure -> (ErrorCodeEnum, String, String)
ikFailureToError robot so f = case f of
  IkFailed (InvalidRequest es) -> (ErrInvalidArgument, fieldOf es, intercalate "; " es)
  IkFailed nc@(NotConverged _ _) -> (ErrNotConverged, "target", describeFailure nc)
  IkFailed other -> (ErrInfeasible, "target", describeFailureFor robot other)
  AllInCollision _ _ -> (ErrInfeasible, "environment", maybe "every solution collides" (`describeSelectIkFailure` f) so)
  where
    fieldOf (e : _) = takeWhile (\c -> c /= ':' && c /= '[') e
    fieldOf [] = "target"
