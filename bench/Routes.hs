{-# LANGUAGE OverloadedStrings #-}
-- | Synthetic routes for the scaling series: deterministic pseudo-random zones (a linear
-- congruential generator, so every run measures the same routes).
module Routes (syntheticRoute, loadCases, shortRoutes) where

import qualified Data.Aeson as A
import qualified Data.Aeson.KeyMap as KM
import qualified Data.ByteString.Lazy as BL
import qualified Data.Text as T
import qualified Data.Vector as V
import System.Directory (doesFileExist)

import VProf.Profile.Format.Json (requestFromValue)
import VProf.Profile.Request
import VProf.Units

-- | A route of the given length with the given number of zones: speeds 1–10 m/s,
-- ±1.5 m/s², ±2 m/s³, from rest to rest.
syntheticRoute :: Double -> Int -> Request
syntheticRoute len nz = defaultRequest
  { rqRouteLength = len *~ meter
  , rqZones = [ SpeedZone ((len * fromIntegral i / fromIntegral nz) *~ meter) (speed i *~ mps) | i <- [0 .. nz - 1] ]
  , rqMinAcceleration = (-1.5) *~ mps2, rqMaxAcceleration = 1.5 *~ mps2
  , rqMinJerk = (-2) *~ mps3, rqMaxJerk = 2 *~ mps3
  , rqTimeBudget = Just (60 *~ second)
  }
  where
    lcg :: Int -> Int
    lcg x = (1103515245 * x + 12345) `mod` 2147483648
    speed i = 1 + 9 * fromIntegral (iterate lcg (i + 7) !! 3 `mod` 1000) / 1000

-- | Two short routes that end in motion with no plateau to join on (requests 3118 and
-- 8820 of the moving-end regression tests): the exact join finds a legal profile for
-- the first and proves the second infeasible, each with linear programs.
shortRoutes :: [(String, Request)]
shortRoutes =
  [ ("3118-legal", short 12.227 6.522 (-2.444, 1.07) (-2.724, 2.746) (6.178, 0) (2.536, -0.617))
  , ("8820-infeasible", short 7.867 5.795 (-2.967, 2.926) (-2.896, 2.017) (4.835, 0) (2.8975, 2.477)) ]
  where
    short len lim (aMin, aMax) (jMin, jMax) (v0, a0) (vE, aE) = defaultRequest
      { rqRouteLength = len *~ meter, rqZones = [SpeedZone (0 *~ meter) (lim *~ mps)]
      , rqMinAcceleration = aMin *~ mps2, rqMaxAcceleration = aMax *~ mps2
      , rqMinJerk = jMin *~ mps3, rqMaxJerk = jMax *~ mps3
      , rqStartVelocity = v0 *~ mps, rqStartAcceleration = a0 *~ mps2
      , rqEndVelocity = vE *~ mps, rqEndAcceleration = aE *~ mps2 }

-- | The reference cases, by name.
loadCases :: IO [(String, Request)]
loadCases = do
  let candidates = ["../shared/reference/velocity-cases.json"]
  found <- filter snd <$> mapM (\p -> (,) p <$> doesFileExist p) candidates
  case found of
    [] -> fail "bench: velocity-cases.json not found in ../shared/reference"
    ((path, _) : _) -> do
      Just (A.Object o) <- A.decode <$> BL.readFile path
      let Just (A.Array cs) = KM.lookup "cases" o
      pure [ (name, rq) | c@(A.Object co) <- V.toList cs
                        , Just (A.String n) <- [KM.lookup "name" co]
                        , let name = T.unpack n
                        , Right rq <- [requestFromValue c] ]
