{-# LANGUAGE BangPatterns #-}
-- | A start for the knot fit that keeps the path continuous (docs/compress.md, "The
-- continuous dynamic program"): waypoints at sample times, the first and last at the first
-- and last sample's time. For given waypoint times up to waypoint j, the least position error of the
-- path so far as a function of waypoint j's position p is a quadratic α|p|² − 2β·p + γ (the
-- earlier positions minimised out), and one more segment maps it to the next waypoint's
-- quadratic in O(1) from prefix sums. A dynamic program over (waypoint, sample) keeps the
-- best few of these functions per state, ranked by their minimum (the minimum over earlier
-- choices is not one quadratic, so keeping them all would be exact but grows); waypoint j is
-- searched at the samples of a band (by default around the line partition's boundaries),
-- each segment at most a given number of samples long.
module VProf.Compress.KnotDP
  ( continuousKnots
  ) where

import Control.Monad (forM_, when)
import Control.Monad.ST (ST, runST)
import qualified Data.Vector.Unboxed as U
import qualified Data.Vector.Unboxed.Mutable as MU

import VProf.Compress.Objective (Prepared (..))
import VProf.Compress.Partition (PrefixSums (..), prefixSums)
import VProf.Compress.Types (Ends (..))

-- | @continuousKnots pr k beam band w@: sample indices of k waypoints (the first 0, the last
-- n−1, strictly increasing) and the position SSE of the best continuous path through them
-- that the search found. @band j@ is the range of samples waypoint j (1 .. k−2) may take;
-- @beam@ functions are kept per state; no segment spans more than @w@ samples. With the
-- first and last waypoint free ('rcEnds') their positions are fitted, else they are the
-- first and last sample's. Requires 2 <= k <= n. When no path fits the bands and @w@, the
-- indices are spread evenly and the SSE is infinite.
continuousKnots :: Prepared -> Int -> Int -> (Int -> (Int, Int)) -> Int -> (U.Vector Int, Double)
continuousKnots pr k beam0 band w0
  | k <= 2 || n <= 2 = (U.fromList (if k <= 1 then [0] else [0, n - 1]), lastValue)
  | otherwise = runST search
  where
    n = U.length (rcT pr)
    beam = max 1 beam0
    w = max 1 w0
    free = rcEnds pr == EndsFree
    s = prefixSums (rcT pr) (rcP pr)
    d :: U.Vector Double -> Int -> Int -> Double
    d v a b = U.unsafeIndex v b - U.unsafeIndex v a
    tc :: Int -> Double
    tc i = d (psT s) i (i + 1)
    -- the first and last sample (centred as the sums are)
    (y0x, y0y, y0z) = (d (psX s) 0 1, d (psY s) 0 1, d (psZ s) 0 1)
    (yNx, yNy, yNz) = (d (psX s) (n - 1) n, d (psY s) (n - 1) n, d (psZ s) (n - 1) n)
    -- the SSE of the straight path first to last sample (k = 2)
    lastValue = segmentValue 0 (n - 1)
    segmentValue a b =
      let (a11, a12, a22, ax, ay, az, bx, by, bz, c0) = segment a b
          (al, gx, gy, gz, ga) = startFn a11 a12 a22 ax ay az bx by bz c0
      in endValue al gx gy gz ga
    -- waypoint ranges: 0 and n−1 at the ends, the band inside (kept feasible)
    lo j | j == 0 = 0
         | j == k - 1 = n - 1
         | otherwise = max j (fst (band j))
    hi j | j == 0 = 0
         | j == k - 1 = n - 1
         | otherwise = min (n - 1 - (k - 1 - j)) (snd (band j))
    -- a segment from waypoint at sample a to one at sample b holds samples a+1 .. b (and
    -- sample 0 for the first); its error is
    -- c0 − 2A·p_a − 2B·p_b + a11|p_a|² + 2a12 p_a·p_b + a22|p_b|²
    segment :: Int -> Int -> (Double, Double, Double, Double, Double, Double, Double, Double, Double, Double)
    segment a b =
      let l = if a == 0 then 0 else a + 1
          e = b + 1
          c = fromIntegral (e - l)
          s1 = d (psT s) l e; s2 = d (psTT s) l e
          sx = d (psX s) l e; sy = d (psY s) l e; sz = d (psZ s) l e
          tx = d (psTX s) l e; ty = d (psTY s) l e; tz = d (psTZ s) l e
          ta = tc a; h = tc b - ta
          su = (s1 - c * ta) / h
          suu = (s2 - 2 * ta * s1 + c * ta * ta) / (h * h)
          bx = (tx - ta * sx) / h; by = (ty - ta * sy) / h; bz = (tz - ta * sz) / h
      in (c - 2 * su + suu, su - suu, suu, sx - bx, sy - by, sz - bz, bx, by, bz, d (psXX s) l e)
    {-# INLINE segment #-}
    -- the first segment's function of p_b: p_a held at the first sample, or minimised out
    startFn :: Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double
            -> (Double, Double, Double, Double, Double)
    startFn a11 a12 a22 ax ay az bx by bz c0
      | free = combine 0 0 0 0 0 a11 a12 a22 ax ay az bx by bz c0
      | otherwise = ( a22, bx - a12 * y0x, by - a12 * y0y, bz - a12 * y0z
                    , c0 - 2 * (y0x * ax + y0y * ay + y0z * az) + a11 * (y0x * y0x + y0y * y0y + y0z * y0z) )
    -- min over p_a of  (α|p_a|² − 2β·p_a + γ) + segment error, as a function of p_b
    combine :: Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double -> Double
            -> Double -> Double -> Double -> Double -> Double -> (Double, Double, Double, Double, Double)
    combine al gx gy gz ga a11 a12 a22 ax ay az bx by bz c0 =
      let dd = max 1e-300 (al + a11)
          ux = gx + ax; uy = gy + ay; uz = gz + az
          r = a12 / dd
      in (a22 - a12 * r, bx - r * ux, by - r * uy, bz - r * uz, ga + c0 - (ux * ux + uy * uy + uz * uz) / dd)
    {-# INLINE combine #-}
    keyOf :: Bool -> Double -> Double -> Double -> Double -> Double -> Double
    keyOf lastL al gx gy gz ga = if lastL then endValue al gx gy gz ga else minValue al gx gy gz ga
    {-# INLINE keyOf #-}
    minValue, endValue :: Double -> Double -> Double -> Double -> Double -> Double
    minValue al gx gy gz ga = ga - (gx * gx + gy * gy + gz * gz) / max 1e-300 al
    endValue al gx gy gz ga
      | free = minValue al gx gy gz ga
      | otherwise = al * (yNx * yNx + yNy * yNy + yNz * yNz) - 2 * (gx * yNx + gy * yNy + gz * yNz) + ga
    size j = hi j - lo j + 1
    offs = U.prescanl' (+) 0 (U.generate k (\j -> size j * beam))

    search :: ST s (U.Vector Int, Double)
    search = do
      back <- MU.replicate (U.last offs + size (k - 1) * beam) (-1 :: Int)
      let layer j (pfs, pcs, plo) = do
            let sz = size j
                lj = lo j
                hj = hi j
                lastL = j == k - 1
                loP = lo (j - 1); hiP = hi (j - 1)
            fs <- MU.replicate (sz * beam * 5) (0 :: Double)
            ks <- MU.replicate (sz * beam) (1 / 0 :: Double)
            cs <- MU.replicate sz (0 :: Int)
            let overB !b
                  | b > hj = pure ()
                  | otherwise = overA b (max loP (b - w)) (min hiP (b - 1)) >> overB (b + 1)
                overA !b !a !aHi
                  | a > aHi = pure ()
                  | otherwise = do
                      let !(!a11, !a12, !a22, !ax, !ay, !az, !bx, !by, !bz, !c0) = segment a b
                          !bi = b - lj
                      if j == 1
                        then do
                          let !(!al, !gx, !gy, !gz, !ga) = startFn a11 a12 a22 ax ay az bx by bz c0
                          offer beam back (U.unsafeIndex offs j) fs ks cs (keyOf lastL al gx gy gz ga) bi 0 al gx gy gz ga
                        else do
                          let !ai = a - plo
                          ca <- MU.unsafeRead pcs ai
                          let overS !sl
                                | sl >= ca = pure ()
                                | otherwise = do
                                    let !o = (ai * beam + sl) * 5
                                    pal <- MU.unsafeRead pfs o
                                    pgx <- MU.unsafeRead pfs (o + 1)
                                    pgy <- MU.unsafeRead pfs (o + 2)
                                    pgz <- MU.unsafeRead pfs (o + 3)
                                    pga <- MU.unsafeRead pfs (o + 4)
                                    let !(!al, !gx, !gy, !gz, !ga) = combine pal pgx pgy pgz pga a11 a12 a22 ax ay az bx by bz c0
                                    offer beam back (U.unsafeIndex offs j) fs ks cs (keyOf lastL al gx gy gz ga) bi (ai * beam + sl) al gx gy gz ga
                                    overS (sl + 1)
                          overS 0
                      overA b (a + 1) aHi
            overB lj
            pure (fs, cs, lj)
          go j prev | j == k = pure prev
                    | otherwise = layer j prev >>= go (j + 1)
      l0 <- (,,) <$> MU.replicate 0 0 <*> MU.replicate 1 1 <*> pure 0
      (fl, cl, _) <- go 1 l0
      cN <- MU.read cl 0
      if cN == 0 then pure (U.generate k (\j -> (j * (n - 1)) `div` (k - 1)), 1 / 0) else do
        [al, gx, gy, gz, ga] <- mapM (MU.read fl) [0 .. 4]
        let best = endValue al gx gy gz ga
        -- follow the back pointers (slot 0 of the last state is the best)
        let follow j bi sl acc
              | j == 0 = pure (0 : acc)
              | otherwise = do
                  p <- MU.read back (U.unsafeIndex offs j + bi * beam + sl)
                  let (ai, sl') = p `divMod` beam
                  follow (j - 1) ai sl' ((lo j + bi) : acc)
        idx <- follow (k - 1) 0 0 []
        pure (U.fromList idx, best)

-- | Insert a function (α, β, γ) with its key into state bi's slots (sorted by key, at most
-- @beam@) when it ranks among them, with its back pointer.
offer :: Int -> MU.MVector s Int -> Int -> MU.MVector s Double -> MU.MVector s Double -> MU.MVector s Int
      -> Double -> Int -> Int -> Double -> Double -> Double -> Double -> Double -> ST s ()
offer !beam back !layerOff fs ks cs !key !bi !from !al !gx !gy !gz !ga = do
  cb <- MU.unsafeRead cs bi
  worst <- if cb < beam then pure (1 / 0) else MU.unsafeRead ks (bi * beam + beam - 1)
  when (cb < beam || key < worst) $ do
    let len = min beam (cb + 1)
        bOff = layerOff + bi * beam
        place i
          | i == 0 = pure 0
          | otherwise = do
              kp <- MU.unsafeRead ks (bi * beam + i - 1)
              if kp <= key then pure i else do
                MU.unsafeWrite ks (bi * beam + i) kp
                forM_ [0 .. 4] $ \q -> MU.unsafeRead fs ((bi * beam + i - 1) * 5 + q) >>= MU.unsafeWrite fs ((bi * beam + i) * 5 + q)
                MU.unsafeRead back (bOff + i - 1) >>= MU.unsafeWrite back (bOff + i)
                place (i - 1)
    pos <- place (len - 1)
    let o = (bi * beam + pos) * 5
    MU.unsafeWrite ks (bi * beam + pos) key
    MU.unsafeWrite fs o al
    MU.unsafeWrite fs (o + 1) gx
    MU.unsafeWrite fs (o + 2) gy
    MU.unsafeWrite fs (o + 3) gz
    MU.unsafeWrite fs (o + 4) ga
    MU.unsafeWrite back (bOff + pos) from
    MU.unsafeWrite cs bi len
