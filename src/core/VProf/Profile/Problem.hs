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
