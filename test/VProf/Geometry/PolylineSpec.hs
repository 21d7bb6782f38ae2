-- | The path's pose at a time ('polylineAt': a segment by bisection, slerp by its sine
-- weights) against the tests' own ("Support.PathError.pathPoseAt": a walk along the knots, the
-- relative rotation's axis and angle), on random paths: times before, inside and past the
-- span, knots exactly, knot quaternions of either sign, nearly equal or half a turn apart.
module VProf.Geometry.PolylineSpec (spec) where

import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import Support.PathError (pathPoseAt, quatProduct)
import VProf.Compress.Types (Track (..))
import VProf.Geometry.Polyline (polylineAt)
import VProf.Geometry.Vec

genUnit :: Gen Q4
genUnit = do
  (w, x, y, z) <- (,,,) <$> choose (-1, 1) <*> choose (-1, 1) <*> choose (-1, 1) <*> choose (-1, 1)
  let n = sqrt (w * w + x * x + y * y + z * z)
  if n < 1e-3 then genUnit else pure (Q4 (w / n) (x / n) (y / n) (z / n))

-- | The next knot's orientation: anything, a hair away, or nearly half a turn, of either sign.
genNext :: Q4 -> Gen Q4
genNext q = do
  sg <- elements [1, -1]
  Q4 a b c d <- oneof
    [ genUnit
    , (\e -> let Q4 a' b' c' d' = q in Q4 (a' + e) (b' - e) (c' + e) d') <$> choose (-1e-6, 1e-6)
      -- nearly half a turn from q (a rotation of π less up to 0.05 rad, never exactly π: there
      -- the two ways round are equally short and the sign of a rounding picks one)
    , do th <- choose (pi - 0.05, pi - 1e-3)
         axis <- genUnit
         let Q4 _ ax ay az = axis
             n = sqrt (ax * ax + ay * ay + az * az)
             s = sin (th / 2) / max 1e-12 n
         pure (quatProduct q (Q4 (cos (th / 2)) (s * ax) (s * ay) (s * az)))
    ]
  let n = sqrt (a * a + b * b + c * c + d * d)
  pure (Q4 (sg * a / n) (sg * b / n) (sg * c / n) (sg * d / n))

-- | The rotation angle between two quaternions (either sign), normalised first: four times
-- the angle whose tangent is |q − q'| / |q + q'| with q' on q's side (acos of their dot would
-- read rounding of 1e-16 as 3e-8 rad).
angleBetween :: Q4 -> Q4 -> Double
angleBetween q q' =
  let Q4 a b c d = unit q
      Q4 e0 f0 g0 h0 = unit q'
      sg = if a * e0 + b * f0 + c * g0 + d * h0 < 0 then -1 else 1
      (e, f, g, h) = (sg * e0, sg * f0, sg * g0, sg * h0)
      norm4 w x y z = sqrt (w * w + x * x + y * y + z * z)
  in 4 * atan2 (norm4 (a - e) (b - f) (c - g) (d - h)) (norm4 (a + e) (b + f) (c + g) (d + h))
  where unit (Q4 w x y z) = let n = sqrt (w * w + x * x + y * y + z * z) in Q4 (w / n) (x / n) (y / n) (z / n)

spec :: Spec
spec = describe "polylineAt" $
  it "gives the pose of the tests' own interpolation at any time (position to 1e-12 m, orientation to 1e-9 rad)" $
    property $ forAll (choose (1, 12)) $ \k -> do
      t0 <- choose (-100, 100)
      durs <- vectorOf (k - 1) (oneof [choose (1e-3, 0.01), choose (0.01, 5)])
      ps <- vectorOf k (P3 <$> choose (-2, 2) <*> choose (-2, 2) <*> choose (-2, 2))
      q0 <- genUnit
      qs <- take k <$> sequence (scanl (\g _ -> g >>= genNext) (pure q0) [2 .. k])
      let ts = scanl (+) t0 durs
          tEnd = last ts
          track = Track (U.fromList ts) (pfromList ps) (pfromList qs)
      times <- vectorOf 10 (oneof [choose (t0 - 1, tEnd + 1), elements ts, choose (t0, tEnd)])
      pure $ conjoin
        [ let (p, q) = polylineAt (tTime track) (tPos track) (tRot track) t
              (p', q') = pathPoseAt track t
          in counterexample (show (t, p, p', q, q')) (distance p p' <= 1e-12 && angleBetween q q' <= 1e-9)
        | t <- times ]
