-- | Exact segment–triangle and segment–segment distances and the BVH queries against the
-- independent brute-force oracle ("Support.DistanceOracle"): random meshes and capsules over
-- scales from 1e-4 to 1e4, slivers and tiny triangles, and capsules built to touch, cross and run
-- parallel to a triangle. Agreement is to 1e-9 of the scene's scale.
module VProf.Geometry.DistanceSpec (spec) where

import qualified Data.Vector.Unboxed as U
import Data.List (sort)
import Test.Hspec
import Test.QuickCheck

import Support.DistanceOracle
import VProf.Geometry.Bvh
import VProf.Geometry.Distance
import VProf.Geometry.Mesh
import VProf.Kinematics.Transform (V3 (..))

pt :: V3 -> Pt
pt (V3 x y z) = (x, y, z)

add3, sub3 :: V3 -> V3 -> V3
add3 (V3 a b c) (V3 x y z) = V3 (a + x) (b + y) (c + z)
sub3 (V3 a b c) (V3 x y z) = V3 (a - x) (b - y) (c - z)

sc :: Double -> V3 -> V3
sc k (V3 x y z) = V3 (k * x) (k * y) (k * z)

crs :: V3 -> V3 -> V3
crs (V3 a b c) (V3 x y z) = V3 (b * z - c * y) (c * x - a * z) (a * y - b * x)

nrm :: V3 -> Double
nrm (V3 x y z) = sqrt (x * x + y * y + z * z)

genScale :: Gen Double
genScale = (10 **) <$> choose (-4, 4)

genPoint :: Double -> Gen V3
genPoint s = V3 <$> c <*> c <*> c where c = choose (-s, s)

genTriangle :: Double -> Gen (V3, V3, V3)
genTriangle s = frequency
  [ (6, (,,) <$> genPoint s <*> genPoint s <*> genPoint s)
  , (2, do a <- genPoint s; b <- genPoint s; u <- choose (-0.5, 1.5)
           e <- (10 **) <$> choose (-9, -3); o <- genPoint (e * s)
           pure (a, b, add3 (add3 a (sc u (sub3 b a))) o))          -- a sliver
  , (1, do a <- genPoint s; b <- genPoint (1e-6 * s); c <- genPoint (1e-6 * s)
           pure (a, add3 a b, add3 a c))                            -- a tiny triangle
  , (1, do a <- genPoint s; b <- genPoint s; pure (a, b, b))        -- two corners equal
  ]

genMesh :: Double -> Gen Mesh
genMesh s = do
  n <- frequency [(3, choose (1, 20)), (2, choose (20, 150))]
  fromTriangles <$> vectorOf n (genTriangle s)

-- | A random capsule, or one built on a triangle of the mesh to touch, cross or run parallel.
genCapsule :: Double -> Mesh -> Gen Capsule
genCapsule s m = do
  r <- (* s) <$> choose (0, 0.1)
  k <- choose (0, triangleCount m - 1)
  let (a, b, c) = triangle m k
      n = crs (sub3 b a) (sub3 c a)
      nh = if nrm n > 0 then sc (1 / nrm n) n else V3 0 0 1
  u <- choose (0, 1); w <- choose (0, 1)
  let (u', w') = if u + w > 1 then (1 - u, 1 - w) else (u, w)
      x = add3 a (add3 (sc u' (sub3 b a)) (sc w' (sub3 c a)))   -- a point of the triangle
  dir <- genPoint s
  h <- (* s) <$> choose (0, 0.5)
  frequency
    [ (4, (\p q -> Capsule p q r) <$> genPoint (2 * s) <*> genPoint (2 * s))
    , (1, (\p -> Capsule p p r) <$> genPoint (2 * s))
    , (1, pure (Capsule (add3 x (sc r nh)) (add3 x (add3 (sc r nh) (add3 (sc (nrm dir) nh) dir))) r))  -- touching
    , (1, pure (Capsule (sub3 x (sc h nh)) (add3 x (add3 (sc h nh) (sc 0.3 (crs nh dir)))) r))          -- crossing
    , (1, let t = crs nh dir in pure (Capsule (sub3 (add3 x (sc h nh)) t) (add3 (add3 x (sc h nh)) t) r))  -- parallel
    , (1, let e = sub3 b a in pure (Capsule (add3 (add3 a (sc h nh)) (sc (-0.3) e)) (add3 (add3 a (sc h nh)) (sc 1.7 e)) r))  -- parallel to an edge
    ]

meshTris :: Mesh -> [(Pt, Pt, Pt)]
meshTris m = [(pt a, pt b, pt c) | (a, b, c) <- triangles m]

spec :: Spec
spec = do
  describe "segmentTriangle and segmentSegment" $ do
    it "agree with the oracle on random segments and triangles (1e-9 of the scale)" $
      property $ forAll genScale $ \s -> forAll (genTriangle s) $ \(a, b, c) ->
        forAll (genMesh s >>= \_ -> genCapsule s (fromTriangles [(a, b, c)])) $ \(Capsule p q _) ->
          let d = sqrt (clSquared (segmentTriangle p q a b c))
              o = oSegmentTriangle (pt p) (pt q) (pt a) (pt b) (pt c)
          in counterexample (show (d, o)) (abs (d - o) <= 1e-9 * s)
    it "segment–segment agrees with the oracle, parallel and degenerate segments included" $
      property $ forAll genScale $ \s -> forAll (genPoint s) $ \p -> forAll (genPoint s) $ \q ->
        forAll (elements [0 :: Int, 1, 2, 3]) $ \kind -> forAll (genPoint s) $ \o -> forAll (choose (-1, 2)) $ \t ->
          let (a, b) = case kind of
                0 -> (o, add3 o (sub3 q p))                           -- parallel, offset
                1 -> (add3 p (sc t (sub3 q p)), add3 p (sc (t + 0.7) (sub3 q p)))  -- collinear
                2 -> (o, o)                                            -- a point
                _ -> (o, add3 o q)
              d = sqrt (clSquared (segmentSegment p q a b))
              od = oSegmentSegment (pt p) (pt q) (pt a) (pt b)
          in counterexample (show (d, od)) (abs (d - od) <= 1e-9 * s)
    it "a crossing segment is at distance 0, a touching capsule at clearance 0, a parallel one at its height" $ do
      let a = V3 0 0 0; b = V3 1 0 0; c = V3 0 1 0
      clSquared (segmentTriangle (V3 0.2 0.2 (-1)) (V3 0.2 0.2 1) a b c) `shouldBe` 0
      sqrt (clSquared (segmentTriangle (V3 0.2 0.2 0.5) (V3 0.3 0.3 2) a b c)) `shouldBe` 0.5
      sqrt (clSquared (segmentTriangle (V3 (-5) 0.2 0.25) (V3 5 0.2 0.25) a b c)) `shouldBe` 0.25
      sqrt (clSquared (segmentTriangle (V3 (-5) (-1) 0) (V3 5 (-1) 0) a b c)) `shouldBe` 1
      let bvh = buildBvh (fromTriangles [(a, b, c)])
          touch = Capsule (V3 0.2 0.2 0.1) (V3 0.2 0.2 1) 0.1
      fmap hitDistance (minimumDistance bvh touch) `shouldBe` Just 0
      clearanceAtLeast bvh touch 0 `shouldBe` True
      clearanceAtLeast bvh touch 1e-12 `shouldBe` False
      fmap hitDistance (minimumDistance bvh (Capsule (V3 0.2 0.2 (-1)) (V3 0.2 0.2 1) 0.1)) `shouldBe` Just (-0.1)

  describe "the BVH" $ do
    it "minimumDistance agrees with the oracle over all triangles: distance, triangle and closest points (1e-8); the oracle's pruned searches agree with its full scan" $
      withMaxSuccess 300 $ property $ forAll genScale $ \s -> forAll (genMesh s) $ \m ->
        forAll (genCapsule s m) $ \cap@(Capsule p q r) ->
          let bvh = buildBvh m
              Just h = minimumDistance bvh cap
              tris = meshTris m
              (od, _) = oSegmentMesh (pt p) (pt q) tris
              (ta, tb, tc) = tris !! hitTriangle h
              tol = 1e-9 * s
          in counterexample (show (h, od)) $ conjoin
               [ abs (hitAxisDistance h - od) <= tol
               , abs (hitDistance h - (hitAxisDistance h - r)) <= 1e-15 * s
               , abs (oSegmentTriangle (pt p) (pt q) ta tb tc - od) <= tol
               -- the oracle's pruned searches find the full scan's distance
               , abs (fst (oSegmentMeshBounded (pt p) (pt q) tris) - od) <= tol
               , abs (fst (oSegmentMeshNear (pt p) (pt q) (oMesh tris)) - od) <= tol
               , abs (nrm (sub3 (hitOnAxis h) (hitOnMesh h)) - hitAxisDistance h) <= tol
               -- the foot point on a sliver is ill-conditioned across its width: 1e-8 of the scale
               , oPointTriangle (pt (hitOnMesh h)) ta tb tc <= 10 * tol
               , oPointSegment (pt (hitOnAxis h)) (pt p) (pt q) <= 10 * tol
               ]
    it "clearanceAtLeast d holds exactly when the minimum distance is at least d" $
      withMaxSuccess 300 $ property $ forAll genScale $ \s -> forAll (genMesh s) $ \m ->
        forAll (genCapsule s m) $ \cap -> forAll (choose (-0.2, 0.2)) $ \k ->
          let bvh = buildBvh m
              Just h = minimumDistance bvh cap
              d = hitDistance h + k * s
          in abs (k * s) > 1e-9 * s ==> clearanceAtLeast bvh cap d === (hitDistance h >= d)
    it "every node's box contains its triangles, and the leaves cover every triangle once" $
      property $ forAll genScale $ \s -> forAll (genMesh s) $ \m ->
        let bvh = buildBvh m
            under i = case bvhChildren bvh i of
              Left (st, n) -> [bvhOrder bvh j | j <- [st .. st + n - 1]]
              Right (l, r) -> under l ++ under r
            inside (V3 lx ly lz, V3 hx hy hz) (V3 x y z) = lx <= x && x <= hx && ly <= y && y <= hy && lz <= z && z <= hz
            ok i = and [inside (bvhBox bvh i) v | k <- under i, let (a, b, c) = triangle m k, v <- [a, b, c]]
        in U.fromList (sortI (under 0)) === U.enumFromN 0 (triangleCount m) .&&. all ok [0 .. bvhNodeCount bvh - 1]
    it "an empty mesh has no nearest triangle and any clearance" $ do
      let bvh = buildBvh (Mesh U.empty)
      minimumDistance bvh (Capsule (V3 0 0 0) (V3 1 0 0) 0.1) `shouldBe` Nothing
      clearanceAtLeast bvh (Capsule (V3 0 0 0) (V3 1 0 0) 0.1) 1e9 `shouldBe` True
  where
    sortI :: [Int] -> [Int]
    sortI = sort
