-- | The velocity-profile generator: validation, the rubber band iterations, convergence,
-- and the verdict of the independent checker.
--
-- The iteration itself is pure ('iterations' is a lazy list of snapshots); 'generate'
-- walks it with the wall clock to honour the time budget, 'generatePure' with the
-- iteration cap only. Either way the result never passes an illegal profile off as
-- success: 'Generated' carries a profile the checker found legal, anything else is a
-- 'Failed' with the reason and, where there is one, the best profile and its violations.
module VProf.Generator
  ( Result (..)
  , Outcome (..)
  , Failure (..)
  , generate
  , generatePure
  , generateProblem
  , iterations
  , Snapshot (..)
  , failureField
  , renderFailure
  , thesisHorizon
  ) where

import qualified Data.Vector.Unboxed as U
import Data.Time.Clock (UTCTime, diffUTCTime, getCurrentTime)
import System.Timeout (timeout)
import Control.Exception (evaluate)

import VProf.Generator.RubberBand
import VProf.Generator.Seed
import VProf.Legality
import VProf.Profile
import VProf.Request

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

-- | The state after each pass.
data Snapshot = Snapshot
  { snVel       :: !(U.Vector Double)
  , snIteration :: !Int
  , snChanged   :: !Int
  , snDone      :: !Bool    -- ^ fixed point: a raising pass changed nothing
  }

-- | The passes of the rubber band for a problem: the starting profile (iteration 0)
-- and one snapshot per pass, ending at the fixed point (or going on for ever).
iterations :: Problem -> Either Failure [Snapshot]
iterations pb = case pbAlgorithm pb of
  Band -> case seed pb of
    Left (Infeasible f m) -> Left (InfeasibleRequest f m)
    Left (LandingFailed m) -> Left (NotConverged ("seed: " ++ m))
    Right v0 -> Right (run Guarded v0)
  Thesis -> Right (run Plain (thesisStart pb))
  where
    run mode v0 = Snapshot v0 0 0 False : go mode 1 (U.replicate (U.length v0) False) [] v0
    go mode !i frozen hist v =
      let PassResult v' changed raising = pass mode pb frozen v
          done = raising && changed == 0
          -- cycle settling (thesis 4.6.2): a profile seen before means the passes flip
          -- between near-finished versions; pin every sample that moved within the cycle
          -- to the lowest value it took there, and freeze it
          (frozen', v'', hist') = case break (== v') hist of
            (cycleRest, _ : _) | not done ->
              let members = v' : cycleRest
                  lowest = foldr1 (U.zipWith min) members
                  moved = U.zipWith (/=) lowest (foldr1 (U.zipWith max) members)
              in (U.zipWith (||) frozen moved, lowest, [])
            _ -> (frozen, v', take 16 (v' : hist))
      in Snapshot v'' i changed done : if done then [] else go mode (i + 1) frozen' hist' v''

-- | The thesis's starting point: an all-zero profile over a horizon sized from the route
-- (not the thesis's fixed 50 s), with the first sample at the start velocity and the
-- last at the end velocity.
thesisStart :: Problem -> U.Vector Double
thesisStart pb =
  let n = thesisHorizon pb
  in U.generate (n + 1) (\k -> if k == 0 then pbV0 pb else if k == n then pbVEnd pb else 0)

-- | Samples of the thesis horizon: the time to drive every zone at its limit, plus the
-- time to speed up and slow down at every zone change, with a margin.
thesisHorizon :: Problem -> Int
thesisHorizon pb =
  let starts = U.toList (pbZoneStarts pb) ++ [pbLength pb]
      speeds = U.toList (pbZoneSpeeds pb)
      cruise = sum (zipWith3 (\a b v -> (b - a) / v) starts (drop 1 starts) speeds)
      ramp v = v / pbAMax pb + v / abs (pbAMin pb) + pbAMax pb / pbJMax pb + abs (pbAMin pb) / abs (pbJMin pb)
      changes = sum (map ramp speeds)
      t = 1.2 * cruise + changes + 2
  in min maxSamples (max 4 (ceiling (t / pbDt pb)))

-- | The verdict on the last snapshot.
finish :: Problem -> Double -> Int -> Bool -> Maybe String -> U.Vector Double -> Result
finish pb secs iters done stopReason v =
  let prof = trimThesis pb (Profile (pbDt pb) v (pbA0 pb) (pbAEnd pb))
      vs = check pb prof
      outcome
        | null vs && done = Generated
        | null vs = Failed (NotConverged (maybe "stopped before the fixed point" id stopReason
                                          ++ "; the best profile so far is legal"))
        | otherwise = Failed (NotConverged (maybe "the fixed point of the iteration breaks limits: "
                                                  (++ "; the best profile breaks limits: ") stopReason
                                           ++ summarise vs))
  in Result outcome (Just prof) vs iters done (pbAlgorithm pb) (pbDt pb) (pbDv pb) secs
  where
    summarise vs = show (length vs) ++ " violation(s), first " ++ renderViolation (head vs)

-- | Thesis profiles run over a horizon: cut the standing still after the route end
-- (the samples after the profile first comes to rest at the end velocity near the end).
trimThesis :: Problem -> Profile -> Profile
trimThesis pb p
  | pbAlgorithm pb /= Thesis = p
  | otherwise =
      let v = prVelocities p
          s = distances p
          n = U.length v - 1
          near k = abs (s U.! k - pbLength pb) <= pbTol pb
          restAt k = v U.! k == pbVEnd pb && near k
          cutAt = case filter restAt [1 .. n] of
            (k : _) | pbVEnd pb > 0 || all (\i -> v U.! i == 0) [k .. n] -> k
            _ -> n
      in p { prVelocities = U.take (cutAt + 1) v }

-- | Generate with the iteration cap only (no clock): a pure function of the problem.
generatePure :: Request -> Result
generatePure rq = case validate rq of
  Left es -> invalid rq es
  Right pb -> case iterations pb of
    Left f -> failed pb f
    Right snaps ->
      let capped = take (pbMaxIter pb + 1) snaps
          lastSnap = last capped
          reason = if snDone lastSnap then Nothing else Just (capReason pb)
      in finish pb 0 (snIteration lastSnap) (snDone lastSnap) reason (snVel lastSnap)

capReason :: Problem -> String
capReason pb = "iteration cap of " ++ show (pbMaxIter pb) ++ " reached"

invalid :: Request -> [FieldError] -> Result
invalid rq es = Result (Failed (InvalidRequest es)) Nothing [] 0 False (rqAlgorithm rq) 0 0 0

failed :: Problem -> Failure -> Result
failed pb f = Result (Failed f) Nothing [] 0 False (pbAlgorithm pb) (pbDt pb) (pbDv pb) 0

-- | Generate with the iteration cap and the wall-clock budget.
generate :: Request -> IO Result
generate rq = case validate rq of
  Left es -> pure (invalid rq es)
  Right pb -> generateProblem pb

-- | The wall-clock budget binds the whole generation: iterations are checked between
-- passes, and the forward pass that seeds them is stopped by a timeout at the budget
-- (plus a quarter, at least 50 ms), answering NOT_CONVERGED rather than running on.
generateProblem :: Problem -> IO Result
generateProblem pb = do
  t0 <- getCurrentTime
  let limitSec = pbBudget pb + max 0.05 (pbBudget pb / 4)
  r <- timeout (ceiling (limitSec * 1e6)) (generateWithin pb t0)
  case r of
    Just res -> pure res
    Nothing -> do
      t1 <- getCurrentTime
      pure (failed pb (NotConverged ("time budget of " ++ show (pbBudget pb)
                                     ++ " s spent before the first pass finished")))
        { resSeconds = realToFrac (diffUTCTime t1 t0) }

generateWithin :: Problem -> UTCTime -> IO Result
generateWithin pb t0 = do
  let elapsed = do t <- getCurrentTime; pure (realToFrac (diffUTCTime t t0) :: Double)
  case iterations pb of
    Left f -> do
      _ <- evaluate f
      secs <- elapsed
      pure (failed pb f) { resSeconds = secs }
    Right snaps -> do
      let walk (sn : rest) = do
            _ <- evaluate (snVel sn)
            secs <- elapsed
            if snDone sn
              then pure (sn, Nothing)
              else if snIteration sn >= pbMaxIter pb
                then pure (sn, Just (capReason pb))
                else if secs > pbBudget pb
                  then pure (sn, Just ("time budget of " ++ show (pbBudget pb) ++ " s spent after "
                                       ++ show (snIteration sn) ++ " iterations"))
                  else case rest of
                    [] -> pure (sn, Nothing)
                    _ -> walk rest
          walk [] = error "iterations: empty"
      (sn, reason) <- walk snaps
      let r0 = finish pb 0 (snIteration sn) (snDone sn) reason (snVel sn)
      _ <- evaluate (length (resViolations r0))
      secs <- elapsed
      pure r0 { resSeconds = secs }
