{-# LANGUAGE OverloadedStrings #-}
-- | Loading the shared reference cases (../shared/reference/kinematics) and the shared URDF files.
module Support.Reference
  ( sharedDir
  , DhFile (..)
  , DhRow (..)
  , UrdfCase (..)
  , DobotFile (..)
  , loadDh
  , loadUrdfCase
  , loadDobot
  , dhRobot
  ) where

import Data.Aeson (FromJSON (..), withObject, (.:), (.:?), eitherDecodeFileStrict)
import Data.Maybe (fromMaybe)
import System.Directory (doesDirectoryExist)
import System.Environment (lookupEnv)

import VProf.Kinematics.Model
import VProf.Kinematics.Transform

-- | $VPROF_SHARED, else ../shared (relative to the project root, where the tests run).
sharedDir :: IO FilePath
sharedDir = do
  d <- maybe "../shared" id <$> lookupEnv "VPROF_SHARED"
  ok <- doesDirectoryExist (d ++ "/reference/kinematics")
  if ok then pure d else fail ("the shared data is not at " ++ d ++ " (set VPROF_SHARED)")

data DhRow = DhRow {rowType :: String, rowTheta, rowD, rowA, rowAlpha, rowOffset :: Double}

instance FromJSON DhRow where
  parseJSON = withObject "dh row" $ \o ->
    DhRow <$> o .: "type" <*> o .: "theta" <*> o .: "d" <*> o .: "a" <*> o .: "alpha" <*> o .: "offset"

data DhFile = DhFile
  { dhName :: String
  , dhConvention :: String
  , dhRows :: [DhRow]
  , dhQlim :: [[Double]]
  , dhBase, dhTool :: [Double]
  , dhCases :: [([Double], [Double])]
  }

instance FromJSON DhFile where
  parseJSON = withObject "dh file" $ \o -> do
    cs <- o .: "cases"
    cases <- mapM (withObject "case" (\c -> (,) <$> c .: "q" <*> c .: "T")) cs
    DhFile <$> o .: "robot" <*> o .: "convention" <*> o .: "dh" <*> o .: "qlim" <*> o .: "base" <*> o .: "tool" <*> pure cases

data UrdfCase = UrdfCase
  { ucName :: String
  , ucUrdf :: FilePath
  , ucTip :: String
  , ucJoints :: [String]
  , ucCases :: [([Double], [Double])]
  }

instance FromJSON UrdfCase where
  parseJSON = withObject "urdf case" $ \o -> do
    cs <- o .: "cases"
    cases <- mapM (withObject "case" (\c -> (,) <$> c .: "q" <*> c .: "T")) cs
    UrdfCase <$> o .: "robot" <*> o .: "urdf" <*> o .: "tip" <*> o .: "joints" <*> pure cases

data DobotFile = DobotFile
  { dbName :: String
  , dbRows :: [[Double]]   -- alpha, a (mm), d (mm), theta offset
  , dbMin, dbMax :: [Double]
  , dbCases :: [([Double], [Double])]
  }

instance FromJSON DobotFile where
  parseJSON = withObject "dobot file" $ \o -> do
    cs <- o .: "cases"
    cases <- mapM (withObject "case" (\c -> (,) <$> c .: "q_deg" <*> c .: "T_mm")) cs
    mn <- o .:? "jointMin_deg"
    mx <- o .:? "jointMax_deg"
    DobotFile <$> o .: "robot" <*> o .: "dhm_rows_alpha_a_d_theta" <*> pure (fromMaybe [] mn) <*> pure (fromMaybe [] mx) <*> pure cases

loadDh :: FilePath -> IO DhFile
loadDh p = either (fail . ((p ++ ": ") ++)) pure =<< eitherDecodeFileStrict p

loadUrdfCase :: FilePath -> IO UrdfCase
loadUrdfCase p = either (fail . ((p ++ ": ") ++)) pure =<< eitherDecodeFileStrict p

loadDobot :: FilePath -> IO DobotFile
loadDobot p = either (fail . ((p ++ ": ") ++)) pure =<< eitherDecodeFileStrict p

-- | The library model built from a reference file's own DH table.
dhRobot :: DhFile -> Robot
dhRobot f =
  (emptyRobot (dhName f))
    { robotJoints =
        [ Joint ("q" ++ show i) kind (Limits lo hi) Nothing Nothing
        | (i, r, [lo, hi]) <- zip3 [1 :: Int ..] (dhRows f) (dhQlim f)
        , let kind = if rowType r == "P" then Prismatic else Revolute ]
    , robotLinks =
        [ Link ("link" ++ show i) (Just kind) geom (directDrive (i - 1) 1 (rowOffset r)) []
        | (i, r) <- zip [1 :: Int ..] (dhRows f)
        , let kind = if rowType r == "P" then Prismatic else Revolute
              geom
                | dhConvention f == "standard" = DhStandard (rowTheta r) (rowD r) (rowA r) (rowAlpha r)
                | otherwise = DhModified (rowAlpha r) (rowA r) (rowTheta r) (rowD r) ]
    , robotBase = maybe identity id (fromRows (dhBase f))
    , robotTool = maybe identity id (fromRows (dhTool f))
    }
