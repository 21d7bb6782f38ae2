-- | Collision-aware IK: the UR5 in the work cell, a reachable target above the table, a target
-- beyond reach, and one below the table top.
module VProf.Select.IkSpec (spec) where

import Data.List (isInfixOf, sort)
import Test.Hspec

import VProf.Geometry.Bvh
import VProf.Geometry.Format.Obj
import VProf.Kinematics.Collision
import VProf.Kinematics.Ik
import VProf.Kinematics.Library
import VProf.Kinematics.Transform
import VProf.Select.Ik

spec :: Spec
spec = do
  cell <- runIO (readObj "../shared/data/cell/cell.obj")
  let bvh = buildBvh (either error id cell)
      ur5 = either error id (lookupRobot "ur5")
      kin = kinematicsFor ur5
      -- the base column is always 0.04 m from the table's edge: left out, so that clearances rank
      cm = collisionModel defaultCollisionOptions {coSceneIgnore = [1]} ur5
      opts = defaultSelectIkOptions {siClearance = 0.01}
      down x y z = trans x y z `compose` rotX pi
  describe "solveCollisionFree" $ do
    it "keeps the branches clear of the cell, best clearance first, and drops the others" $ do
      let Right all' = solveIk defaultIkOptions {ikAllSolutions = True} kin (down 0.5 0.2 0.3) Nothing
          r = solveCollisionFree opts kin cm bvh (down 0.5 0.2 0.3) Nothing
      case r of
        Left f -> expectationFailure (describeSelectIkFailure opts f)
        Right cs -> do
          length cs `shouldSatisfy` (\n -> n > 0 && n <= length all')
          mapM_ (\c -> do
                   fmap clrDistance (cdClearance c) `shouldSatisfy` maybe False (>= 0.01)
                   selfCollides cm 0 (solJoints (cdSolution c)) `shouldBe` False
                   robotClearanceAtLeast cm bvh (solJoints (cdSolution c)) 0.01 `shouldBe` True) cs
          let mmOf c = maybe 0 (\cl -> floor (1000 * clrDistance cl)) (cdClearance c) :: Integer
          map mmOf cs `shouldBe` reverse (sort (map mmOf cs))
          -- within a millimetre of clearance, nearer the seed first
          and [ solSeedDistance (cdSolution a) <= solSeedDistance (cdSolution b)
              | (a, b) <- zip cs (drop 1 cs), mmOf a == mmOf b ] `shouldBe` True
          -- the dropped ones really collide
          let kept = map (solJoints . cdSolution) cs
              dropped = [s | s <- all', solJoints s `notElem` kept]
          mapM_ (\s -> (robotClearanceAtLeast cm bvh (solJoints s) 0.01 && not (selfCollides cm 0 (solJoints s))) `shouldBe` False) dropped
    it "passes on the IK's failure for a target beyond reach" $
      case solveCollisionFree opts kin cm bvh (down 3 0 0.5) Nothing of
        Left (IkFailed _) -> pure ()
        other -> expectationFailure ("expected an IK failure, got " ++ either (describeSelectIkFailure opts) (show . length) other)
    it "says which body hits which triangle when every solution collides (a target below the table top)" $
      case solveCollisionFree opts kin cm bvh (down 0.5 0 (-0.1)) Nothing of
        Left f@(AllInCollision n best) -> do
          n `shouldSatisfy` (> 0)
          fmap clrDistance (cdClearance best) `shouldSatisfy` maybe False (< 0.01)
          describeSelectIkFailure opts f `shouldSatisfy` ("clearance" `isInfixOf`)
          describeSelectIkFailure opts f `shouldSatisfy` ("scene triangle" `isInfixOf`)
        other -> expectationFailure ("expected all in collision, got " ++ either (describeSelectIkFailure opts) (show . length) other)
