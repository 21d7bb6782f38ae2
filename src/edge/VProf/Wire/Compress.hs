{-# LANGUAGE TypeFamilies #-}
{-# LANGUAGE OverloadedStrings #-}
-- | Path compression on the wire: 'CompressRequestMsg' to the domain (with validation
-- errors that name the proto field and the value) and the result to 'CompressedPathMsg'.
--
-- Weights on the wire are SI (1/m², 1/rad², s²/m²); 0 means the default, which is the
-- thesis's @vekt = [1 1 1]@ in its units (mm, degrees, m/s): position 1, orientation
-- (180/π)²·10⁻⁶ ≈ 3.28·10⁻³, velocity 10⁻⁶ (see 'thesisWeights').
module VProf.Wire.Compress
  ( requestToDomain
  , requestToDomainW
  , wireLocator
  , posesToTrack
  , trackToPoses
  , metricsToMsg
  , outcomeToMsg
  , errorResponse
  ) where

import Data.ProtocolBuffers (getField, putField)
import qualified Data.Text as T
import qualified Data.Vector.Unboxed as U
import Data.Word (Word64)
import Numeric (showFFloat)
import Numeric.Units.Dimensional.Prelude (metre, (*~))
import Prelude

import VProf.Compress
import VProf.Compress.Clean
import VProf.Geometry.Vec
import VProf.Wire.Messages

-- | Validate a request and turn it into a recording and settings. A field left at 0 takes
-- its default; the settings are then checked by the core ('validateSettings'), whose
-- field names are the proto's. The recording is cleaned by the same rules as a file
-- ("VProf.Compress.Clean", default options: duplicates merged, no outlier rejection).
requestToDomain :: CompressRequestMsg -> Either [FieldError] (Recording, Settings)
requestToDomain = fmap (\(r, s, _) -> (r, s)) . requestToDomainW

-- | 'requestToDomain' with what cleaning the recording changed (samples named by index,
-- see 'wireLocator'). The response has no field for them yet.
requestToDomainW :: CompressRequestMsg -> Either [FieldError] (Recording, Settings, [CleanWarning])
requestToDomainW m = do
  poses <- maybe (Left [literalError "recording" "" "is missing: it must hold at least 2 poses"]) Right
                 (getField (crqRecording m))
  cl <- posesToTrack poses
  let tr = clTrack cl
      n = U.length (tTime tr)
      wpos = orDefault (getField (crqWeightPosition m))
      wori = orDefault (getField (crqWeightOrientation m))
      wvel = orDefault (getField (crqWeightVelocity m))
      Weights dp doo dv = defaultWeights
      pts = orDefault (getField (crqPoints m))
      margin = orDefault (getField (crqMargin m))
      tol = orDefault (getField (crqTolerance m))
      -- the default is the CLI's: the knot fit (which runs the thesis method for a margin)
      method = case getEnum (getField (crqMethod m)) of
        CompressRdp -> MethodRdp
        CompressThesis -> MethodThesis
        _ -> MethodKnots
      pick d v = if v == 0 then d else v
      settings = Settings
        { sMethod = method
        , sWeights = Weights (pick dp wpos) (pick doo wori) (pick dv wvel)
        , sPoints = if pts == 0 then Nothing else Just (fromIntegral pts)
        , sMargin = if margin == 0 then Nothing else Just margin
        , sTolerance = if tol == 0 then Nothing else Just (tol *~ metre)
        , sSearch = fromIntegral (orDefault (getField (crqSearchRounds m)))
        , sEnds = if orDefault (getField (crqFreeEnds m)) then EndsFree else EndsPinned
        , sPolish = not (orDefault (getField (crqLeastSquaresOnly m)))
        }
  case getEnum (getField (crqMethod m)) of
    CompressUnknown k -> Left [literalError "method" (show k) "is not a method: 0 (the default, knots), 1 (thesis), 2 (rdp) or 3 (knots)"]
    _ -> Right ()
  validated [map asSent (inUserTerms protoField (validateSettings n settings))] (Recording tr, settings, clWarnings cl)
  where
    protoField = \case
      "weights.position" -> Just (UserField "weight_position" "" 1)
      "weights.orientation" -> Just (UserField "weight_orientation" "" 1)
      "weights.velocity" -> Just (UserField "weight_velocity" "" 1)
      "search" -> Just (UserField "search_rounds" "" 1)
      "ends" -> Just (UserField "free_ends" "" 1)
      _ -> Nothing
    -- the core names the ends "free"; the wire sent a boolean
    asSent e | feField e == "free_ends" = e { feValue = Literal "true" }
             | otherwise = e

-- | How the wire names samples and fields: @recording.time@ and so on, samples by their
-- index from 0.
wireLocator :: Locator
wireLocator = indexLocator "recording"

-- | Poses on the wire to a cleaned track (default cleaning options); errors name the
-- field and the sample index.
posesToTrack :: PosesMsg -> Either [FieldError] Cleaned
posesToTrack p = do
  let ts = getField (posTime p)
      cols = [ ("recording.x", getField (posX p)), ("recording.y", getField (posY p)), ("recording.z", getField (posZ p))
             , ("recording.qw", getField (posQw p)), ("recording.qx", getField (posQx p))
             , ("recording.qy", getField (posQy p)), ("recording.qz", getField (posQz p)) ]
      n = length ts
  case [ (f, length c) | (f, c) <- cols, length c /= n ] of
    ((f, l) : _) -> Left [literalError f "" ("has " ++ show l ++ " values but recording.time has " ++ show n)]
    [] -> Right ()
  let [xs, ys, zs, qw, qx, qy, qz] = map snd cols
      samples = zipWith4' Sample [0 ..] ts (zipWith3 P3 xs ys zs) (zipWith4' Q4 qw qx qy qz)
  cleanSamples wireLocator defaultCleanOptions samples
  where
    zipWith4' f (a : as) (b : bs) (c : cs) (d : ds) = f a b c d : zipWith4' f as bs cs ds
    zipWith4' _ _ _ _ _ = []

trackToPoses :: Track -> PosesMsg
trackToPoses (Track ts ps qs) = PosesMsg
  { posTime = putField (U.toList ts)
  , posX = putField [ x | P3 x _ _ <- pl ], posY = putField [ y | P3 _ y _ <- pl ], posZ = putField [ z | P3 _ _ z <- pl ]
  , posQw = putField [ w | Q4 w _ _ _ <- ql ], posQx = putField [ x | Q4 _ x _ _ <- ql ]
  , posQy = putField [ y | Q4 _ _ y _ <- ql ], posQz = putField [ z | Q4 _ _ _ z <- ql ]
  }
  where pl = ptoList ps
        ql = ptoList qs

metricsToMsg :: Metrics -> CompressMetricsMsg
metricsToMsg m = CompressMetricsMsg
  { cmPositionSse = d (mPositionSse m), cmPositionRmse = d (mPositionRmse m)
  , cmPositionMean = d (mPositionMean m), cmPositionMax = d (mPositionMax m)
  , cmOrientationRmse = d (mOrientationRmse m), cmOrientationMean = d (mOrientationMean m)
  , cmOrientationMax = d (mOrientationMax m)
  , cmVelocityRmse = d (mVelocityRmse m), cmVelocityMean = d (mVelocityMean m), cmVelocityMax = d (mVelocityMax m)
  , cmGeometricRmse = d (mGeometricRmse m), cmGeometricMax = d (mGeometricMax m)
  , cmLengthRatio = d (mLengthRatio m), cmOrientationRatio = d (mOrientationRatio m)
  , cmPoints = putField (nonDefault (fromIntegral (mPoints m)))
  , cmSamples = putField (nonDefault (fromIntegral (mSamples m)))
  , cmReduction = d (mReduction m)
  }
  where d x = putField (nonDefault x)

-- | A compressed path as the response, with the warnings of cleaning its recording.
outcomeToMsg :: Word64 -> Double -> [String] -> Compressed -> CompressedPathMsg
outcomeToMsg rid secs warns o = CompressedPathMsg
  { cpRequestId = putField (nonDefault rid)
  , cpPath = putField (Just (trackToPoses (pathTrack (oPath o))))
  , cpMetrics = putField (Just (metricsToMsg (oMetrics o)))
  , cpComputeTime = putField (nonDefault secs)
  , cpError = putField errTol
  , cpWarnings = putField (map T.pack warns)
  }
  where
    errTol | oToleranceMet o = Nothing
           | otherwise = Just (mkError ErrInfeasible "tolerance"
                                ("tolerance not met: largest position error "
                                 ++ showFFloat (Just 7) (mPositionMax (oMetrics o)) " m with " ++ show (mPoints (oMetrics o))
                                 ++ " points, the most the thesis method reaches (about 15 % of the samples);"
                                 ++ " the path is that one. For a finer one ask for more points (the points field) or a larger tolerance"))

mkError :: ErrorCodeEnum -> String -> String -> ErrorMsg
mkError code field msg = ErrorMsg
  { errCode = putField (enumField code)
  , errField = putField (nonDefault (T.pack field))
  , errMessage = putField (nonDefault (T.pack msg))
  }

errorResponse :: Word64 -> Double -> ErrorCodeEnum -> String -> String -> CompressedPathMsg
errorResponse rid secs code field msg = CompressedPathMsg
  { cpRequestId = putField (nonDefault rid)
  , cpPath = putField Nothing
  , cpMetrics = putField Nothing
  , cpComputeTime = putField (nonDefault secs)
  , cpError = putField (Just (mkError code field msg))
  , cpWarnings = putField []
  }
