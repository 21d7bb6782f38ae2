{-# LANGUAGE OverloadedStrings #-}
-- | Synthetic routes for the scaling series: deterministic pseudo-random zones (a linear
-- congruential generator, so every run measures the same routes).
module Routes (syntheticRoute, loadCases) where

import qualified Data.Aeson as A
import qualified Data.Aeson.KeyMap as KM
import qualified Data.ByteString.Lazy as BL
import qualified Data.Text as T
import qualified Data.Vector as V
import System.Directory (doesFileExist)

import VProf.Json (requestFromValue)
import VProf.Request
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

-- | The reference cases, by name.
loadCases :: IO [(String, Request)]
loadCases = do
  let candidates = ["../shared/reference/velocity-cases.json", "/work/shared/reference/velocity-cases.json"]
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
