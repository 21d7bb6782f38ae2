-- | When the lead-in is tried. A start (or end) state the hardest braking cannot save gets a
-- search over its first steps only where the braking misses its rule by less than a few
-- steps' change of velocity ('leadInMayHelp'); where it misses by more, the search must find
-- nothing (checked here by running it), and the request is called infeasible at once.
module VProf.Profile.Generate.Seed.LeadInSpec (spec) where

import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import Support.Wide (logUniform)
import VProf.Profile.Generate.Seed (SeedFailure (..), mirror, seed, seedWithLeadIn)
import VProf.Profile.Generate.Seed.Brake (St (..), policyFor)
import VProf.Profile.Generate.Seed.LeadIn (leadIn, leadInMayHelp, startTerm)
import VProf.Profile.Problem (Algorithm (..), Problem (..))

-- | A start in trouble, of two kinds. A low zone of 2 to 80 % of the first zone's limit
-- some way after the start (from v0 up to that limit), then a faster one; or the start in a
-- short low zone, 0.2 to 2 steps' travel at its limit long, that a fast first step may leave behind
-- (the lead-in's own case). A rising start acceleration; ranges of 0.3 to 5 m/s² and 0.3 to
-- 20 m/s³, a 2 to 250 ms step, ending at rest or (a third of the time) in motion.
genStart :: Gen Problem
genStart = do
  len <- logUniform 1 100
  aMin <- logUniform 0.3 5
  aMax <- logUniform 0.3 5
  jMin <- logUniform 0.3 20
  jMax <- logUniform 0.3 20
  a0 <- choose (0, aMax)
  dt <- logUniform 2e-3 0.25
  v2 <- logUniform 1 20
  shortFirst <- arbitrary
  (starts, speeds, v0) <-
    if shortFirst
      then do
        low <- logUniform 0.05 5
        v0 <- (* low) <$> logUniform 0.05 1
        w <- (* (low * dt)) <$> logUniform 0.2 2
        v1 <- (* low) <$> logUniform 1.05 4
        pure ([0, w, w + 0.3 * len], [low, v1, v2], v0)
      else do
        v1 <- logUniform 1 20
        v0 <- choose (0.3 * v1, v1)
        d <- logUniform 0.02 (0.5 * len)
        w <- logUniform 0.005 (0.4 * len)
        low <- (* v1) <$> logUniform 0.02 0.8
        pure ([0, d, d + w], [v1, low, v2], v0)
  vEnd <- frequency [(2, pure 0), (1, choose (0, min v2 5))]
  pure Problem
    { pbLength = len, pbZoneStarts = U.fromList starts, pbZoneSpeeds = U.fromList speeds
    , pbAMin = negate aMin, pbAMax = aMax, pbJMin = negate jMin, pbJMax = jMax
    , pbV0 = v0, pbA0 = a0, pbVEnd = vEnd, pbAEnd = 0, pbDt = dt, pbDv = 1e-9
    , pbMaxIter = 100, pbBudget = 10, pbTol = 1e-2, pbAlgorithm = Band, pbSeedSearch = False }

moving :: Problem -> Bool
moving pb = pbVEnd pb > 0 || pbAEnd pb /= 0

stuck :: Problem -> Bool
stuck pb = either (const True) (const False) (policyFor pb (startTerm (moving pb) pb) (St (pbV0 pb) (pbA0 pb) 0))

-- | A route at 0.1 ms whose end velocity, 9.92 m/s, cannot be reached after a 0.93 m/s zone
-- that ends 113 m before the end at 0.42 m/s² (the hardest braking backwards from the end is
-- still at 2.83 m/s there): the lead-in on its mirror took 51 s to find nothing.
farFromEnd :: Problem
farFromEnd = Problem
  { pbLength = 126.71571815387064, pbZoneStarts = U.fromList [0, 13.712828675801564, 40.79093037059283]
  , pbZoneSpeeds = U.fromList [0.9340691373694857, 24.433731561994655, 11.4572315721152]
  , pbAMin = -1.4501220919770994, pbAMax = 0.4218227489795961, pbJMin = -0.3619984390927118, pbJMax = 0.4071834598360001
  , pbV0 = 0, pbA0 = 0, pbVEnd = 9.923891450787451, pbAEnd = 0, pbDt = 1e-4, pbDv = 1e-9
  , pbMaxIter = 1000, pbBudget = 20, pbTol = 1e-2, pbAlgorithm = Band, pbSeedSearch = False }

spec :: Spec
spec = describe "when the lead-in is tried" $ do
  it "a start the hardest braking misses its rule from by more than the lead-in can make up: the lead-in finds nothing either" $
    -- the lead-in saves 1 to 3 starts in 3000 here, each within 0.05 to 0.5 of the
    -- (a_max - a_min)*dt that 'leadInReachSteps' counts 8 of (a count of 0.05 fails here)
    withMaxSuccess 3000 $ forAllBlind genStart $ \pb ->
      let help = leadInMayHelp (moving pb) pb
          saved = either (const False) (const True) (leadIn seedWithLeadIn 2 pb)
      in stuck pb ==>
           classify help "near miss: the lead-in is tried" $
             classify saved "the lead-in saves it" $
               counterexample (show pb) (help || not saved)

  it "a start the hardest braking saves needs no lead-in" $
    withMaxSuccess 200 $ forAllBlind genStart $ \pb ->
      not (stuck pb) ==> not (leadInMayHelp (moving pb) pb)

  it "an end velocity missed under a zone 113 m away, at 0.1 ms: no lead-in on the mirror, and the seed's claim names end_velocity" $ do
    stuck (mirror farFromEnd) `shouldBe` True
    leadInMayHelp True (mirror farFromEnd) `shouldBe` False
    case seed farFromEnd of
      Left (Unattainable field _) -> field `shouldBe` "end_velocity"
      other -> expectationFailure (either show (const "a profile") other)
