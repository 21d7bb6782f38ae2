-- | The independent proofs of "Support.Proofs" are themselves sound: on random requests
-- the generator solves, no proof claims that no profile exists, and the rows a
-- certificate is checked against hold for every legal profile.
module Support.ProofsSpec (spec) where

import qualified Data.Vector.Unboxed as U
import System.IO.Unsafe (unsafePerformIO)
import Test.Hspec
import Test.QuickCheck hiding (generate, Result)

import Support.Arbitrary
import Support.Proofs
import VProf.Profile.Generate
import VProf.Profile.Request
import VProf.Profile.Sampled
import VProf.Units

cases :: Int
cases = unsafePerformIO propertyCount
{-# NOINLINE cases #-}

-- | Make sure the request ends in motion.
moving :: Request -> Request
moving rq = let vLast = si (zoneSpeed (last (rqZones rq)))
            in if si (rqEndVelocity rq) > 0 then rq else rq { rqEndVelocity = (vLast / 2) *~ mps }

spec :: Spec
spec = describe "the independent proofs" $ do
    it "the rows a certificate is checked against hold for every legal profile (so no certificate can pass for a step count that has one)" $
      withMaxSuccess (max 100 (cases `div` 5)) $ property $ forAll (moving <$> genRequest) $ \rq ->
        let pb = problemOf rq
        in case (resOutcome (generatePure rq), resProfile (generatePure rq)) of
             (Generated, Just p) ->
               let v = prVelocities p
                   n = U.length v - 1
               in n >= 1 ==> forAll (vectorOf (2 * n + 2) (choose (-1, 1))) $ \ys ->
                    case certificateTerms pb n (U.fromList ys) of
                      Just (least, r, combined, margin) ->
                        let rv = U.sum (U.zipWith (*) r v)
                        in counterexample (show (least, rv, combined, margin)) (least <= rv + margin && rv <= combined + margin)
                      Nothing -> counterexample "the multipliers were refused" False
             _ -> property Discard

    it "the state-gap bound never claims a request the generator solved (it is a sound proof)" $
      withMaxSuccess cases $ property $ forAll (moving <$> genRequest) $ \rq ->
        let r = generatePure rq
            pb = problemOf rq
        in case resOutcome r of
             Generated -> counterexample "a legal profile exists, yet the bound says none does" (not (stateGapProof pb))
             _ -> property Discard

