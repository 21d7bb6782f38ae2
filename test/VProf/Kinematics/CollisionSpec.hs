-- | The robot's collision model: body frames against the compiled FK, default bones against the
-- library's capsules, the UR5 in the work cell against the brute-force oracle over every triangle,
-- the tool capsule and self-collision.
module VProf.Kinematics.CollisionSpec (spec) where

import Control.Monad (forM_)
import Data.List (minimumBy)
import Data.Ord (comparing)
import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import Support.DistanceOracle
import VProf.Geometry.Bvh
import VProf.Geometry.Distance
import VProf.Geometry.Format.Obj
import VProf.Geometry.Mesh (triangles)
import VProf.Kinematics.Collision
import VProf.Kinematics.Forward (forward)
import VProf.Kinematics.Library
import VProf.Kinematics.Model hiding (Capsule (..))
import VProf.Kinematics.Transform

pt :: V3 -> Pt
pt (V3 x y z) = (x, y, z)

ur5 :: Robot
ur5 = either error id (lookupRobot "ur5")

genQ :: Robot -> Gen (U.Vector Double)
genQ r = U.fromList <$> mapM (\j -> let Limits lo hi = jointLimits j in choose (max (-pi) lo, min pi hi)) (robotJoints r)

tfClose :: Double -> Tf -> Tf -> Bool
tfClose tol a b = maximum (map abs (zipWith (-) (toRows a) (toRows b))) <= tol

stripCapsules :: Robot -> Robot
stripCapsules r = r {robotLinks = [l {linkCapsules = []} | l <- robotLinks r]}

segClose :: Capsule -> Capsule -> Bool
segClose (Capsule a b r) (Capsule c d s) =
  abs (r - s) < 1e-12 && ((near a c && near b d) || (near a d && near b c))
  where near x y = v3Norm (v3Sub x y) < 1e-9

spec :: Spec
spec = do
  cell <- runIO (readObj "../shared/data/cell/cell.obj")
  let mesh = either error id cell
      bvh = buildBvh mesh
      tris = [(pt a, pt b, pt c) | (a, b, c) <- triangles mesh]

  describe "body frames" $
    it "end in the compiled chain's tool pose for every library robot" $
      property $ conjoin
        [ counterexample (robotName r) $ forAll (genQ r) $ \q ->
            tfClose 1e-9 (last (bodyFrames r q)) (forward (compile r) q)
        | (_, Right r) <- libraryRobots ]

  describe "default capsules" $ do
    it "are bones between consecutive frame origins, equal to the library's standard-DH capsules" $
      property $ forAll (genQ ur5) $ \q ->
        let own = map wcCapsule (robotCapsules (collisionModel defaultCollisionOptions ur5) q)
            cm = collisionModel defaultCollisionOptions {coRadius = Just 0.06} (stripCapsules ur5)
            bones = map wcCapsule (robotCapsules cm q)
        in conjoin (zipWith segClose own bones) .&&. length own === length bones
    it "take the radius rule: a twentieth of the stretched length, within [0.01, 0.1] m" $ do
      let cm = collisionModel defaultCollisionOptions (stripCapsules ur5)
      cmDefaulted cm `shouldSatisfy` maybe False (\r -> abs (r - 1.192509 / 20) < 1e-6)
      cmDefaulted (collisionModel defaultCollisionOptions ur5) `shouldBe` Nothing
    it "add a tool capsule in the tool frame" $ do
      let tool = Capsule (V3 0 0 0) (V3 0 0 0.1) 0.03
          cm = collisionModel defaultCollisionOptions {coTool = Just tool} ur5
          q = U.fromList [0.1, -1, 1.2, 0.3, 0.4, 0.5]
          t = forward (compile ur5) q
          w = last (robotCapsules cm q)
      wcBody w `shouldBe` length (robotLinks ur5) + 1
      wcCapsule w `shouldSatisfy` segClose (Capsule (applyPoint t (V3 0 0 0)) (applyPoint t (V3 0 0 0.1)) 0.03)

  describe "the UR5 in the work cell" $ do
    let cm = collisionModel defaultCollisionOptions ur5
        oracle q =
          minimumBy (comparing (\(d, _, _) -> d))
            [ (d - capRadius c, wcBody w, k)
            | w <- robotCapsules cm q, let c = wcCapsule w
            , let (d, k) = oSegmentMeshBounded (pt (capA c)) (pt (capB c)) tris ]
    it "clearance agrees with the oracle over every triangle (1e-9 m): distance, and the part and triangle named" $
      withMaxSuccess 15 $ property $ forAll (genQ ur5) $ \q ->
        let Just c = robotClearance cm bvh q
            (od, ob, _) = oracle q
            w = head [x | x <- robotCapsules cm q, wcPart x == clrPart c]
            cap = wcCapsule w
            (a, b, t) = tris !! clrTriangle c
        in counterexample (show (c, od, ob)) $ conjoin
             [ abs (clrDistance c - od) <= 1e-9
             , abs (oSegmentTriangle (pt (capA cap)) (pt (capB cap)) a b t - capRadius cap - od) <= 1e-9
             ]
    it "robotClearanceAtLeast agrees with the clearance" $
      withMaxSuccess 100 $ property $ forAll (genQ ur5) $ \q -> forAll (choose (-0.1, 0.1)) $ \k ->
        let Just c = robotClearance cm bvh q
            d = clrDistance c + k
        in abs k > 1e-9 ==> robotClearanceAtLeast cm bvh q d === (clrDistance c >= d)
    it "an arm reaching down into the table overlaps it, one held up is clear of everything" $ do
      let down = U.fromList [0, -0.3, 1.6, 0, 0, 0]   -- forearm pitched into the table top
          up = U.fromList [0, -pi / 2, 0, -pi / 2, 0, 0]
      fmap clrDistance (robotClearance cm bvh down) `shouldSatisfy` maybe False (< 0)
      fmap clrDistance (robotClearance cm bvh up) `shouldSatisfy` maybe False (> 0)

    it "leaves out the bodies of coSceneIgnore: the base column is what keeps the UR5 within 0.04 m of the table" $ do
      let up = U.fromList [0, -pi / 2, 0, -pi / 2, 0, 0]
          cm' = collisionModel defaultCollisionOptions {coSceneIgnore = [1]} ur5
          Just c = robotClearance cm bvh up
          Just c' = robotClearance cm' bvh up
      clrBody c `shouldBe` 1
      clrDistance c `shouldSatisfy` (\d -> abs (d - 0.04) < 1e-6)
      clrBody c' `shouldSatisfy` (/= 1)
      clrDistance c' `shouldSatisfy` (> clrDistance c)
      robotClearanceAtLeast cm' bvh up (clrDistance c') `shouldBe` True
      robotClearanceAtLeast cm bvh up (clrDistance c') `shouldBe` False

  describe "self-collision" $ do
    let cm = collisionModel defaultCollisionOptions ur5
    it "checks only non-adjacent bodies clear of each other at the reference configuration" $ do
      cmSelfPairs cm `shouldSatisfy` (not . null)
      selfCollides cm 0 (referenceConfiguration ur5) `shouldBe` False
      forM_ (selfDistances cm (referenceConfiguration ur5)) $ \s -> do
        let (a, b) = scBodies s
        abs (a - b) `shouldSatisfy` (>= 2)
        scDistance s `shouldSatisfy` (> 0)
    it "finds the elbow folded back onto the upper arm" $ do
      let q = U.fromList [0, 0, pi, 0, 0, 0]
      selfCollides cm 0 q `shouldBe` True
      fmap scDistance (selfClearance cm q) `shouldSatisfy` maybe False (< 0)
    it "self distances agree with the oracle's segment distances" $
      property $ forAll (genQ ur5) $ \q ->
        let ws = robotCapsules cm q
        in conjoin
             [ abs (scDistance s - (oSegmentSegment (pt (capA a)) (pt (capB a)) (pt (capA b)) (pt (capB b)) - capRadius a - capRadius b)) <= 1e-9
             | s <- selfDistances cm q, let (i, j) = scParts s; a = wcCapsule (ws !! i); b = wcCapsule (ws !! j) ]
