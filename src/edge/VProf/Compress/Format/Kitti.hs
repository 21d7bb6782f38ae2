-- | KITTI odometry poses: one pose a line, the 3×4 matrix [R | t] row by row (12 numbers,
-- metres), without times; KITTI keeps the times in a separate file (@times.txt@: one time
-- in seconds a line, the same count). The rotation becomes a unit quaternion.
module VProf.Compress.Format.Kitti
  ( readKitti
  , looksLikeKitti
  ) where

import qualified Data.ByteString.Char8 as B

import VProf.Compress.Clean (Sample (..))
import VProf.Compress.Format.Common (dataLines, numberFields)
import VProf.Geometry.Vec (P3 (..), Q4 (..))
import VProf.Kinematics.Transform (Quat (..), fromRows, isRigid, toQuat)

-- | Whether the first data line holds 12 numbers (a TUM line holds 8).
looksLikeKitti :: B.ByteString -> Bool
looksLikeKitti src = case dataLines (const False) src of
  (_, l) : _ -> length (B.words l) == 12
  [] -> False

-- | The samples of a KITTI pose file (first argument) with the times of the second, each
-- with its line number in the pose file. Errors name the file ("poses" or "times"), the
-- line and the value; a rotation that is not one (columns not orthonormal to 1e-3, or a
-- reflection) is an error naming its line.
readKitti :: B.ByteString -> B.ByteString -> Either String [Sample]
readKitti poses times = do
  ps <- traverse pose (dataLines (const False) poses)
  ts <- traverse time (dataLines (const False) times)
  if length ps /= length ts
    then Left ("KITTI: " ++ show (length ps) ++ " poses but " ++ show (length ts)
               ++ " times (the times file needs one time a pose)")
    else Right [ Sample i t p q | ((i, p, q), t) <- zip ps ts ]
  where
    pose (i, l) = case B.words l of
      ws@[_, _, _, _, _, _, _, _, _, _, _, _] -> do
        vs <- numberFields "KITTI poses" i ws
        case fromRows vs of
          Just tf | isRigid 1e-3 tf ->
            let Quat w x y z = toQuat tf
            in Right (i, P3 (vs !! 3) (vs !! 7) (vs !! 11), Q4 w x y z)
          _ -> Left ("KITTI poses line " ++ show i ++ ": the first three columns of [R | t] are not a rotation "
                     ++ "(orthonormal to 1e-3, determinant +1): " ++ show (B.unpack (B.take 120 l)))
      ws -> Left ("KITTI poses line " ++ show i ++ ": expected 12 numbers (the 3x4 matrix [R | t] row by row), got "
                  ++ show (length ws))
    time (i, l) = case B.words l of
      [w] -> do
        vs <- numberFields "KITTI times" i [w]
        case vs of
          [t] -> Right t
          _ -> Left "impossible"
      ws -> Left ("KITTI times line " ++ show i ++ ": expected one number (s), got " ++ show (length ws))
