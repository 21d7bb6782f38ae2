-- | Jerk-limited velocity profiles over a route's speed limits: the one module a user
-- imports. A 'Request' (in units) is validated into a 'Problem'; 'generate' (under the
-- wall-clock budget) or 'generatePure' (under the iteration cap only) answers a 'Result'
-- whose profile, when it says legal, the independent checker ('check') has passed.
module VProf.Profile
  ( module VProf.Profile.Request
  , module VProf.Profile.Sampled
  , module VProf.Profile.Result
  , module VProf.Profile.Legality
  , generate
  , generatePure
  , generateProblem
  ) where

import VProf.Profile.Generate (generate, generatePure, generateProblem)
import VProf.Profile.Legality
import VProf.Profile.Request
import VProf.Profile.Result
import VProf.Profile.Sampled
