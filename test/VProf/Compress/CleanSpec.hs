-- | Cleaning real recordings: random smooth tracks with injected duplicates, sign flips,
-- gaps, outliers and swapped samples; the cleaned track is strictly increasing, nothing
-- is dropped silently, and the warnings count exactly what was injected.
module VProf.Compress.CleanSpec (spec) where

import Data.Either (isLeft, isRight)
import Control.Monad (forM_)
import Data.List (isInfixOf, nub, sort, zip4)
import qualified Data.Vector.Unboxed as U
import Numeric (showFFloat)
import Test.Hspec
import Test.Hspec.QuickCheck (modifyMaxSuccess)
import Test.QuickCheck

import VProf.Compress
import VProf.Compress.Clean
import VProf.Geometry.Quaternion (qdot, qexp, qmul, qneg, qnormalize)
import VProf.Geometry.Vec
import Support.Recordings (loadTum)

-- | A smooth recording: 30–150 samples, steps of 5–50 ms with ±10 % jitter, positions a
-- sum of slow sines (amplitude up to 0.3 m, up to 1 Hz), a steady rotation up to 1 rad/s.
-- Locations are line numbers from 1.
-- | The longest run of spiked samples the outlier rule removes whole.
maxRun :: Int
maxRun = 2

genBase :: Gen [Sample]
genBase = do
  n <- choose (30, 150)
  dt <- choose (0.005, 0.05)
  jit <- vectorOf (n - 1) (choose (0.9, 1.1))
  t0 <- choose (0, 1000)
  axes <- vectorOf 3 ((,,) <$> choose (0.05, 0.3) <*> choose (0.1, 1) <*> choose (0, 2 * pi))
  w <- P3 <$> choose (-1, 1) <*> choose (-1, 1) <*> choose (-1, 1)
  q0 <- qnormalize <$> (Q4 <$> choose (-1, 1) <*> choose (-1, 1) <*> choose (-1, 1) <*> choose (-1, 1))
  let ts = scanl (+) t0 (map (* dt) jit)
      pos t = let [x, y, z] = [ a * sin (2 * pi * f * (t - t0) + ph) | (a, f, ph) <- axes ] in P3 x y z
      rot t = qnormalize (qmul (qexp ((t - t0) *^ w)) q0)
  pure (renumber [ Sample 0 t (pos t) (rot t) | t <- ts ])

renumber :: [Sample] -> [Sample]
renumber = zipWith (\i s -> s { smLoc = i }) [1 ..]

-- | k distinct indices in [lo, hi], at least gap apart.
genIndices :: Int -> Int -> Int -> Int -> Gen [Int]
genIndices k lo hi gap = go (100 :: Int) []
  where
    go 0 acc = pure (sort acc)
    go tries acc
      | length acc == k = pure (sort acc)
      | otherwise = do
          i <- choose (lo, hi)
          if all (\j -> abs (i - j) >= gap) acc then go tries (i : acc) else go (tries - 1) acc

clean :: CleanOptions -> [Sample] -> Either [FieldError] Cleaned
clean = cleanSamples fileLocator

strictlyIncreasing :: Track -> Bool
strictlyIncreasing tr = let t = tTime tr in U.and (U.zipWith (<) t (U.tail t))

continuous :: Track -> Bool
continuous tr = let qs = ptoList (tRot tr) in and (zipWith (\a b -> qdot a b >= 0) qs (drop 1 qs))

countOf :: (CleanWarning -> Bool) -> Cleaned -> Int
countOf p = sum . map warningCount . filter p . clWarnings

isDup, isFlip, isGap, isOutlier, isNonUnit :: CleanWarning -> Bool
isDup = \case DuplicateTimes {} -> True; _ -> False
isFlip = \case SignFlips {} -> True; _ -> False
isGap = \case Gaps {} -> True; _ -> False
isOutlier = \case OutliersRejected {} -> True; _ -> False
isNonUnit = \case NonUnitQuaternions {} -> True; _ -> False

isMissing :: CleanWarning -> Bool
isMissing = \case MissingPoses {} -> True; _ -> False

isLong :: CleanWarning -> Bool
isLong = \case LongMedianStep {} -> True; _ -> False

-- | After each chosen index, a second sample of the same time with another pose (moved up
-- to 5 mm, turned a little, and with its quaternion negated half the time).
injectDuplicates :: [Int] -> [Sample] -> Gen [Sample]
injectDuplicates idx ss = renumber . concat <$> mapM one (zip [0 ..] ss)
  where
    one (i, s)
      | i `elem` idx = do
          d <- P3 <$> choose (-5e-3, 5e-3) <*> choose (-5e-3, 5e-3) <*> choose (-5e-3, 5e-3)
          r <- P3 <$> choose (-0.05, 0.05) <*> choose (-0.05, 0.05) <*> choose (-0.05, 0.05)
          neg <- arbitrary
          let q = qnormalize (qmul (qexp r) (smRot s))
          pure [s, s { smPos = smPos s ^+^ d, smRot = if neg then qneg q else q }]
      | otherwise = pure [s]

-- | Lengthen the step before each chosen index by 20–100 median steps.
injectGaps :: [Int] -> [Sample] -> Gen ([Sample], [Double])
injectGaps idx ss = do
  let dts = zipWith (\a b -> smTime b - smTime a) ss (drop 1 ss)
      med = sort dts !! (length dts `div` 2)
  extras <- mapM (\i -> (i,) . (* med) <$> choose (20, 100)) idx
  let shift i = sum [ e | (j, e) <- extras, j <= i ]
      out = [ s { smTime = smTime s + shift i } | (i, s) <- zip [0 ..] ss ]
      steps = [ smTime b - smTime a | (a, b) <- zip out (drop 1 out) ]
  pure (out, [ steps !! (i - 1) | i <- idx ])

spec :: Spec
spec = describe "VProf.Compress.Clean" $ do
  it "leaves a clean recording alone: no warnings, every sample kept, same poses" $
    property $ forAll genBase $ \ss -> case clean defaultCleanOptions ss of
      Left e -> counterexample (show e) False
      Right c -> clWarnings c === [] .&&. trackLength (clTrack c) === length ss
                 .&&. U.toList (clLocs c) === map smLoc ss
                 .&&. ptoList (tPos (clTrack c)) === map smPos ss

  describe "duplicate timestamps" $ do
    it "are merged (position mean, quaternions sign-aligned then normalised mean), counted and located" $
      property $ forAll genBase $ \ss -> forAll (choose (1, 5)) $ \k ->
        forAll (genIndices k 0 (length ss - 1) 1) $ \idx -> forAll (injectDuplicates idx ss) $ \dup ->
          case clean defaultCleanOptions dup of
            Left e -> counterexample (show e) False
            Right c ->
              let tr = clTrack c
                  groups = [ (a, b) | (a, b) <- zip dup (drop 1 dup), smTime a == smTime b ]
                  merged = [ (i, a, b) | (a, b) <- groups, let Just i = U.elemIndex (smTime a) (tTime tr) ]
                  qa = [ qnormalize (let Q4 w x y z = smRot a; Q4 w' x' y' z' = if qdot (smRot a) (smRot b) < 0 then qneg (smRot b) else smRot b
                                     in Q4 (w + w') (x + x') (y + y') (z + z')) | (_, a, b) <- merged ]
                  close (P3 a b c') (P3 x y z) = maximum (map abs [a - x, b - y, c' - z]) < 1e-12
                  qclose p q = abs (abs (qdot p q) - 1) < 1e-12
              in counterexample (show (clWarnings c)) $
                   strictlyIncreasing tr .&&. countOf isDup c === k
                   .&&. trackLength tr + countOf isDup c === length dup
                   .&&. length (filter isDup (clWarnings c)) === 1
                   .&&. conjoin [ counterexample (show (i, a, b)) (close (pindex (tPos tr) i) ((smPos a ^+^ smPos b) ^/ 2))
                                | (i, a, b) <- merged ]
                   .&&. conjoin [ qclose (pindex (tRot tr) i) q | ((i, _, _), q) <- zip merged qa ]
                   .&&. continuous tr
    it "are dropped with DropDuplicates (the first of each time kept), counted" $
      property $ forAll genBase $ \ss -> forAll (choose (1, 5)) $ \k ->
        forAll (genIndices k 0 (length ss - 1) 1) $ \idx -> forAll (injectDuplicates idx ss) $ \dup ->
          case clean defaultCleanOptions { cleanDuplicates = DropDuplicates } dup of
            Left e -> counterexample (show e) False
            Right c -> strictlyIncreasing (clTrack c) .&&. countOf isDup c === k
                       .&&. ptoList (tPos (clTrack c)) === map smPos ss
                       .&&. U.toList (clLocs c) === [ smLoc s | (s, p) <- zip dup (Nothing : map Just dup), fmap smTime p /= Just (smTime s) ]
    it "the warning names the time and both lines" $ do
      let s t x = Sample 0 t (P3 x 0 0) (Q4 1 0 0 0)
          Right c = clean defaultCleanOptions (renumber [s 1 0, s 2 1, s 2 3, s 3 2])
          msg = concatMap (renderCleanWarning fileLocator) (clWarnings c)
      ptoList (tPos (clTrack c)) `shouldBe` [P3 0 0 0, P3 2 0 0, P3 2 0 0]
      msg `shouldSatisfy` ("t = 2.0 s at line 2, line 3" `isInfixOf`)
      msg `shouldSatisfy` ("1 sample merged" `isInfixOf`)

  describe "unsorted input" $ do
    it "is an error naming every sample that goes back in time (up to 5), with its time" $
      property $ forAll genBase $ \ss -> forAll (choose (1, 5)) $ \k ->
        forAll (genIndices k 0 (length ss - 2) 3) $ \idx ->
          let swapped = concat [ if i `elem` idx then [b, a] else if (i - 1) `elem` idx then [] else [a]
                               | (i, a, b) <- zip3 [0 ..] ss (drop 1 ss ++ [last ss]) ]
          in case clean defaultCleanOptions swapped of
               Right _ -> counterexample "accepted" False
               Left es -> counterexample (show es) $
                 length es === length idx
                 .&&. conjoin [ counterexample (renderFieldError e) $
                                  feField e === "time" .&&. ("at line " ++ show (smLoc a) ++ ":") `isInfixOf` renderFieldError e
                                  .&&. feValue e === Number (smTime a)
                              | (e, i) <- zip es idx, let a = ss !! i ]
    it "says how many more there are past the first five" $ do
      let ss = renumber [ Sample 0 t (P3 0 0 0) (Q4 1 0 0 0) | t <- [20, 19 .. 1] ]
          Left es = clean defaultCleanOptions ss
      length es `shouldBe` 6
      renderFieldError (last es) `shouldSatisfy` ("and 14 more" `isInfixOf`)

    it "a time more than 1e19 s from 0 is an error naming it and its line (a span of -1e308 to 1.7e308 s is infinite and the thesis method wrote NaN times; 1e300 s was written back as a 300-digit time); 1e19 s is taken" $ do
      let s t x = Sample 0 t (P3 x 0 0) (Q4 1 0 0 0)
      case clean defaultCleanOptions (renumber [s (-1e308) 0, s 0 1, s 1e308 2, s 1.7e308 3]) of
        Left es -> map renderFieldError es `shouldSatisfy` (\m -> length m == 3 && all ("is more than 1e19 s from 0, more than any clock counts in any unit (is the number right?)" `isInfixOf`) m)
        Right _ -> expectationFailure "times beyond 1e19 s were accepted"
      case clean defaultCleanOptions (renumber [s 0 0, s 1 1, s 1e300 2]) of
        Left [e] -> renderFieldError e `shouldSatisfy` ("time = 1.0e300 s" `isInfixOf`)
        other -> expectationFailure (show other)
      clean defaultCleanOptions (renumber [s (-1e19) 0, s 0 1, s 1e19 2]) `shouldSatisfy` either (const False) (const True)

  describe "quaternion sign flips" $
    it "are aligned (the cleaned track is continuous and equals the unflipped one), every negated sample and every sign change counted" $
      property $ forAll genBase $ \ss -> forAll (choose (1, 10)) $ \k ->
        forAll (genIndices k 1 (length ss - 1) 1) $ \idx ->
          let flipped = [ if i `elem` idx then s { smRot = qneg (smRot s) } else s | (i, s) <- zip [0 :: Int ..] ss ]
          in case clean defaultCleanOptions flipped of
               Left e -> counterexample (show e) False
               Right c -> continuous (clTrack c) .&&. countOf isFlip c === length (nub idx)
                          .&&. [ ch | SignFlips _ ch _ <- clWarnings c ]
                               === [ length [ i | i <- [1 .. length ss - 1], (i `elem` idx) /= ((i - 1) `elem` idx) ] ]
                          .&&. conjoin [ counterexample (show (a, b)) (abs (qdot a b - 1) < 1e-12)
                                       | (a, b) <- zip (ptoList (tRot (clTrack c))) (map smRot ss) ]
                          .&&. trackLength (clTrack c) === length ss

  describe "gaps" $ do
    it "are accepted and reported: how many, the largest and where" $
      property $ forAll genBase $ \ss -> forAll (choose (1, 4)) $ \k ->
        forAll (genIndices k 1 (length ss - 1) 1) $ \idx -> forAll (injectGaps idx ss) $ \(gapped, steps) ->
          case clean defaultCleanOptions gapped of
            Left e -> counterexample (show e) False
            Right c -> counterexample (show (clWarnings c)) $
              trackLength (clTrack c) === length ss .&&. countOf isGap c === k
              .&&. conjoin [ abs (d - maximum steps) < 1e-9 .&&. l === smLoc (gapped !! (idx !! j))
                           | Gaps _ _ _ (d, _, l) _ <- clWarnings c
                           , let Just j = lookup (maximum steps) (zip steps [0 ..]) ]

    it "shows a step as the times read give it, not as their subtraction rounds it (210.52 - 0.2 s is 210.32 s, not 210.32000000000002)" $ do
      let ss = [ Sample (i + 1) t (P3 0 0 0) (Q4 1 0 0 0) | (i, t) <- zip [0 ..] ([ k * 0.01 | k <- [0 .. 20] ] ++ [ 210.52 + k * 0.01 | k <- [0 .. 20] ]) ]
          Right c = clean defaultCleanOptions ss
          msg = concatMap (renderCleanWarning fileLocator) (clWarnings c)
      msg `shouldSatisfy` ("the largest 210.32 s before t = 210.52 s at line 22" `isInfixOf`)

    it "shows a step between large times to the digits the times hold (TUM's 1305031108.9458 - 1305031108.8357 s is 0.1101 s, not 0.110100030899 s)" $ do
      -- as a TUM file writes them: 1305031108.7357, .7457, ..., .8357, then .9458, .9558, ...
      let ts = [ read ("1305031108." ++ show k) | k <- [7357, 7457 .. 8357 :: Int] ++ [9458, 9558 .. 9958] ] :: [Double]
          ss = [ Sample (i + 1) t (P3 0 0 0) (Q4 1 0 0 0) | (i, t) <- zip [0 ..] ts ]
          Right c = clean defaultCleanOptions ss
          msg = concatMap (renderCleanWarning fileLocator) (clWarnings c)
      msg `shouldSatisfy` ("times the median 0.01 s) accepted; the largest 0.1101 s before t = 1305031108.9458 s" `isInfixOf`)

    it "shows the largest gap as its times' decimals give it, at any time up to 1e9 s (times of 4 decimals)" $
      property $ forAll (elements [0, 1, 1e3, 1e6, 3e8, 1e9 :: Double]) $ \base -> forAll (choose (0, 99999 :: Int)) $ \off ->
        forAll (choose (1, 1000 :: Int)) $ \h -> forAll (choose (30, 99999 :: Int)) $ \g ->
          let t0 = base + fromIntegral off * 1e-4
              -- times as a file gives them: decimals with 4 places, read
              at :: Int -> Double
              at k = read (showFFloat (Just 4) (t0 + fromIntegral k * 1e-4) "")
              ticks = [ k * h | k <- [0 .. 20] ] ++ [ 20 * h + max (20 * h) g + k * h | k <- [0 .. 20] ]
              ss = [ Sample (i + 1) (at k) (P3 0 0 0) (Q4 1 0 0 0) | (i, k) <- zip [0 ..] ticks ]
              gap = fromIntegral (max (20 * h) g) * 1e-4 :: Double
              shown = "the largest " ++ showNumber (read (showFFloat (Just 4) gap "") :: Double) ++ " s before"
          in case clean defaultCleanOptions ss of
               Left e -> counterexample (show e) False
               Right c -> let msg = concatMap (renderCleanWarning fileLocator) (clWarnings c)
                          in counterexample msg (shown `isInfixOf` msg)

  describe "times in another unit than seconds" $ do
    it "times in ms, us or ns read as seconds are kept as read, with a warning giving the median step, when it is at least 1e4 s" $
      property $ forAll genBase $ \ss -> forAll (elements [1e3, 1e6, 1e9]) $ \scale ->
        let scaled = [ s { smTime = smTime s * scale } | s <- ss ]
            steps = sort (zipWith (-) (map smTime (drop 1 scaled)) (map smTime scaled))
            med = let n = length steps in if odd n then steps !! (n `div` 2) else (steps !! (n `div` 2 - 1) + steps !! (n `div` 2)) / 2
        in case clean defaultCleanOptions scaled of
             Left e -> counterexample (show e) False
             Right c -> counterexample (show (clWarnings c)) $
               trackLength (clTrack c) === length ss
               .&&. [ (m, n) | LongMedianStep m n <- clWarnings c ] === [ (med, length ss) | med >= longMedianStep ]
    it "real recordings in seconds (freiburg1_xyz, V1_01) get no such warning" $
      forM_ ["freiburg1_xyz-groundtruth.txt", "V101_gt.txt"] $ \f -> do
        Recording tr <- loadTum f
        let ss = [ Sample i t p q | (i, t, p, q) <- zip4 [1 ..] (U.toList (tTime tr)) (ptoList (tPos tr)) (ptoList (tRot tr)) ]
        fmap (filter isLong . clWarnings) (clean defaultCleanOptions ss) `shouldBe` Right []
    it "steps of up to an hour get no such warning" $
      property $ forAll genBase $ \ss -> forAll (choose (1, 3600)) $ \dt ->
        let slow = [ s { smTime = fromIntegral i * dt } | (i, s) <- zip [0 :: Int ..] ss ]
        in fmap (filter isLong . clWarnings) (clean defaultCleanOptions slow) === Right []

  describe "outliers" $ do
    let spike ss idx = do
          ds <- vectorOf (length idx) (P3 <$> choose (1, 2) <*> choose (-1, 1) <*> choose (-1, 1))
          pure [ maybe s (\d -> s { smPos = smPos s ^+^ d }) (lookup i (zip idx ds)) | (i, s) <- zip [0 :: Int ..] ss ]
    it "are kept by default (no sample dropped, no outlier warning)" $
      property $ forAll genBase $ \ss -> forAll (choose (1, 4)) $ \k ->
        forAll (genIndices k 2 (length ss - 3) 4) $ \idx -> forAll (spike ss idx) $ \sp ->
          case clean defaultCleanOptions sp of
            Left e -> counterexample (show e) False
            Right c -> trackLength (clTrack c) === length ss .&&. countOf isOutlier c === 0
    it "with rejection, exactly the injected spikes are removed and reported with their lines" $
      property $ forAll genBase $ \ss -> forAll (choose (1, 4)) $ \k ->
        forAll (genIndices k 2 (length ss - 3) 4) $ \idx -> forAll (spike ss idx) $ \sp ->
          case clean defaultCleanOptions { cleanRejectOutliers = Just defaultOutlierFactor } sp of
            Left e -> counterexample (show e) False
            Right c -> counterexample (show (clWarnings c)) $
              countOf isOutlier c === length idx
              .&&. trackLength (clTrack c) + countOf isOutlier c === length ss
              .&&. U.toList (clLocs c) === [ smLoc s | (i, s) <- zip [0 ..] ss, i `notElem` idx ]
              .&&. conjoin [ sort (map snd xs) === map (smLoc . (ss !!)) idx | OutliersRejected _ _ xs <- clWarnings c, k <= 5 ]
    it "with rejection, a run of one or two spiked samples anywhere, the first and last sample included, is removed exactly (a two-sample spike used to cost its good neighbours, an end spike was kept)" $
      property $ forAll genBase $ \ss -> forAll (choose (1, maxRun)) $ \len -> forAll (choose (0, length ss - len)) $ \i0 ->
        forAll (P3 <$> choose (1, 2) <*> choose (-1, 1) <*> choose (-1, 1)) $ \d ->
          let idx = [i0 .. i0 + len - 1]
              sp = [ if i `elem` idx then s { smPos = smPos s ^+^ d } else s | (i, s) <- zip [0 :: Int ..] ss ]
          in case clean defaultCleanOptions { cleanRejectOutliers = Just defaultOutlierFactor } sp of
               Left e -> counterexample (show e) False
               Right c -> counterexample (show (clWarnings c)) $
                 U.toList (clLocs c) === [ smLoc s | (i, s) <- zip [0 ..] ss, i `notElem` idx ]
    it "with rejection, a recording of 2 to 6 samples is kept whole, spiked or not, and a warning says none was judged; from 7 samples on, no such warning (was silent)" $
      property $ forAll genBase $ \ss0 -> forAll (choose (2, 12)) $ \n -> forAll (choose (0, n - 1)) $ \i ->
        forAll (P3 <$> choose (1, 2) <*> choose (-1, 1) <*> choose (-1, 1)) $ \d ->
          let ss = [ if j == i then s { smPos = smPos s ^+^ d } else s | (j, s) <- zip [0 :: Int ..] (take n ss0) ]
          in case clean defaultCleanOptions { cleanRejectOutliers = Just defaultOutlierFactor } ss of
               Left e -> counterexample (show e) False
               Right c -> counterexample (show (clWarnings c)) $
                 if n < 7 then trackLength (clTrack c) === n .&&. [ m | OutliersNotJudged m <- clWarnings c ] === [n]
                 else [ m | OutliersNotJudged m <- clWarnings c ] === []
    it "with rejection, a clean recording loses nothing" $
      property $ forAll genBase $ \ss ->
        case clean defaultCleanOptions { cleanRejectOutliers = Just defaultOutlierFactor } ss of
          Left e -> counterexample (show e) False
          Right c -> trackLength (clTrack c) === length ss .&&. clWarnings c === []

  describe "samples without a pose (tracking lost)" $
    it "are dropped: the result is the recording cleaned without them, each counted and located" $
      property $ forAll genBase $ \ss -> forAll (sublistOf [0 .. length ss - 1]) $ \idx0 ->
        forAll (vectorOf (length idx0) (choose (0 :: Int, 8))) $ \kinds ->
          let idx = take (length ss - 2) idx0
              lose k x = case k of   -- one NaN component, all of them, or a zero quaternion
                7 -> x { smPos = P3 (0 / 0) (0 / 0) (0 / 0), smRot = Q4 (0 / 0) (0 / 0) (0 / 0) (0 / 0) }
                8 -> x { smRot = Q4 0 0 0 0 }
                _ -> let P3 a b c = smPos x; Q4 w i j l = smRot x
                         v = [a, b, c, w, i, j, l]
                         [a', b', c', w', i', j', l'] = [ if m == k then 0 / 0 else e | (m, e) <- zip [0 ..] v ]
                     in x { smPos = P3 a' b' c', smRot = Q4 w' i' j' l' }
              dirty = [ maybe x (`lose` x) (lookup i (zip idx kinds)) | (i, x) <- zip [0 ..] ss ]
              kept = [ x | (i, x) <- zip [0 ..] ss, i `notElem` idx ]
          in case (clean defaultCleanOptions dirty, clean defaultCleanOptions kept) of
               (Right c, Right c0) -> counterexample (show (clWarnings c)) $
                 clTrack c === clTrack c0 .&&. clLocs c === clLocs c0
                 .&&. [ (n, xs) | MissingPoses n xs <- clWarnings c ]
                      === [ (length idx, take 5 [ (smTime x, smLoc x) | (i, x) <- zip [0 ..] ss, i `elem` idx ]) | not (null idx) ]
                 .&&. filter (not . isMissing) (clWarnings c) === clWarnings c0
               r -> counterexample (show r) False
  it "everything at once (duplicates, flips, gaps): strictly increasing, continuous, every removed sample counted" $
    property $ forAll genBase $ \ss -> forAll ((,,) <$> choose (0, 4) <*> choose (0, 6) <*> choose (0, 3)) $ \(kd, kf, kg) ->
      forAll (genIndices kg 1 (length ss - 1) 1) $ \gi -> forAll (injectGaps gi ss) $ \(gapped, _) ->
      forAll (genIndices kf 1 (length ss - 1) 2) $ \fi ->
      forAll (genIndices kd 0 (length ss - 1) 3) $ \di ->
        let flipped = [ if i `elem` fi then s { smRot = qneg (smRot s) } else s | (i, s) <- zip [0 :: Int ..] gapped ]
        in forAll (injectDuplicates di flipped) $ \dirty ->
          case clean defaultCleanOptions dirty of
            Left e -> counterexample (show e) False
            Right c -> counterexample (show (clWarnings c)) $
              strictlyIncreasing (clTrack c) .&&. continuous (clTrack c)
              .&&. trackLength (clTrack c) + countOf isDup c === length dirty
              .&&. countOf isDup c === length di .&&. countOf isGap c === length gi
              .&&. property (null fi || countOf isFlip c >= 1)

  describe "values" $ do
    let s t q = Sample 0 t (P3 t 0 0) q
    it "normalises non-unit quaternions, with a warning naming the line and the norm" $ do
      let Right c = clean defaultCleanOptions (renumber [s 0 (Q4 1 0 0 0), s 1 (Q4 2 0 0 0), s 2 (Q4 0.9995 0 0 0)])
      countOf isNonUnit c `shouldBe` 1
      pindex (tRot (clTrack c)) 1 `shouldBe` Q4 1 0 0 0
      pindex (tRot (clTrack c)) 2 `shouldBe` Q4 1 0 0 0
      concatMap (renderCleanWarning fileLocator) (clWarnings c) `shouldSatisfy` ("line 2: norm 2.0" `isInfixOf`)
    it "refuses a time that is not finite and infinite values, naming the line" $ do
      let bad = [ [s 0 (Q4 1 0 0 0), s (0 / 0) (Q4 1 0 0 0)]
                , [s 0 (Q4 1 0 0 0), s (1 / 0) (Q4 1 0 0 0)]
                , [s 0 (Q4 1 0 0 0), (s 1 (Q4 1 0 0 0)) { smPos = P3 (1 / 0) 0 0 }]
                , [s 0 (Q4 1 0 0 0), s 1 (Q4 (-1 / 0) 0 0 0)]
                , [s 0 (Q4 1 0 0 0), (s 1 (Q4 (1 / 0) 0 0 0)) { smPos = P3 (0 / 0) 0 0 }] ]
      mapM_ (\ss -> case clean defaultCleanOptions (renumber ss) of
                      Left [e] -> renderFieldError e `shouldSatisfy` ("at line 2" `isInfixOf`)
                      r -> expectationFailure (show r)) bad
    it "drops samples without a pose (tracking lost: a NaN component, a zero quaternion), with a warning naming time and line" $ do
      let ss = renumber [s 0 (Q4 1 0 0 0), (s 1 (Q4 1 0 0 0)) { smPos = P3 (0 / 0) 0 0 }, s 2 (Q4 0 0 0 0), s 3 (Q4 1 0 0 0)]
          Right c = clean defaultCleanOptions ss
      U.toList (tTime (clTrack c)) `shouldBe` [0, 3]
      U.toList (clLocs c) `shouldBe` [1, 4]
      [ (n, xs) | MissingPoses n xs <- clWarnings c ] `shouldBe` [(2, [(1, 2), (2, 3)])]
      concatMap (renderCleanWarning fileLocator) (clWarnings c)
        `shouldSatisfy` ("2 samples without a pose" `isInfixOf`)
      concatMap (renderCleanWarning fileLocator) (clWarnings c)
        `shouldSatisfy` ("t = 1.0 s at line 2; t = 2.0 s at line 3" `isInfixOf`)
      -- a recording the tracker never saw: an error, not an empty path
      let Left [e] = clean defaultCleanOptions (renumber [s 0 (Q4 0 0 0 0), s 1 (Q4 (0 / 0) 0 0 0), s 2 (Q4 1 0 0 0)])
      renderFieldError e `shouldSatisfy` ("1 sample with distinct times after cleaning (of 3 read)" `isInfixOf`)
    it "a quaternion of huge components is the rotation it points to (1e200 squared overflowed: the zero quaternion was written); one of norm below 1e-6 is no pose" $ do
      let Right c = clean defaultCleanOptions (renumber [s 0 (Q4 1 0 0 0), s 1 (Q4 0 1e200 0 0), s 2 (Q4 0 1e-150 1e-150 0), s 3 (Q4 1e308 1e308 0 0)])
          qs = ptoList (tRot (clTrack c))
      map (\(Q4 w a b c') -> map (\x -> fromIntegral (round (x * 1e6) :: Integer) / 1e6 :: Double) [w, a, b, c']) qs
        `shouldBe` [[1, 0, 0, 0], [0, 1, 0, 0], [0.707107, 0.707107, 0, 0]]
      [ n | MissingPoses n _ <- clWarnings c ] `shouldBe` [1]
    it "refuses a position more than 1e9 m from the origin, naming the line (1e300 m gave infinite errors)" $ do
      let Left [e] = clean defaultCleanOptions (renumber [s 0 (Q4 1 0 0 0), (s 1 (Q4 1 0 0 0)) { smPos = P3 0 (-2e9) 0 }, s 2 (Q4 1 0 0 0)])
      renderFieldError e `shouldSatisfy` ("at line 2" `isInfixOf`)
      isRight (clean defaultCleanOptions (renumber [s 0 (Q4 1 0 0 0), (s 1 (Q4 1 0 0 0)) { smPos = P3 6.4e6 5.3e6 0 }])) `shouldBe` True
    it "a recording whose every pose is missing says so in its error" $ do
      let Left [e] = clean defaultCleanOptions (renumber [s 0 (Q4 0 0 0 0), s 1 (Q4 0 0 0 0)])
      renderFieldError e `shouldSatisfy` ("2 samples without a pose" `isInfixOf`)
    it "refuses an empty recording and one of fewer than 2 distinct times" $ do
      clean defaultCleanOptions [] `shouldSatisfy` isLeft
      clean defaultCleanOptions [s 0 (Q4 1 0 0 0)] `shouldSatisfy` isLeft
      let Left [e] = clean defaultCleanOptions (renumber [s 1 (Q4 1 0 0 0), s 1 (Q4 1 0 0 0)])
      renderFieldError e `shouldSatisfy` ("1 sample with distinct times after cleaning (of 2 read)" `isInfixOf`)
  modifyMaxSuccess (const 20) $ it "compress keeps a recording with sign flips continuous even uncleaned (preparation aligns)" $
    property $ forAll genBase $ \ss -> forAll (genIndices 5 1 (length ss - 1) 1) $ \idx ->
      let flipped = [ if i `elem` idx then qneg (smRot x) else smRot x | (i, x) <- zip [0 :: Int ..] ss ]
          Right rec = recordingFromArrays (U.fromList (map smTime ss)) (pfromList (map smPos ss)) (pfromList flipped)
      in case compress defaultSettings { sPoints = Just 5 } rec of
           Left e -> counterexample (show e) False
           Right o -> property (continuous (pathTrack (oPath o)))
