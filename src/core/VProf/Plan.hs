-- | Planning a path for a robot: the one module a user imports. 'planPath' turns waypoints
-- (a compressed recording, or a task's targets), a robot and its limits into a timed joint
-- trajectory whose TCP speed profile the velocity-profile generator made and its legality
-- checker passed, or stops with the reason and the distance along the route where the robot
-- cannot follow (docs/plan.md).
module VProf.Plan
  ( module VProf.Plan.Route
  , module VProf.Plan.Track
  , module VProf.Plan.Limits
  , module VProf.Plan.Trajectory
  ) where

import VProf.Plan.Limits
import VProf.Plan.Route
import VProf.Plan.Track
import VProf.Plan.Trajectory
