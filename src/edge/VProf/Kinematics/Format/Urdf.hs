{-# LANGUAGE OverloadedStrings, RecordWildCards, LambdaCase, ScopedTypeVariables #-}
-- | Reads a URDF file into a 'Robot': the serial chain from a base link to a tip link.
--
-- Supported: @revolute@, @continuous@, @prismatic@ and @fixed@ joints with @origin@ (xyz, rpy;
-- R = Rz(y)·Ry(p)·Rx(r)), @axis@ (default x, normalised), @limit@ and @mimic@. Fixed joints are
-- folded into the transforms; links, inertials, visuals, transmissions and everything else are
-- ignored. Invariant: every error names the element (@joint "elbow_joint"@, @<origin>@) and what is
-- wrong with it; all problems of the chain are reported at once, and nothing throws.
module VProf.Kinematics.Format.Urdf
  ( UrdfOptions (..)
  , defaultUrdfOptions
  , readUrdf
  , readUrdfFile
  , urdfJointNames
  ) where

import Control.Exception (IOException, try)
import VProf.Format.IOError (ioReason)
import qualified Data.ByteString.Lazy as BL
import Data.Either (lefts, rights)
import Data.List (isPrefixOf, isSuffixOf, stripPrefix)
import qualified Data.Map.Strict as Map
import qualified Data.Set as Set
import Data.Maybe (fromMaybe, listToMaybe, mapMaybe)
import qualified Data.Text as T
import Text.Read (readMaybe)
import qualified Text.XML as X
import Text.XML.Cursor (Cursor, attribute, element, fromDocument, node, ($/))

import VProf.Kinematics.Model
import VProf.Kinematics.Transform
import Data.Char (isDigit)
import VProf.Validation (FieldError (..), finite)
import VProf.Kinematics.Validate (renderFieldError, validateRobot)

data UrdfOptions = UrdfOptions
  { urdfBase :: Maybe String  -- ^ base link (default: the root link)
  , urdfTip :: Maybe String   -- ^ tip link (default: the only leaf link)
  }
  deriving (Eq, Show)

defaultUrdfOptions :: UrdfOptions
defaultUrdfOptions = UrdfOptions Nothing Nothing

data UJoint = UJoint
  { ujName :: String
  , ujType :: String
  , ujParent :: String
  , ujChild :: String
  , ujOrigin :: Tf
  , ujAxis :: V3
  , ujLimit :: Maybe (Maybe Double, Maybe Double, Maybe Double)  -- lower, upper, velocity
  , ujMimic :: Maybe (String, Double, Double)                    -- joint, multiplier, offset
  }

readUrdfFile :: UrdfOptions -> FilePath -> IO (Either [String] Robot)
readUrdfFile opts path = do
  r <- try (BL.readFile path)
  pure $ case r of
    Left (e :: IOException) -> Left ["cannot read " ++ path ++ ": " ++ ioReason e]
    Right bs -> (\r -> r {robotSources = ["URDF file " ++ path]}) <$> readUrdf opts bs

-- | The names of the actuated joints of the chain, in order (the order of q).
urdfJointNames :: Robot -> [String]
urdfJointNames = map jointName . robotJoints

readUrdf :: UrdfOptions -> BL.ByteString -> Either [String] Robot
readUrdf opts bs = case X.parseLBS X.def bs of
  Left e -> Left ["not well-formed XML: " ++ xmlError (takeWhile (/= '\n') (show e))]
  Right doc -> do
    r <- fromDoc opts doc
    case validateRobot r of
      [] -> Right r
      es -> Left (map (renderFieldError . inUrdfTerms r) es)

-- | A model error in the URDF's words: joints[1].limits.max is the joint's name and its
-- <limit upper>.
inUrdfTerms :: Robot -> FieldError -> FieldError
inUrdfTerms r fe = case stripPrefix "joints[" (feField fe) of
  Just rest | (ds, ']' : '.' : key) <- span isDigit rest, not (null ds)
            , [j] <- take 1 (drop (read ds) (robotJoints r)) ->
      fe { feField = "joint " ++ show (jointName j) ++ " " ++ urdfKey key, feRule = limitWords (feRule fe) }
  -- a link of the model is the joint into a URDF link (its child)
  _ | Just rest <- stripPrefix "links[" (feField fe), (ds, ']' : key) <- span isDigit rest, not (null ds)
    , [l] <- take 1 (drop (read ds) (robotLinks r)) ->
      fe { feField = "the joint into link " ++ show (linkName l) ++ linkKey (dropWhile (== '.') key) }
  _ -> fe
  where
    linkKey k
      | Just t <- stripPrefix "drive[" k, "].coefficient" `isSuffixOf` t = " <mimic multiplier>"
      | k == "drive.offset" = " <mimic offset>"
      | k `elem` ["origin.xyz", "transform.xyz"] = " <origin xyz>"
      | k `elem` ["origin.rotation", "transform.rotation"] = " <origin rpy>"
      | k `elem` ["origin", "transform"] = " <origin>"
      | k == "axis" = " <axis xyz>"
      | null k = ""
      | otherwise = " (" ++ k ++ ")"
    urdfKey = \case
      "limits.max" -> "<limit upper>"
      "limits.min" -> "<limit lower>"
      k -> k
    limitWords m = case breakOn' "limits.min" m of
      (a, Just b) -> a ++ "<limit lower>" ++ b
      (a, Nothing) -> a
    breakOn' pat str = case [ i | i <- [0 .. length str - length pat], pat `isPrefixOf` drop i str ] of
      i : _ -> (take i str, Just (drop (i + length pat) str))
      [] -> (str, Nothing)

-- | The XML parser's message in a person's words: its Haskell records (@Name {nameLocalName =
-- "link", …}@, @ParseError {errorContexts = …}@) become @<link>@ and "line 2, column 66: …".
xmlError :: String -> String
xmlError msg
  | Just rest <- stripPrefix ("ParseError {errorContexts = " :: String) msg =
      let (ctx, r1) = break (== ']') rest
          pos = takeWhile (/= ' ') (drop (length posKey) (snd (breakOn posKey r1)))
          (line, col) = break (== ':') pos
          what = concatMap (\c -> if c == ',' then ", " else [c]) [ c | c <- ctx, c `notElem` ("[]\"" :: String) ]
      in "line " ++ line ++ ", column " ++ drop 1 col ++ ": malformed XML (in: " ++ what ++ ")"
  -- the text decoder's own words, with the bad bytes: the file is not UTF-8 text
  | Just rest <- stripPrefix ("Data.Conduit.Text.decode: " :: String) msg =
      let offset = takeWhile isDigit (snd (breakOn ("at offset " :: String) rest) `after` "at offset ")
      in "not UTF-8 text" ++ (if null offset then "" else " (a byte that is not UTF-8 at offset " ++ offset ++ ")") ++ "; is it a URDF?"
  | otherwise = replace ("EventEndElement " :: String) "the end tag " (replace ("EventBeginElement " :: String) "the start tag " (names msg))
  where
    after s' pat = drop (length (pat :: String)) s'
    posKey = "errorPosition = " :: String
    nameKey = "Name {nameLocalName = \"" :: String
    replace pat new s = case breakOn pat s of
      (a, "") -> a
      (a, b) -> a ++ new ++ replace pat new (drop (length pat) b)
    names s = case breakOn nameKey s of
      (a, "") -> a
      (a, b) -> let nm = takeWhile (/= '"') (drop (length nameKey) b)
                    after = drop 1 (dropWhile (/= '}') b)
                in a ++ "<" ++ nm ++ ">" ++ names after
    breakOn pat s = case [ i | i <- [0 .. length s - length pat], pat `isPrefixOf` drop i s ] of
      i : _ -> splitAt i s
      [] -> (s, "")

fromDoc :: UrdfOptions -> X.Document -> Either [String] Robot
fromDoc UrdfOptions{..} doc
  | X.nameLocalName (X.elementName (X.documentRoot doc)) /= "robot" =
      Left ["root element is <" ++ T.unpack (X.nameLocalName (X.elementName (X.documentRoot doc))) ++ ">, expected <robot>"]
  | not (null jointErrs) = Left jointErrs
  | not (null treeErrs) = Left treeErrs
  | otherwise = do
      tip <- maybe pickLeaf Right urdfTip
      let known l = l `Set.member` linkSet
      if not (known tip) then Left ["tip link " ++ show tip ++ " is not a <link> of the robot (links: " ++ unwords (take 30 allLinks) ++ ")"] else pure ()
      base <- maybe (rootAbove tip) Right urdfBase
      if not (known base) then Left ["base link " ++ show base ++ " is not a <link> of the robot"] else pure ()
      path <- pathTo base tip
      buildChain robotName path
  where
    cur = fromDocument doc
    robotName = maybe "urdf" T.unpack (listToMaybe (attribute "name" cur))
    allLinks = map T.unpack (concatMap (attribute "name") (cur $/ element "link"))
    -- (sets and maps throughout: a chain of 10,000 joints took seconds by lists)
    linkSet = Set.fromList allLinks
    parsed = map parseJoint (cur $/ element "joint")
    jointErrs = concat (lefts parsed)
    joints = rights parsed
    byChild = Map.fromList [(ujChild j, j) | j <- joints]
    -- a URDF is a tree of declared links: each link the child of one joint at most
    treeErrs =
      [ "link " ++ show l ++ " is the child of " ++ show (length js) ++ " joints (" ++ unwords (map (show . ujName) js)
        ++ "); in a URDF each link has one parent joint"
      | (l, js) <- Map.toList (Map.fromListWith (flip (++)) [ (ujChild j, [j]) | j <- joints ]), length js > 1 ]
      ++ [ "joint " ++ show (ujName j) ++ ": its " ++ role ++ " link " ++ show l ++ " is not a <link> of the robot"
         | j <- joints, (role, l) <- [("parent", ujParent j), ("child", ujChild j)], not (l `Set.member` linkSet) ]
      ++ [ "joint " ++ show (ujName j) ++ ": its parent and child are the same link " ++ show (ujChild j)
         | j <- joints, ujParent j == ujChild j ]
    children = Set.fromList (map ujChild joints)
    parents = Set.fromList (map ujParent joints)
    -- the root of the tree the tip is in: links of other trees (a second robot, a link no joint
    -- touches) do not matter
    rootAbove tip = go tip (0 :: Int)
      where
        go l k
          | k > length joints = Left ["the joints form a loop above link " ++ show tip]
          | otherwise = maybe (Right l) (\j -> go (ujParent j) (k + 1)) (Map.lookup l byChild)
    -- the leaves of the joints' trees (a link no joint touches is none)
    pickLeaf = case [l | l <- allLinks, not (l `Set.member` parents), l `Set.member` children] of
      [l] -> Right l
      [] | null joints -> Left ["no <joint>: a robot's links must be joined by joints"]
         | otherwise -> Left ["cannot choose the tip link: every child link is also a parent, so the joints ("
                              ++ unwords (map (show . ujName) joints) ++ ") form a loop; a URDF is a tree"]
      ls -> Left ["cannot choose the tip link: " ++ show (length ls) ++ " leaf links (" ++ unwords ls ++ "); choose one with --tip LINK"]
    pathTo base tip = walk tip [] (0 :: Int)
      where
        walk l acc k
          | l == base = Right acc
          | k > length joints = Left ["the joints form a loop above link " ++ show tip]
          | otherwise = case Map.lookup l byChild of
              Nothing -> Left ["tip link " ++ show tip ++ " is not below base link " ++ show base]
              Just j -> walk (ujParent j) (j : acc) (k + 1)

buildChain :: String -> [UJoint] -> Either [String] Robot
buildChain name path
  | not (null errs) = Left errs
  | null actuated = Left ["the chain from base to tip has no movable joint"]
  | not (null mimicErrs) = Left mimicErrs
  | otherwise =
      Right
        (emptyRobot name)
          { robotDescription = "URDF chain"
          , robotSources = ["URDF file"]
          , robotJoints = mapMaybe toJoint actuated
          , robotLinks = map toLink path
          }
  where
    movable j = ujType j `elem` ["revolute", "continuous", "prismatic"]
    actuated = [j | j <- path, movable j, ujMimic j == Nothing]
    index = Map.fromList (zip (map ujName actuated) [0 :: Int ..])
    kindOf j = if ujType j == "prismatic" then Prismatic else Revolute
    errs =
      [ "joint " ++ show (ujName j) ++ ": type " ++ show (ujType j) ++ " is not supported in a serial chain (revolute, continuous, prismatic, fixed)"
      | j <- path, not (movable j || ujType j == "fixed") ]
      ++ concatMap limitErr actuated
      ++ [ "joint " ++ show (ujName j) ++ ": <mimic joint=" ++ show m ++ "> names no actuated joint of the chain"
         | j <- path, movable j, Just (m, _, _) <- [ujMimic j], resolve (0 :: Int) m == Nothing ]
    limitErr j = case (ujType j, ujLimit j) of
      ("continuous", _) -> []
      (t, Nothing) -> ["joint " ++ show (ujName j) ++ ": a " ++ t ++ " joint needs a <limit> with lower and upper"]
      (_, Just (lo, hi, _)) ->
        ["joint " ++ show (ujName j) ++ ": <limit> lacks lower" | lo == Nothing]
          ++ ["joint " ++ show (ujName j) ++ ": <limit> lacks upper" | hi == Nothing]
          ++ [ "joint " ++ show (ujName j) ++ ": <limit> lower " ++ show l ++ " is above upper " ++ show h
             | Just l <- [lo], Just h <- [hi], l > h ]
    -- a mimic of a mimic resolves to (actuated index, multiplier, offset)
    resolve depth m
      | depth > 10 = Nothing
      | Just i <- Map.lookup m index = Just (i, 1, 0)
      | Just j <- Map.lookup m byName, Just (m', k, o) <- ujMimic j = do
          (i, k', o') <- resolve (depth + 1) m'
          pure (i, k * k', k * o' + o)
      | otherwise = Nothing
    toJoint j = do
      i <- Map.lookup (ujName j) index
      let (lo0, hi0, vel) = ownLimits j
          -- a mimic joint at k·q + o has limits of its own: they bound q too
          bounds = [ if k > 0 then ((ml - o) / k, (mh - o) / k) else ((mh - o) / k, (ml - o) / k)
                   | (_, (k, o), (ml, mh)) <- mimicsOf i, k /= 0 ]
          lo = maximum (lo0 : map fst bounds)
          hi = minimum (hi0 : map snd bounds)
      pure (i `seq` Joint (ujName j) (kindOf j) (Limits lo hi) (mfilter (> 0) vel) Nothing)
    ownLimits j = case (ujType j, ujLimit j) of
      ("continuous", l) -> (-1 / 0, 1 / 0, l >>= \(_, _, v) -> v)
      (_, Just (l, h, v)) -> (fromMaybe 0 l, fromMaybe 0 h, v)
      _ -> (0, 0, Nothing)
    byName = Map.fromListWith (\_ first -> first) [ (ujName j, j) | j <- path ]
    -- the mimic joints driven by actuated joint i: name, (multiplier, offset), own limits
    mimicsOf i = Map.findWithDefault [] i mimics
    mimics = Map.fromListWith (flip (++))
      [ (i', [(ujName j, (k * k', k * o' + o), (ml, mh))])
      | j <- path, movable j, Just (m, k, o) <- [ujMimic j], Just (i', k', o') <- [resolve (0 :: Int) m]
      , let (ml, mh, _) = ownLimits j ]
    mimicErrs =
      [ "joint " ++ show (ujName a) ++ ": no value within its limits keeps its mimic joints within theirs ("
        ++ unwords [ show m ++ " = " ++ show k ++ " q + " ++ show o ++ " in [" ++ show ml ++ ", " ++ show mh ++ "]" | (m, (k, o), (ml, mh)) <- ms ] ++ ")"
      | (i, a) <- zip [0 :: Int ..] actuated
      , let ms = mimicsOf i
      , not (null ms)
      , Just (Joint _ _ (Limits lo hi) _ _) <- [toJoint a]
      , lo > hi ]
    toLink j
      | not (movable j) = Link (ujChild j) Nothing (FixedTransform (ujOrigin j)) (Drive 0 []) []
      | otherwise =
          let drive = case ujMimic j of
                Nothing -> directDrive (fromMaybe 0 (Map.lookup (ujName j) index)) 1 0
                Just (m, k, o) -> case resolve (0 :: Int) m of
                  Just (i, k', o') -> Drive (k * o' + o) [(i, k * k')]
                  Nothing -> Drive 0 []
          in Link (ujChild j) (Just (kindOf j)) (UrdfJoint (ujOrigin j) (ujAxis j)) drive []
    mfilter p = \case Just x | p x -> Just x; _ -> Nothing

parseJoint :: Cursor -> Either [String] UJoint
parseJoint c =
  case errs of
    [] -> Right UJoint
            { ujName = name
            , ujType = typ
            , ujParent = fromMaybe "" parent
            , ujChild = fromMaybe "" childL
            , ujOrigin = fromRpy (either (const (V3 0 0 0)) id xyz) (either (const (V3 0 0 0)) id rpy)
            , ujAxis = either (const (V3 1 0 0)) id axis
            , ujLimit = limit
            , ujMimic = either (const Nothing) id mimic
            }
    _ -> Left errs
  where
    name = maybe "" T.unpack (listToMaybe (attribute "name" c))
    what = "joint " ++ show name
    typ = maybe "" T.unpack (listToMaybe (attribute "type" c))
    sub n = listToMaybe (c $/ element n)
    attr n el = T.unpack <$> listToMaybe (attribute n el)
    parent = sub "parent" >>= attr "link"
    childL = sub "child" >>= attr "link"
    vec el n dflt = case sub el >>= attr n of
      Nothing -> Right dflt
      Just s -> case mapM readNum (words s) of
        Just [x, y, z] | all finite [x, y, z] -> Right (V3 x y z)
        _ -> Left (what ++ ": <" ++ T.unpack (X.nameLocalName el) ++ " " ++ T.unpack (X.nameLocalName n) ++ "=" ++ show s ++ "> is not three finite numbers")
    xyz = vec "origin" "xyz" (V3 0 0 0)
    rpy = vec "origin" "rpy" (V3 0 0 0)
    axis = vec "axis" "xyz" (V3 1 0 0) >>= \a ->
      if typ == "fixed" then Right (V3 1 0 0)
      else if v3Norm a < 1e-12 then Left (what ++ ": <axis xyz> is the zero vector") else Right (v3Scale (1 / v3Norm a) a)
    numAttr el n = case attr n el of
      Nothing -> Right Nothing
      Just s -> case readNum s of
        Just x | finite x -> Right (Just x)
        _ -> Left (what ++ ": <" ++ T.unpack (elName el) ++ " " ++ T.unpack (X.nameLocalName n) ++ "=" ++ show s ++ "> is not a finite number")
    elName el = case node el of
      X.NodeElement e -> X.nameLocalName (X.elementName e)
      _ -> "?"
    limitE = sub "limit"
    limitParts = case limitE of
      Nothing -> Right Nothing
      Just el -> do
        lo <- numAttr el "lower"
        hi <- numAttr el "upper"
        v <- numAttr el "velocity"
        pure (Just (lo, hi, v))
    limit = either (const Nothing) id limitParts
    mimic = case sub "mimic" of
      Nothing -> Right Nothing
      Just el -> case attr "joint" el of
        Nothing -> Left (what ++ ": <mimic> has no joint attribute")
        Just m -> do
          k <- numAttr el "multiplier"
          o <- numAttr el "offset"
          pure (Just (m, fromMaybe 1 k, fromMaybe 0 o))
    errs =
      [what ++ ": no name attribute" | name == ""]
        ++ [what ++ ": no type attribute" | typ == ""]
        ++ [what ++ ": no <parent link=...>" | parent == Nothing]
        ++ [what ++ ": no <child link=...>" | childL == Nothing]
        ++ lefts [() <$ xyz, () <$ rpy, () <$ axis, () <$ limitParts, () <$ mimic]


-- | A decimal number as URDF files write them (".5", "-.5", "1.", "+2", "1e-3").
readNum :: String -> Maybe Double
readNum s0 = readMaybe (fix s0)
  where
    fix ('+' : r) = fix r
    fix ('-' : r) = '-' : fix r
    fix r@('.' : _) = fixEnd ('0' : r)
    fix r = fixEnd r
    fixEnd r = case break (== '.') r of
      (a, ".") -> a ++ ".0"
      (a, '.' : b@(c : _)) | c `elem` ("eE" :: String) -> a ++ ".0" ++ b
      _ -> r
