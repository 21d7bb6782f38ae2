-- | Forward kinematics and clearance of a whole robot by the test oracles, apart from the library's
-- chain, frames and BVH: every body frame as a product of "Support.FkOracle"'s textbook 4×4
-- matrices (read from the model's link table and drives), the collision parts placed in those
-- frames, each part's distance to the scene by "Support.DistanceOracle" over every triangle, and
-- the distance of every pair of parts the model checks against each other.
module Support.RobotOracle
  ( oracleFrames
  , oracleTool
  , oracleClearance
  , oracleSelfClearance
  , poseGap
  ) where

import qualified Data.Vector as V

import Support.DistanceOracle
import Support.FkOracle
import VProf.Kinematics.Collision (CollisionModel (..), Part (..))
import VProf.Kinematics.Model
import VProf.Kinematics.Transform (V3 (..), toRows)

-- | Frames of the base, of every link and of the tool at joint values q.
oracleFrames :: Robot -> [Double] -> [Mat]
oracleFrames r q =
  let base = matFromRows (toRows (robotBase r))
      fs = scanl (\acc l -> acc `mmul` linkMat l) base (robotLinks r)
  in fs ++ [last fs `mmul` matFromRows (toRows (robotTool r))]
  where
    var l = let Drive off ts = linkDrive l in off + sum [c * (q !! j) | (j, c) <- ts]
    linkMat l = case (linkGeometry l, linkJointKind l) of
      (FixedTransform t, _) -> matFromRows (toRows t)
      (DhStandard th d a al, Just Revolute) -> dhStd (th + var l) d a al
      (DhStandard th d a al, Just Prismatic) -> dhStd th (d + var l) a al
      (DhStandard th d a al, Nothing) -> dhStd th d a al
      (DhModified al a th d, Just Revolute) -> dhMod al a (th + var l) d
      (DhModified al a th d, Just Prismatic) -> dhMod al a th (d + var l)
      (DhModified al a th d, Nothing) -> dhMod al a th d
      (UrdfJoint o (V3 x y z), k) ->
        let n = sqrt (x * x + y * y + z * z); u@(ux, uy, uz) = (x / n, y / n, z / n)
            motion = case k of
              Nothing -> ident
              Just Revolute -> axisAngle u (var l)
              Just Prismatic -> tr (var l * ux) (var l * uy) (var l * uz)
        in matFromRows (toRows o) `mmul` motion

oracleTool :: Robot -> [Double] -> Mat
oracleTool r q = last (oracleFrames r q)

-- | The largest entry of the difference of two poses' 3×4 parts.
poseGap :: Mat -> Mat -> Double
poseGap = maxDiff

-- | The least surface distance between the model's parts (but those of ignored bodies) and the
-- triangles: every triangle (skipped only by a lower bound of its distance), no hierarchy.
oracleClearance :: CollisionModel -> OMesh -> [Double] -> Double
oracleClearance cm tris q =
  minimum (1 / 0 : [fst (oSegmentMeshNear a e tris) - rad | (b, a, e, rad) <- oracleParts cm q, b `notElem` cmSceneIgnore cm])

-- | The least surface distance between the pairs of parts the model checks against each other
-- (its list of pairs, by part index), the parts placed by the oracle's frames; infinite when no
-- pair is checked.
oracleSelfClearance :: CollisionModel -> [Double] -> Double
oracleSelfClearance cm q =
  let ps = V.fromList (oracleParts cm q)
      gap (_, a, e, ra) (_, b, f, rb) = oSegmentSegment a e b f - ra - rb
  in minimum (1 / 0 : [gap (ps V.! i) (ps V.! j) | (i, j) <- cmSelfPairs cm])

-- | Every part of the model as (body, one end, the other end, radius) in the world at q.
oracleParts :: CollisionModel -> [Double] -> [(Int, Pt, Pt, Double)]
oracleParts cm q =
  let fs = V.fromList (oracleFrames (cmRobot cm) q)
      point m (V3 x y z) = let [a, b, c] = map (\row -> sum (zipWith (*) row [x, y, z, 1])) (take 3 m) in (a, b, c)
      origin m = point m (V3 0 0 0)
      place (Attached b (Capsule a e rad)) = (b, point (fs V.! b) a, point (fs V.! b) e, rad)
      place (Bone b rad) = (b, origin (fs V.! (b - 1)), origin (fs V.! b), rad)
  in map place (V.toList (cmParts cm))
