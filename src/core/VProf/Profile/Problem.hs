-- | The validated problem the generators and the checker work on: a request in SI
-- doubles with every default filled in ("VProf.Profile.Request" makes it).
--
-- Invariant (kept by 'VProf.Profile.Request.validate' and by every transform in
-- "VProf.Profile.Problem.Transform"): the zones are parallel vectors sorted by strictly
-- increasing start, the first starting at 0, every limit positive; the acceleration and
-- jerk ranges contain 0 strictly inside.
module VProf.Profile.Problem
  ( Problem (..)
  , Algorithm (..)
  , endsInMotion
  , checkerSlack
  ) where

import qualified Data.Vector.Unboxed as U

-- | Which generator runs.
data Algorithm
  = Band    -- ^ seeded windowed raise iteration: the default, fast and near time-optimal
  | Thesis  -- ^ the thesis's windowed iteration, grown from rest to a legal fixed point
  deriving (Eq, Show, Enum, Bounded)

-- | A validated request: SI doubles, defaults filled in. Zones are parallel unboxed
-- vectors sorted by start; the first starts at 0.
data Problem = Problem
  { pbLength     :: !Double
  , pbZoneStarts :: !(U.Vector Double)
  , pbZoneSpeeds :: !(U.Vector Double)
  , pbAMin       :: !Double
  , pbAMax       :: !Double
  , pbJMin       :: !Double
  , pbJMax       :: !Double
  , pbV0         :: !Double
  , pbA0         :: !Double
  , pbVEnd       :: !Double
  , pbAEnd       :: !Double
  , pbDt         :: !Double
  , pbDv         :: !Double
  , pbMaxIter    :: !Int
  , pbBudget     :: !Double
  , pbTol        :: !Double
  , pbAlgorithm  :: !Algorithm
  , pbSeedSearch :: !Bool     -- ^ try the seed's variants and thesis mode ('rqSeedSearch')
  } deriving (Eq, Show)

-- | The route ends in motion: a moving end velocity or a nonzero end acceleration.
endsInMotion :: Problem -> Bool
endsInMotion pb = pbVEnd pb > 0 || pbAEnd pb /= 0

-- | The legality checker's rounding slack: 1e-9 relative to a limit, and at least 1e-9 in
-- the limit's unit ("VProf.Profile.Legality"'s @slack@). Validation's floor on weak limits
-- ("VProf.Profile.Request"'s @speedResolution@) is the same figure at zero speed.
checkerSlack :: Double
checkerSlack = 1e-9
