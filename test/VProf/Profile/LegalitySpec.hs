-- | The checker catches each rule on profiles built to break exactly that rule, and agrees with
-- an oracle written apart from it ("Support.LegalityOracle") on the generator's profiles for
-- random requests and on those profiles broken by small and large changes.
module VProf.Profile.LegalitySpec (spec) where

import Data.List (nub, sort)
import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck hiding (generate, Result)

import Support.Arbitrary (genRequest, problemOf)
import Support.LegalityOracle
import Support.Wide (logUniform)
import VProf.Profile.Generate (Result (..), generate)

import VProf.Profile.Legality
import VProf.Profile.Sampled
import VProf.Profile.Request
import VProf.Units

-- | 10 m at up to 2 m/s, then 1 m/s from 6 m; ±1 m/s², ±2 m/s³; dt = 0.5 s.
problem :: Problem
problem = either (error . show) id $ validate defaultRequest
  { rqRouteLength = 10 *~ meter
  , rqZones = [SpeedZone (0 *~ meter) (2 *~ mps), SpeedZone (6 *~ meter) (1 *~ mps)]
  , rqMinJerk = (-2) *~ mps3, rqMaxJerk = 2 *~ mps3
  , rqTimeStep = Just (0.5 *~ second)
  }

-- | A hand-made legal profile for 'problem': velocity ramps 0 → 1 m/s with jerk ±2
-- (a: 0.5, 0.5, …), cruises at 1 m/s, ramps down; landing at exactly 10 m.
legalV :: [Double]
legalV = [0, 0.25, 0.75, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0.75, 0.25, 0]

prof :: [Double] -> Profile
prof vs = Profile 0.5 (U.fromList vs) 0 0

rules :: [Violation] -> [Rule]
rules = map vRule

spec :: Spec
spec = do
  it "the hand-made profile is legal (it lands on 10 m)" $ do
    finalDistance (prof legalV) `shouldBe` 10
    check problem (prof legalV) `shouldBe` []

  it "catches a negative velocity" $ do
    let vs = [0, 0.25, 0.25, 0, -0.125, 0] ++ drop 6 legalV
    rules (check problem (prof vs)) `shouldContain` [NegativeVelocity]

  it "catches a speed limit broken inside a zone (and only that)" $ do
    -- 2.25 m/s in the first zone at one sample, jerk-smooth because dt is large: keep
    -- accelerations and jerks legal by using a different problem with loose a/j
    let loose = problem { pbAMin = -100, pbAMax = 100, pbJMin = -1000, pbJMax = 1000 }
        vs = [0, 2.25] ++ replicate 8 0.5 ++ [0.25, 0]
        p = prof vs
    [ vRule v | v <- check loose p, vRule v `notElem` [RouteEnd] ] `shouldBe` [Speed, Speed]

  it "catches a step that touches a lower zone only at its end (closed interval)" $ do
    -- s: 0, .5, 1.5, …, 5.5, 6.0: the last step [5.5, 6.0] touches the 1 m/s zone at 6
    -- with max(v) = 2; every other step stays inside the 2 m/s zone
    let loose = problem { pbAMin = -100, pbAMax = 100, pbJMin = -1000, pbJMax = 1000, pbLength = 6 }
        p = prof [0, 2, 2, 2, 2, 2, 2, 0]
    finalDistance p `shouldBe` 6
    [ (vRule v, vSample v) | v <- check loose p ] `shouldBe` [(Speed, 6)]

  it "catches an acceleration above the maximum" $ do
    let vs = [0, 0.25, 0.75, 1.5] ++ drop 4 legalV
    rules (check problem (prof vs)) `shouldContain` [AccelerationRule]

  it "catches a deceleration below the minimum" $ do
    let p = problem { pbJMin = -100, pbJMax = 100 }
        vs = take 10 legalV ++ [0.25] ++ drop 11 legalV
    rules (check p (prof vs)) `shouldContain` [AccelerationRule]

  it "catches a jerk beyond the range, including into the first acceleration" $ do
    -- a_0 = 1 m/s² from a start acceleration of 0 in 0.5 s: jerk 2 is fine, 2.5 is not
    let vs = [0, 0.625] ++ drop 2 legalV
        p = prof vs
    [ vSample v | v <- check problem p, vRule v == JerkRule ] `shouldContain` [0]
    let p2 = (prof legalV) { prStartAcc = -0.6 }
    [ (vRule v, vSample v) | v <- check problem p2 ] `shouldBe` [(JerkRule, 0)]
    let p3 = (prof legalV) { prEndAcc = 0.6 }
    [ (vRule v, vSample v) | v <- check problem p3 ] `shouldBe` [(JerkRule, length legalV - 1)]

  it "catches a wrong start and end velocity" $ do
    let p = problem { pbV0 = 0.5 }
    rules (check p (prof legalV)) `shouldBe` [StartVelocity]
    let q = problem { pbVEnd = 0.25 }
    rules (check q (prof legalV)) `shouldBe` [EndVelocity]

  it "catches a profile that stops short of the route end, by how much (value s_N - L, limit the tolerance)" $ do
    let p = problem { pbLength = 10.02 }
    rules (check p (prof legalV)) `shouldBe` [RouteEnd]
    [ (vValue v, vLimit v) | v <- check p (prof legalV) ] `shouldSatisfy` (\[(o, l)] -> abs (o + 0.02) < 1e-12 && l == pbTol p)
    map renderViolation (check p (prof legalV)) `shouldBe` ["route_end at sample 23: the profile ends 0.020000 m short of the route end, more than the end tolerance 0.010000 m"]
  it "says a route end off by less than a millimetre in three digits (a 1 µm route's 0.1 µm tolerance read \"0.000000 m\")" $
    renderViolation (Violation RouteEnd 1 (-1e-6) 1e-7) `shouldBe` "route_end at sample 1: the profile ends 1.00e-6 m short of the route end, more than the end tolerance 1.00e-7 m"

  it "a value past its limit by less than six decimals show says by how much" $ do
    renderViolation (Violation JerkRule 21904 0.50000008194 0.5)
      `shouldBe` "jerk at sample 21904: 0.500000 m/s³ beyond the limit 0.500000 m/s³ (by 8.2e-8 m/s³)"
    renderViolation (Violation AccelerationRule 17 5 1)
      `shouldBe` "acceleration at sample 17: 5.000000 m/s² beyond the limit 1.000000 m/s²"

  it "a NaN or infinite velocity is a violation at its sample (every comparison with NaN is false)" $
    property $ forAll (choose (0, length legalV - 1)) $ \k -> forAll (elements [0 / 0, 1 / 0, -1 / 0]) $ \x ->
      let vs = [ if i == k then x else v | (i, v) <- zip [0 ..] legalV ]
      in rules (check problem (prof vs)) === [NonFinite] .&&. map vSample (check problem (prof vs)) === [k]

  it "catches samples beyond the route end plus tolerance" $ do
    let r = problem { pbLength = 9.8, pbTol = 0.1 }
        sN = U.toList (distances (prof legalV))
        beyond = [ k | (k, x) <- zip [0 :: Int ..] sN, x > 9.9 ]
        vio = check r (prof legalV)
    beyond `shouldSatisfy` (not . null)
    [ vSample v | v <- vio, vRule v == Overshoot ] `shouldBe` beyond
    [ vRule v | v <- vio, vRule v /= Overshoot ] `shouldBe` [RouteEnd]

  it "allows rounding slack of 1e-9 and no more" $ do
    let vs = map (* (1 + 1e-12)) legalV
    check problem (prof vs) `shouldBe` []
    -- 1 µm/s above the 1 m/s zone (sample 15 lies beyond 6 m) is a violation
    let ws = [ if k == 15 then x + 1e-6 else x | (k, x) <- zip [0 :: Int ..] legalV ]
    distances (prof legalV) U.! 14 `shouldSatisfy` (> 6)
    map vRule (check problem (prof ws)) `shouldBe` [Speed, Speed]

  it "catches a profile that arrives and then stands or creeps (crawl), at the arrival sample" $ do
    -- standing at rest at the end for three more samples
    map (\v -> (vRule v, vSample v)) (check problem (prof (legalV ++ [0, 0, 0]))) `shouldBe` [(Crawl, 23)]
    -- creeping 1 mm further at 2 mm/s after arriving 1 mm short of a 10.001 m route
    let pb = problem { pbLength = 10.001 }
        creep = legalV ++ [0.002, 0.002, 0]
    finalDistance (prof creep) `shouldSatisfy` (\s -> abs (s - 10.002) < 1e-12)
    map vRule (check pb (prof creep)) `shouldBe` [Crawl]
    -- the same profile ending where it arrived is legal
    check pb (prof legalV) `shouldBe` []

  it "no crawl where ending early would break the jerk into the end acceleration" $ do
    -- ending in motion at 0.75 m/s: sample 21 is within the tolerance at 0.75 m/s, after a
    -- step at -0.5 m/s²; ending there is possible into an end acceleration of 0 (jerk 1)
    -- but not of 0.6 m/s² (jerk 2.2 > 2)
    let vs = U.fromList (take 22 legalV ++ [0.75])
        pb = problem { pbLength = 10.0625, pbVEnd = 0.75, pbTol = 0.4 }
    check pb (Profile 0.5 vs 0 0.6) `shouldBe` []
    map (\v -> (vRule v, vSample v)) (check pb (Profile 0.5 vs 0 0)) `shouldBe` [(Crawl, 21)]

  it "an empty profile is a violation" $
    rules (check problem (Profile 0.5 U.empty 0 0)) `shouldBe` [EmptyProfile]

  it "property: raising any one cruise sample by a visible amount breaks a rule" $
    property $ forAll (choose (4, 19)) $ \k -> forAll (choose (0.05, 2)) $ \d ->
      let vs = [ if i == k then x + d else x | (i, x) <- zip [0 :: Int ..] legalV ]
      in check problem (prof vs) /= []

  describe "against the independent oracle (Support.LegalityOracle)" $ do
    it "agrees on every hand-made case above" $
      mapM_ (\(pb, vs, a0, aE) -> let p = Profile 0.5 (U.fromList vs) a0 aE
                                   in (oracleVerdict pb p == SurelyLegal, nub (sort (map (ruleName . vRule) (check pb p))))
                                        `shouldBe` (null (check pb p), nub (sort (map fst (oracleViolations checkerAllowance pb p)))))
        [ (problem, legalV, 0, 0), (problem, [0, 0.25, 0.25, 0, -0.125, 0] ++ drop 6 legalV, 0, 0)
        , (problem { pbAMin = -100, pbAMax = 100, pbJMin = -1000, pbJMax = 1000, pbLength = 6 }, [0, 2, 2, 2, 2, 2, 2, 0], 0, 0)
        , (problem, [0, 0.25, 0.75, 1.5] ++ drop 4 legalV, 0, 0), (problem, [0, 0.625] ++ drop 2 legalV, 0, 0)
        , (problem, legalV, -0.6, 0), (problem, legalV, 0, 0.6), (problem { pbV0 = 0.5 }, legalV, 0, 0)
        , (problem, legalV ++ [0, 0, 0], 0, 0), (problem { pbLength = 10.001 }, legalV ++ [0.002, 0.002, 0], 0, 0)
        , (problem { pbLength = 10.0625, pbVEnd = 0.75, pbTol = 0.4 }, take 22 legalV ++ [0.75], 0, 0.6)
        , (problem { pbLength = 10.0625, pbVEnd = 0.75, pbTol = 0.4 }, take 22 legalV ++ [0.75], 0, 0) ]

    it "property: on the generator's profiles for random requests, and on them changed by 1e-13 to 1e-3 relative or more, the checker's verdict is the oracle's wherever the oracle's is free of rounding, and the rules it names lie between the oracle's with a tighter and a looser allowance" $
      withMaxSuccess 400 $ checkCoverage $ forAll genRequest $ \rq -> forAll genChange $ \change -> ioProperty $ do
        r <- generate rq
        let pb = problemOf rq
        pure $ case resProfile r of
          Nothing -> label "no profile" True
          Just p0 ->
            let p = applyChange change p0
                verdict = oracleVerdict pb p
                mine = nub (sort (map (ruleName . vRule) (check pb p)))
                rulesAt al = nub (sort (map fst (oracleViolations al pb p)))
                fewest = rulesAt (Allowance 1.01e-9 0.99e-9)
                most = rulesAt (Allowance 0.99e-9 1.01e-9)
            in cover 10 (verdict == SurelyLegal) "legal beyond rounding"
               . cover 15 (verdict == SurelyIllegal) "illegal beyond rounding"
               . tabulate "change" [changeName change]
               . counterexample (show (verdict, mine, fewest, most))
               $ (case verdict of
                    SurelyLegal -> null mine
                    SurelyIllegal -> not (null mine)
                    Borderline -> True)
                 && all (`elem` mine) fewest && all (`elem` most) mine

-- | A change to a profile: none, one sample scaled, every sample scaled, a constant added,
-- the last sample dropped or repeated, the start or end acceleration moved.
data Change = Same | One Double Double | Every Double | Shift Double | DropLast | RepeatLast | StartAcc Double | EndAcc Double
  deriving (Show)

changeName :: Change -> String
changeName = \case
  Same -> "none"; One {} -> "one sample scaled"; Every _ -> "all scaled"; Shift _ -> "shifted"
  DropLast -> "last dropped"; RepeatLast -> "last repeated"; StartAcc _ -> "start acceleration"; EndAcc _ -> "end acceleration"

genChange :: Gen Change
genChange = do
  e <- (*) <$> elements [-1, 1] <*> logUniform 1e-13 1e-3
  oneof [ pure Same, One <$> choose (0, 1) <*> pure e, pure (Every e), Shift <$> elements [e, 1e3 * e]
        , pure DropLast, pure RepeatLast, StartAcc <$> pure (1e3 * e), EndAcc <$> pure (1e3 * e) ]

applyChange :: Change -> Profile -> Profile
applyChange c p@(Profile dt v a0 aE) = case c of
  Same -> p
  One u e -> let k = min (U.length v - 1) (floor (u * fromIntegral (U.length v)))
             in p { prVelocities = v U.// [(k, (v U.! k) * (1 + e))] }
  Every e -> p { prVelocities = U.map (* (1 + e)) v }
  Shift e -> p { prVelocities = U.map (+ e) v }
  DropLast -> if U.length v > 1 then p { prVelocities = U.init v } else p
  RepeatLast -> p { prVelocities = U.snoc v (U.last v) }
  StartAcc e -> Profile dt v (a0 + e) aE
  EndAcc e -> Profile dt v a0 (aE + e)
