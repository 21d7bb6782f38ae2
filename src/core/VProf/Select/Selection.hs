-- | Robot selection: which robots of a list can do a task in its cell, ranked, with the reason for
-- every failure.
--
-- Per robot, placed at the task's base with the task's tool: the payload filter (a rated payload
-- below the task's rejects the robot before any IK), the reach filter (a target farther from the
-- first joint than the arm stretched with its tool fails without IK, with both distances), then
-- collision-aware IK ("VProf.Select.Ik") of every target in order, each seeded by the previous
-- target's solution so that the robot stays on one branch where it can; with a path task the
-- segments between targets are followed by IK continuation. Then the minimum clearance (and the
-- body), the minimum manipulability, the cycle time ("VProf.Select.CycleTime"), the score and the
-- ranking; the formula is in docs/select.md. Pure: the records are plain, for any front end.
module VProf.Select.Selection
  ( SelectOptions (..)
  , defaultSelectOptions
  , TargetResult (..)
  , FailureKind (..)
  , SegmentResult (..)
  , RobotResult (..)
  , robotComplete
  , selectRobots
  , evaluateRobot
  , scoreAndRank
  , maxJointStep
  ) where

import Data.Containers.ListUtils (nubOrdOn)
import Data.List (find, minimumBy, sortBy, sortOn)
import Data.Either (isRight)
import Data.Maybe (catMaybes, fromMaybe, isJust, isNothing, listToMaybe, mapMaybe)
import Data.Ord (comparing)
import qualified Data.Vector.Unboxed as U
import Numeric (showFFloat)

import VProf.Geometry.Bvh (Bvh)
import VProf.Kinematics.Collision
import VProf.Kinematics.Ik
import VProf.Kinematics.Ik.Numeric (reachBound)
import VProf.Kinematics.Jacobian (jacobian, manipulability, manipulabilityQr)
import VProf.Kinematics.Model
import VProf.Kinematics.Transform
import VProf.Select.CycleTime
import VProf.Select.Ik
import VProf.Select.Task

data SelectOptions = SelectOptions
  { soIk :: IkOptions
  , soSelfMargin :: Double      -- ^ m, least distance between checked parts of the robot
  , soRestarts :: Int           -- ^ numerical IK: random restarts when the seed's solution collides
  , soSeeded :: Bool            -- ^ seed each target by the previous one's solution (default);
                                --   False solves every target on its own
  }

defaultSelectOptions :: SelectOptions
defaultSelectOptions = SelectOptions defaultIkOptions 0 40 True

-- | Along a path, no joint may move more than this between two samples (rad or m): a larger
-- step is a jump to another branch (a wrist flip), not a continuation.
maxJointStep :: Double
maxJointStep = 0.2

data TargetResult = TargetResult
  { trLabel :: String
  , trJoints :: Maybe (U.Vector Double)   -- ^ rad, m (controller convention)
  , trBranch :: Maybe String
  , trClearance :: Maybe Double           -- ^ m (Nothing: not reached, or an empty scene)
  , trClearanceBody :: Maybe String
  , trManipulability :: Maybe Double
  , trFailure :: Maybe String
  , trFailureKind :: Maybe FailureKind    -- ^ the kind of trFailure, for a program
  }
  deriving (Eq, Show)

-- | Why a target is not reached, as a kind: beyond (or inside) the reach, every solution outside a
-- joint limit, an orientation the arm cannot take, every solution in collision (with the cell or
-- itself), a singularity, the numerical solver's budget, anything else (a bad request).
data FailureKind
  = FailReach | FailJointLimits | FailOrientation | FailCollision | FailSingular | FailBudget | FailOther
  deriving (Eq, Show, Enum, Bounded)

ikFailureKind :: IkFailure -> FailureKind
ikFailureKind = \case
  BeyondReach {} -> FailReach
  InsideReach {} -> FailReach
  Unreachable {} -> FailReach
  OutsideLimits {} -> FailJointLimits
  OrientationUnreachable {} -> FailOrientation
  Singular {} -> FailSingular
  NotConverged {} -> FailBudget
  InvalidRequest {} -> FailOther

-- | Path tasks: the segment from target sgFrom to the next.
data SegmentResult = SegmentResult
  { sgFrom :: Int
  , sgSamples :: Int               -- ^ poses checked
  , sgFailure :: Maybe String
  , sgTo :: Int                    -- ^ the target the segment leads to
  }
  deriving (Eq, Show)

data RobotResult = RobotResult
  { rrKey :: String
  , rrName :: String
  , rrRejected :: Maybe String          -- ^ the payload filter's reason
  , rrTargets :: [TargetResult]         -- ^ empty when rejected
  , rrSegments :: [SegmentResult]       -- ^ path tasks only
  , rrReached :: Int                    -- ^ targets reached (in a path task: and the segment into them)
  , rrTotal :: Int
  , rrMinClearance :: Maybe (Double, String)  -- ^ m and the body
  , rrMinManipulability :: Maybe Double
  , rrCycleTime :: Maybe Double         -- ^ s, when every target is reached
  , rrCycleNote :: Maybe String         -- ^ why there is no cycle time
  , rrScore :: Double
  }
  deriving (Eq, Show)

-- | Every target reached (and every segment followed).
robotComplete :: RobotResult -> Bool
robotComplete r = isNothing (rrRejected r) && rrReached r == rrTotal r

-- | Every robot evaluated, scored and ranked (best first).
selectRobots :: SelectOptions -> Task -> Bvh -> [(String, Robot)] -> [RobotResult]
selectRobots opts task bvh robots = scoreAndRank [evaluateRobot opts task bvh k r | (k, r) <- robots]

-- | One robot through the filters and the targets (score 0: 'scoreAndRank' sets it).
evaluateRobot :: SelectOptions -> Task -> Bvh -> String -> Robot -> RobotResult
evaluateRobot opts task bvh key robot0
  | Just p <- robotPayload robot0, p < taskPayload task =
      (empty (length targets))
        { rrRejected = Just ("payload: rated " ++ showKg p ++ ", the task needs " ++ showKg (taskPayload task)) }
  | otherwise =
      let results = solveAll
          targetsR = map fst results
          segs = catMaybes (map snd results)
          reachedFlags = [isJust (trJoints t) && maybe True (isNothing . sgFailure) s | (t, s) <- results]
          n = length (filter id reachedFlags)
          clears = [ (c, b) | t <- targetsR, Just c <- [trClearance t], Just b <- [trClearanceBody t] ]
          manips = mapMaybe trManipulability targetsR
          total = length targets
          complete = n == total
          (cyc, note)
            | not complete = (Nothing, Just "not every target is reached")
            | otherwise = case cycleTime (jointRates robot) (mapMaybe trJoints targetsR) of
                Right t -> (Just t, Nothing)
                Left e -> (Nothing, Just e)
      in (empty total)
           { rrTargets = targetsR, rrSegments = segs, rrReached = n
           , rrMinClearance = if null clears then Nothing else Just (minimumBy (comparing fst) clears)
           , rrMinManipulability = if null manips then Nothing else Just (minimum manips)
           , rrCycleTime = cyc, rrCycleNote = note }
  where
    targets = taskTargets task
    empty total = RobotResult key (robotName robot0) Nothing [] [] 0 total Nothing Nothing Nothing Nothing 0
    robot = placeRobot task robot0
    kin = kinematicsFor robot
    ch = kinChain kin
    cm = collisionModel defaultCollisionOptions { coTool = taskToolCapsule task, coSceneIgnore = taskIgnoreBodies task } robot
    d = taskClearance task
    sopts = defaultSelectIkOptions { siIk = (soIk opts) { ikMaxRestarts = soRestarts opts }, siClearance = d, siSelfMargin = soSelfMargin opts }
    (centre, bound) = reachBound ch
    -- a part nearer the cell than d whatever the joints are (a base column standing in the
    -- table): every target fails without IK
    fixedHit = case fixedCollisions cm bvh d of
      [] -> Nothing
      cs -> Just (minimumBy (comparing clrDistance) cs)

    -- targets in order; in a path task each target after the first comes with its segment
    -- (the first segment already walked when the first target was chosen by it)
    solveAll = go Nothing Nothing (zip [0 :: Int ..] targets)
      where
        go _ _ [] = []
        go prev walked ((i, t) : rest) =
          let (res, seg, walkedNext) = case (taskPath task, prev) of
                (True, Just (j, q0, p0)) -> case fromMaybe (walk q0 p0 (tgPose t)) walked of
                  Right (k, qEnd) -> (describe t qEnd Nothing, Just (SegmentResult j k Nothing i), Nothing)
                  Left (k, why) ->
                    ( solveTarget (Just q0) t
                    , Just (SegmentResult j k (Just ("segment " ++ show j ++ " -> " ++ show i ++ " " ++ why)) i)
                    , Nothing )
                (True, Nothing) | (_, t1) : _ <- rest -> let (r, w) = solveFirst t t1 in (r, Nothing, w)
                _ -> (solveTarget (if soSeeded opts then (\(_, q, _) -> q) <$> prev else Nothing) t, Nothing, Nothing)
              next = case trJoints res of
                Just q -> Just (i, q, tgPose t)
                Nothing -> prev
          in (res, seg) : go next walkedNext rest

    distanceOf t = v3Norm (v3Sub (translation (tgPose t)) centre)
    solveTarget seed t
      | distanceOf t > bound + 1e-9 =
          failed t FailReach ("beyond reach: " ++ showM (distanceOf t) ++ " from the shoulder (the arm's last point no joint moves), the arm with its tool reaches at most "
                              ++ showM bound ++ " (" ++ show (roundTo 1 (1000 * (distanceOf t - bound))) ++ " mm too far)")
      | Just cl <- fixedHit = failed t FailCollision (describeFixedCollision d cl)
      | otherwise = case fastPath seed (tgPose t) of
          Just c -> describe t (solJoints (cdSolution c)) (solBranch (cdSolution c))
          -- with a seed the clear solution nearest it (no exact clearance but the one taken's),
          -- without one the clearest
          Nothing -> case (if isJust seed then collisionFreeCandidates else solveCollisionFree) sopts kin cm bvh (tgPose t) seed of
            Left (IkFailed f) -> failed t (ikFailureKind f) (describeFailureFor robot f)
            Left f -> failed t FailCollision (describeSelectIkFailure sopts f)
            Right cs ->
              let pick = case seed of
                    Nothing -> head cs
                    Just _ -> minimumBy (comparing (solSeedDistance . cdSolution)) cs
              in describe t (solJoints (cdSolution pick)) (solBranch (cdSolution pick))

    -- with a seed: the solution nearest it that keeps the clearance, among one solution per
    -- closed-form branch (its whole-turn variant nearest the seed; 'solveIkDistinct'), or for a
    -- numerical robot among those nearest the seed (the solver from the seed alone, no
    -- restarts); without one, of the distinct geometries (whole turns of revolute joints apart
    -- are one) the most dexterous that keeps it. Only the clearance test with early exit runs
    -- here; the full search (every solution's exact clearance, for the failure's reason) only
    -- when no solution passes.
    fastPath seed pose = case seed of
      Just _ | NumericLM <- kinMethod kin -> case solveIk (soIk opts) { ikAllSolutions = False, ikMaxRestarts = 0 } kin pose seed of
        Right sols -> (\s -> Candidate s Nothing Nothing) <$> find (clearOk . solJoints) (take 8 sols)
        Left _ -> Nothing
      Just _ -> case solveIkDistinct (soIk opts) kin pose seed of
        Right sols -> (\s -> Candidate s Nothing Nothing) <$> find (clearOk . solJoints) sols
        Left _ -> Nothing
      Nothing -> (\s -> Candidate s Nothing Nothing) <$> listToMaybe (clearByDexterity pose)

    -- the distinct geometries that keep the clearance, the most dexterous first
    clearByDexterity pose = case solveIkDistinct (soIk opts) { ikMaxRestarts = soRestarts opts } kin pose Nothing of
      Right sols -> filter (clearOk . solJoints) (sortOn (negate . dexterity . solJoints) (nubOrdOn (canonical . solJoints) sols))
      Left _ -> []

    -- a path's first target: the most dexterous clear geometry from which the first segment
    -- can be followed. The most dexterous alone can be one whose gap to itself closes along the
    -- segment (a UR5 elbow-down, 9 mm from self-collision at the target, failed a straight
    -- 10 cm move at its 15th sample without the cell, which ruled that branch out, and passed
    -- with it). When no geometry follows it, the target is solved as any other (the segment's
    -- failure then says why). With the target, the walk of the first segment from it, when
    -- it was walked here.
    solveFirst t t1
      | distanceOf t > bound + 1e-9 || isJust fixedHit = (solveTarget Nothing t, Nothing)
      | otherwise = case [ (s, w) | s <- clearByDexterity (tgPose t), let w = walk (solJoints s) (tgPose t) (tgPose t1), isRight w ] of
          (s, w) : _ -> (describe t (solJoints s) (solBranch s), Just w)
          [] -> (solveTarget Nothing t, Nothing)

    canonical q = [ if rev then round (1e6 * (x - 2 * pi * fromIntegral (round (x / (2 * pi)) :: Int))) else round (1e6 * x) :: Int
                  | (rev, x) <- zip (U.toList (chainRevoluteJoint ch)) (U.toList q) ]
    -- the manipulability to 1e-9 (as vprof plan ranks its start), so that equally dexterous
    -- geometries (a UR's wrist-flipped branches) keep their order, nearest mid-limits first,
    -- rather than one set by rounding
    dexterity q = let (_, jac) = jacobian ch q in round (1e9 * manipulabilityQr (chainDof ch) jac) :: Int

    clearOk q = robotClearanceAtLeast cm bvh q d && not (selfCollides cm (soSelfMargin opts) q)

    describe t q br =
      let cl = robotClearance cm bvh q
          (_, jac) = jacobian ch q
      in TargetResult (tgLabel t) (Just q) br (clrDistance <$> cl) (clrBodyName <$> cl)
                      (Just (manipulability (chainDof ch) jac)) Nothing Nothing
    failed t kind why = TargetResult (tgLabel t) Nothing Nothing Nothing Nothing Nothing (Just why) (Just kind)

    -- IK continuation along the straight segment: each sample's solution nearest the previous
    -- one, clear of the cell and of itself, no joint stepping more than maxJointStep. A larger
    -- step (a coarse path_step) is walked again from the previous sample in sub-steps of an
    -- eighth of it, at most the default 5 mm: only a jump that stays a jump at that finer
    -- sampling is a change of branch.
    walk q0 p0 p1 = go' (0 :: Int) q0 p0 samples
      where
        samples = segmentSamples (taskPathStep task) p0 p1
        n = segmentSampleCount (taskPathStep task) p0 p1
        segLen = v3Norm (v3Sub (translation p1) (translation p0))
        turn = rotationAngle (inverse p0 `compose` p1)
        go' k q _ [] = Right (k, q)
        go' k q prev (p : ps) =
          let f = fromIntegral (k + 1) / fromIntegral n
              -- along the move and the turn: a segment that only turns the tool said "0.0 m"
              deg = show (roundTo 1 (f * turn * 180 / pi)) ++ "°"
              at | segLen < 1e-9 = deg
                 | turn > 1e-3 = showM (f * segLen) ++ " and " ++ deg
                 | otherwise = showM (f * segLen)
              nearest from pose = case solveIk (soIk opts) { ikAllSolutions = False, ikMaxRestarts = 0 } kin pose (Just from) of
                Left f -> Left (Just f)
                Right [] -> Left Nothing
                Right sols -> Right (solJoints (minimumBy (comparing (stepOf from . solJoints)) sols))
              -- the sub-steps from the previous sample: each within maxJointStep
              finer = foldl (\acc pose -> acc >>= \from -> case nearest from pose of
                                Right q'' | stepOf from q'' <= maxJointStep -> Right q''
                                _ -> Left ())
                            (Right q) (segmentSamples (min (taskPathStep task / 8) defaultPathStep) prev p)
          in case nearest q p of
               Left (Just f) -> Left (k + 1, "at sample " ++ show (k + 1) ++ " (about " ++ at ++ " along): " ++ describeFailureFor robot f)
               Left Nothing -> Left (k + 1, "at sample " ++ show (k + 1) ++ ": no IK solution")
               Right q1 ->
                 let q' = if stepOf q q1 > maxJointStep then either (const Nothing) Just finer else Just q1
                 in case q' of
                      Nothing -> Left (k + 1, "at sample " ++ show (k + 1) ++ " (about " ++ at ++ " along): the nearest solution jumps "
                                              ++ show (roundTo 3 (stepOf q q1)) ++ " rad in one step (a change of branch)")
                      Just q2
                        | not (robotClearanceAtLeast cm bvh q2 d) ->
                            Left (k + 1, "at sample " ++ show (k + 1) ++ " (about " ++ at ++ " along): clearance "
                                         ++ maybe "?" (\c -> showM (clrDistance c) ++ " at " ++ clrBodyName c) (robotClearance cm bvh q2)
                                         ++ ", below " ++ showM d)
                        | selfCollides cm (soSelfMargin opts) q2 ->
                            Left (k + 1, "at sample " ++ show (k + 1) ++ " (about " ++ at ++ " along): self-collision")
                        | otherwise -> go' (k + 1) q2 p ps
    stepOf a b = U.maximum (U.map abs (U.zipWith (-) a b))

-- | The score (docs/select.md) and the ranking, best first. With N targets, a robot reaching n
-- scores 100·(n + 0.9·s)/(N + 0.9) (0 to 100), s = 0.6·(T_min/T) + 0.3·min(c, 5 cm)/5 cm + 0.1·(w/w_max) in [0, 1]:
-- T its cycle time (the term is 0 without one), T_min the fastest robot's, c its minimum
-- clearance (1 for an empty scene), w its minimum manipulability and w_max the largest. So a
-- robot reaching more targets always ranks higher; among equals the faster, then the clearer,
-- then the more dexterous. Rejected robots score 0.
scoreAndRank :: [RobotResult] -> [RobotResult]
scoreAndRank rs =
  let tMin = minimumOr [t | r <- rs, Just t <- [rrCycleTime r]]
      wMax = maximumOr [w | r <- rs, Just w <- [rrMinManipulability r]]
      score r
        | isJust (rrRejected r) || rrTotal r == 0 = 0
        | otherwise =
            let sT = case (rrCycleTime r, tMin) of
                  (Just t, Just m) | t > 0 -> m / t
                  (Just _, Just _) -> 1
                  _ -> 0
                sC = case rrMinClearance r of
                  Just (c, _) -> max 0 (min 0.05 c) / 0.05
                  Nothing | rrReached r > 0 -> 1
                  Nothing -> 0
                sW = case (rrMinManipulability r, wMax) of
                  (Just w, Just m) | m > 0 -> w / m
                  _ -> 0
                s = 0.6 * sT + 0.3 * sC + 0.1 * sW
            in 100 * (fromIntegral (rrReached r) + 0.9 * s) / (fromIntegral (rrTotal r) + 0.9)
      scored = [r {rrScore = score r} | r <- rs]
  in sortBy (comparing (negate . rrScore) <> comparing rrKey) scored
  where
    minimumOr xs = if null xs then Nothing else Just (minimum xs)
    maximumOr xs = if null xs then Nothing else Just (maximum xs)

showKg :: Double -> String
showKg x = show (roundTo 3 x) ++ " kg"

showM :: Double -> String
showM x = let r = roundTo 4 x in if abs r >= 0.1 || r == 0 then show r ++ " m" else showFFloat Nothing r " m"

roundTo :: Int -> Double -> Double
roundTo k x = fromIntegral (round (x * 10 ^ k) :: Integer) / 10 ^ k
