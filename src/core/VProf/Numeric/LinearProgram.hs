-- | A small, pure, dense linear-programming solver with verified answers: minimise c·x
-- subject to colLo ≤ x ≤ colHi and rowLo ≤ A x ≤ rowHi (any bound may be infinite), for
-- problems up to a few hundred rows and columns. A bounded-variable primal simplex on a
-- condensed tableau (composite phase I, partial steepest-edge pricing with Bland's rule
-- against cycling, Harris' ratio test), its mutable state in one 'Tableau' record.
--
-- Invariant: no answer is returned unverified. An 'Optimal' point is recomputed from its
-- basis and meets every bound within 1e-9 relative ('residuals'); an 'Infeasible' answer
-- carries a 'Farkas' certificate that 'certifies' accepts in exact arithmetic; an
-- 'Unbounded' ray is checked within a tolerance; anything else is 'Undecided'. The
-- method, the tolerances and what a certificate proves are in docs/linear-program.md.
module VProf.Numeric.LinearProgram
  ( Lp (..), Row (..), LpResult (..), Farkas (..)
  , solve, certifies, residuals
  ) where

import Control.Monad.ST (ST, runST)
import Data.Bits (shiftL)
import qualified Data.IntMap.Strict as IM
import Data.List (foldl')
import qualified Data.Vector.Unboxed as U
import qualified Data.Vector.Unboxed.Mutable as UM
import qualified Numeric.LinearAlgebra as LA

-- | minimize  objective · x  subject to  colLo ≤ x ≤ colHi  and  rowLo ≤ terms·x ≤ rowHi.
-- Bounds may be infinite (±1/0); colLo = colHi fixes a variable; rowLo = rowHi is an
-- equality.
data Lp = Lp
  { lpCols      :: !Int
  , lpColLo     :: !(U.Vector Double)
  , lpColHi     :: !(U.Vector Double)
  , lpRows      :: [Row]
  , lpObjective :: !(U.Vector Double)   -- ^ length lpCols; all zeros = pure feasibility
  }
  deriving Show

-- | One row: sparse terms (column index, coefficient; repeated columns add up) and
-- bounds on their sum.
data Row = Row { rowTerms :: [(Int, Double)], rowLo :: !Double, rowHi :: !Double }
  deriving Show

data LpResult
  = Optimal (U.Vector Double)   -- ^ a point satisfying every bound within 1e-9 (relative to max 1 |bound|), optimal
  | Infeasible Farkas           -- ^ with a certificate that 'certifies' accepts
  | Unbounded
  | Undecided String            -- ^ iteration cap, numerical trouble, a certificate that did not verify: never a wrong answer
  deriving Show

-- | Multipliers, one per row (in lpRows order): y_i > 0 uses the row's upper bound,
-- y_i < 0 its lower.
newtype Farkas = Farkas (U.Vector Double) deriving Show

------------------------------------------------------------------------------------
-- Tolerances

-- | Output feasibility (what 'Optimal' promises, measured by 'residuals').
outputTol :: Double
outputTol = 1e-9

-- | Internal primal feasibility, relative to max 1 |bound| in the row's original units.
primalTol :: Double
primalTol = 1e-10

-- | Reduced costs (phase I costs are ±1; the objective is scaled to [0.5, 1)).
dualTol :: Double
dualTol = 1e-9

-- | Dual feasibility demanded of the recomputed multipliers at an optimum.
dualCheckTol :: Double
dualCheckTol = 1e-7

-- | The Harris ratio test relaxes bounds by this fraction of 'primalTol'.
harris :: Double
harris = 0.5

-- | Smallest pivot the ratio test takes.
pivotTol :: Double
pivotTol = 1e-9

-- | Tableau entries that cancel to below this fraction of their old value become 0.
dropTol :: Double
dropTol = 1.4210854715202004e-14  -- 2^-46

-- | A step shorter than this is degenerate.
degenerateStep :: Double
degenerateStep = 1e-12

-- | How many of the columns with the largest reduced costs the pricing compares by
-- their steepest-edge norms.
shortList :: Int
shortList = 8

-- | Iterations between recomputations of the reduced costs from scratch.
refreshEvery :: Int
refreshEvery = 64

-- | Consecutive degenerate steps before Bland's rule takes over.
blandAfter :: Int
blandAfter = 50

-- | Tableau rebuilds (and simplex restarts) allowed when a verification fails.
maxRefactor :: Int
maxRefactor = 3

-- | Relative tolerance of the recession-direction check behind 'Unbounded'.
rayTol :: Double
rayTol = 1e-10

-- | A column whose infinite side would be used is ignored by 'certifies' when
-- |r_j| ≤ cancelTol · Σ_i |y_i A_ij| ...
cancelTol :: Double
cancelTol = 2 ** (-40)

-- | ... and then m(y) − B(y) must exceed this fraction of the sum of the magnitudes
-- of the terms of m(y) and B(y).
concessionMargin :: Double
concessionMargin = 1e-6

------------------------------------------------------------------------------------
-- Residuals

-- | The largest bound violation of a point, over columns and rows, each relative to
-- @max 1 |bound|@ (0 for a feasible point; +∞ for a point of the wrong length, NaN
-- entries or out-of-range column indices). 'Optimal' points have @residuals ≤ 1e-9@.
residuals :: Lp -> U.Vector Double -> Double
residuals Lp{..} x
  | U.length x /= lpCols = 1 / 0
  | U.any isNaN x = 1 / 0
  | otherwise = foldl' max colViol (map rowViol lpRows)
  where
    colViol = U.maximum (U.cons 0 (U.zipWith3 violation x lpColLo lpColHi))
    rowViol Row{..}
      | any (\(j, _) -> j < 0 || j >= lpCols) rowTerms = 1 / 0
      | otherwise = violation (sum [a * x U.! j | (j, a) <- rowTerms]) rowLo rowHi

-- | How far v lies outside [lo, hi], relative to max 1 |bound|.
violation :: Double -> Double -> Double -> Double
violation v lo hi
  | isNaN v = 1 / 0
  | otherwise = max 0 (max below above)
  where
    below | isInfinite lo = if lo > 0 then 1 / 0 else 0
          | otherwise = (lo - v) / max 1 (abs lo)
    above | isInfinite hi = if hi < 0 then 1 / 0 else 0
          | otherwise = (v - hi) / max 1 (abs hi)

------------------------------------------------------------------------------------
-- Certificate check, in exact dyadic arithmetic

-- | @Dy m e@ is the number m·2^e, exactly.
data Dy = Dy !Integer !Int

dyZero :: Dy
dyZero = Dy 0 0

dyOf :: Double -> Dy
dyOf x = let (m, e) = decodeFloat x in Dy m e

dyMul :: Dy -> Dy -> Dy
dyMul (Dy a e) (Dy b f) = Dy (a * b) (e + f)

dyAdd :: Dy -> Dy -> Dy
dyAdd p@(Dy a e) q@(Dy b f)
  | a == 0 = q
  | b == 0 = p
  | e <= f = Dy (a + (b `shiftL` (f - e))) e
  | otherwise = Dy ((a `shiftL` (e - f)) + b) f

dyNeg :: Dy -> Dy
dyNeg (Dy a e) = Dy (negate a) e

dySignum :: Dy -> Integer
dySignum (Dy a _) = signum a

dyToDouble :: Dy -> Double
dyToDouble (Dy a e) = encodeFloat a e

finite :: Double -> Bool
finite x = not (isNaN x || isInfinite x)

-- | Does y prove the problem infeasible? With r = Aᵀy, B(y) = Σ_i y_i·(rowHi_i if
-- y_i > 0 else rowLo_i) and m(y) = Σ_j min(r_j·colLo_j, r_j·colHi_j), it accepts when
-- m(y) > B(y), computed exactly (see the module header: the margin is 0 because
-- nothing is rounded, except when a free column is dropped, which needs
-- m(y) − B(y) > 1e-6·S). False when y has the wrong length, a NaN or infinite entry,
-- is all zero, uses an infinite row bound (y_i > 0 with rowHi_i = +∞ or y_i < 0 with
-- rowLo_i = −∞), or needs an infinite column bound for an r_j that does not cancel to
-- within 2^-40 · Σ_i |y_i A_ij|; also False for malformed problems (wrong vector
-- lengths, out-of-range column indices, non-finite coefficients).
certifies :: Lp -> Farkas -> Bool
certifies Lp{..} (Farkas y)
  | U.length y /= length lpRows = False
  | U.length lpColLo /= lpCols || U.length lpColHi /= lpCols = False
  | not (U.all finite y) || U.all (== 0) y = False
  | otherwise = case (bound, rvec) of
      (Just (b, sb), Just rs) -> case foldl' addCol (Just (dyZero, 0, False)) (IM.toList rs) of
        Just (mm, sm, dropped) ->
          let gap = dyAdd mm (dyNeg b)
          in if dropped then dySignum (dyAdd gap (dyNeg (dyOf (concessionMargin * (sb + sm))))) > 0
                        else dySignum gap > 0
        Nothing -> False
      _ -> False
  where
    used = [(yi, row) | (yi, row) <- zip (U.toList y) lpRows, yi /= 0]

    -- B(y), exactly, and Σ|terms| roughly; Nothing when an infinite (or NaN) bound is used.
    bound = foldl' step (Just (dyZero, 0)) used
      where
        step acc (yi, Row{..}) = do
          (s, sa) <- acc
          let b = if yi > 0 then rowHi else rowLo
          if finite b then Just (dyAdd s (dyMul (dyOf yi) (dyOf b)), sa + abs (yi * b))
                      else Nothing

    -- r_j exactly, with Σ_i |y_i A_ij| beside it; Nothing on a malformed term.
    rvec :: Maybe (IM.IntMap (Dy, Double))
    rvec
      | all ok [t | (_, row) <- used, t <- rowTerms row] =
          Just $ IM.fromListWith plus
            [ (j, (dyMul (dyOf yi) (dyOf a), abs (yi * a)))
            | (yi, row) <- used, (j, a) <- rowTerms row ]
      | otherwise = Nothing
      where
        ok (j, a) = j >= 0 && j < lpCols && finite a
        plus (p, u) (q, v) = (dyAdd p q, u + v)

    -- m(y): adds min(r_j lo_j, r_j hi_j), with Σ|terms| roughly and whether a column
    -- was dropped under the cancellation concession.
    addCol acc (j, (r, mag)) = do
      (s, sa, dropped) <- acc
      let sg = dySignum r
          b = if sg > 0 then lpColLo U.! j else lpColHi U.! j
          term = dyMul r (dyOf b)
      if sg == 0 then Just (s, sa, dropped)
      else if isNaN b then Nothing
      else if finite b then Just (dyAdd s term, sa + abs (dyToDouble term), dropped)
      else if abs (dyToDouble r) <= cancelTol * mag then Just (s, sa, True)
      else Nothing

------------------------------------------------------------------------------------
-- The prepared problem

-- | Variables 0..n−1 are the columns, n..n+m−1 the (scaled) row activities.
data Prob = Prob
  { pN       :: !Int
  , pM       :: !Int
  , pA       :: !(U.Vector Double)   -- ^ scaled A, m × n row-major
  , pLo      :: !(U.Vector Double)   -- ^ n + m lower bounds (rows scaled)
  , pHi      :: !(U.Vector Double)
  , pTolLo   :: !(U.Vector Double)   -- ^ feasibility tolerance at each lower bound
  , pTolHi   :: !(U.Vector Double)
  , pCost    :: !(U.Vector Double)   -- ^ n, scaled objective
  , pHasCost :: !Bool
  , pScale   :: !(U.Vector Double)   -- ^ m row scales (powers of two)
  }

-- | 2^(−e) with x·2^(−e) in [0.5, 1), for x > 0 (1 for x = 0).
pow2Inv :: Double -> Double
pow2Inv x
  | x > 0 = scaleFloat (negate (exponent x)) 1
  | otherwise = 1

standardForm :: Lp -> Either String Prob
standardForm Lp{..} = do
  let n = lpCols
      m = length lpRows
  check (n >= 0) "negative column count"
  check (U.length lpColLo == n && U.length lpColHi == n && U.length lpObjective == n)
    "lpColLo, lpColHi and lpObjective must have lpCols entries"
  check (U.all finite lpObjective) "the objective has a NaN or infinite coefficient"
  mapM_ (\(j, lo, hi) -> goodBox ("column " ++ show j) lo hi)
        (zip3 [0 :: Int ..] (U.toList lpColLo) (U.toList lpColHi))
  mapM_ (\(i, Row{..}) -> do
            goodBox ("row " ++ show i) rowLo rowHi
            check (all (\(j, _) -> j >= 0 && j < n) rowTerms)
                  ("row " ++ show i ++ " has a column index outside 0.." ++ show (n - 1))
            check (all (finite . snd) rowTerms)
                  ("row " ++ show i ++ " has a NaN or infinite coefficient"))
        (zip [0 :: Int ..] lpRows)
  let raw = U.accum (+) (U.replicate (m * n) 0)
              [(i * n + j, a) | (i, Row{..}) <- zip [0 ..] lpRows, (j, a) <- rowTerms]
      scales = U.generate m $ \i ->
        pow2Inv (U.maximum (U.cons 0 (U.map abs (U.slice (i * n) n raw))))
      a' = U.imap (\ix a -> a * scales U.! (ix `div` max 1 n)) raw
      rowLos = U.fromList (map rowLo lpRows)
      rowHis = U.fromList (map rowHi lpRows)
      tolOf s b = if finite b then primalTol * s * max 1 (abs b) else 0
      cmax = U.maximum (U.cons 0 (U.map abs lpObjective))
  pure Prob
    { pN = n
    , pM = m
    , pA = a'
    , pLo = lpColLo U.++ U.zipWith (*) scales rowLos
    , pHi = lpColHi U.++ U.zipWith (*) scales rowHis
    , pTolLo = U.map (tolOf 1) lpColLo U.++ U.zipWith tolOf scales rowLos
    , pTolHi = U.map (tolOf 1) lpColHi U.++ U.zipWith tolOf scales rowHis
    , pCost = U.map (* pow2Inv cmax) lpObjective
    , pHasCost = cmax > 0
    , pScale = scales
    }
  where
    check ok msg = if ok then Right () else Left ("invalid LP: " ++ msg)
    goodBox what lo hi = do
      check (not (isNaN lo || isNaN hi)) (what ++ " has a NaN bound")
      check (lo <= hi) (what ++ " has lo > hi (empty, not certifiable by row multipliers)")
      check (lo < 1 / 0 && hi > -1 / 0) (what ++ " has an infinite bound on the wrong side")

-- | Basic variables by tableau row, nonbasic variables by tableau column, and the
-- values of the nonbasic ones.
data Basis = Basis
  { bBasic :: !(U.Vector Int)
  , bNonb  :: !(U.Vector Int)
  , bXN    :: !(U.Vector Double)
  }

initialBasis :: Prob -> Basis
initialBasis Prob{..} = Basis
  { bBasic = U.enumFromN pN pM
  , bNonb = U.enumFromN 0 pN
  , bXN = U.generate pN $ \j ->
      let lo = pLo U.! j; hi = pHi U.! j
      in if finite lo then lo else if finite hi then hi else 0
  }

------------------------------------------------------------------------------------
-- The simplex iterations

data Stop
  = SOptimal                  -- ^ no basic infeasible, no improving column
  | SInfeasible               -- ^ infeasible basics and no column reduces them
  | SUnbounded !Int !Double   -- ^ improving nonbasic position and direction, no block
  | SCap
  | STrouble String

data Step
  = NoBlock
  | Flip !Double              -- ^ the entering variable crosses its own range
  | Pivot !Int !Double !Double -- ^ leaving row, step, the bound the leaving variable takes

data SegOut = SegOut !Stop !Basis !(U.Vector Double) !Int

loopN :: Monad m => Int -> Int -> (Int -> m ()) -> m ()
loopN from to f = go from
  where
    go !i | i >= to = pure ()
          | otherwise = f i >> go (i + 1)
{-# INLINE loopN #-}

-- | The mutable state of a simplex segment: the tableau and what the iterations keep
-- beside it. Invariant between iterations: row i of @t@ expresses the basic variable
-- @basic[i]@ in the nonbasic ones (x_B = T x_N), @xB@ holds their values for the
-- nonbasic values @xN@, and @dv@ holds the reduced costs for the cost kept in @eB@ and
-- @eN@; @gv@ is the last 'classify' of the basic variables.
data Tableau s = Tableau
  { t       :: !(UM.MVector s Double)  -- ^ T, m × n row-major
  , basic   :: !(UM.MVector s Int)     -- ^ the basic variable of each row
  , nonb    :: !(UM.MVector s Int)     -- ^ the nonbasic variable of each column
  , xN      :: !(UM.MVector s Double)  -- ^ the nonbasic variables' values
  , xB      :: !(UM.MVector s Double)  -- ^ the basic variables' values
  , dv      :: !(UM.MVector s Double)  -- ^ reduced costs d_k, by column
  , eB      :: !(UM.MVector s Double)  -- ^ the cost dv is for, by basic row
  , eN      :: !(UM.MVector s Double)  -- ^ the cost dv is for, by nonbasic column
  , candK   :: !(UM.MVector s Int)     -- ^ pricing's short list: columns,
  , candD   :: !(UM.MVector s Double)  -- ^ their |d_k|,
  , candDir :: !(UM.MVector s Double)  -- ^ and directions
  , gv      :: !(UM.MVector s Int)     -- ^ g_i ∈ {−1, 0, 1}: below, within, above the bounds
  , nz      :: !(UM.MVector s Int)     -- ^ the nonzero columns of the pivot row
  }

-- | Runs simplex iterations on tableau t (x_B = T x_N) from the given basis until a
-- stop or until the budget of iterations is spent.
runSegment :: Prob -> U.Vector Double -> Basis -> Int -> SegOut
runSegment pr tab0 (Basis bas0 nb0 xn0) budget = runST $ do
  tb@Tableau{..} <- newTableau pr tab0 bas0 nb0 xn0
  (stop, its) <- iterateSegment pr tb budget 0 0
  tab <- U.freeze t
  bas <- U.freeze basic
  nb <- U.freeze nonb
  xn <- U.freeze xN
  pure (SegOut stop (Basis bas nb xn) tab its)

-- | The state for a tableau and basis: the basic values computed from the nonbasic
-- ones, the reduced costs and their cost at zero.
newTableau :: Prob -> U.Vector Double -> U.Vector Int -> U.Vector Int -> U.Vector Double -> ST s (Tableau s)
newTableau Prob{..} tab0 bas0 nb0 xn0 = do
  t <- U.thaw tab0
  basic <- U.thaw bas0
  nonb <- U.thaw nb0
  xN <- U.thaw xn0
  xB <- UM.replicate m 0
  dv <- UM.replicate n 0
  eB <- UM.replicate m 0
  eN <- UM.replicate n 0
  candK <- UM.replicate shortList (0 :: Int)
  candD <- UM.replicate shortList (0 :: Double)
  candDir <- UM.replicate shortList (0 :: Double)
  gv <- UM.replicate m (0 :: Int)
  nz <- UM.replicate (max 1 n) (0 :: Int)
  loopN 0 m $ \i -> dotRow n t i xN >>= UM.unsafeWrite xB i
  pure Tableau{..}
  where
    n = pN
    m = pM

lo, hi, cost :: Prob -> Int -> Double
lo Prob{..} v = U.unsafeIndex pLo v
hi Prob{..} v = U.unsafeIndex pHi v
cost Prob{..} v = if v < pN then U.unsafeIndex pCost v else 0
{-# INLINE lo #-}
{-# INLINE hi #-}
{-# INLINE cost #-}

-- | g_i ∈ {−1, 0, 1}: below, within, above the bounds; returns how many are outside.
classify :: Prob -> Tableau s -> ST s Int
classify pr@Prob{..} Tableau{..} = go 0 (0 :: Int)
  where
    go !i !cnt
      | i >= pM = pure cnt
      | otherwise = do
          v <- UM.unsafeRead basic i
          x <- UM.unsafeRead xB i
          let g | x < lo pr v - U.unsafeIndex pTolLo v = -1
                | x > hi pr v + U.unsafeIndex pTolHi v = 1
                | otherwise = 0
          UM.unsafeWrite gv i g
          go (i + 1) (if g /= 0 then cnt + 1 else cnt)

-- | Reduced costs: dv holds d_k = e_{N_k} + Σ_i e_{B_i} T[i][k] for the cost e kept in
-- eB (by basic row) and eN (by nonbasic column). A pivot transforms dv like a row of the
-- tableau (the function is the same, the nonbasics change); retarget then adds the
-- change of e: phase I, e = g on the basic variables and 0 on the nonbasic ones; phase
-- II, e = c. Usually only a few rows change, so pricing costs O(n) per iteration instead
-- of O(mn); 'refresh' recomputes from scratch.
retarget :: Prob -> Tableau s -> Bool -> ST s ()
retarget pr@Prob{..} Tableau{..} phase1 = do
  loopN 0 n $ \k -> do
    tgt <- if phase1 then pure 0 else cost pr <$> UM.unsafeRead nonb k
    e <- UM.unsafeRead eN k
    if e == tgt then pure () else do
      d <- UM.unsafeRead dv k
      UM.unsafeWrite dv k (d + (tgt - e))
      UM.unsafeWrite eN k tgt
  loopN 0 m $ \i -> do
    tgt <- if phase1 then fromIntegral <$> UM.unsafeRead gv i
                     else cost pr <$> UM.unsafeRead basic i
    e <- UM.unsafeRead eB i
    if e == tgt then pure () else do
      let w = tgt - e
          io = i * n
      loopN 0 n $ \k -> do
        a <- UM.unsafeRead t (io + k)
        if a == 0 then pure () else do
          d <- UM.unsafeRead dv k
          UM.unsafeWrite dv k (d + w * a)
      UM.unsafeWrite eB i tgt
  where
    n = pN
    m = pM

refresh :: Tableau s -> ST s ()
refresh Tableau{..} = do
  UM.set dv 0
  UM.set eB 0
  UM.set eN 0

-- | Column k's variable, its reduced cost, and the direction it may enter in (0: not
-- eligible).
eligible :: Prob -> Tableau s -> Int -> ST s (Int, Double, Double)
eligible pr Tableau{..} k = do
  v <- UM.unsafeRead nonb k
  x <- UM.unsafeRead xN k
  d <- UM.unsafeRead dv k
  let l = lo pr v; h = hi pr v
      dir | l == h = 0
          | d < -dualTol && x < h = 1
          | d > dualTol && x > l = -1
          | otherwise = 0 :: Double
  pure (v, d, dir)

-- | Entering position and direction (k = −1: none). Bland: the eligible variable of
-- smallest index. Otherwise a partial steepest edge: the 'shortList' columns with the
-- largest |d_k| (Dantzig's choice among them), and of those the one with the largest
-- d_k² / (1 + Σ_i T[i][k]²), the squared rate of improvement per unit length of the edge.
entering :: Prob -> Tableau s -> Bool -> ST s (Int, Double)
entering pr@Prob{..} tb True = go 0 (-1) 0 maxBound
  where
    go !k !bestK !bestDir !bestVar
      | k >= pN = pure (bestK, bestDir)
      | otherwise = do
          (v, _, dir) <- eligible pr tb k
          if dir /= 0 && v < bestVar then go (k + 1) k dir v
                                     else go (k + 1) bestK bestDir bestVar
entering pr@Prob{..} tb@Tableau{..} False = do
  -- the short list, kept sorted by |d| descending (earlier k first among ties)
  let collect !k !cnt
        | k >= n = pure cnt
        | otherwise = do
            (_, d, dir) <- eligible pr tb k
            if dir == 0 then collect (k + 1) cnt else do
              let a = abs d
              lastA <- if cnt < shortList then pure (-1)
                       else UM.unsafeRead candD (shortList - 1)
              if a <= lastA then collect (k + 1) cnt else do
                let cnt' = min shortList (cnt + 1)
                    -- shift smaller entries down, then insert
                    place !j
                      | j > 0 = do
                          prev <- UM.unsafeRead candD (j - 1)
                          if prev < a
                            then do
                              UM.unsafeRead candK (j - 1) >>= UM.unsafeWrite candK j
                              UM.unsafeWrite candD j prev
                              UM.unsafeRead candDir (j - 1) >>= UM.unsafeWrite candDir j
                              place (j - 1)
                            else pure j
                      | otherwise = pure 0
                j <- place (cnt' - 1)
                UM.unsafeWrite candK j k
                UM.unsafeWrite candD j a
                UM.unsafeWrite candDir j dir
                collect (k + 1) cnt'
  cnt <- collect 0 0
  let pick !c !bestK !bestDir !bestScore
        | c >= cnt = pure (bestK, bestDir)
        | otherwise = do
            k <- UM.unsafeRead candK c
            a <- UM.unsafeRead candD c
            dir <- UM.unsafeRead candDir c
            g <- colNorm pr tb k
            let score = a * a / g
            if score > bestScore then pick (c + 1) k dir score
                                 else pick (c + 1) bestK bestDir bestScore
  pick 0 (-1) 0 (-1)
  where
    n = pN

-- | 1 + Σ_i T[i][k]².
colNorm :: Prob -> Tableau s -> Int -> ST s Double
colNorm Prob{..} Tableau{..} k = go 0 1
  where
    go !i !acc
      | i >= pM = pure acc
      | otherwise = do
          a <- UM.unsafeRead t (i * pN + k)
          go (i + 1) (acc + a * a)

-- | The blocking ratio of basic row i for column k moving in direction dir:
-- (relaxed ratio, exact ratio, bound value, pivot), or Nothing.
rowRatio :: Prob -> Tableau s -> Int -> Double -> Int -> ST s (Maybe (Double, Double, Double, Double))
rowRatio pr@Prob{..} Tableau{..} k dir i = do
  a0 <- UM.unsafeRead t (i * pN + k)
  let a = a0 * dir
  if abs a <= pivotTol then pure Nothing else do
    v <- UM.unsafeRead basic i
    x <- UM.unsafeRead xB i
    g <- UM.unsafeRead gv i
    let l = lo pr v; h = hi pr v
        tl = U.unsafeIndex pTolLo v; th = U.unsafeIndex pTolHi v
    pure $! case g of
      0 | a > 0 && finite h -> Just ((h + harris * th - x) / a, (h - x) / a, h, a)
        | a < 0 && finite l -> Just ((l - harris * tl - x) / a, (l - x) / a, l, a)
        | otherwise -> Nothing
      -1 | a > 0 -> let r = (l - x) / a in Just (r, r, l, a)
         | otherwise -> Nothing
      _  | a < 0 -> let r = (h - x) / a in Just (r, r, h, a)
         | otherwise -> Nothing

-- | The ratio test for column k entering in direction dir: Bland's textbook test, or
-- Harris' two passes.
ratio :: Prob -> Tableau s -> Bool -> Int -> Double -> ST s Step
ratio pr@Prob{..} tb@Tableau{..} bland k dir = do
  v <- UM.unsafeRead nonb k
  let range = hi pr v - lo pr v
  if bland
    then do
      -- textbook: the smallest ratio, ties to the smallest basic variable
      let go !i !bestR !bestRat !bestB !bestVar
            | i >= m = pure (bestR, bestRat, bestB)
            | otherwise = rowRatio pr tb k dir i >>= \case
                Nothing -> go (i + 1) bestR bestRat bestB bestVar
                Just (_, r0, b, _) -> do
                  u <- UM.unsafeRead basic i
                  let r = max 0 r0
                      better
                        | bestR < 0 = True
                        | abs (r - bestRat) <= 1e-12 * max 1 r = u < bestVar
                        | otherwise = r < bestRat
                  if better then go (i + 1) i r b u
                            else go (i + 1) bestR bestRat bestB bestVar
      (r, rat, b) <- go 0 (-1) (1 / 0) 0 maxBound
      pure $! if r < 0 && isInfinite range then NoBlock
              else if r < 0 || range <= rat then Flip range
              else Pivot r rat b
    else do
      -- Harris pass 1: the step with every bound relaxed by half its tolerance
      let pass1 !i !tmax
            | i >= m = pure tmax
            | otherwise = rowRatio pr tb k dir i >>= \case
                Nothing -> pass1 (i + 1) tmax
                Just (rr, _, _, _) -> pass1 (i + 1) (min tmax rr)
      tmax <- pass1 0 (1 / 0)
      if isInfinite tmax && isInfinite range then pure NoBlock
      else if range <= tmax then pure (Flip range)
      else do
        -- pass 2: the largest pivot among the rows blocking within tmax
        let pass2 !i !bestR !bestRat !bestB !bestAbs
              | i >= m = pure (bestR, bestRat, bestB)
              | otherwise = rowRatio pr tb k dir i >>= \case
                  Just (_, r, b, a) | r <= tmax && abs a > bestAbs ->
                    pass2 (i + 1) i r b (abs a)
                  _ -> pass2 (i + 1) bestR bestRat bestB bestAbs
        (r, rat, b) <- pass2 0 (-1) 0 0 0
        pure $! if r < 0 then NoBlock else Pivot r (max 0 rat) b
  where
    m = pM

-- | The basic values after column k moved by step in direction dir.
moveBasics :: Prob -> Tableau s -> Int -> Double -> Double -> ST s ()
moveBasics Prob{..} Tableau{..} k dir step =
  if step == 0 then pure () else
    loopN 0 pM $ \i -> do
      a <- UM.unsafeRead t (i * pN + k)
      if a == 0 then pure () else do
        x <- UM.unsafeRead xB i
        UM.unsafeWrite xB i (x + a * dir * step)

-- | Pivot on (r, s): the basic variable of row r and the nonbasic of column s swap.
pivot :: Prob -> Tableau s -> Int -> Int -> ST s ()
pivot Prob{..} Tableau{..} r s = do
  p <- UM.unsafeRead t (r * n + s)
  let ro = r * n
  cnt <- let go !k !c
               | k >= n = pure c
               | k == s = UM.unsafeWrite t (ro + k) (1 / p) >> go (k + 1) c
               | otherwise = do
                   a <- UM.unsafeRead t (ro + k)
                   if a == 0 then go (k + 1) c else do
                     UM.unsafeWrite t (ro + k) (negate a / p)
                     UM.unsafeWrite nz c k
                     go (k + 1) (c + 1)
         in go 0 0
  let invP = 1 / p
  -- the reduced costs, like a row
  ds <- UM.unsafeRead dv s
  if ds == 0 then pure () else do
    loopN 0 cnt $ \c -> do
      k <- UM.unsafeRead nz c
      rk <- UM.unsafeRead t (ro + k)
      d <- UM.unsafeRead dv k
      UM.unsafeWrite dv k (d + ds * rk)
    UM.unsafeWrite dv s (ds * invP)
  eR <- UM.unsafeRead eB r
  eS <- UM.unsafeRead eN s
  UM.unsafeWrite eB r eS
  UM.unsafeWrite eN s eR
  loopN 0 m $ \i -> if i == r then pure () else do
    let io = i * n
    f <- UM.unsafeRead t (io + s)
    if f == 0 then pure () else do
      let upd k = do
            rk <- UM.unsafeRead t (ro + k)
            x <- UM.unsafeRead t (io + k)
            let y = x + f * rk
            UM.unsafeWrite t (io + k) (if abs y <= dropTol * abs x then 0 else y)
      -- a dense pivot row is run through directly, a sparse one by its nonzeros
      if 2 * cnt > n
        then axpy t f ro io n
        else loopN 0 cnt $ \c -> UM.unsafeRead nz c >>= upd
      UM.unsafeWrite t (io + s) (f * invP)
  where
    n = pN
    m = pM

-- | Iterations from iteration @it@ (with @degen@ degenerate steps in a row) until a stop
-- or the budget: the stop and the iterations done.
iterateSegment :: Prob -> Tableau s -> Int -> Int -> Int -> ST s (Stop, Int)
iterateSegment pr@Prob{..} tb@Tableau{..} budget = iterate'
  where
    iterate' !it !degen
      | it >= budget = pure (SCap, it)
      | otherwise = do
          nInf <- classify pr tb
          let phase1 = nInf > 0
          if not phase1 && not pHasCost then pure (SOptimal, it) else do
            if it `mod` refreshEvery == 0 then refresh tb else pure ()
            retarget pr tb phase1
            let bland = degen >= blandAfter
            (k, dir) <- entering pr tb bland
            if k < 0 then pure (if phase1 then SInfeasible else SOptimal, it) else do
              st <- ratio pr tb bland k dir
              case st of
                NoBlock
                  | phase1 -> pure (STrouble "a phase I direction without a breakpoint", it)
                  | otherwise -> pure (SUnbounded k dir, it)
                Flip step -> do
                  moveBasics pr tb k dir step
                  v <- UM.unsafeRead nonb k
                  UM.unsafeWrite xN k (if dir > 0 then hi pr v else lo pr v)
                  iterate' (it + 1) 0
                Pivot r step b -> do
                  moveBasics pr tb k dir step
                  v <- UM.unsafeRead nonb k
                  xv <- UM.unsafeRead xN k
                  u <- UM.unsafeRead basic r
                  UM.unsafeWrite basic r v
                  UM.unsafeWrite xB r (xv + dir * step)
                  UM.unsafeWrite nonb k u
                  UM.unsafeWrite xN k b
                  pivot pr tb r k
                  iterate' (it + 1) (if step < degenerateStep then degen + 1 else 0)

-- | Row i of the tableau times the nonbasic values.
dotRow :: Int -> UM.MVector s Double -> Int -> UM.MVector s Double -> ST s Double
dotRow n t i xs = go 0 0
  where
    go !k !acc
      | k >= n = pure acc
      | otherwise = do
          a <- UM.unsafeRead t (i * n + k)
          x <- UM.unsafeRead xs k
          go (k + 1) (if a == 0 then acc else acc + a * x)

-- | t[io + k] += f · t[ro + k] for k < len (the dense row update of a pivot;
-- unrolled by four, which the native code generator rewards).
axpy :: UM.MVector s Double -> Double -> Int -> Int -> Int -> ST s ()
axpy t !f !ro !io !len = go 0
  where
    go !k
      | k + 4 <= len = do
          r0 <- UM.unsafeRead t (ro + k)
          r1 <- UM.unsafeRead t (ro + k + 1)
          r2 <- UM.unsafeRead t (ro + k + 2)
          r3 <- UM.unsafeRead t (ro + k + 3)
          x0 <- UM.unsafeRead t (io + k)
          x1 <- UM.unsafeRead t (io + k + 1)
          x2 <- UM.unsafeRead t (io + k + 2)
          x3 <- UM.unsafeRead t (io + k + 3)
          UM.unsafeWrite t (io + k) (x0 + f * r0)
          UM.unsafeWrite t (io + k + 1) (x1 + f * r1)
          UM.unsafeWrite t (io + k + 2) (x2 + f * r2)
          UM.unsafeWrite t (io + k + 3) (x3 + f * r3)
          go (k + 4)
      | k < len = do
          r0 <- UM.unsafeRead t (ro + k)
          x0 <- UM.unsafeRead t (io + k)
          UM.unsafeWrite t (io + k) (x0 + f * r0)
          go (k + 1)
      | otherwise = pure ()

------------------------------------------------------------------------------------
-- Fresh linear algebra on a basis (LAPACK through hmatrix)

-- | Rebuilds the tableau T = −B⁻¹N of a basis from the data.
refactor :: Prob -> Basis -> Maybe (U.Vector Double)
refactor Prob{..} (Basis bas nb _)
  | pM == 0 || pN == 0 = Just (U.replicate (pM * pN) 0)
  | otherwise = do
      let col v | v < pN = LA.fromList [pA U.! (i * pN + v) | i <- [0 .. pM - 1]]
                | otherwise = LA.fromList [if i == v - pN then -1 else 0 | i <- [0 .. pM - 1]]
          bmat = LA.fromColumns (map col (U.toList bas))
          nmat = LA.fromColumns (map col (U.toList nb))
      sol <- LA.linearSolve bmat nmat
      let tab = U.map negate (U.convert (LA.flatten sol))
      if U.all finite tab then Just tab else Nothing

-- | Solves K z = b with LU and one step of iterative refinement.
solveRefined :: LA.Matrix Double -> [Double] -> Maybe [Double]
solveRefined k bs = do
  let b = LA.asColumn (LA.fromList bs)
  z0 <- LA.linearSolve k b
  dz <- LA.linearSolve k (b - k LA.<> z0)
  let z = LA.toList (LA.flatten (z0 + dz))
  if all finite z then Just z else Nothing

-- | The basic columns of a basis against its nonbasic rows (the square matrix K of
-- both the primal and the dual solve): basic columns, nonbasic rows with their values,
-- and the values of all columns with the basic ones still 0.
basisParts :: Prob -> Basis -> ([Int], [(Int, Double)], U.Vector Double)
basisParts Prob{..} (Basis bas nb xn) =
  ( [v | v <- U.toList bas, v < pN]
  , [(v - pN, x) | (v, x) <- zip (U.toList nb) (U.toList xn), v >= pN]
  , U.accum (\_ x -> x) (U.replicate pN 0)
      [(v, x) | (v, x) <- zip (U.toList nb) (U.toList xn), v < pN] )

-- | The basic solution, computed afresh: K x_B = w_NR − A[NR, NS] x_NS.
basicSolution :: Prob -> Basis -> Maybe (U.Vector Double)
basicSolution pr@Prob{..} basis
  | p /= length nrs = Nothing
  | p == 0 = Just xs0
  | otherwise = do
      let aij i j = pA U.! (i * pN + j)
          kmat = (p LA.>< p) [aij i j | (i, _) <- nrs, j <- bs]
          rhs = [w - sum [aij i j * x | (j, x) <- zip [0 ..] (U.toList xs0), x /= 0] | (i, w) <- nrs]
      z <- solveRefined kmat rhs
      Just (xs0 U.// zip bs z)
  where
    (bs, nrs, xs0) = basisParts pr basis
    p = length bs

-- | The simplex multipliers π (one per scaled row) of a basis for the cost e over all
-- variables: d_v = e_v − (Mᵀπ)_v vanishes on the basic variables, M = [A | −I].
multipliers :: Prob -> Basis -> (Int -> Double) -> Maybe (U.Vector Double)
multipliers pr@Prob{..} basis e
  | p /= length nrs = Nothing
  | otherwise = do
      let aij i j = pA U.! (i * pN + j)
          basicRows = [v - pN | v <- U.toList (bBasic basis), v >= pN]
          piB = [(i, negate (e (pN + i))) | i <- basicRows]
          rhs = [e j - sum [aij i j * pii | (i, pii) <- piB, pii /= 0] | j <- bs]
          kt = (p LA.>< p) [aij i j | j <- bs, (i, _) <- nrs]
      piN <- if p == 0 then Just [] else solveRefined kt rhs
      Just (U.accum (\_ x -> x) (U.replicate pM 0) (piB ++ zip (map fst nrs) piN))
  where
    (bs, nrs, _) = basisParts pr basis
    p = length bs

-- | Values of all n + m variables for the given column values.
allValues :: Prob -> U.Vector Double -> U.Vector Double
allValues Prob{..} x = x U.++ U.generate pM (\i ->
  U.sum (U.zipWith (*) (U.slice (i * pN) pN pA) x))

-- | Phase I multipliers turned into certificates in the original rows' terms: the
-- multipliers as solved (with a multiplier that would use an infinite row bound set to
-- 0), then the same with the entries below 1e-14, 1e-11 and 1e-8 of the largest set to
-- 0 (rounding leaves tiny multipliers on rows that play no part, and such a row
-- through a free column would spoil the proof). The caller keeps the first that
-- 'certifies' accepts.
farkasOf :: Prob -> Basis -> U.Vector Double -> Maybe [U.Vector Double]
farkasOf pr@Prob{..} basis x = do
  let vals = allValues pr x
      g v = let z = vals U.! v in
            if z < pLo U.! v - pTolLo U.! v then -1
            else if z > pHi U.! v + pTolHi U.! v then 1 else 0 :: Double
      gs = U.generate (pN + pM) g
      isBasic = U.accum (\_ b -> b) (U.replicate (pN + pM) False)
                  [(v, True) | v <- U.toList (bBasic basis)]
      e v = if isBasic U.! v then gs U.! v else 0
  if U.all (== 0) (U.ifilter (\v _ -> isBasic U.! v) gs) then Nothing else do
    piv <- multipliers pr basis e
    let clean i yi
          | yi > 0 && not (finite (pHi U.! (pN + i))) = 0
          | yi < 0 && not (finite (pLo U.! (pN + i))) = 0
          | otherwise = yi
        y' = U.imap clean (U.map negate piv)
        y = U.zipWith (*) y' pScale
        ymax = U.maximum (U.cons 0 (U.map abs y))
        yn = U.map (* pow2Inv ymax) y
        cut r = U.map (\v -> if abs v <= r then 0 else v) yn
    if ymax == 0 then Nothing else Just (yn : map cut [1e-14, 1e-11, 1e-8])

-- | Are the multipliers of the final basis dual feasible for the objective?
dualFeasible :: Prob -> Basis -> Bool
dualFeasible pr@Prob{..} basis@(Basis _ nb xn) =
  case multipliers pr basis (\v -> if v < pN then pCost U.! v else 0) of
    Nothing -> False
    Just piv -> and (zipWith ok (U.toList nb) (U.toList xn))
      where
        ok v x
          | l == h = True
          | x <= l = d >= -dualCheckTol
          | x >= h = d <= dualCheckTol
          | otherwise = abs d <= dualCheckTol
          where
            l = pLo U.! v
            h = pHi U.! v
            d | v < pN = pCost U.! v
                         - U.sum (U.generate pM (\i -> pA U.! (i * pN + v) * piv U.! i))
              | otherwise = piv U.! (v - pN)

-- | The improving ray of an unbounded stop, recomputed: the entering variable moves
-- by dir, the other nonbasics stay, the basic columns follow.
rayOf :: Prob -> Basis -> Int -> Double -> Maybe (U.Vector Double)
rayOf pr@Prob{..} basis k dir
  | p /= length nrs = Nothing
  | p == 0 = Just dx0
  | otherwise = do
      let aij i j = pA U.! (i * pN + j)
          kmat = (p LA.>< p) [aij i j | (i, _) <- nrs, j <- bs]
          rhs = [ (if pN + i == v then dir else 0) - (if v < pN then aij i v * dir else 0)
                | (i, _) <- nrs ]
      z <- solveRefined kmat rhs
      Just (dx0 U.// zip bs z)
  where
    (bs, nrs, _) = basisParts pr basis
    p = length bs
    v = bNonb basis U.! k
    dx0 = U.generate pN (\j -> if j == v then dir else 0)

-- | Is d (columns) a recession direction along which the objective falls, within
-- 'rayTol'? With d scaled to ‖d‖∞ = 1: a finite column bound tolerates rayTol the
-- wrong way, a finite row bound rayTol·Σ_j |A_ij|, and c·d must be below
-- −rayTol·Σ_j |c_j|.
rayOk :: Lp -> U.Vector Double -> Bool
rayOk Lp{..} d0 =
  nrm > 0 && finite nrm && colsOk && rowsOk && objOk
  where
    nrm = U.maximum (U.cons 0 (U.map abs d0))
    d = U.map (/ nrm) d0
    colsOk = U.and (U.zipWith3 (\dj l h -> (not (finite h) || dj <= rayTol)
                                        && (not (finite l) || dj >= -rayTol)) d lpColLo lpColHi)
    rowsOk = all rowOk lpRows
    rowOk Row{..} =
      let act = sum [a * d U.! j | (j, a) <- rowTerms]
          mag = sum [abs a | (_, a) <- rowTerms]
      in (not (finite rowHi) || act <= rayTol * mag)
         && (not (finite rowLo) || act >= -rayTol * mag)
    cd = U.sum (U.zipWith (*) lpObjective d)
    objOk = cd < -rayTol * U.sum (U.map abs lpObjective)

------------------------------------------------------------------------------------
-- The driver

-- | Solves the LP; deterministic, terminates (see the module header for the
-- algorithm and for what each answer guarantees).
solve :: Lp -> LpResult
solve lp = case standardForm lp of
  Left msg -> Undecided msg
  Right pr -> go pr maxRefactor (50 * (pM pr + pN pr) + 100) (pA pr) (initialBasis pr)
  where
    go pr refs budget tab basis =
      let SegOut stop basis' _ used = runSegment pr tab basis budget
          budget' = budget - used
          retry why
            | refs <= 0 = Undecided why
            | otherwise = case refactor pr basis' of
                Nothing -> Undecided (why ++ "; the basis is singular")
                Just tab' -> go pr (refs - 1) budget' tab' basis'
      in case stop of
        SCap -> Undecided ("iteration cap of " ++ show (50 * (pM pr + pN pr) + 100) ++ " reached")
        STrouble why -> retry why
        SOptimal -> case basicSolution pr basis' of
          Nothing -> retry "singular basis at the optimum"
          Just x
            | res > outputTol -> retry ("the final point violates a bound by " ++ show res)
            | pHasCost pr && not (dualFeasible pr basis') ->
                retry "the final basis is not dual feasible"
            | otherwise -> Optimal x
            where res = residuals lp x
        SInfeasible -> case basicSolution pr basis' of
          Nothing -> retry "singular basis at the end of phase I"
          Just x -> case farkasOf pr basis' x of
            Nothing -> retry "phase I stopped at a point that is feasible after all"
            Just ys -> case filter (certifies lp . Farkas) ys of
              y : _ -> Infeasible (Farkas y)
              [] -> retry "the infeasibility certificate did not verify"
        SUnbounded k dir -> case (basicSolution pr basis', rayOf pr basis' k dir) of
          (Just x, Just d)
            | residuals lp x <= outputTol && rayOk lp d -> Unbounded
          _ -> retry "the unbounded ray did not verify"
