-- | Robot kinematics for vprof: robot models (standard DH, modified DH, URDF joints, couplings),
-- forward kinematics, the geometric Jacobian, and inverse kinematics (the Dobot closed form and a
-- numerical solver for any chain). This facade re-exports the pure core; robot files, URDF and
-- the built-in library are at the edges ('VProf.Kinematics.Format.RobotFile',
-- 'VProf.Kinematics.Format.Urdf', 'VProf.Kinematics.Library').
--
-- Invariant of the whole core: SI units inside (m, rad, kg), joint values in the controller's
-- convention, no exceptions for bad input (validation returns every problem at once).
module VProf.Kinematics
  ( module VProf.Kinematics.Transform
  , module VProf.Kinematics.Model
  , module VProf.Kinematics.Validate
  , module VProf.Kinematics.Forward
  , module VProf.Kinematics.Jacobian
  , module VProf.Kinematics.Ik
  , DobotGeometry (..)
  , dobotModel
  , dobotGeometry
  , levelTarget
  ) where

import VProf.Kinematics.Forward
import VProf.Kinematics.Ik
import VProf.Kinematics.Ik.Dobot (DobotGeometry (..), dobotGeometry, dobotModel, levelTarget)
import VProf.Kinematics.Jacobian
import VProf.Kinematics.Model
import VProf.Kinematics.Transform
import VProf.Kinematics.Validate
