{-# LANGUAGE OverloadedStrings #-}
-- | Every output format tells the same story about a result: the summary, JSON, the
-- protobuf response, CSV and the table agree on whether the profile is legal, whether it
-- converged, and on its samples. The requests cover a legal converged profile, a legal
-- profile stopped by the iteration cap before convergence, an illegal best attempt, an
-- infeasible request and an invalid one.
module VProf.Profile.Format.AgreementSpec (spec) where

import qualified Data.Aeson as A
import qualified Data.Aeson.KeyMap as KM
import qualified Data.ByteString.Lazy as BL
import qualified Data.ByteString.Lazy.Char8 as BLC
import Data.List (isPrefixOf)
import Data.ProtocolBuffers (getField)
import qualified Data.Vector.Unboxed as U
import Test.Hspec

import Support.Cli (splitComma)
import VProf.Profile.Format.Json (profileToJson, requestFromJson)
import VProf.Profile.Format.Text (csv, summary, table)
import VProf.Profile.Generate
import VProf.Profile.Legality (Rule (..), Violation (..))
import VProf.Profile.Request
import VProf.Profile.Sampled
import VProf.Units
import VProf.Wire.Messages
import VProf.Wire.Profile (resultToMsg)

-- | The "simple" case of the thesis: 10 m at 4 m/s, |a| <= 1, |j| <= 2.
simple :: Request
simple = defaultRequest { rqZones = [SpeedZone (0 *~ meter) (4 *~ mps)]
                        , rqMinJerk = (-2) *~ mps3, rqMaxJerk = 2 *~ mps3 }

summaryFlag :: String -> Result -> Maybe Bool
summaryFlag name r = case [ drop (length name + 1) l | l <- lines (summary r), (name ++ ":") `isPrefixOf` l ] of
  [v] -> case words v of
    ["yes"] -> Just True
    ["no"] -> Just False
    _ -> Nothing
  _ -> Nothing

jsonFlag :: A.Key -> Result -> Maybe Bool
jsonFlag k r = case profileToJson r of
  A.Object o -> case KM.lookup k o of
    Just (A.Bool b) -> Just b
    _ -> Nothing
  _ -> Nothing

agree :: String -> Result -> Spec
agree name r = describe name $ do
  let msg = resultToMsg 7 r
      legal = resultLegal r
  it "legal: the same in the summary, JSON and protobuf" $ do
    summaryFlag "legal" r `shouldBe` Just legal
    jsonFlag "legal" r `shouldBe` Just legal
    orDefault (getField (prsLegal msg)) `shouldBe` legal
  it "converged: the same in the summary, JSON and protobuf" $ do
    summaryFlag "converged" r `shouldBe` Just (resConverged r)
    jsonFlag "converged" r `shouldBe` Just (resConverged r)
    orDefault (getField (prsConverged msg)) `shouldBe` resConverged r
  it "the samples: the same count in CSV, the table and protobuf, the same velocities in CSV" $ do
    let n = maybe 0 sampleCount (resProfile r)
        csvRows = drop 1 (lines (maybe "" (BLC.unpack . csv) (resProfile r)))
    length csvRows `shouldBe` n
    length (drop 1 (lines (maybe "" table (resProfile r)))) `shouldBe` n
    length (getField (prsVelocity msg)) `shouldBe` n
    map (read . (!! 2) . splitComma) csvRows `shouldBe` maybe [] (U.toList . prVelocities) (resProfile r)

spec :: Spec
spec = do
  movingStartEnd <- runIO (either error id . requestFromJson <$> BL.readFile "examples/moving-start-end.json")
  let converged = generatePure simple
      -- its seed is legal, and one raising pass still changes it
      capped = generatePure movingStartEnd { rqMaxIterations = Just 1 }
      Just best = resProfile converged
      broken = converged
        { resOutcome = Failed (NotConverged "the best profile breaks limits")
        , resViolations = [Violation JerkRule 3 9 2]
        , resProfile = Just best }
      infeasible = generatePure simple { rqStartVelocity = 4 *~ mps, rqRouteLength = 1 *~ meter }
      invalid = generatePure simple { rqMaxJerk = (-1) *~ mps3 }
  it "the cases are what they claim to be" $ do
    (resOutcome converged, resultLegal converged) `shouldBe` (Generated, True)
    (resConverged capped, resultLegal capped) `shouldBe` (False, True)
    resultLegal broken `shouldBe` False
    resultLegal infeasible `shouldBe` False
    resultLegal invalid `shouldBe` False
  agree "a legal, converged profile" converged
  agree "a legal profile stopped before convergence" capped
  agree "an illegal best attempt" broken
  agree "an infeasible request" infeasible
  agree "an invalid request" invalid
