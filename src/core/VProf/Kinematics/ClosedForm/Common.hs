{-# LANGUAGE BangPatterns, RecordWildCards #-}
-- | What both closed forms share: the table unpacked into strict constants ('Consts'), the
-- raw solution record, the first joint from the wrist point ('shoulderAngles') and the
-- planar two-link elbow ('elbowAngle'), both written with atan2 of accurately formed
-- quantities (no acos/asin near their poles) and never NaN: out of reach is a 'Left' with
-- the distance, positive beyond the reach and negative closer in than the arm can fold; a
-- coincident pair of solutions is returned once.
module VProf.Kinematics.ClosedForm.Common
  ( Consts (..), mkConsts
  , Raw (..)
  , shoulderAngles, elbowAngle, elbowLabel
  , dhRot, dhLinkCS, wrap
  , tolReach, tolSing
  , closestMiss
  ) where

import qualified Data.Vector.Unboxed as U
import VProf.Kinematics.ClosedForm.Types

-- | Of several misses (signed as 'elbowAngle''s), the one nearest to a solution.
closestMiss :: [Double] -> Double
closestMiss = foldr1 (\a b -> if abs a <= abs b then a else b)

-- | The DH table as strict constants (lengths m, angles as cos/sin), base/tool inverses.
data Consts = Consts
  { cA1, cA2, cA3, cA4, cA5, cA6 :: !Double
  , cD1, cD2, cD3, cD4, cD5, cD6 :: !Double
  , cCa1, cSa1, cCa2, cSa2, cCa3, cSa3, cCa4, cSa4, cCa5, cSa5 :: !Double
  , cO1, cO2, cO3, cO4, cO5, cO6 :: !Double
  , cBaseInv, cToolInv, cLastInv :: !Pose
    -- ^ base⁻¹, tool⁻¹ and (Dx(a6)·Rx(α6))⁻¹
  }

mkConsts :: SixAxisDh -> Consts
mkConsts SixAxisDh{..} =
  let a i = sdA U.! i; d i = sdD U.! i; al i = sdAlpha U.! i; o i = sdOffset U.! i
      ca i = cos (al i); sa i = sin (al i)
      lastInv = inversePose (Pose (rotX (al 5)) (V3 (a 5) 0 0))
  in Consts (a 0) (a 1) (a 2) (a 3) (a 4) (a 5) (d 0) (d 1) (d 2) (d 3) (d 4) (d 5)
            (ca 0) (sa 0) (ca 1) (sa 1) (ca 2) (sa 2) (ca 3) (sa 3) (ca 4) (sa 4)
            (o 0) (o 1) (o 2) (o 3) (o 4) (o 5)
            (inversePose sdBase) (inversePose sdTool) lastInv

-- | A solution in DH angles θ1..θ6 (not yet q, not yet wrapped), with its label.
data Raw = Raw {-# UNPACK #-} !Double {-# UNPACK #-} !Double {-# UNPACK #-} !Double
               {-# UNPACK #-} !Double {-# UNPACK #-} !Double {-# UNPACK #-} !Double !Branch ![Singularity]

-- | Reach tolerance (m): a target this far outside the reach is clamped onto it.
tolReach :: Double
tolReach = 1e-9

-- | Elbow angles this close to 0 or π count as stretched or folded.
tolElbow :: Double
tolElbow = 1e-7

-- | Below this a sine (or a distance in m, for the wrist point to axis 1) counts as zero.
tolSing :: Double
tolSing = 1e-12

-- | Rotation part of a DH link: Rz(θ)·Rx(α).
dhRot :: Double -> Double -> Double -> Rot
dhRot th ca sa =
  let c = cos th; s = sin th
  in Rot (V3 c (-s * ca) (s * sa)) (V3 s (c * ca) (-c * sa)) (V3 0 sa ca)
{-# INLINE dhRot #-}

-- | A DH link from cos θ and sin θ (no trigonometry): Rz(θ)·Dz(d)·Dx(a)·Rx(α).
dhLinkCS :: Double -> Double -> Double -> Double -> Double -> Double -> Pose
dhLinkCS c s d a ca sa =
  Pose (Rot (V3 c (-s * ca) (s * sa)) (V3 s (c * ca) (-c * sa)) (V3 0 sa ca)) (V3 (a * c) (a * s) d)
{-# INLINE dhLinkCS #-}

-- | Into (−π, π].
wrap :: Double -> Double
wrap x
  | x > pi = if x < 7 * pi then wrap (x - 2 * pi) else far
  | x <= -pi = if x > -7 * pi then wrap (x + 2 * pi) else far
  | otherwise = x
  where far = let y = x - 2 * pi * fromIntegral (round (x / (2 * pi)) :: Int)
              in if y <= -pi then y + 2 * pi else if y > pi then y - 2 * pi else y
{-# INLINE wrap #-}

-- | θ1 from the wrist point p (frame 0) and the constant height dz of the wrist point
-- along axis 2 (in frame 1): the wrist point must satisfy
-- −sin α1·(−s1 px + c1 py) + cos α1·(pz − d1) = dz, i.e. (−s1 px + c1 py) = K.
-- Returns the right-shoulder (x₁·p ≥ 0) solution first. On axis 1 with K = 0
-- (shoulder singularity) θ1 is free: q1 = 0 and its opposite are returned, flagged.
-- On the cylinder of radius |K| the two shoulders coincide: one solution, flagged.
shoulderAngles :: Consts -> Double -> V3 -> Either Double [(Double, Shoulder, Bool)]
shoulderAngles Consts{..} dz (V3 px py pz) =
  let k = (cCa1 * (pz - cD1) - dz) / cSa1
      r2 = px * px + py * py
      r = sqrt r2
  in if r < tolSing && abs k < tolSing
       then Right [(cO1, ShoulderRight, True), (cO1 + pi, ShoulderLeft, True)]
       else
         let h2 = (r - abs k) * (r + abs k)
             phi = atan2 py px
         in if h2 < 0
              then if abs k - r <= tolReach
                     then Right [(phi - atan2 k 0, ShoulderRight, True)]
                     else Left (negate (abs k - r))   -- inside the cylinder: too close
              else let h = sqrt h2
                   in if h < tolElbow * r
                        -- on the cylinder |K| (within 1e-7 rad): one shoulder, flagged
                        then Right [(phi - atan2 k 0, ShoulderRight, True)]
                        else Right [(phi - atan2 k h, ShoulderRight, False), (phi - atan2 k (-h), ShoulderLeft, False)]
{-# INLINE shoulderAngles #-}

-- | The planar elbow: γ ∈ [0, π] with r² = a² + b² + 2ab·cos γ (a, b signed link
-- vectors' lengths along their x axes), from the half-angle form
-- tan²(γ'/2) = ((|a|+|b|)² − r²)/(r² − (|a|−|b|)²), which keeps its accuracy near the
-- stretched and folded poses. 'Left' the distance by which r is outside the annulus,
-- positive beyond it, negative inside its hole;
-- the flag says γ is 0 or π (the two elbow solutions coincide).
elbowAngle :: Double -> Double -> Double -> Either Double (Double, Bool)
elbowAngle a b r =
  let am = abs a; bm = abs b
      outer = am + bm; inner = abs (am - bm)
      num0 = (outer - r) * (outer + r)
      den0 = (r - inner) * (r + inner)
  in if num0 < 0 && r - outer > tolReach then Left (r - outer)
     else if den0 < 0 && inner - r > tolReach then Left (negate (inner - r))   -- too close
     else
       let num = max 0 num0; den = max 0 den0
           g0 | num == 0 && den == 0 = if r < 0.5 * outer then pi else 0
              | otherwise = 2 * atan2 (sqrt num) (sqrt den)
           -- within 1e-7 rad of stretched or folded the pair is one solution (a length
           -- error of 1e-16 m already moves γ by 1e-8 there; snapping costs < 1e-14 m)
           coincide = g0 < tolElbow || pi - g0 < tolElbow
           g' | not coincide = g0
              | g0 < tolElbow = 0
              | otherwise = pi
           g = if a * b >= 0 then g' else pi - g'
       in Right (g, coincide)
{-# INLINE elbowAngle #-}

-- | Elbow label of γ (the elbow angle measured as in 'elbowAngle'; sign s α1 of link 1):
-- up when sin α1 · a · b · sin γ < 0 (or γ is 0 or π).
elbowLabel :: Double -> Double -> Double -> Double -> Elbow
elbowLabel sa1 a b g = if sa1 * a * b * sin g > 0 then ElbowDown else ElbowUp
{-# INLINE elbowLabel #-}
