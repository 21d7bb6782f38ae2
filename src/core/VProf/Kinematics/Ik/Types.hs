-- | The vocabulary of inverse kinematics shared by every solver: options, a solution, and the
-- reasons a target has no solution.
--
-- Invariant: a solver returns solutions only within the joint limits (to 'ikLimitTolerance') whose
-- forward kinematics matches the target to the tolerances, sorted by distance to the seed; a
-- failure always says why, with the amount in SI units (m, rad).
module VProf.Kinematics.Ik.Types
  ( IkOptions (..)
  , defaultIkOptions
  , IkSolution (..)
  , IkFailure (..)
  , describeFailure
  , limitMisses
  , residual
  , sortBySeed
  , seedDistance
  ) where

import Control.DeepSeq (NFData (..))
import qualified Data.Vector.Unboxed as U
import Data.List (intercalate, sortOn)
import Data.Word (Word64)
import Numeric (showFFloat)

import VProf.Kinematics.Transform

data IkOptions = IkOptions
  { ikTolPosition :: Double     -- ^ m (default 1e-6)
  , ikTolRotation :: Double     -- ^ rad (default 1e-6)
  , ikMaxIterations :: Int      -- ^ numerical: iterations per start (default 60)
  , ikMaxRestarts :: Int        -- ^ numerical: random restarts after the seed (default 200)
  , ikAllSolutions :: Bool      -- ^ numerical: keep restarting for more distinct solutions
  , ikRandomSeed :: Word64      -- ^ numerical: seed of the pure generator for the restarts
  , ikLimitTolerance :: Double  -- ^ how far past a limit still counts as within (default 1e-9)
  , ikDampingGain :: Double     -- ^ numerical: λ = gain · E in the Levenberg–Marquardt step (default 0.1)
  }
  deriving (Eq, Show)

defaultIkOptions :: IkOptions
defaultIkOptions = IkOptions 1e-6 1e-6 60 200 False 0x9E3779B97F4A7C15 1e-9 0.1

data IkSolution = IkSolution
  { solJoints :: U.Vector Double  -- ^ controller joint values (rad, m)
  , solPositionError :: Double    -- ^ m, by forward kinematics
  , solRotationError :: Double    -- ^ rad, by forward kinematics
  , solSeedDistance :: Double     -- ^ Euclidean distance to the seed (or to mid-limits)
  , solBranch :: Maybe String     -- ^ the closed form's branch label (shoulder, elbow, wrist: "RUN" …), if any
  }
  deriving (Eq, Show)

instance NFData IkSolution where
  rnf (IkSolution q a b c l) = q `seq` a `seq` b `seq` c `seq` rnf l

data IkFailure
  = BeyondReach {failDistance :: Double, failReach :: Double}
    -- ^ the target is failDistance from the reference point, the arm reaches failReach (m)
  | InsideReach {failDistance :: Double, failReach :: Double}
    -- ^ closer than the arm can fold (m): failReach is the minimum distance
  | OutsideLimits [[(String, Double)]]
    -- ^ every solution found breaks a limit: per solution, the joints and by how much (rad or m;
    -- negative below the minimum, positive above the maximum)
  | OrientationUnreachable {failTilt :: Double}
    -- ^ the arm keeps its tool level: the target is tilted by this angle (rad)
  | Singular String
  | NotConverged {failPositionResidual :: Double, failRotationResidual :: Double}
    -- ^ the best residual found within the budget (m, rad)
  | Unreachable String Double
    -- ^ what cannot be reached (a closed form's test, or the numerical solver's wrist bound), and
    -- by how much (m): positive too far, negative too close
  | InvalidRequest [String]
  deriving (Eq, Show)

instance NFData IkFailure where
  rnf f = length (show f) `seq` ()

-- | The sentence of 'OutsideLimits' from each solution's misses (a note on units after
-- "limit"): one solution's misses as a list, several solutions' numbered, "(1) J2 above its
-- maximum by …, J3 …; (2) …".
limitMisses :: String -> [[String]] -> String
limitMisses note = \case
  [one] -> "every solution breaks a joint limit" ++ note ++ ": " ++ intercalate ", " one
  sols -> "every one of the " ++ show (length sols) ++ " solutions breaks a joint limit" ++ note ++ ": "
            ++ intercalate "; " ["(" ++ show i ++ ") " ++ intercalate ", " s | (i, s) <- zip [1 :: Int ..] sols]

-- | One sentence for a user.
describeFailure :: IkFailure -> String
describeFailure = \f -> case f of
  BeyondReach d r -> "beyond reach: the target is " ++ mm d ++ " away, the arm reaches " ++ mm r ++ " (" ++ mm (d - r) ++ " too far)"
  InsideReach d r -> "too close: the target is " ++ mm d ++ " away, the arm cannot fold closer than " ++ mm r ++ " (" ++ mm (r - d) ++ " too close)"
  OutsideLimits sols -> limitMisses " (rad, m for a prismatic joint; negative below the minimum)" [[j ++ " by " ++ showFFloat (Just 6) v "" | (j, v) <- s] | s <- sols]
  OrientationUnreachable t -> "the tool stays level: the target is tilted by " ++ showFFloat (Just 4) (t * 180 / pi) " deg"
  Singular why -> "singular: " ++ why
  NotConverged p r
    | isInfinite p || isNaN p || isInfinite r || isNaN r -> "not converged: no pose was reached (no attempt of the search finished)"
    | otherwise -> "not converged: best residual " ++ mm p ++ ", " ++ showFFloat (Just 4) (r * 180 / pi) "°"
                   ++ (if p >= 1e-3 || r >= pi / 180
                         then " (the nearest pose the search reached; the target may be out of reach at this orientation)"
                         else " (the nearest pose the search reached, just outside the tolerance)")
  Unreachable what d
    | d >= 0 -> "beyond reach: " ++ what ++ " (" ++ mm d ++ " too far)"
    | otherwise -> "too close: " ++ what ++ " (" ++ mm (negate d) ++ " too close)"
  InvalidRequest es -> "invalid request: " ++ intercalate "; " es
  where
    mm x = showFFloat Nothing (fromIntegral (round (x * 1e6) :: Integer) / 1000 :: Double) " mm"

-- | Position (m) and rotation (rad) error between a reached and a target transform.
residual :: Tf -> Tf -> (Double, Double)
residual reached target =
  ( v3Norm (v3Sub (translation reached) (translation target))
  , rotationAngle (compose (inverse target) reached) )

seedDistance :: U.Vector Double -> U.Vector Double -> Double
seedDistance a b = sqrt (U.sum (U.zipWith (\x y -> (x - y) * (x - y)) a b))

sortBySeed :: [IkSolution] -> [IkSolution]
sortBySeed = sortOn solSeedDistance
