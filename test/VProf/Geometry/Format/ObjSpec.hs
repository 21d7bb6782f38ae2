{-# LANGUAGE OverloadedStrings #-}
-- | The OBJ reader: every face form, negative indices, polygons, ignored statements, errors that
-- name the line, an empty file, non-finite and huge coordinates, numbers, and the work cell of
-- ../shared/data/cell.
module VProf.Geometry.Format.ObjSpec (spec) where

import qualified Data.ByteString.Char8 as BC
import Data.Either (isLeft)
import Data.List (isInfixOf)
import qualified Data.Vector.Unboxed as U
import Test.Hspec
import Test.QuickCheck

import VProf.Geometry.Format.Obj
import VProf.Geometry.Format.Scene
import VProf.Geometry.Mesh
import VProf.Kinematics.Transform (V3 (..), trans, rotZ, compose)
import VProf.Validation (renderFieldError)

square :: BC.ByteString
square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n"

tri :: Double -> Double -> Double -> (V3, V3, V3)
tri _ _ _ = (V3 0 0 0, V3 1 0 0, V3 1 1 0)

ok :: BC.ByteString -> Mesh
ok s = either (error . renderFieldError) id (parseObj s)

err :: BC.ByteString -> String
err s = either renderFieldError (const "parsed") (parseObj s)

spec :: Spec
spec = describe "VProf.Geometry.Format.Obj" $ do
  it "reads every face form alike: v, v/vt, v//vn, v/vt/vn" $ do
    let expect = fromTriangles [tri 0 0 0]
    ok (square <> "f 1 2 3\n") `shouldBe` expect
    ok (square <> "f 1/1 2/2 3/3\n") `shouldBe` expect
    ok (square <> "f 1//1 2//1 3//1\n") `shouldBe` expect
    ok (square <> "f 1/1/1 2/2/1 3/3/1\n") `shouldBe` expect
  it "skips a UTF-8 byte-order mark before the first line (was 'unknown statement')" $
    ok ("\xEF\xBB\xBF" <> square <> "f 1 2 3\n") `shouldBe` ok (square <> "f 1 2 3\n")
  it "reads negative (relative) indices" $ do
    ok (square <> "f -4 -3 -2\n") `shouldBe` ok (square <> "f 1 2 3\n")
    ok ("v 9 9 9\n" <> square <> "f -4/-3/-1 -3/-2/-1 -2/-1/-1\n") `shouldBe` ok (square <> "f 1 2 3\n")
  it "fan-triangulates polygons" $
    ok (square <> "f 1 2 3 4\n") `shouldBe` fromTriangles [(V3 0 0 0, V3 1 0 0, V3 1 1 0), (V3 0 0 0, V3 1 1 0, V3 0 1 0)]
  it "accepts o, g, s, usemtl, mtllib, vn, vt, l, comments, blank lines and CRLF" $ do
    let m = ok ("# a comment\r\nmtllib x.mtl\r\no thing\r\ng group\r\ns off\r\nusemtl red\r\n\r\n" <> square
                <> "l 1 2\r\nf 1 2 3 # trailing comment\r\n")
    triangleCount m `shouldBe` 1
  it "names the line and quotes it for a bad number" $ do
    let e = err "v 0 0 0\nv 1 0 0\nv 1 1 zero\nf 1 2 3\n"
    e `shouldSatisfy` ("line 3" `isInfixOf`)
    e `shouldSatisfy` ("v 1 1 zero" `isInfixOf`)
    e `shouldSatisfy` ("bad number" `isInfixOf`)
  it "rejects an index out of range, index 0, a bad index and a face of fewer than 3 vertices, naming the line" $ do
    err (square <> "f 1 2 9\n") `shouldSatisfy` (\e -> "line 9" `isInfixOf` e && "out of range" `isInfixOf` e && "f 1 2 9" `isInfixOf` e)
    err (square <> "f -1 -2 -5\n") `shouldSatisfy` ("out of range" `isInfixOf`)
    err (square <> "f 0 1 2\n") `shouldSatisfy` ("index 0" `isInfixOf`)
    -- beyond a 64-bit integer: named as written, not wrapped (18446744073709551617 used to read as 1)
    err (square <> "f 1 2 18446744073709551617\n") `shouldSatisfy` (\e -> "18446744073709551617 out of range" `isInfixOf` e)
    err (square <> "f 1 2 -99999999999999999999999\n") `shouldSatisfy` ("-99999999999999999999999 out of range" `isInfixOf`)
    err (square <> "f 1/x 2 3\n") `shouldSatisfy` ("bad index" `isInfixOf`)
    err (square <> "f 1 2\n") `shouldSatisfy` (\e -> "line 9" `isInfixOf` e && "at least 3 vertices" `isInfixOf` e)
    err (square <> "foo 1 2\n") `shouldSatisfy` ("unknown statement" `isInfixOf`)
  it "rejects an empty file and a file without faces" $ do
    err "" `shouldSatisfy` ("no faces" `isInfixOf`)
    err square `shouldSatisfy` ("no faces" `isInfixOf`)
  it "rejects non-finite and absurdly huge coordinates" $ do
    err "v 1e300 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n" `shouldSatisfy` (\e -> "line 1" `isInfixOf` e && "absurdly large" `isInfixOf` e)
    err "v 1 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n" `shouldSatisfy` (\e -> "line 2" `isInfixOf` e && "not a finite" `isInfixOf` e)
    err "v 1 0 0\nv 0 -inf 0\nv 0 1 0\nf 1 2 3\n" `shouldSatisfy` ("not a finite" `isInfixOf`)
    err "v 1 0 0\nv 0 1e999 0\nv 0 1 0\nf 1 2 3\n" `shouldSatisfy` ("not a finite" `isInfixOf`)
  it "reads every double's shown form back exactly" $
    property $ \x -> readDouble (BC.pack (show (x :: Double))) === Just x
  it "reads the short forms and rejects malformed numbers" $ do
    map readDouble ["5.", ".5", "+1e3", "1E-3", "-0.25", "007", "1.5e+2"] `shouldBe` map Just [5, 0.5, 1000, 1e-3, -0.25, 7, 150]
    map readDouble ["", ".", "e5", "1e", "1.2.3", "--1", "1x", "0x10"] `shouldSatisfy` all (== Nothing)
  it "composes a scene: scale then pose, triangles in order" $ do
    let m = fromTriangles [tri 0 0 0]
        s = composeScene [ScenePart m 1 (trans 0 0 0), ScenePart m 2 (trans 1 2 3 `compose` rotZ (pi / 2))]
    triangleCount s `shouldBe` 2
    let (_, b, c) = triangle s 1
    b `shouldSatisfy` near (V3 1 4 3)
    c `shouldSatisfy` near (V3 (-1) 4 3)
  it "loads the work cell: 13,392 triangles, the table top at z = 0, the wall at x = -0.45" $ do
    r <- readObj "../shared/data/cell/cell.obj"
    r `shouldSatisfy` not . isLeft
    let Right m = r
    triangleCount m `shouldBe` 13392
    U.all (\x -> not (isNaN x) && abs x < 10) (meshCoords m) `shouldBe` True
    let Just (V3 lx _ lz, V3 hx _ _) = meshBounds m
    lx `shouldSatisfy` (\x -> abs (x + 0.45) < 0.05)
    hx `shouldSatisfy` (\x -> x >= 1.55 && x < 1.7)
    lz `shouldSatisfy` (< 0)
  it "loads a scene of several files with scale and pose" $ do
    r <- loadScene [ SceneFile "../shared/data/cell/cell.obj" 1 (trans 0 0 0)
                   , SceneFile "../shared/data/cell/cell.obj" 0.5 (trans 10 0 0) ]
    let Right s = r
    triangleCount s `shouldBe` 2 * 13392
    let (a, _, _) = triangle s 13392
        (a0, _, _) = triangle s 0
        V3 x0 y0 z0 = a0
    a `shouldSatisfy` near (V3 (10 + 0.5 * x0) (0.5 * y0) (0.5 * z0))
    bad <- loadScene [SceneFile "../shared/data/cell/cell.obj" 0 (trans 0 0 0)]
    either id (const "") bad `shouldSatisfy` ("scale" `isInfixOf`)
  it "names the file in an error" $ do
    r <- readObj "../shared/data/cell/no-such.obj"
    either id (const "") r `shouldSatisfy` ("no-such.obj" `isInfixOf`)
  where
    near (V3 a b c) (V3 x y z) = abs (a - x) + abs (b - y) + abs (c - z) < 1e-12
