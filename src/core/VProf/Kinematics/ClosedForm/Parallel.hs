{-# LANGUAGE BangPatterns, RecordWildCards #-}
-- | Closed form for three parallel axes (2, 3, 4; the Universal Robots arms): the point
-- o5 on axis 6 fixes θ1 (two shoulders); the angle between axis 6 and the common
-- direction of axes 2–4 fixes θ5 (two wrists) and then θ6; what is left is a planar
-- two-link for θ2, θ3 (two elbows) and θ4 = θ234 − θ2 − θ3. Up to 8 solutions. At
-- sin θ5 = 0 the wrist keeps q6 = 0 (or the first of q6 = kπ/8 for which the arm reaches),
-- one wrist solution, flagged 'WristSingular'. Derivation: @docs/closed-form-ik.md@.
module VProf.Kinematics.ClosedForm.Parallel (parallelRaw) where

import VProf.Kinematics.ClosedForm.Common
import VProf.Kinematics.ClosedForm.Types

-- | Every solution for T' = T05·Rz(θ6)·Dz(d6), or the smallest reach excess met.
parallelRaw :: Consts -> Pose -> Either Double [Raw]
parallelRaw c@Consts{..} tgt@(Pose rp tp) =
  let zt = rotCol 2 rp
      p5 = vsub tp (vscale cD6 zt)
      dz = cD2 + cD3 + cD4 + cCa4 * cD5
      s4g = signum cSa4; s5g = signum cSa5
  in case shoulderAngles c dz p5 of
       Left e -> Left e
       Right shoulders ->
         let perShoulder (t1, sh, shSing) =
               let !c1 = cos t1; !s1 = sin t1
                   !z1 = V3 (s1 * cSa1) (-c1 * cSa1) cCa1
                   !c5 = -s4g * s5g * dot zt z1
                   !s5a = norm3 (cross zt z1)
                   V3 vx vy _ = rotApply (rotT rp) z1
                   sing0 = [ShoulderSingular | shSing]
                   !t01inv = inversePose (dhLinkCS c1 s1 cD1 cA1 cCa1 cSa1)
                   -- θ5 = atan2(y5, x5), θ6 = atan2(y6, x6): their links from the normalised pairs
                   withWrist x5 y5 x6 y6 w sing =
                     let !n5 = sqrt (x5 * x5 + y5 * y5); !n6 = sqrt (x6 * x6 + y6 * y6)
                     in arm c t01inv tgt t1 (atan2 y5 x5) (x5 / n5) (y5 / n5) (atan2 y6 x6) (x6 / n6) (y6 / n6)
                            sh w (sing0 ++ sing)
               in if s5a < tolSing
                    then
                      let tries = [ withWrist c5 0 (cos t6) (sin t6) WristNoFlip [WristSingular]
                                  | k <- [0 .. 15 :: Int], let t6 = cO6 + fromIntegral k * pi / 8 ]
                      in case [s | Right s <- tries] of
                           (s : _) -> Right s
                           [] -> head tries
                    else
                      let one sg w = withWrist c5 (sg * s5a) (s4g * sg * vx) (-s4g * sg * vy) w []
                          rs = [one 1 WristNoFlip, one (-1) WristFlip]
                      in case [s | Right s <- rs] of
                           [] -> head rs
                           ss -> Right (concat ss)
             results = map perShoulder shoulders
             sols = concat [s | Right s <- results]
         in if null sols then Left (closestMiss [e | Left e <- results]) else Right sols

-- | The planar part for given θ1, θ5, θ6 (each with its cosine and sine):
-- T14 = T01⁻¹·T'·(T45·Rz(θ6)Dz(d6))⁻¹ = Rz(θ234)Rx(α4) with origin
-- (a2 c2 + a3 c23 + a4 c234, …, d2 + d3 + d4).
arm :: Consts -> Pose -> Pose -> Double -> Double -> Double -> Double -> Double -> Double -> Double
    -> Shoulder -> Wrist -> [Singularity] -> Either Double [Raw]
arm Consts{..} t01inv tgt t1 t5 c5 s5 t6 c6 s6 sh w sing =
  let !t46 = composePose (dhLinkCS c5 s5 cD5 cA5 cCa5 cSa5) (dhLinkCS c6 s6 cD6 0 1 0)
      !t14 = composePose t01inv (composePose tgt (inversePose t46))
      Pose (Rot (V3 r00 _ _) (V3 r10 _ _) _) (V3 px py _) = t14
      !t234 = atan2 r10 r00
      !n234 = sqrt (r00 * r00 + r10 * r10)
      !wx = px - cA4 * r00 / n234
      !wy = py - cA4 * r10 / n234
      !r = sqrt (wx * wx + wy * wy)
  in case elbowAngle cA2 cA3 r of
       Left e -> Left e
       Right (g, coinc) ->
         let one g' =
               let !ux = cA2 + cA3 * cos g'
                   !uy = cA3 * sin g'
                   !t2 = atan2 (ux * wy - uy * wx) (ux * wx + uy * wy)
                   !el = elbowLabel cSa1 cA2 cA3 g'
               in Raw t1 t2 g' (t234 - t2 - g') t5 t6 (Branch sh el w) (sing ++ [ElbowStretched | coinc])
         in Right (if coinc then [one g] else [one g, one (-g)])
