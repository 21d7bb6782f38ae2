-- | Cleaning a real recording before compression: what motion capture delivers is not
-- always a clean, strictly increasing series of unit quaternions. Pure; the formats only
-- parse (into 'Sample's with the line or index they came from) and every interface runs
-- the same rules:
--
-- * a time that is not a finite number, an infinite position or quaternion component, or
--   a position more than 'maxCoordinate' from the origin: an error naming the sample;
-- * a sample without a pose (a position or quaternion component NaN, which the formats
--   read from an empty or @nan@ field, or a quaternion of norm below 1e-6): what motion
--   capture writes while the tracker has lost the body; dropped, with a warning that says
--   how many and where (the hole it leaves is a gap like any other);
-- * a time before the previous one (unsorted input): an error naming the sample and both
--   times; nothing is sorted behind the user's back;
-- * a quaternion whose norm differs from 1 by more than 1e-3: normalised, with a warning
--   (smaller deviations, such as four printed decimals, are normalised silently);
-- * samples sharing a time: merged into one by default (positions averaged, quaternions
--   sign-aligned to the first of the group, averaged and normalised) or, with
--   'DropDuplicates', only the first kept; a warning says how many and where;
-- * q and −q are the same orientation: the cleaned track is sign-aligned so that
--   consecutive quaternions have a non-negative dot product (a note counts the flips);
-- * optionally ('cleanRejectOutliers'), position spikes are removed: see
--   'rejectOutliers'; a warning says how many and where, or that a recording too short for
--   the robust line was not judged;
-- * fewer than 2 samples left: an error;
-- * a time step more than 'cleanGapFactor' times the median step: accepted, with a warning
--   (how many, the largest and where).
--
-- Every sample of the input is either kept, dropped for want of a pose, merged into another
-- sample of the same time, dropped as a duplicate or rejected as an outlier, and each of
-- those is counted in a warning: nothing is dropped silently.
module VProf.Compress.Clean
  ( Sample (..)
  , Duplicates (..)
  , CleanOptions (..)
  , defaultCleanOptions
  , defaultOutlierFactor
  , CleanWarning (..)
  , Cleaned (..)
  , Locator (..)
  , fileLocator
  , indexLocator
  , cleanSamples
  , warningCount
  , longMedianStep
  , renderCleanWarning
  , unitTolerance
  , nonUnitWarning
  ) where

import Data.List (partition, sort, sortOn)
import qualified Data.Vector as V
import qualified Data.Vector.Unboxed as U

import VProf.Compress.Types
import VProf.Geometry.Quaternion (qdot, qneg)
import VProf.Geometry.Vec
import VProf.Validation

-- | One parsed sample: where it came from (a line number of a file, an index of a wire
-- message; see 'Locator'), time (s), position (m), quaternion (w, x, y, z) as read.
data Sample = Sample
  { smLoc  :: !Int
  , smTime :: !Double
  , smPos  :: !P3
  , smRot  :: !Q4
  } deriving (Show, Eq)

-- | What to do with samples that share a time.
data Duplicates = MergeDuplicates | DropDuplicates deriving (Show, Eq)

data CleanOptions = CleanOptions
  { cleanDuplicates     :: !Duplicates
  , cleanRejectOutliers :: !(Maybe Double)  -- ^ the factor k of 'rejectOutliers'; Nothing: keep every sample
  , cleanGapFactor      :: !Double          -- ^ a step longer than this times the median step is a gap
  } deriving (Show, Eq)

-- | The factor k of 'rejectOutliers' when none is given.
defaultOutlierFactor :: Double
defaultOutlierFactor = 5

-- | Merge duplicates, keep outliers, gaps beyond 10 median steps.
defaultCleanOptions :: CleanOptions
defaultCleanOptions = CleanOptions MergeDuplicates Nothing 10

-- | What cleaning changed (or noticed). Locations are 'smLoc's; lists hold the first few.
data CleanWarning
  = MissingPoses !Int [(Double, Int)]
    -- ^ samples without a pose (tracking lost) dropped; (time, where) of the first few
  | NonUnitQuaternions !Int [(Int, Double)]
    -- ^ how many quaternions were normalised; (where, norm) of the first few
  | DuplicateTimes !Duplicates !Int !Int [(Double, [Int])]
    -- ^ merged or dropped; samples removed (merged into another or dropped); times that
    -- had more than one sample; (time, where) of the first few
  | SignFlips !Int !Int [Int]
    -- ^ quaternions negated to keep the track continuous; sign changes in the input
    -- (consecutive samples with a negative dot product); where they are, first few
  | OutliersRejected !Double !Int [(Double, Int)]
    -- ^ factor k; samples removed; (time, where) of the first few
  | OutliersNotJudged !Int
    -- ^ rejection asked for, but the recording has fewer samples than the robust line needs
    -- ('outlierWindow'): how many it has
  | Gaps !Double !Double !Int (Double, Double, Int) [(Double, Int)]
    -- ^ factor, median step (s), how many, (largest step, time after it, where), (step,
    -- where) of the first few
  | LongMedianStep !Double !Int
    -- ^ the median time step (s), at least 'longMedianStep', and the samples: times
    -- written in ms, µs or ns but read as seconds
  deriving (Show, Eq)

-- | The cleaned recording, its warnings, and where each kept sample came from (the first
-- sample of a merged group).
data Cleaned = Cleaned
  { clTrack    :: !Track
  , clWarnings :: ![CleanWarning]
  , clLocs     :: !(U.Vector Int)
  } deriving (Show, Eq)

-- | How an interface names a sample and the fields of the recording: a file by its line,
-- a wire message by its index.
data Locator = Locator
  { lcField :: String -> String  -- ^ "time", "position", "orientation" or "" (the recording)
  , lcAt    :: Int -> String
  }

-- | Samples by line number (from 1); fields by their plain name.
fileLocator :: Locator
fileLocator = Locator (\f -> if null f then "recording" else f) (\l -> "line " ++ show l)

-- | Samples by index (from 0) in a field named with the given prefix, e.g. @recording@.
indexLocator :: String -> Locator
indexLocator pre = Locator (\f -> if null f then pre else pre ++ "." ++ f) (\i -> "sample " ++ show i)

-- | Norms within this of 1 are normalised without a warning.
unitTolerance :: Double
unitTolerance = 1e-3

-- | How many samples (or quaternions) a warning is about.
warningCount :: CleanWarning -> Int
warningCount = \case
  MissingPoses n _ -> n
  NonUnitQuaternions n _ -> n
  DuplicateTimes _ n _ _ -> n
  SignFlips n _ _ -> n
  OutliersRejected _ n _ -> n
  OutliersNotJudged n -> n
  Gaps _ _ n _ _ -> n
  LongMedianStep _ n -> n

firstFew :: Int
firstFew = 5

-- | Clean a recording: every error at once (up to a few of each kind), or the track
-- with its warnings.
cleanSamples :: Locator -> CleanOptions -> [Sample] -> Either [FieldError] Cleaned
cleanSamples loc opts raw
  | null raw = Left [literalError (lcField loc "") "" "has no samples (an empty file, or only comments and blank lines)"]
  | not (null badValues) = Left badValues
  | not (null backwards) = Left backwards
  | otherwise = do
      let (present, missing) = partition hasPose raw
          (normed, nonUnit) = normalise present
          groups = groupTimes normed
          merged = map (collapse (cleanDuplicates opts)) groups
          (aligned, flips) = alignSigns merged
          changes = [ smLoc b | (a, b) <- zip merged (drop 1 merged), qdot (smRot a) (smRot b) < 0 ]
          (kept, outliers) = case cleanRejectOutliers opts of
            Just k -> rejectOutliers k aligned
            Nothing -> (aligned, [])
          dupGroups = [ g | g <- groups, length g > 1 ]
          nDup = sum [ length g - 1 | g <- dupGroups ]
          warnings = concat
            [ [ MissingPoses (length missing) (take firstFew [ (smTime m, smLoc m) | m <- missing ]) | not (null missing) ]
            , [ NonUnitQuaternions (length nonUnit) (take firstFew nonUnit) | not (null nonUnit) ]
            , [ DuplicateTimes (cleanDuplicates opts) nDup (length dupGroups)
                  (take firstFew [ (smTime (head g), map smLoc g) | g <- dupGroups ]) | nDup > 0 ]
            , [ SignFlips (length flips) (length changes) (take firstFew changes) | not (null flips) ]
            , case cleanRejectOutliers opts of
                Just k | not (null outliers) ->
                  [OutliersRejected k (length outliers) (take firstFew [ (smTime s, smLoc s) | s <- outliers ])]
                Just _ | length aligned < outlierWindow -> [OutliersNotJudged (length aligned)]
                _ -> []
            , gapWarning (cleanGapFactor opts) kept
            , [ LongMedianStep m (length kept) | length kept >= 2
                                              , let m = median (zipWith (-) (map smTime (drop 1 kept)) (map smTime kept))
                                              , m >= longMedianStep ]
            ]
      if length kept < 2
        then Left [literalError (lcField loc "") ""
                     ("has " ++ show (length kept) ++ " sample" ++ (if length kept == 1 then "" else "s")
                      ++ " with distinct times" ++ (if length raw > length kept then " after cleaning (of " ++ show (length raw) ++ " read)" else "")
                      ++ "; at least 2 are needed"
                      ++ concat [ ": " ++ renderCleanWarning loc w | w@(MissingPoses _ _) <- warnings ])]
        else Right (Cleaned (Track (U.fromList (map smTime kept)) (pfromList (map smPos kept)) (pfromList (map smRot kept)))
                            warnings (U.fromList (map smLoc kept)))
  where
    capped es = case splitAt firstFew es of
      (a, []) -> a
      (a, rest) -> a ++ [literalError (lcField loc "") "" ("and " ++ show (length rest) ++ " more such problems")]
    badValues = capped (concatMap checkValues raw)
    -- NaN is a missing value ('hasPose'); an infinity is no marker of anything
    checkValues (Sample l t (P3 x y z) (Q4 w a b c))
      | not (finite t) = [fieldError (lcField loc "time") t "s" ("at " ++ lcAt loc l ++ ": must be a finite number")]
      -- (so every span between times is finite too: -1e308 to 1.7e308 s is not, and the
      -- thesis method's waypoint times became NaN)
      | abs t > maxTime = [fieldError (lcField loc "time") t "s" ("at " ++ lcAt loc l ++ ": " ++ tooLateRule)]
      | any isInfinite [x, y, z] =
          [literalError (lcField loc "position") (show (x, y, z)) ("at " ++ lcAt loc l ++ ": must be finite numbers (m)")]
      | any isInfinite [w, a, b, c] =
          [literalError (lcField loc "orientation") (show (w, a, b, c)) ("at " ++ lcAt loc l ++ ": must be finite numbers (w, x, y, z)")]
      | any ((> maxCoordinate) . abs) [x, y, z] =
          [literalError (lcField loc "position") (show (x, y, z))
             ("at " ++ lcAt loc l ++ ": more than " ++ showBound maxCoordinate ++ " m from the origin, beyond any place a robot or a vehicle records (is the unit right?)")]
      | otherwise = []
    backwards = capped
      [ fieldError (lcField loc "time") (smTime s) "s"
          ("at " ++ lcAt loc (smLoc s) ++ ": goes back before the previous time " ++ showNumber (smTime p)
           ++ " s at " ++ lcAt loc (smLoc p) ++ " (times must never decrease; sort the recording first)")
      | (p, s) <- zip raw (drop 1 raw), smTime s < smTime p ]

-- | Whether a sample has a pose: no position or quaternion component NaN, and a quaternion
-- of norm at least 1e-6 (a zero quaternion is what some trackers write when they lose the
-- body). Infinite components are refused before this is asked.
hasPose :: Sample -> Bool
hasPose (Sample _ _ (P3 x y z) q@(Q4 w a b c)) = not (any isNaN [x, y, z, w, a, b, c]) && qnorm q >= 1e-6

-- | The norm of a quaternion without overflow or underflow: scaled by its largest
-- component first (1e200 squared is infinity, and a quaternion of such components is as
-- good a rotation as any).
qnorm :: Q4 -> Double
qnorm (Q4 w a b c) =
  let m = maximum (map abs [w, a, b, c])
  in if m == 0 || isInfinite m then m else m * sqrt ((w / m) ^ (2 :: Int) + (a / m) ^ (2 :: Int) + (b / m) ^ (2 :: Int) + (c / m) ^ (2 :: Int))

-- | Normalise every quaternion; (where, norm) of those off unit length by more than
-- 'unitTolerance'.
normalise :: [Sample] -> ([Sample], [(Int, Double)])
normalise ss = (map fst r, [ w | (_, Just w) <- r ])
  where
    r = map one ss
    one s = let q@(Q4 w a b c) = smRot s
                n = qnorm q
            in ( s { smRot = Q4 (w / n) (a / n) (b / n) (c / n) }
               , if abs (n - 1) > unitTolerance then Just (smLoc s, n) else Nothing )

-- | The warning 'cleanSamples' gives for quaternions off unit length by more than
-- 'unitTolerance', if any: for readers of poses that are not recordings (a path to plan).
nonUnitWarning :: [Sample] -> Maybe CleanWarning
nonUnitWarning ss = case snd (normalise ss) of
  [] -> Nothing
  xs -> Just (NonUnitQuaternions (length xs) (take firstFew xs))

-- | Runs of samples with the same time (the input is sorted).
groupTimes :: [Sample] -> [[Sample]]
groupTimes [] = []
groupTimes (s : rest) = let (same, others) = span ((== smTime s) . smTime) rest in (s : same) : groupTimes others

-- | One sample for a group of samples with the same time.
collapse :: Duplicates -> [Sample] -> Sample
collapse _ [s] = s
collapse DropDuplicates (s : _) = s
collapse MergeDuplicates g@(s : _) = s { smPos = meanP, smRot = Q4 (w / n) (a / n) (b / n) (c / n) }
  where
    k = fromIntegral (length g)
    meanP = foldr1 (^+^) (map smPos g) ^/ k
    q0 = smRot s
    qs = [ if qdot q0 q < 0 then qneg q else q | q <- map smRot g ]
    Q4 w a b c = foldr1 (\(Q4 a1 b1 c1 d1) (Q4 a2 b2 c2 d2) -> Q4 (a1 + a2) (b1 + b2) (c1 + c2) (d1 + d2)) qs
    n = sqrt (w * w + a * a + b * b + c * c)
collapse _ [] = error "collapse: empty group"

-- | Negate every quaternion whose dot product with the previous (already aligned) one is
-- negative; where it happened.
alignSigns :: [Sample] -> ([Sample], [Int])
alignSigns [] = ([], [])
alignSigns (s0 : rest) = go (smRot s0) rest [s0] []
  where
    go _ [] acc fl = (reverse acc, reverse fl)
    go prev (s : ss) acc fl
      | qdot prev (smRot s) < 0 = let s' = s { smRot = qneg (smRot s) } in go (smRot s') ss (s' : acc) (smLoc s : fl)
      | otherwise = go (smRot s) ss (s : acc) fl

-- | The samples the robust line of 'rejectOutliers' is fitted through (i−3 … i+3): a
-- recording with fewer is not judged.
outlierWindow :: Int
outlierWindow = 7

-- | Position spikes, removed. Each sample i is compared with a robust line in time through
-- the seven samples around it (i−3 … i+3, shifted inward at the ends of the recording so that
-- it stays seven wide): per coordinate the repeated-median line (Siegel 1982: the slope the
-- median over j of the median over l ≠ j of the slopes between samples j and l, the intercept
-- the median of what is left), which a few spiked samples among the seven do not move. The
-- residual r_i is the distance from that line at t_i; the sample is rejected when
--
-- > r_i > k · max(median step, median r + 1.4826 · MAD r)
--
-- A corner of the motion leaves a residual of a few steps, sensor noise one of about its
-- robust spread (the median absolute deviation scaled to a standard deviation); a spike of k
-- times both is not motion. Spikes of one or two samples, the first and last samples
-- included, are removed exactly (tested); three in a row can cost a good neighbour. (The line
-- through the neighbours that an earlier rule used rejected a two-sample spike's good
-- neighbours instead of it, and never judged the ends.) A recording of fewer than 7 samples
-- is left alone. Passes repeat (at most 10) until none is rejected.
rejectOutliers :: Double -> [Sample] -> ([Sample], [Sample])
rejectOutliers k ss0 = go (10 :: Int) ss0 []
  where
    go 0 ss out = (ss, sortOn smTime out)
    go m ss out =
      let v = V.fromList ss
          bad = spikes v
      in if null bad then (ss, sortOn smTime out)
         else go (m - 1) [ s | (i, s) <- zip [0 ..] ss, i `notElem` bad ] (map (v V.!) bad ++ out)
    spikes v
      | n < outlierWindow = []
      | otherwise = [ i | i <- [0 .. n - 1], r U.! i > k * max sigma medStep ]
      where
        n = V.length v
        t i = smTime (v V.! i)
        p i = smPos (v V.! i)
        r = U.generate n $ \i ->
          let lo = max 0 (min (n - 7) (i - 3))
              js = [lo .. lo + 6]
              fit f = let tc = t i   -- times relative to t_i, for the intercept's precision
                          pts = [ (t j - tc, f (p j)) | j <- js ]
                          slope = median [ median [ (yb - ya) / (xb - xa) | (b, (xb, yb)) <- zip [0 :: Int ..] pts, b /= a ]
                                         | (a, (xa, ya)) <- zip [0 ..] pts ]
                      in median [ y - slope * x | (x, y) <- pts ]
          in distance (p i) (P3 (fit (\(P3 a _ _) -> a)) (fit (\(P3 _ b _) -> b)) (fit (\(P3 _ _ c) -> c)))
        rs = U.toList r
        medR = median rs
        sigma = medR + 1.4826 * median [ abs (x - medR) | x <- rs ]
        medStep = median [ distance (p j) (p (j - 1)) | j <- [1 .. n - 1] ]

median :: [Double] -> Double
median [] = 0
median xs = let ys = sort xs; n = length ys
            in if odd n then ys !! (n `div` 2) else (ys !! (n `div` 2 - 1) + ys !! (n `div` 2)) / 2

-- | A median time step (s) at which the times are most likely not seconds: 10⁴ s, almost
-- three hours between samples (a recording at 100 Hz written in µs has 10⁴, in ns 10⁷).
longMedianStep :: Double
longMedianStep = 1e4

-- | Steps longer than the factor times the median step.
gapWarning :: Double -> [Sample] -> [CleanWarning]
gapWarning f ss
  | length ss < 3 || null gaps = []
  | otherwise = [Gaps f med (length gaps) largest (take firstFew [ (d, l) | (d, _, l) <- gaps ])]
  where
    steps = [ (smTime b - smTime a, smTime b, smLoc b) | (a, b) <- zip ss (drop 1 ss) ]
    med = median [ d | (d, _, _) <- steps ]
    gaps = [ g | g@(d, _, _) <- steps, d > f * med ]
    largest = foldr1 (\x@(d, _, _) y@(e, _, _) -> if d >= e then x else y) gaps

-- | One line of text for a warning.
renderCleanWarning :: Locator -> CleanWarning -> String
renderCleanWarning loc = \case
  MissingPoses n xs ->
    show n ++ " sample" ++ plural n ++ " without a pose (a position or orientation value empty or NaN, or a zero quaternion: "
    ++ "the tracker lost the body) dropped (" ++ list [ "t = " ++ showNumber t ++ " s at " ++ lcAt loc l | (t, l) <- xs ] n ++ ")"
  NonUnitQuaternions n xs ->
    show n ++ " quaternion" ++ plural n ++ " of norm off 1 by more than " ++ showNumber unitTolerance
    ++ " normalised (" ++ list [ lcAt loc l ++ ": norm " ++ showNumber nm | (l, nm) <- xs ] n ++ ")"
  DuplicateTimes act n g xs ->
    show g ++ " time" ++ plural g ++ " with more than one sample: " ++ show n ++ " sample" ++ plural n ++ " "
    ++ (case act of MergeDuplicates -> "merged into the first of the same time (poses averaged)"
                    DropDuplicates -> "dropped (the first of each time kept)")
    ++ " (" ++ list [ "t = " ++ showNumber t ++ " s at " ++ joinWith ", " (map (lcAt loc) ls) | (t, ls) <- xs ] g ++ ")"
  SignFlips n c xs ->
    show c ++ " quaternion sign change" ++ plural c ++ " (q and -q are the same orientation) at "
    ++ list (map (lcAt loc) xs) c ++ "; " ++ show n ++ " quaternion" ++ plural n ++ " negated to keep the track continuous"
  OutliersRejected k n xs ->
    show n ++ " outlier" ++ plural n ++ " rejected (position spike above " ++ showNumber k ++ " times the local step) ("
    ++ list [ "t = " ++ showNumber t ++ " s at " ++ lcAt loc l | (t, l) <- xs ] n ++ ")"
  OutliersNotJudged n ->
    "no outlier judged: the rejection fits a line through " ++ show outlierWindow ++ " samples around each one, and the recording has "
    ++ show n ++ " sample" ++ plural n ++ "; every one kept"
  Gaps f med n (d, t, l) xs ->
    show n ++ " gap" ++ plural n ++ " (time step above " ++ showNumber f ++ " times the median " ++ showStep t med
    ++ " s) accepted; the largest " ++ showStep t d ++ " s before t = " ++ showNumber t ++ " s at " ++ lcAt loc l
    ++ (if n > 1 then " (" ++ list [ showStep t dd ++ " s before " ++ lcAt loc ll | (dd, ll) <- xs ] n ++ ")" else "")
  LongMedianStep m n ->
    "the median time step is " ++ showNumber m ++ " s over " ++ show n ++ " samples: the times are read in seconds; "
    ++ "if they are in ms, us or ns, convert them (or write a CSV whose header gives the unit, e.g. time [ns])"
  where
    -- a difference of two times read near tRef, to the digits the subtraction keeps (about
    -- 15 less the decades between them, 3 to 12): 0.01 s between times near 1.3e9 s, not
    -- 0.00999999046326 s; 210.32 s between 0.2 and 210.52 s, not 210.32000000000002 s
    showStep tRef d
      | d == 0 || tRef == 0 = showNumber (roundSignificant d)
      | otherwise =
          let decades = max 0 (ceiling (logBase 10 (abs tRef / abs d))) :: Int
          in showNumber (roundSignificantTo (max 3 (min 12 (15 - decades))) d)
    plural n = if n == 1 then "" else "s"
    list items total = joinWith "; " items ++ (if total > length items then "; ..." else "")
    joinWith s = foldr1' (\a b -> a ++ s ++ b)
    foldr1' _ [] = ""
    foldr1' f xs = foldr1 f xs
