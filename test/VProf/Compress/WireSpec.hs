{-# LANGUAGE DataKinds #-}
-- | The protobuf side: request validation, conversion and serveCompress.
module VProf.Compress.WireSpec (spec) where

import qualified Data.ByteString as B
import Data.ProtocolBuffers (getField, putField)
import Data.List (isInfixOf)
import qualified Data.Text as T
import qualified Data.Vector.Unboxed as U
import Test.Hspec

import VProf.Compress
import VProf.Compress.Clean
import VProf.Geometry.Vec (P3 (..), pifilter, pindex, ptoList)
import Support.Recordings
import Support.WireError (errorShouldBe)
import VProf.Service.Compress (serveCompress, serveCompressWithin)
import VProf.Wire.Compress
import VProf.Wire.Messages
import VProf.Wire.Validate (MsgType (..), validateWire)

request :: Track -> Word -> CompressRequestMsg
request tr pts = CompressRequestMsg
  { crqRequestId = putField (Just 7)
  , crqRecording = putField (Just (trackToPoses tr))
  , crqMethod = putField Nothing
  , crqPoints = putField (nonDefault (fromIntegral pts))
  , crqMargin = putField Nothing
  , crqTolerance = putField Nothing
  , crqWeightPosition = putField Nothing
  , crqWeightOrientation = putField Nothing
  , crqWeightVelocity = putField Nothing
  , crqSearchRounds = putField Nothing
  , crqFreeEnds = putField Nothing
  , crqLeastSquaresOnly = putField Nothing
  }

spec :: Spec
spec = describe "serveCompress" $ do
  it "compresses a recording sent as Poses, echoes the id, measures compute time, survives encode/decode" $ do
    Recording tr <- loadTum "freiburg1_xyz-groundtruth.txt"
    let req = request tr 60
    decodeBare (encodeBare req) `shouldBe` Right req
    rsp <- serveCompress req
    getField (cpRequestId rsp) `shouldBe` Just 7
    getField (cpError rsp) `shouldBe` Nothing
    let Just path = getField (cpPath rsp)
        Just m = getField (cpMetrics rsp)
    length (getField (posTime path)) `shouldBe` 60
    getField (cmPoints m) `shouldBe` Just 60
    getField (cmSamples m) `shouldBe` Just 3000
    fmap (> 0) (getField (cpComputeTime rsp)) `shouldBe` Just True
    head (getField (posTime path)) `shouldBe` U.head (tTime tr)
    decodeBare (encodeBare rsp) `shouldBe` Right rsp
    -- a clean recording (but for one gap) has no other warning
    map T.unpack (getField (cpWarnings rsp)) `shouldSatisfy` all ("1 gap" `isInfixOf`)
  it "fits by the CLI's method: DEFAULT and KNOTS the knot fit, THESIS the thesis method, RDP the baseline" $ do
    Recording tr0 <- loadTum "freiburg1_xyz-groundtruth.txt"
    let tr = Track (U.take 600 (tTime tr0)) (pifilter (< 600) (tPos tr0)) (pifilter (< 600) (tRot tr0))
        timesBy meth = do
          rsp <- serveCompress (request tr 18) { crqMethod = putField meth }
          pure (fmap (U.fromList . getField . posTime) (getField (cpPath rsp)))
        core meth = either (error . show) (tTime . pathTrack . oPath)
                      (compress defaultSettings { sMethod = meth, sPoints = Just 18 } (Recording tr))
    wireDefault <- timesBy Nothing
    wireKnots <- timesBy (Just CompressKnots)
    wireThesis <- timesBy (Just CompressThesis)
    wireRdp <- timesBy (Just CompressRdp)
    wireDefault `shouldBe` Just (core MethodKnots)
    wireKnots `shouldBe` Just (core MethodKnots)
    wireThesis `shouldBe` Just (core MethodThesis)
    wireRdp `shouldBe` Just (core MethodRdp)
    -- the knot fit and the thesis method are different algorithms: their times differ here
    core MethodKnots `shouldNotBe` core MethodThesis

  it "search_rounds runs the CLI's wider search (the same path as --search), and is refused for the thesis method" $ do
    Recording tr0 <- loadTum "freiburg1_xyz-groundtruth.txt"
    let tr = Track (U.take 600 (tTime tr0)) (pifilter (< 600) (tPos tr0)) (pifilter (< 600) (tRot tr0))
    rsp <- serveCompress (request tr 12) { crqSearchRounds = putField (Just 3) }
    let core = either (error . show) (tTime . pathTrack . oPath)
                 (compress defaultSettings { sPoints = Just 12, sSearch = 3 } (Recording tr))
    fmap (U.fromList . getField . posTime) (getField (cpPath rsp)) `shouldBe` Just core
    bad <- serveCompress (request tr 12) { crqSearchRounds = putField (Just 3), crqMethod = putField (Just CompressThesis) }
    let Just err = getField (cpError bad)
    getEnum (getField (errCode err)) `shouldBe` ErrInvalidArgument
    getField (errField err) `shouldBe` Just (T.pack "search_rounds")
  it "free_ends fits the first and last waypoint as --ends free does, and is refused for RDP naming free_ends" $ do
    Recording tr0 <- loadTum "freiburg1_xyz-groundtruth.txt"
    let tr = Track (U.take 600 (tTime tr0)) (pifilter (< 600) (tPos tr0)) (pifilter (< 600) (tRot tr0))
    rsp <- serveCompress (request tr 12) { crqFreeEnds = putField (Just True) }
    let core = either (error . show) (tPos . pathTrack . oPath)
                 (compress defaultSettings { sPoints = Just 12, sEnds = EndsFree } (Recording tr))
        xs = fmap (getField . posX) (getField (cpPath rsp))
    xs `shouldBe` Just [ x | P3 x _ _ <- ptoList core ]
    -- fitted, not pinned: the first waypoint is not the first sample
    fmap head xs `shouldNotBe` Just (let P3 x _ _ = pindex (tPos tr) 0 in x)
    bad <- serveCompress (request tr 12) { crqFreeEnds = putField (Just True), crqMethod = putField (Just CompressRdp) }
    errorShouldBe (getField (cpError bad)) ErrInvalidArgument "free_ends" "free_ends = true"
  it "least_squares_only skips the orientation balance and the worst-error polish as --least-squares-only does: the core's times and positions either way, a larger largest error than the default's" $ do
    Recording tr0 <- loadTum "freiburg1_xyz-groundtruth.txt"
    let tr = Track (U.take 600 (tTime tr0)) (pifilter (< 600) (tPos tr0)) (pifilter (< 600) (tRot tr0))
        xsOf rsp = fmap (getField . posX) (getField (cpPath rsp))
        maxOf rsp = getField . cmPositionMax =<< getField (cpMetrics rsp)
        core polish = either (error . show) (pathTrack . oPath)
                        (compress defaultSettings { sPoints = Just 12, sPolish = polish } (Recording tr))
    plain <- serveCompress (request tr 12) { crqLeastSquaresOnly = putField (Just True) }
    polished <- serveCompress (request tr 12)
    xsOf plain `shouldBe` Just [ x | P3 x _ _ <- ptoList (tPos (core False)) ]
    xsOf polished `shouldBe` Just [ x | P3 x _ _ <- ptoList (tPos (core True)) ]
    fmap (U.fromList . getField . posTime) (getField (cpPath plain)) `shouldBe` Just (tTime (core False))
    fmap (U.fromList . getField . posTime) (getField (cpPath polished)) `shouldBe` Just (tTime (core True))
    ((<) <$> maxOf polished <*> maxOf plain) `shouldBe` Just True
  it "answers NOT_CONVERGED naming search_rounds (or the tolerance) when the compression outlasts the time limit (was the server's INTERNAL)" $ do
    Recording tr <- loadTum "freiburg1_xyz-groundtruth.txt"
    rsp <- serveCompressWithin 0.05 (request tr 90) { crqSearchRounds = putField (Just 50) }
    errorShouldBe (getField (cpError rsp)) ErrNotConverged "search_rounds" "0.05 s"
    -- the search for the fewest points within a tolerance names the tolerance
    tolRsp <- serveCompressWithin 0.05 (request tr 0) { crqTolerance = putField (Just 1e-6) }
    errorShouldBe (getField (cpError tolRsp)) ErrNotConverged "tolerance" "tolerance = 0.000001 m"
  it "refuses a method number it does not know (7, -1 as sent) naming method, instead of running the default" $ do
    Recording tr0 <- loadTum "freiburg1_xyz-groundtruth.txt"
    let tr = Track (U.take 300 (tTime tr0)) (pifilter (< 300) (tPos tr0)) (pifilter (< 300) (tRot tr0))
        -- field 3 (varint, tag 0x18) appended as a newer client would send it
        withMethod bytes = either error id (decodeBare (encodeBare (request tr 12) <> B.pack (0x18 : bytes))) :: CompressRequestMsg
    mapM_ (\(bytes, shown) -> do
             bad <- serveCompress (withMethod bytes)
             errorShouldBe (getField (cpError bad)) ErrInvalidArgument "method" shown
             getField (cpPath bad) `shouldBe` Nothing)
          [([7], "7"), (replicate 9 0xff ++ [0x01], "-1")]
    -- a known number still runs
    ok <- serveCompress (withMethod [2])
    getField (cpError ok) `shouldBe` Nothing
  it "answers a bad request with INVALID_ARGUMENT naming the field and the value" $ do
    Recording tr <- loadTum "freiburg1_xyz-groundtruth.txt"
    let req = (request tr 60) { crqMargin = putField (Just 0.5) }
    rsp <- serveCompress req
    let Just err = getField (cpError rsp)
    getEnum (getField (errCode err)) `shouldBe` ErrInvalidArgument
    getField (errField err) `shouldBe` Just (T.pack "margin")
    fmap (T.isInfixOf (T.pack "0.5")) (getField (errMessage err)) `shouldBe` Just True
    getField (cpPath rsp) `shouldBe` Nothing
  it "names recording.time and the sample when times go backwards" $ do
    let poses = PosesMsg (putField [2, 1]) (putField [0, 0]) (putField [0, 0]) (putField [0, 0])
                         (putField [1, 1]) (putField [0, 0]) (putField [0, 0]) (putField [0, 0])
        req = CompressRequestMsg (putField Nothing) (putField (Just poses)) (putField Nothing) (putField Nothing)
                (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing)
                (putField Nothing)
    rsp <- serveCompress req
    let Just err = getField (cpError rsp)
    getEnum (getField (errCode err)) `shouldBe` ErrInvalidArgument
    getField (errField err) `shouldBe` Just (T.pack "recording.time")
    fmap (T.isInfixOf (T.pack "sample 1")) (getField (errMessage err)) `shouldBe` Just True
  it "cleans a recording sent over the wire as a file is: a duplicated time with another pose is merged" $ do
    Recording tr <- loadTum "freiburg1_xyz-groundtruth.txt"
    let poses = trackToPoses tr
        dupWith f k xs = take (k + 1) xs ++ [f (xs !! k)] ++ drop (k + 1) xs
        dupAt = dupWith id
        req = (request tr 60) { crqRecording = putField (Just poses
                 { posTime = putField (dupAt 700 (getField (posTime poses)))
                 , posX = putField (dupWith (+ 0.01) 700 (getField (posX poses))) -- the copy 1 cm away
                 , posY = putField (dupAt 700 (getField (posY poses))), posZ = putField (dupAt 700 (getField (posZ poses)))
                 , posQw = putField (dupAt 700 (getField (posQw poses))), posQx = putField (dupAt 700 (getField (posQx poses)))
                 , posQy = putField (dupAt 700 (getField (posQy poses))), posQz = putField (dupAt 700 (getField (posQz poses))) }) }
    case requestToDomainW req of
      Left e -> expectationFailure (show e)
      Right (Recording tr', _, ws) -> do
        trackLength tr' `shouldBe` 3000
        map warningCount ws `shouldSatisfy` (1 `elem`)
        any (\w -> case w of DuplicateTimes _ 1 1 [(_, [700, 701])] -> True; _ -> False) ws `shouldBe` True
    rsp <- serveCompress req
    getField (cpError rsp) `shouldBe` Nothing
    fmap (getField . cmSamples) (getField (cpMetrics rsp)) `shouldBe` Just (Just 3000)
    -- the response's warnings (field 6) say so, naming the samples by index
    map T.unpack (getField (cpWarnings rsp)) `shouldSatisfy` any ("at sample 700, sample 701" `isInfixOf`)
    decodeBare (encodeBare rsp) `shouldBe` Right rsp
    validateWire TCompressedPath (encodeBare rsp) `shouldBe` Right ()
  it "drops samples sent without a pose (NaN components, a zero quaternion) and says which; an infinite value is refused" $ do
    Recording tr <- loadTum "freiburg1_xyz-groundtruth.txt"
    let poses = trackToPoses tr
        setAt k v xs = take k xs ++ [v] ++ drop (k + 1) xs
        req = (request tr 60) { crqRecording = putField (Just poses
                 { posX = putField (setAt 500 (0 / 0) (getField (posX poses)))
                 , posQw = putField (setAt 900 0 (getField (posQw poses))), posQx = putField (setAt 900 0 (getField (posQx poses)))
                 , posQy = putField (setAt 900 0 (getField (posQy poses))), posQz = putField (setAt 900 0 (getField (posQz poses))) }) }
    rsp <- serveCompress req
    getField (cpError rsp) `shouldBe` Nothing
    fmap (getField . cmSamples) (getField (cpMetrics rsp)) `shouldBe` Just (Just 2998)
    map T.unpack (getField (cpWarnings rsp)) `shouldSatisfy` any (\w -> "2 samples without a pose" `isInfixOf` w
                                                                   && "at sample 500" `isInfixOf` w && "at sample 900" `isInfixOf` w)
    let inf = (request tr 60) { crqRecording = putField (Just poses { posY = putField (setAt 500 (1 / 0) (getField (posY poses))) }) }
    rspI <- serveCompress inf
    let Just err = getField (cpError rspI)
    getEnum (getField (errCode err)) `shouldBe` ErrInvalidArgument
    getField (errField err) `shouldBe` Just (T.pack "recording.position")
    fmap (T.isInfixOf (T.pack "sample 500")) (getField (errMessage err)) `shouldBe` Just True
  it "names the missing recording" $ do
    let req = CompressRequestMsg (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing)
                (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing) (putField Nothing)
                (putField Nothing)
    rsp <- serveCompress req
    let Just err = getField (cpError rsp)
    getField (errField err) `shouldBe` Just (T.pack "recording")
  it "to a tolerance by default (the knot fit): met, no error, and points is the fewest allowed" $ do
    Recording tr <- loadTum "freiburg1_xyz-groundtruth.txt"
    let maxOf rsp = fmap (getField . cmPositionMax) (getField (cpMetrics rsp))
        count rsp = fmap (length . getField . posTime) (getField (cpPath rsp))
    free <- serveCompress (request tr 0) { crqTolerance = putField (Just 10e-3) }
    floored <- serveCompress (request tr 120) { crqTolerance = putField (Just 10e-3) }
    mapM_ (\rsp -> do
             getField (cpError rsp) `shouldBe` Nothing
             maxOf rsp `shouldSatisfy` maybe False (maybe False (<= 10e-3))) [free, floored]
    count free `shouldSatisfy` maybe False (\k -> k > 2 && k < 120)
    count floored `shouldSatisfy` maybe False (>= 120)
  it "reports a tolerance the thesis method does not meet as INFEASIBLE with the best path" $ do
    Recording tr <- loadTum "freiburg1_xyz-groundtruth.txt"
    let req = (request tr 0) { crqTolerance = putField (Just 1e-7), crqMethod = putField (Just CompressThesis) }
    rsp <- serveCompress req
    let Just err = getField (cpError rsp)
    getEnum (getField (errCode err)) `shouldBe` ErrInfeasible
    fmap (not . null . getField . posTime) (getField (cpPath rsp)) `shouldBe` Just True
