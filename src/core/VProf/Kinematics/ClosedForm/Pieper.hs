{-# LANGUAGE BangPatterns, RecordWildCards #-}
-- | Closed form for a spherical wrist (Pieper): axes 4, 5, 6 meet in the wrist centre,
-- axes 2 and 3 are parallel. The wrist centre fixes θ1 (two shoulders), then θ3 and θ2
-- by the planar two-link (two elbows); the orientation left for the wrist fixes θ4, θ5,
-- θ6 (two wrists). Up to 8 solutions. At sin θ5 = 0 the wrist keeps q4 = 0 and returns
-- one wrist solution, flagged 'WristSingular'. Derivation: @docs/closed-form-ik.md@.
module VProf.Kinematics.ClosedForm.Pieper (pieperRaw) where

import VProf.Kinematics.ClosedForm.Common
import VProf.Kinematics.ClosedForm.Types

-- | Every solution for T' = T05·Rz(θ6)·Dz(d6) (base, tool and the last link's constant
-- part already removed), or the reach excesses met on the way when there is none.
pieperRaw :: Consts -> Pose -> Either Double [Raw]
pieperRaw c@Consts{..} (Pose rp tp) =
  let zt = rotCol 2 rp
      pw@(V3 px py pz) = vsub tp (vscale cD6 zt)
      bb = cSa3 * cD4                      -- forearm offset across the arm plane
      rr = sqrt (cA3 * cA3 + bb * bb)       -- joint 3 → wrist centre, in the arm plane
      psi = atan2 bb cA3
      dz = cD2 + cD3 + cCa3 * cD4
  in case shoulderAngles c dz pw of
       Left e -> Left e
       Right shoulders ->
         let perShoulder (t1, sh, shSing) =
               let !c1 = cos t1; !s1 = sin t1
                   !qx = c1 * px + s1 * py
                   !qy = -s1 * px + c1 * py
                   !wx = qx - cA1
                   !wy = cCa1 * qy + cSa1 * (pz - cD1)
                   !r = sqrt (wx * wx + wy * wy)
               in case elbowAngle cA2 rr r of
                    Left e -> Left e
                    Right (g, coinc) ->
                      let gs = if coinc then [g] else [g, -g]
                          sing0 = [ShoulderSingular | shSing] ++ [ElbowStretched | coinc]
                          r01 = Rot (V3 c1 (-s1 * cCa1) (s1 * cSa1)) (V3 s1 (c1 * cCa1) (-c1 * cSa1)) (V3 0 cSa1 cCa1)
                      in Right (concatMap (perElbow t1 r01 sh sing0 wx wy) gs)
             perElbow t1 r01 sh sing0 wx wy g =
               let !t3 = psi + g
                   !c3 = cos t3; !s3 = sin t3
                   !ux = cA2 + cA3 * c3 + bb * s3
                   !uy = cA3 * s3 - bb * c3
                   -- the angle from u to w in one atan2
                   !t2 = atan2 (ux * wy - uy * wx) (ux * wx + uy * wy)
                   !el = elbowLabel cSa1 cA2 rr g
                   -- α2 = 0: Rz(θ2)·Rz(θ3) = Rz(θ2 + θ3)
                   !r03 = rotMul r01 (dhRot (t2 + t3) cCa3 cSa3)
                   !m = rotMul (rotT r03) rp
               in wristAngles c m (\t4 t5 t6 w sing -> Raw t1 t2 t3 t4 t5 t6 (Branch sh el w) (sing0 ++ sing))
             results = map perShoulder shoulders
             sols = concat [s | Right s <- results]
         in if null sols then Left (closestMiss [e | Left e <- results]) else Right sols

-- | θ4, θ5, θ6 from M = R03ᵀ·R' = Rz(θ4)Rx(α4)Rz(θ5)Rx(α5)Rz(θ6) with α4, α5 = ±90°:
-- M's third column is (σ5 c4 s5, σ5 s4 s5, −σ4 σ5 c5); θ6 then from the rest of M.
wristAngles :: Consts -> Rot -> (Double -> Double -> Double -> Wrist -> [Singularity] -> Raw) -> [Raw]
wristAngles Consts{..} m k =
  let Rot (V3 _ _ m02) (V3 _ _ m12) (V3 _ _ m22) = m
      s4g = signum cSa4; s5g = signum cSa5
      !c5 = -s4g * s5g * m22
      !s5a = sqrt (m02 * m02 + m12 * m12)
      Rot _ _ (V3 m20 m21 _) = m
      -- well conditioned (sin θ5 > 1e-3): M's third row is (σ4 s5 c6, −σ4 s5 s6, ·);
      -- otherwise θ6 from N = (Rz(θ4)Rx(α4)Rz(θ5)Rx(α5))ᵀ·M = Rz(θ6), consistent with θ4
      -- sgn5 is the sign of sin θ5 on the branch
      theta6 sgn5 t4 t5
        | s5a > 1e-3 = let sg = s4g * sgn5 in atan2 (-sg * m21) (sg * m20)
        | otherwise =
            let n = rotMul (rotT (rotMul (dhRot t4 cCa4 cSa4) (dhRot t5 cCa5 cSa5))) m
                Rot (V3 n00 _ _) (V3 n10 _ _) _ = n
            in atan2 n10 n00
  in if s5a < tolSing
       then let t4 = cO4; t5 = atan2 0 c5
            in [k t4 t5 (theta6 1 t4 t5) WristNoFlip [WristSingular]]
       else let !t4 = atan2 (s5g * m12) (s5g * m02)
                !t5 = atan2 s5a c5
                !t4' = t4 + pi; !t5' = -t5
            in [ k t4 t5 (theta6 1 t4 t5) WristNoFlip []
               , k t4' t5' (theta6 (-1) t4' t5') WristFlip [] ]
{-# INLINE wristAngles #-}
