{-# LANGUAGE RecordWildCards #-}
-- | Collision-aware IK for robot selection: every IK solution of a target pose (every closed-form
-- branch, or the numerical solver's distinct solutions over its restarts) within the joint limits,
-- kept when its clearance to the scene is at least d and no checked pair of its own parts comes
-- closer than the self margin; the kept ones sorted by clearance (whole millimetres, larger first),
-- then by distance to the seed. A failure says why: the IK's own failure (beyond reach, joint
-- limits, orientation, budget), or every solution in collision with the best one found (its
-- clearance, the body and the triangle, or the self-colliding pair).
module VProf.Select.Ik
  ( SelectIkOptions (..)
  , defaultSelectIkOptions
  , Candidate (..)
  , SelectIkFailure (..)
  , describeSelectIkFailure
  , describeFixedCollision
  , solveCollisionFree
  , solveCollisionFreeIO
  , collisionFreeCandidates
  ) where

import Data.List (sortOn)
import Numeric (showFFloat)
import qualified Data.Map.Strict as M
import qualified Data.Vector.Unboxed as U

import VProf.Geometry.Bvh (Bvh)
import VProf.Kinematics.Collision
import VProf.Kinematics.Ik
import VProf.Kinematics.Model (Robot (..), Joint (..), JointKind (..))
import VProf.Kinematics.Transform (Tf, V3 (..))

data SelectIkOptions = SelectIkOptions
  { siIk :: IkOptions          -- ^ the IK's options (all solutions are asked for)
  , siClearance :: Double      -- ^ d: least clearance to the scene (m)
  , siSelfMargin :: Double     -- ^ least distance between checked parts of the robot (m)
  }

defaultSelectIkOptions :: SelectIkOptions
defaultSelectIkOptions = SelectIkOptions defaultIkOptions 0.01 0

-- | An IK solution with its clearances.
data Candidate = Candidate
  { cdSolution :: IkSolution
  , cdClearance :: Maybe Clearance     -- ^ to the scene (Nothing: an empty scene)
  , cdSelf :: Maybe SelfContact        -- ^ the nearest checked pair (Nothing: none checked)
  }
  deriving (Show)

data SelectIkFailure
  = IkFailed IkFailure
    -- ^ no IK solution at all (beyond reach, joint limits, orientation, budget, bad request)
  | AllInCollision {failCount :: Int, failBest :: Candidate}
    -- ^ every one of failCount solutions collides; the best is the one whose worse margin
    -- (scene clearance − d, self distance − margin) is largest
  deriving (Show)

describeSelectIkFailure :: SelectIkOptions -> SelectIkFailure -> String
describeSelectIkFailure SelectIkOptions{..} = \case
  IkFailed f -> describeFailure f
  AllInCollision n (Candidate _ c s) ->
    "all " ++ show n ++ " IK solutions collide; the best one: "
      ++ case (c, s) of
        (Just cl, _) | clrDistance cl < siClearance ->
          clearanceWords (clrDistance cl) siClearance ++ " between "
            ++ clrBodyName cl ++ " and scene triangle " ++ show (clrTriangle cl) ++ " near " ++ showP (clrOnScene cl)
        (_, Just sc) ->
          let (a, b) = scNames sc
              d = scDistance sc
          in "self-collision: " ++ a ++ " and " ++ b
               ++ (if d < 0 then " overlap by " ++ mm (negate d)
                   else " are " ++ mm d ++ " apart (at least " ++ mm siSelfMargin ++ " asked)")
        _ -> "in collision"
  where
    mm = showMm
    showP = showPoint

-- | Why no joint vector keeps the clearance d, from one of 'fixedCollisions': the body, the
-- point of it that no joint moves, its clearance and the triangle.
describeFixedCollision :: Double -> Clearance -> String
describeFixedCollision d cl =
  "every configuration collides: " ++ clrBodyName cl ++ " keeps the point " ++ showPoint (clrOnRobot cl)
    ++ " whatever the joints are, " ++ clearanceWords (clrDistance cl) d ++ (if clrDistance cl < 0 then " with" else " from")
    ++ " scene triangle " ++ show (clrTriangle cl)
    ++ " near " ++ showPoint (clrOnScene cl)
    ++ " (ignore_bodies leaves a body out of the cell check)"

-- | A clearance d below the one asked for: "clearance 8.1 mm (at least 10.0 mm asked)", or
-- where the two overlap, "overlapping by 60.0 mm (a clearance of at least 10.0 mm asked)".
clearanceWords :: Double -> Double -> String
clearanceWords d asked
  | d < 0 = "overlapping by " ++ showMm (negate d) ++ " (a clearance of at least " ++ showMm asked ++ " asked)"
  | otherwise = "clearance " ++ showMm d ++ " (at least " ++ showMm asked ++ " asked)"

showMm :: Double -> String
showMm x = showFFloat Nothing (fromIntegral (round (x * 10000) :: Integer) / 10 :: Double) " mm"

showPoint :: V3 -> String
showPoint (V3 x y z) = "(" ++ concatMap (\(k, v) -> k ++ showFFloat Nothing (fromIntegral (round (v * 1000) :: Integer) / 1000 :: Double) "") [("", x), (", ", y), (", ", z)] ++ ") m"

-- | Solutions clear of the scene and of themselves, best first, or why there are none.
solveCollisionFree
  :: SelectIkOptions -> Kinematics -> CollisionModel -> Bvh -> Tf -> Maybe (U.Vector Double)
  -> Either SelectIkFailure [Candidate]
solveCollisionFree opts kin cm bvh target seed = sortOn candidateOrder <$> collisionFreeCandidates opts kin cm bvh target seed

-- | Largest clearance first (whole millimetres), then nearest the seed.
candidateOrder :: Candidate -> (Double, Double)
candidateOrder c =
  ( negate (fromIntegral (floor (1000 * maybe 1e9 clrDistance (cdClearance c)) :: Integer) :: Double)
  , solSeedDistance (cdSolution c) )

-- | 'solveCollisionFree' without the order: the solutions clear of the scene and of themselves in
-- the IK's order (nearest the seed first), each with its exact clearance computed only when it is
-- looked at; or why there are none.
--
-- Work is done once per geometry (solutions a whole turn of a revolute joint apart share one),
-- and the exact clearance only where it is reported: first the early-exit test "clearance ≥ d
-- and no self-contact closer than the margin" of every geometry; the exact clearance of those
-- that pass when asked (the order of 'solveCollisionFree' asks for all); when none passes, a
-- branch and bound for the best one (a geometry whose self margin, or whose scene clearance by
-- the early-exit test, is already below the best margin so far cannot be the best and gets no
-- exact clearance).
collisionFreeCandidates
  :: SelectIkOptions -> Kinematics -> CollisionModel -> Bvh -> Tf -> Maybe (U.Vector Double)
  -> Either SelectIkFailure [Candidate]
collisionFreeCandidates opts kin cm bvh target seed =
  candidatesOf opts cm bvh (solveIk (everySolution opts) kin target seed)

-- | 'solveCollisionFree' with a wall-time budget (seconds) for the IK's search: the numerical
-- solver restarts until the budget is spent (or its restart count), as 'solveIkIO'; the
-- clearances of the solutions found are checked after it.
solveCollisionFreeIO
  :: Double -> SelectIkOptions -> Kinematics -> CollisionModel -> Bvh -> Tf -> Maybe (U.Vector Double)
  -> IO (Either SelectIkFailure [Candidate])
solveCollisionFreeIO budget opts kin cm bvh target seed = do
  sols <- solveIkIO budget (everySolution opts) kin target seed
  pure (sortOn candidateOrder <$> candidatesOf opts cm bvh sols)

-- | The IK's options for a collision check: every solution, as the nearest may collide
-- where another is clear.
everySolution :: SelectIkOptions -> IkOptions
everySolution opts = (siIk opts) {ikAllSolutions = True}

-- | The candidates among the IK's answer (every solution, nearest the seed first).
candidatesOf
  :: SelectIkOptions -> CollisionModel -> Bvh -> Either IkFailure [IkSolution]
  -> Either SelectIkFailure [Candidate]
candidatesOf SelectIkOptions{..} cm bvh ik =
  case ik of
    Left f -> Left (IkFailed f)
    Right [] -> Left (IkFailed (Unreachable "no solution" 0))
    Right sols ->
      let -- solutions that differ by whole turns of revolute joints have the same geometry: their
          -- clearances are computed once (a UR's ±360° limits give 64 copies of each branch),
          -- at the last of them
          kinds = map jointKind (robotJoints (cmRobot cm))
          canonical q = [ if k == Revolute then round (1e9 * (x - 2 * pi * fromIntegral (round (x / (2 * pi)) :: Integer))) else round (1e9 * x)
                        | (k, x) <- zip kinds (U.toList q) ] :: [Integer]
          keyed = [ (canonical (solJoints s), s) | s <- sols ]
          geometry = M.fromList [ (g, Geometry q (passes q) (robotClearance cm bvh q) (selfClearance cm q))
                                | (g, s) <- keyed, let q = solJoints s ]
          passes q = robotClearanceAtLeast cm bvh q siClearance && not (selfCollides cm siSelfMargin q)
          candidate (g, s) = let Geometry _ _ c sc = geometry M.! g in Candidate s c sc
          good = [ candidate gs | gs@(g, _) <- keyed, geoPasses (geometry M.! g) ]
      in case good of
           [] -> let best = bestGeometry siClearance siSelfMargin cm bvh (M.toList geometry)
                 in Left (AllInCollision (length sols) (candidate (last [ gs | gs@(g, _) <- keyed, g `elem` best ])))
           _ -> Right good

-- | A geometry: a representative joint vector, whether it passes the early-exit tests, its exact
-- scene clearance and nearest self-contact (both lazy).
data Geometry = Geometry
  { geoJoints :: U.Vector Double
  , geoPasses :: Bool
  , geoClearance :: Maybe Clearance
  , geoSelf :: Maybe SelfContact
  }

-- | The keys of the geometries whose worse margin (scene clearance − d, self distance − margin)
-- is the largest, by branch and bound.
bestGeometry :: Ord k => Double -> Double -> CollisionModel -> Bvh -> [(k, Geometry)] -> [k]
bestGeometry d selfM cm bvh = go (-1 / 0) []
  where
    sceneMargin g = maybe (1 / 0) (\cl -> clrDistance cl - d) (geoClearance g)
    selfMargin g = maybe (1 / 0) (\sc -> scDistance sc - selfM) (geoSelf g)
    go _ acc [] = acc
    go k acc ((key, g) : rest)
        -- a checked pair nearer than k + the self margin (with an allowance for rounding): the
        -- margin is below k, found without the distance of every pair
      | k > -1 / 0 && selfCollides cm (k + selfM - 1e-9 * (1 + abs k + abs selfM)) (geoJoints g) = go k acc rest
      | selfMargin g < k = go k acc rest
        -- the scene clearance is below k + d (with an allowance for rounding): the margin is below k
      | k > -1 / 0 && not (robotClearanceAtLeast cm bvh (geoJoints g) (k + d - 1e-9 * (1 + abs k + abs d))) = go k acc rest
      | otherwise =
          let m = min (sceneMargin g) (selfMargin g)
          in if m > k then go m [key] rest else if m == k then go k (key : acc) rest else go k acc rest
