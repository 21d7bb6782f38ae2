{-# LANGUAGE LambdaCase #-}
{-# LANGUAGE OverloadedStrings #-}
-- | The roboticstoolbox reference files in @shared/reference/kinematics/@ (read with
-- aeson): a DH table, limits, base, tool and FK cases. The shared directory is
-- @$VPROF_SHARED@ or @../shared@ relative to the project root.
module Support.DhReference
  ( RefRobot (..), RefCase (..), loadReference, sharedDir, rowsToMatrix
  ) where

import Data.Aeson
import qualified Data.ByteString.Lazy as BL
import System.Environment (lookupEnv)
import Support.DhOracle

data RefCase = RefCase { caseQ :: [Double], caseT :: [Double] }

data RefRobot = RefRobot
  { refName :: String
  , refConvention :: String
  , refRows :: [DhRow]
  , refTypes :: [String]
  , refQlim :: [[Double]]
  , refBase, refTool :: [Double]
  , refCases :: [RefCase]
  }

instance FromJSON RefCase where
  parseJSON = withObject "case" $ \o -> RefCase <$> o .: "q" <*> o .: "T"

instance FromJSON RefRobot where
  parseJSON = withObject "robot" $ \o -> do
    rows <- o .: "dh"
    parsed <- mapM (withObject "dh row" (\r -> (,) <$> r .: "type"
                     <*> (DhRow <$> r .: "offset" <*> r .: "d" <*> r .: "a" <*> r .: "alpha"))) rows
    RefRobot <$> o .: "robot" <*> o .: "convention" <*> pure (map snd parsed) <*> pure (map fst parsed)
             <*> o .: "qlim" <*> o .: "base" <*> o .: "tool" <*> o .: "cases"

sharedDir :: IO FilePath
sharedDir = lookupEnv "VPROF_SHARED" >>= case'
  where
    case' (Just d) = pure d
    case' Nothing = pure "../shared"

loadReference :: String -> IO RefRobot
loadReference name = do
  dir <- sharedDir
  bytes <- BL.readFile (dir ++ "/reference/kinematics/" ++ name ++ ".json")
  either (fail . ((name ++ ": ") ++)) pure (eitherDecode bytes)

-- | Row-major 16 numbers to a 4×4 matrix.
rowsToMatrix :: [Double] -> Mat4
rowsToMatrix xs = [take 4 (drop (4 * i) xs) | i <- [0 .. 3]]
