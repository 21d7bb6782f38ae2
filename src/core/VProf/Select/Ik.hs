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
  , solveCollisionFree
  ) where

import Data.List (sortOn)
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
          "clearance " ++ mm (clrDistance cl) ++ " (at least " ++ mm siClearance ++ " asked) between "
            ++ clrBodyName cl ++ " and scene triangle " ++ show (clrTriangle cl) ++ " near " ++ showP (clrOnScene cl)
        (_, Just sc) ->
          let (a, b) = scNames sc
          in "self-collision: " ++ a ++ " and " ++ b ++ " at " ++ mm (scDistance sc)
        _ -> "in collision"
  where
    mm x = show (fromIntegral (round (x * 10000) :: Integer) / 10 :: Double) ++ " mm"
    showP (V3 x y z) = "(" ++ concatMap (\(k, v) -> k ++ show (fromIntegral (round (v * 1000) :: Integer) / 1000 :: Double)) [("", x), (", ", y), (", ", z)] ++ ") m"

-- | Solutions clear of the scene and of themselves, best first, or why there are none.
solveCollisionFree
  :: SelectIkOptions -> Kinematics -> CollisionModel -> Bvh -> Tf -> Maybe (U.Vector Double)
  -> Either SelectIkFailure [Candidate]
solveCollisionFree SelectIkOptions{..} kin cm bvh target seed =
  case solveIk siIk {ikAllSolutions = True} kin target seed of
    Left f -> Left (IkFailed f)
    Right [] -> Left (IkFailed (Unreachable "no solution" 0))
    Right sols ->
      let -- solutions that differ by whole turns of revolute joints have the same geometry: their
          -- clearances are computed once (a UR's ±360° limits give 64 copies of each branch)
          kinds = map jointKind (robotJoints (cmRobot cm))
          canonical q = [ if k == Revolute then round (1e9 * (x - 2 * pi * fromIntegral (round (x / (2 * pi)) :: Integer))) else round (1e9 * x)
                        | (k, x) <- zip kinds (U.toList q) ] :: [Integer]
          geometry = M.fromList [ (canonical q, (robotClearance cm bvh q, selfClearance cm q))
                                | s <- sols, let q = solJoints s ]
          cands = [ Candidate s c sc | s <- sols, let (c, sc) = geometry M.! canonical (solJoints s) ]
          sceneMargin c = maybe (1 / 0) (\cl -> clrDistance cl - siClearance) (cdClearance c)
          selfMargin c = maybe (1 / 0) (\sc -> scDistance sc - siSelfMargin) (cdSelf c)
          ok c = sceneMargin c >= 0 && selfMargin c >= 0
          good = filter ok cands
          key c = ( negate (fromIntegral (floor (1000 * maybe 1e9 clrDistance (cdClearance c)) :: Integer) :: Double)
                  , solSeedDistance (cdSolution c) )
      in case good of
           [] -> Left (AllInCollision (length cands) (last (sortOn (\c -> min (sceneMargin c) (selfMargin c)) cands)))
           _ -> Right (sortOn key good)
