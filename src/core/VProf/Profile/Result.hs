-- | What the generator answers: the outcome, the profile (the legal one, or the best
-- attempt) with the checker's verdict on it, and how it got there. 'resultLegal' is the
-- one definition of "legal" that every output format reports.
module VProf.Profile.Result
  ( Result (..)
  , Outcome (..)
  , Failure (..)
  , resultLegal
  , failureField
  , renderFailure
  ) where

import VProf.Profile.Legality
import VProf.Profile.Request
import VProf.Profile.Sampled

-- | Why there is no legal profile.
data Failure
  = InvalidRequest [FieldError]
  | InfeasibleRequest String String   -- ^ field, explanation
  | NotConverged String
  deriving (Eq, Show)

failureField :: Failure -> String
failureField = \case
  InvalidRequest (e : _) -> feField e
  InvalidRequest [] -> ""
  InfeasibleRequest f _ -> f
  NotConverged _ -> ""

renderFailure :: Failure -> String
renderFailure = \case
  InvalidRequest es -> unlines (map renderFieldError es)
  InfeasibleRequest f m -> "infeasible (" ++ f ++ "): " ++ m
  NotConverged m -> "not converged: " ++ m

data Outcome
  = Generated                 -- ^ legal, converged
  | Failed Failure
  deriving (Eq, Show)

data Result = Result
  { resOutcome    :: !Outcome
  , resProfile    :: !(Maybe Profile)   -- ^ the legal profile, or the best attempt
  , resViolations :: ![Violation]        -- ^ the checker's verdict on 'resProfile'
  , resIterations :: !Int
  , resConverged  :: !Bool
  , resAlgorithm  :: !Algorithm
  , resTimeStep   :: !Double
  , resVelStep    :: !Double
  , resSeconds    :: !Double             -- ^ wall-clock compute time (0 from 'generatePure')
  } deriving (Eq, Show)

-- | The result carries a profile and the checker found no violation in it. A legal
-- profile need not have converged: 'resOutcome' says whether it did.
resultLegal :: Result -> Bool
resultLegal r = maybe False (const True) (resProfile r) && null (resViolations r)

