{-# LANGUAGE BangPatterns, RecordWildCards #-}
-- | The robot as capsules at a joint vector, its clearance to a scene (a 'Bvh' of triangles) and
-- its self-collision.
--
-- Bodies are numbered along the chain: 0 the base frame, k + 1 the frame of link k (every entry of
-- 'robotLinks', fixed ones included), and n + 1 the tool frame (link n − 1's frame · the robot's
-- tool transform), n the number of links. A part of the robot is a capsule attached to one body:
--
-- * the model's own capsules ('linkCapsules', in the link's frame);
-- * if no link has any, the default: per link a "bone" from the previous frame's origin to the
--   link frame's origin, in the world at each joint vector (so it is right for DH and URDF
--   alike), with the radius rule of 'defaultRadius';
-- * optionally a tool capsule in the tool frame ('coTool').
--
-- Self-collision is checked between parts of non-adjacent bodies (body numbers at least 2 apart)
-- that are clear of each other at the reference configuration (the middle of the joint ranges,
-- 0 for an unbounded side): parts that already touch there (a compact wrist, whose short links are
-- thinner than two radii) are taken as touching by design, as an allowed-collision matrix would.
-- See docs/collision.md.
module VProf.Kinematics.Collision
  ( CollisionOptions (..)
  , defaultCollisionOptions
  , Part (..)
  , CollisionModel (..)
  , collisionModel
  , defaultRadius
  , bodyFrames
  , bodyName
  , unknownBody
  , WorldCapsule (..)
  , robotCapsules
  , Clearance (..)
  , robotClearance
  , robotClearanceAtLeast
  , fixedCollisions
  , SelfContact (..)
  , selfDistances
  , selfClearance
  , selfCollides
  , referenceConfiguration
  ) where

import Data.List (minimumBy, sortOn)
import Data.Ord (comparing)
import qualified Data.Vector as V
import qualified Data.Vector.Unboxed as U

import VProf.Geometry.Distance
import VProf.Kinematics.Model hiding (Capsule (..))
import qualified VProf.Kinematics.Model as M
import VProf.Kinematics.Transform

data CollisionOptions = CollisionOptions
  { coTool :: Maybe Capsule       -- ^ a capsule in the tool frame (a gripper, a torch)
  , coRadius :: Maybe Double      -- ^ the radius of default capsules instead of 'defaultRadius'
  , coForceDefault :: Bool        -- ^ default capsules even when the model has its own
  , coSceneIgnore :: [Int]        -- ^ bodies left out of the scene check (e.g. 1, a base column
                                  --   standing on the cell's table)
  }

defaultCollisionOptions :: CollisionOptions
defaultCollisionOptions = CollisionOptions Nothing Nothing False []

-- | A capsule attached to a body, or the default bone of a body (from the previous body's frame
-- origin to this body's), with its radius.
data Part
  = Attached !Int Capsule
  | Bone !Int !Double
  deriving (Eq, Show)

partBody :: Part -> Int
partBody (Attached b _) = b
partBody (Bone b _) = b

data CollisionModel = CollisionModel
  { cmRobot :: Robot
  , cmParts :: V.Vector Part
  , cmSelfPairs :: [(Int, Int)]    -- ^ part indices checked for self-collision (i < j)
  , cmDefaulted :: Maybe Double    -- ^ the radius, when default bones were generated
  , cmSceneIgnore :: [Int]         -- ^ bodies left out of the scene check
  }

-- | The default radius: a twentieth of the arm's stretched length L (the sum of the distances
-- between consecutive frame origins at the reference configuration), clamped to [0.01 m, 0.1 m].
-- For the UR5 (L ≈ 1.19 m) this is 0.06 m, the radius its library file states.
defaultRadius :: Robot -> Double
defaultRadius r =
  let fs = bodyFrames r (referenceConfiguration r)
      os = map translation (take (length (robotLinks r) + 1) fs)
      l = sum (zipWith (\a b -> v3Norm (v3Sub a b)) os (drop 1 os))
  in max 0.01 (min 0.1 (l / 20))

-- | The middle of each joint's range (0 for an unbounded side).
referenceConfiguration :: Robot -> U.Vector Double
referenceConfiguration r = U.fromList [mid (jointLimits j) | j <- robotJoints r]
  where
    mid (Limits lo hi)
      | isInfinite lo || isInfinite hi = 0
      | otherwise = 0.5 * (lo + hi)

collisionModel :: CollisionOptions -> Robot -> CollisionModel
collisionModel CollisionOptions{..} robot =
  let nl = length (robotLinks robot)
      own = [Attached (k + 1) (toCap c) | (k, l) <- zip [0 ..] (robotLinks robot), c <- linkCapsules l]
      useDefault = coForceDefault || null own
      rad = maybe (defaultRadius robot) id coRadius
      linkParts = if useDefault then [Bone (k + 1) rad | k <- [0 .. nl - 1]] else own
      tool = [Attached (nl + 1) c | Just c <- [coTool]]
      parts = V.fromList (linkParts ++ tool)
      m0 = CollisionModel robot parts [] (if useDefault then Just rad else Nothing) coSceneIgnore
      ref = worldParts m0 (referenceConfiguration robot)
      pairs =
        [ (i, j)
        | i <- [0 .. V.length parts - 1], j <- [i + 1 .. V.length parts - 1]
        , abs (partBody (parts V.! i) - partBody (parts V.! j)) >= 2
        , capsuleGap (ref V.! i) (ref V.! j) > 0
        ]
  in m0 {cmSelfPairs = pairs}
  where
    toCap (M.Capsule a b r) = Capsule a b r

-- | The world frame of every body at joint vector q (length n + 2): base, each link, tool. The
-- textbook product of 'linkTransform' over the links (fixed links included).
bodyFrames :: Robot -> U.Vector Double -> [Tf]
bodyFrames Robot{..} q =
  let links = scanl step robotBase robotLinks
      step acc l = acc `compose` linkTransform l (variable l)
      variable l = case linkJointKind l of
        Nothing -> 0
        Just _ -> let Drive off ts = linkDrive l in off + sum [c * q U.! j | (j, c) <- ts]
  in links ++ [last links `compose` robotTool]

-- | "base", the link's name (or "link k" when it has none), or "tool".
bodyName :: Robot -> Int -> String
bodyName r b
  | b == 0 = "base"
  | b > length (robotLinks r) = "tool"
  | otherwise = let n = linkName (robotLinks r !! (b - 1)) in if null n then "link " ++ show (b - 1) else n

-- | Why a body number given to leave out of the scene check ('coSceneIgnore') names none of the
-- robot's bodies (1 … n its links, n + 1 the tool when it has a capsule), if it does not.
unknownBody :: Robot -> Bool -> Int -> Maybe String
unknownBody r hasTool b
  | b >= 1 && b <= top = Nothing
  | otherwise = Just ("body " ++ show b ++ " is not one of " ++ robotName r ++ "'s: its bodies are 1 to " ++ show n
                      ++ " (" ++ bodyName r 1 ++ " to " ++ bodyName r n ++ ")"
                      ++ (if hasTool then " and " ++ show (n + 1) ++ " (the tool capsule)" else ""))
  where
    n = length (robotLinks r)
    top = if hasTool then n + 1 else n

-- | A part of the robot placed in the world.
data WorldCapsule = WorldCapsule {wcPart :: !Int, wcBody :: !Int, wcCapsule :: !Capsule}
  deriving (Show)

worldParts :: CollisionModel -> U.Vector Double -> V.Vector Capsule
worldParts cm q = V.map wcCapsule (V.fromList (robotCapsules cm q))

-- | Every part at joint vector q, in the world.
robotCapsules :: CollisionModel -> U.Vector Double -> [WorldCapsule]
robotCapsules CollisionModel{..} q =
  let fs = V.fromList (bodyFrames cmRobot q)
      place (Attached b (Capsule a e r)) = let t = fs V.! b in Capsule (applyPoint t a) (applyPoint t e) r
      place (Bone b r) = Capsule (translation (fs V.! (b - 1))) (translation (fs V.! b)) r
  in [WorldCapsule i (partBody p) (place p) | (i, p) <- zip [0 ..] (V.toList cmParts)]

capsuleGap :: Capsule -> Capsule -> Double
capsuleGap (Capsule a b r) (Capsule c d s) = sqrt (clSquared (segmentSegment a b c d)) - r - s

-- | The robot's nearest approach to the scene.
data Clearance = Clearance
  { clrDistance :: !Double   -- ^ capsule surface to the scene (negative: overlapping)
  , clrPart :: !Int
  , clrBody :: !Int
  , clrBodyName :: String
  , clrTriangle :: !Int
  , clrOnRobot :: !V3        -- ^ on the capsule's axis
  , clrOnScene :: !V3
  }
  deriving (Show)

-- | The minimum over the parts (but those of 'cmSceneIgnore') of their distance to the scene;
-- Nothing for an empty scene or a robot without parts. Among parts at the same distance the
-- first in the model's order, and within a part the triangle 'minimumDistance' finds.
--
-- Only the minimum is reported, so the parts share one bound: a cheap probe of every part (one
-- leaf of the BVH each, 'probeDistance') gives an upper bound of the answer and an order, nearest
-- probe first, and each part is then searched only below the best distance so far
-- ('nearestWithin'). A part far from the scene costs a few nodes instead of a full search.
robotClearance :: CollisionModel -> Bvh -> U.Vector Double -> Maybe Clearance
robotClearance cm bvh q =
  case [ (probeDistance bvh c - capRadius c, i, w) | (i, w) <- zip [0 :: Int ..] (sceneParts cm q), let c = wcCapsule w ] of
    [] -> Nothing
    probes ->
      let start = minimum [s | (s, _, _) <- probes]
          step best (_, i, WorldCapsule pt b c) =
            let bound = maybe start (\(h, _, _, _) -> hitDistance h) best + capRadius c
            in case nearestWithin bvh c (slack bound) of
                 Just h | better (hitDistance h, i) best -> Just (h, i, pt, b)
                 _ -> best
          better (d, i) = maybe True (\(h, j, _, _) -> d < hitDistance h || (d == hitDistance h && i < j))
          slack x = x + 1e-9 * abs x + 1e-12
      in (\(Hit{..}, _, pt, b) -> Clearance hitDistance pt b (bodyName (cmRobot cm) b) hitTriangle hitOnAxis hitOnMesh)
           <$> foldl step Nothing (sortOn (\(s, _, _) -> s) probes)

-- | Whether every part keeps at least d from the scene (stops at the first that does not).
robotClearanceAtLeast :: CollisionModel -> Bvh -> U.Vector Double -> Double -> Bool
robotClearanceAtLeast cm bvh q d = all (\w -> clearanceAtLeast bvh (wcCapsule w) d) (sceneParts cm q)

-- | The scene parts that are nearer the scene than d whatever the joints are: a part with a point
-- of its axis that no joint moves (an end of a part of a body before the first moving link, or an
-- end on the first moving link's axis of a part of the body it moves, e.g. the base column's foot)
-- and that point nearer the scene than d + its radius. A part's clearance at any joint vector is
-- at most the point's, so no joint vector keeps d (the point's clearance is below d − 1e-9).
-- Each as a 'Clearance' at that point ('clrOnRobot' the point).
--
-- An end is on the axis when it stays put as the first moving joint turns a third of a turn (a
-- point off a rotation's axis moves on a circle: √3 · its distance to the axis); a prismatic first
-- joint moves every point.
fixedCollisions :: CollisionModel -> Bvh -> Double -> [Clearance]
fixedCollisions cm bvh d =
  [ Clearance (hitDistance h) i b (bodyName robot b) (hitTriangle h) x (hitOnMesh h)
  | (i, WorldCapsule _ b (Capsule p0 q0 r), WorldCapsule _ _ (Capsule p1 q1 _)) <- zip3 [0 :: Int ..] (robotCapsules cm qa) (robotCapsules cm qb)
  , b `notElem` cmSceneIgnore cm
  , x <- [ e0 | (e0, e1) <- [(p0, p1), (q0, q1)], b <= k || (b == k + 1 && turned && still e0 e1) ]
  , Just h <- [minimumDistance bvh (Capsule x x r)]
  , hitDistance h < d - 1e-9 ]
  where
    robot = cmRobot cm
    qa = referenceConfiguration robot
    -- the first moving link (bodies up to k do not move) and a joint vector that turns it by 2π/3
    k = length (takeWhile ((== Nothing) . linkJointKind) (robotLinks robot))
    (turned, qb) = case drop k (robotLinks robot) of
      Link {linkJointKind = Just Revolute, linkDrive = Drive _ ts} : _
        | (j, c) : _ <- [t | t@(_, c) <- ts, c /= 0] -> (True, qa U.// [(j, qa U.! j + 2 * pi / 3 / c)])
      _ -> (False, qa)
    still (V3 ax ay az) (V3 bx by bz) =
      let dd = abs (ax - bx) + abs (ay - by) + abs (az - bz)
      in dd <= 1e-12 * (1 + abs ax + abs ay + abs az)

sceneParts :: CollisionModel -> U.Vector Double -> [WorldCapsule]
sceneParts cm q = [w | w <- robotCapsules cm q, wcBody w `notElem` cmSceneIgnore cm]

-- | Two parts of the robot and their surface distance.
data SelfContact = SelfContact
  { scDistance :: !Double
  , scParts :: !(Int, Int)
  , scBodies :: !(Int, Int)
  , scNames :: (String, String)
  }
  deriving (Show)

-- | Every checked pair ('cmSelfPairs') with its distance at q.
selfDistances :: CollisionModel -> U.Vector Double -> [SelfContact]
selfDistances cm q =
  let ws = V.fromList (robotCapsules cm q)
      nm = bodyName (cmRobot cm)
  in [ SelfContact (capsuleGap (wcCapsule a) (wcCapsule b)) (i, j) (wcBody a, wcBody b) (nm (wcBody a), nm (wcBody b))
     | (i, j) <- cmSelfPairs cm, let a = ws V.! i; b = ws V.! j ]

-- | The nearest checked pair; Nothing when no pair is checked.
selfClearance :: CollisionModel -> U.Vector Double -> Maybe SelfContact
selfClearance cm q = case selfDistances cm q of
  [] -> Nothing
  cs -> Just (minimumBy (comparing scDistance) cs)

-- | Whether two checked parts come closer than the margin d (with d = 0: overlap).
selfCollides :: CollisionModel -> Double -> U.Vector Double -> Bool
selfCollides cm d q = any ((< d) . scDistance) (selfDistances cm q)
