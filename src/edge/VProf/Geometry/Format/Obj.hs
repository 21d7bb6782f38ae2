{-# LANGUAGE OverloadedStrings, BangPatterns #-}
-- | Wavefront OBJ meshes into a 'Mesh' (strict ByteString, one pass).
--
-- Read: @v x y z@ (a fourth weight or trailing vertex colours are ignored) and @f@ with vertices
-- written @v@, @v/vt@, @v//vn@ or @v/vt/vn@, 1-based or negative (relative: −1 is the last vertex
-- defined so far); a polygon is fan-triangulated (v0 v1 v2, v0 v2 v3, …). Accepted and ignored:
-- @o g s usemtl mtllib vn vt vp l p@, comments (@#@) and blank lines. Any other statement is an
-- error. Every error names the line number and quotes the line: a bad number, a vertex index 0 or
-- out of range, a face with fewer than three vertices, a coordinate that is not finite or whose
-- magnitude exceeds 'maxCoordinate'; a file with no faces is an error too. Coordinates are as in
-- the file (scale and pose them with 'VProf.Geometry.Mesh.composeScene').
module VProf.Geometry.Format.Obj
  ( parseObj
  , readObj
  , readDouble
  ) where

import Control.Exception (IOException, try)
import VProf.Format.IOError (ioReason)
import VProf.Format.Text (dropBom)
import qualified Data.ByteString as BS
import qualified Data.ByteString.Char8 as BC
import qualified Data.Vector.Unboxed as U
import qualified Data.Vector.Unboxed.Mutable as MU
import Control.Monad.ST (runST)
import Data.STRef
import Control.Monad (forM_, when)

import VProf.Format.Number (readDouble)
import VProf.Geometry.Mesh (Mesh (..))
import VProf.Validation

-- | Reads and parses an OBJ file; errors are prefixed with the path.
readObj :: FilePath -> IO (Either String Mesh)
readObj path = do
  r <- try (BS.readFile path)
  pure $ case r of
    Left (e :: IOException) -> Left ("cannot read " ++ path ++ ": " ++ ioReason e)
    Right bs -> either (Left . ((path ++ ": ") ++) . renderFieldError) Right (parseObj bs)

data Stmt = SVertex !Double !Double !Double | SFace [Int] | SSkip

-- | The triangles of an OBJ text, or the first error ("line 12 = f 1 2: a face needs at least 3
-- vertices").
parseObj :: BS.ByteString -> Either FieldError Mesh
parseObj bs = go 1 0 [] [] (BC.lines (dropBom bs))
  where
    -- vertex count, vertices (reversed, flat xyz), triangles (reversed, vertex indices)
    go :: Int -> Int -> [Double] -> [[Int]] -> [BS.ByteString] -> Either FieldError Mesh
    go !_ !nv vs fs [] = finish nv vs fs
    go !ln !nv vs fs (l : ls) = case statement nv (stripCR l) of
      Left rule -> Left (literalError ("line " ++ show ln) (BC.unpack (BC.strip (stripCR l))) rule)
      Right SSkip -> go (ln + 1) nv vs fs ls
      Right (SVertex x y z) -> go (ln + 1) (nv + 1) (z : y : x : vs) fs ls
      Right (SFace ix) -> go (ln + 1) nv vs (ix : fs) ls
    stripCR l = if not (BS.null l) && BC.last l == '\r' then BS.init l else l
    finish nv vs fs
      | null fs = Left (literalError "faces" "" "no faces in the file (an empty mesh)")
      | otherwise =
          let verts = U.fromListN (3 * nv) (reverse vs)
              tris = concatMap fan (reverse fs)
              nt = length tris
          in Right . Mesh $ runST $ do
               m <- MU.unsafeNew (9 * nt)
               k <- newSTRef (0 :: Int)
               forM_ tris $ \(a, b, c) -> do
                 i <- readSTRef k
                 forM_ (zip [0, 3, 6] [a, b, c]) $ \(o, vi) ->
                   forM_ [0, 1, 2] $ \j -> MU.unsafeWrite m (9 * i + o + j) (U.unsafeIndex verts (3 * vi + j))
                 writeSTRef k (i + 1)
               U.unsafeFreeze m
    fan (v0 : rest) = zipWith (\a b -> (v0, a, b)) rest (drop 1 rest)
    fan [] = []

statement :: Int -> BS.ByteString -> Either String Stmt
statement nv l = case BC.words (BC.takeWhile (/= '#') l) of
  [] -> Right SSkip
  (k : args)
    | k == "v" -> vertex args
    | k == "f" -> face args
    | k `elem` ignored -> Right SSkip
    | otherwise -> Left ("unknown statement " ++ show (BC.unpack k))
  where
    ignored = ["o", "g", "s", "usemtl", "mtllib", "vn", "vt", "vp", "l", "p"]
    vertex args
      | length args < 3 = Left "a vertex needs three coordinates x y z"
      | otherwise = do
          (x, y, z) <- case args of
            (a : b : c : _) -> (,,) <$> coord a <*> coord b <*> coord c
            _ -> Left "a vertex needs three coordinates x y z"
          mapM_ number (drop 3 args)
          Right (SVertex x y z)
    coord t = do
      x <- number t
      if isNaN x || isInfinite x then Left ("coordinate " ++ BC.unpack t ++ " is not a finite number")
      else if abs x > maxCoordinate then Left ("coordinate " ++ BC.unpack t ++ " is absurdly large (magnitude above 1e9)")
      else Right x
    number t = maybe (Left ("bad number " ++ show (BC.unpack t))) Right (readDouble t)
    face args
      | length args < 3 = Left ("a face needs at least 3 vertices, this one has " ++ show (length args))
      | otherwise = SFace <$> mapM corner args
    corner t = do
      let (vpart, rest) = case BC.split '/' t of
            (x : xs) -> (x, xs)
            [] -> (t, [])
      when (length rest > 2) (Left ("bad face vertex " ++ show (BC.unpack t)))
      mapM_ (\p -> if BS.null p || isInt p then Right () else Left ("bad index in face vertex " ++ show (BC.unpack t))) rest
      when (length rest == 2 && BS.null (head rest) && BS.null (rest !! 1)) (Left ("bad face vertex " ++ show (BC.unpack t)))
      -- read as an Integer: an Int would wrap 18446744073709551617 round to 1
      i <- case BC.readInteger vpart of
        Just (i, r) | BS.null r -> Right i
        _ -> Left ("bad vertex index " ++ show (BC.unpack t))
      let a | i > 0 = i - 1
            | otherwise = fromIntegral nv + i
      if i == 0 then Left ("vertex index 0 in " ++ show (BC.unpack t) ++ " (indices start at 1)")
      else if a < 0 || a >= fromIntegral nv
        then Left ("vertex index " ++ show i ++ " out of range (" ++ show nv ++ " vertices defined so far)")
        else Right (fromIntegral a)
    isInt p = case BC.readInteger p of Just (_, r) -> BS.null r; Nothing -> False
