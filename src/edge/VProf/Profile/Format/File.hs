{-# LANGUAGE OverloadedStrings #-}
-- | Profile requests and profiles as files, by extension: a request is proto3 JSON
-- (@.json@) or a binary ProfileRequest (anything else); a profile is CSV (@.csv@), JSON
-- (@.json@) or a binary ProfileResponse. Every failure is a message naming the file (and
-- the line, for CSV).
module VProf.Profile.Format.File
  ( readRequest
  , readRequestWithId
  , readProfile
  ) where

import Control.Exception (IOException, try)
import qualified Data.Aeson as A
import qualified Data.ByteString as B
import qualified Data.ByteString.Lazy as BL
import qualified Data.ByteString.Lazy.Char8 as BLC
import Data.Char (isSpace, toLower)
import Data.List (elemIndex, intercalate)
import Data.ProtocolBuffers (getField)
import Data.Word (Word64)
import qualified Data.Vector.Unboxed as U
import System.FilePath (takeExtension)

import VProf.Format.IOError (ioReason)
import VProf.Format.Text (dropBom)
import VProf.Format.DuplicateKeys (duplicateJsonKeyErrors)
import VProf.Profile.Format.Json
import VProf.Profile.Request
import VProf.Wire.Messages
import VProf.Wire.Profile
import VProf.Wire.Packing (packRepeated)
import VProf.Wire.Validate (MsgType (..), validateWire)

-- | Read a request file; Left is a message for the user.
readRequest :: FilePath -> IO (Either String Request)
readRequest path = fmap snd <$> readRequestWithId path

-- | 'readRequest' with the request's @request_id@ (0 when it has none), which the answer echoes.
readRequestWithId :: FilePath -> IO (Either String (Word64, Request))
readRequestWithId path = do
  r <- try (B.readFile path)
  pure $ case r of
    Left (e :: IOException) -> Left (path ++ ": " ++ ioReason e)
    Right bytes
      | map toLower (takeExtension path) == ".json" ->
          let lazy = BL.fromStrict bytes
          in either (\e -> Left (path ++ ": not a valid JSON ProfileRequest: " ++ e)) Right
                    ((,) <$> requestIdFromJson lazy <*> requestFromJson lazy)
      | otherwise -> case validateWire TProfileRequest bytes >> decodeBare (packRepeated TProfileRequest bytes) of
          Left e -> Left (path ++ ": not a valid binary ProfileRequest: " ++ e)
          Right m -> Right (maybe 0 id (getField (prqRequestId m)), requestFromMsg m)

-- | A profile file: the time step and the velocities.
readProfile :: FilePath -> IO (Either String (Double, U.Vector Double))
readProfile path = do
  r <- try (B.readFile path)
  pure $ case r of
    Left (e :: IOException) -> Left (path ++ ": " ++ ioReason e)
    Right bytes0 -> let bytes = dropBom bytes0 in case map toLower (takeExtension path) of
      ".csv" -> fromColumns =<< parseCsv (BLC.unpack (BL.fromStrict bytes))
      ".json" -> case A.eitherDecodeStrict bytes of
        Left e -> Left (path ++ ": " ++ e)
        Right (A.Object _) | dups@(_ : _) <- duplicateJsonKeyErrors bytes -> Left (path ++ ": " ++ intercalate "; " dups)
        Right (A.Object _) -> case A.eitherDecodeStrict bytes :: Either String ProfileJson of
          Left e -> Left (path ++ ": " ++ e)
          Right (ProfileJson ts vs) -> sameLength ts vs >> fromColumns (zip ts vs)
        Right _ -> Left (path ++ ": expected a JSON object with time and velocity arrays")
      _ -> case validateWire TProfileResponse bytes >> decodeBare (packRepeated TProfileResponse bytes) of
        Left e -> Left (path ++ ": not a binary ProfileResponse: " ++ e)
        Right m -> let ts = getField (prsTime m); vs = getField (prsVelocity m)
                   in sameLength ts vs >> fromColumns (zip ts vs)
  where
    -- the header names the columns (vprof writes t,s,v,a,j); every row has as many
    parseCsv txt = case [ (i, filter (/= '\r') l) | (i, l) <- zip [1 :: Int ..] (lines txt) ] of
      (_, hdr) : rest -> do
        let names = map strip (splitOn ',' hdr)
            col n = maybe (Left (path ++ ":1: the header " ++ show hdr ++ " names no column " ++ n
                                 ++ " (expected t,s,v,a,j as vprof writes it)")) Right (elemIndex n names)
        tc <- col "t"
        vc <- col "v"
        mapM (parseRow (length names) tc vc) [ r | r@(_, l) <- rest, not (all isSpace l) ]
      [] -> Left (path ++ ": empty; expected a CSV header t,s,v,a,j and a row a sample")
    parseRow n tc vc (ln, row) =
      let fs = map strip (splitOn ',' row)
      in if length fs /= n
           then Left (path ++ ":" ++ show ln ++ ": expected " ++ show n ++ " columns as in the header, got "
                      ++ show (length fs) ++ ": " ++ show row)
           else case (reads (fs !! tc), reads (fs !! vc)) of
             ([(t', "")], [(v', "")]) -> Right (t', v')
             _ -> Left (path ++ ":" ++ show ln ++ ": cannot read t and v from " ++ show row)
    strip = dropWhile isSpace . reverse . dropWhile isSpace . reverse
    splitOn c s = case break (== c) s of
      (a, _ : b) -> a : splitOn c b
      (a, []) -> [a]
    sameLength ts vs
      | length ts == length vs = Right ()
      | otherwise = Left (path ++ ": time has " ++ show (length ts) ++ " values but velocity " ++ show (length vs)
                          ++ " (one of each a sample)")
    fromColumns :: [(Double, Double)] -> Either String (Double, U.Vector Double)
    fromColumns rows = case rows of
      _ | ((k, t) : _) <- [ (k, t) | (k, (t, _)) <- zip [0 :: Int ..] rows, isNaN t || isInfinite t ] ->
            Left (path ++ ": sample " ++ show k ++ ": its time " ++ show t ++ " is not a finite number")
      ((t0, _) : _) | t0 /= 0 -> Left (path ++ ": the first sample is at t = " ++ show t0 ++ " s; sample k is at k times the time step, from 0")
      ((t0, _) : (t1, _) : _) ->
        let dt = t1 - t0
            uneven = [ (k, t) | (k, (t, _)) <- zip [0 :: Int ..] rows, abs (t - (t0 + fromIntegral k * dt)) > 1e-9 * max 1 (abs t) ]
        in if dt <= 0 then Left (path ++ ": sample 1 is at t = " ++ show t1 ++ " s, not after sample 0 at 0 s: times must increase by the time step")
           else case uneven of
             ((k, t) : _) -> Left (path ++ ": sample " ++ show k ++ " at t = " ++ show t ++ " is off the uniform time step " ++ show dt)
             [] -> Right (dt, U.fromList (map snd rows))
      [(_, v)] -> Right (1, U.singleton v)
      [] -> Left (path ++ ": no samples (a profile is read as CSV t,s,v,a,j from .csv, JSON from .json, a binary ProfileResponse from any other name)")

data ProfileJson = ProfileJson [Double] [Double]
instance A.FromJSON ProfileJson where
  parseJSON = A.withObject "profile" $ \o -> ProfileJson <$> o A..: "time" <*> o A..: "velocity"
