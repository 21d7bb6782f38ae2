-- | ABB RAPID modules (thesis figures 34–35, @lesMod.m@ and @LagRapidBane.m@).
--
-- Reading: every @robtarget@ declaration (position in mm, orientation quaternion
-- [q1 q2 q3 q4] = [w x y z]) and, in order, the @MoveL@ / @PaintL@ / @MoveJ@ instructions
-- that use them; the @\\T:=@ of a move is the time it takes, so the waypoint times are the
-- running sum (the first move starts at 0, or at the time in a @! vprof start time:@
-- comment). Names ignore case, as in RAPID; a robtarget declared twice, moves in more than
-- one procedure, and loops, branches or jumps (FOR, WHILE, IF, TEST, GOTO) are refused with
-- their lines, since the written order would not be the order the moves run in. Writing: one @CONST robtarget@ a waypoint and a @MoveL@ with @\\T:=@ for every
-- segment, so that the recorded timing is kept.
module VProf.Compress.Format.Rapid
  ( RapidOptions (..)
  , defaultRapidOptions
  , parseRapid
  , rapidTrack
  , readRapid
  , renderRapid
  , rapidReserved
  ) where

import qualified Data.ByteString.Char8 as B
import Data.Char (isAlphaNum, isSpace, toLower)
import Data.List (isPrefixOf, sortBy)
import Data.Ord (comparing)
import qualified Data.Map.Strict as M
import qualified Data.Vector.Unboxed as U
import Numeric (showFFloat)

import VProf.Compress.Format.Common (readDouble)
import VProf.Compress.Clean (Sample (..))
import VProf.Compress.Types
import VProf.Geometry.Vec

data RapidOptions = RapidOptions
  { roModule :: !String   -- ^ module name
  , roSpeed  :: !String   -- ^ speed data, e.g. v500 (the \T:= time overrides the speed)
  , roZone   :: !String   -- ^ zone data, e.g. z10 or fine
  , roTool   :: !String   -- ^ tool data name
  , roWobj   :: !String   -- ^ work object name
  } deriving (Show, Eq)

defaultRapidOptions :: RapidOptions
defaultRapidOptions = RapidOptions "VprofPath" "v500" "z10" "tool0" "wobj0"

-- | The statements (each up to its ';', comments removed) with the lines they start on, the
-- start time of a @vprof start time:@ comment, and the text after the last statement's end (a
-- keyword line such as ENDMODULE, which needs no ';', or a statement the file was cut short in).
statements :: String -> ([(Int, String)], Maybe Double, Maybe (Int, String))
statements src = go (zip [1 ..] (lines src)) Nothing none Nothing []
  where
    -- the statement being read: its pieces, last first (appended to at every line, so kept
    -- in pieces: a long text without ';' would otherwise be copied once a line), and whether
    -- all of them are blank
    none = ([], True)
    add piece (ps, blank) = (piece : ps, blank && all isSpace piece)
    text (ps, _) = trim (concat (reverse ps))
    -- the text after the last ';' (an ENDMODULE, or a statement the file was cut short in)
    go [] start cur st acc = (reverse acc, st, if snd cur then Nothing else Just (maybe 0 id start, text cur))
    go ((i, l) : rest) start cur st acc =
      let (code, comment) = break (== '!') l
          st' = case parseStart comment of
                  Just t -> Just t
                  Nothing -> st
          -- MODULE, PROC, ENDPROC ... end without ';': a line starting with a keyword
          -- begins a new statement
          startsNew = case words (lower code) of
            (w : _) -> w `elem` keywords
            [] -> False
          (start', cur', acc')
            | startsNew && not (snd cur) = (Nothing, none, (maybe i id start, text cur) : acc)
            | otherwise = (start, cur, acc)
      in split i rest start' (add " " cur') code st' acc'
    keywords = [ "module", "endmodule", "proc", "endproc", "func", "endfunc", "trap", "endtrap"
               , "local", "const", "pers", "var", "movel", "movej", "paintl", "moveabsj", "movec" ]
               ++ controlWords ++ [ "end" ++ w | w <- ["for", "while", "if", "test"] ]
    split i rest start cur code st acc =
      case break (== ';') code of
        (a, ';' : b) ->
          let s0 = maybe i id start
              stmt = text (add a cur)
          in split i rest Nothing none b st (if null stmt then acc else (s0, stmt) : acc)
        (a, _) ->
          let cur' = add a cur
              start' = if snd cur' then Nothing else Just (maybe i id start)
          in go rest start' cur' st acc
    parseStart c =
      let c' = dropWhile (\x -> x == '!' || isSpace x) c
          key = "vprof start time:"
      in if key `isPrefixOf` map toLower c'
           then readDouble (B.pack (drop (length key) c'))
           else Nothing

-- | RAPID's control statements: a module using them does not run its moves in the order
-- they are written, which is how vprof reads them.
controlWords :: [String]
controlWords = ["for", "while", "if", "test", "goto"]

-- | RAPID's reserved words (Technical reference manual, RAPID kernel), in lower case: no
-- name may be one.
rapidReserved :: [String]
rapidReserved = map lower
  [ "ALIAS", "AND", "BACKWARD", "CASE", "CONNECT", "CONST", "DEFAULT", "DIV", "DO", "ELSE", "ELSEIF"
  , "ENDFOR", "ENDFUNC", "ENDIF", "ENDMODULE", "ENDPROC", "ENDRECORD", "ENDTEST", "ENDTRAP", "ENDWHILE"
  , "ERROR", "EXIT", "FALSE", "FOR", "FROM", "FUNC", "GOTO", "IF", "INOUT", "LOCAL", "MOD", "MODULE"
  , "NOSTEPIN", "NOT", "NOVIEW", "OR", "PERS", "PROC", "RAISE", "READONLY", "RECORD", "RETRY", "RETURN"
  , "STEP", "SYSMODULE", "TEST", "THEN", "TO", "TRAP", "TRUE", "TRYNEXT", "UNDO", "VAR", "VIEWONLY"
  , "WHILE", "WITH", "XOR" ]

trim :: String -> String
trim = f . f where f = reverse . dropWhile isSpace

lower :: String -> String
lower = map toLower

-- | Parse a module into a path (positions in m).
parseRapid :: B.ByteString -> Either String Track
parseRapid bs = readRapid bs >>= rapidTrack

-- | A module's waypoints ('readRapid') as a path, checked as a recording's samples are.
rapidTrack :: [Sample] -> Either String Track
rapidTrack ss =
  case recordingFromArrays (U.fromList (map smTime ss)) (pfromList (map smPos ss)) (pfromList (map smRot ss)) of
    Left e -> Left ("RAPID: " ++ e ++ " (waypoint k is the k-th move, counting from 0)")
    Right (Recording tr) -> Right tr

-- | The waypoints of a module as samples, each with the line its move starts on.
readRapid :: B.ByteString -> Either String [Sample]
readRapid bs = do
  let (stmts0, startT, tailStmt) = statements (B.unpack bs)
      stmts = stmts0 ++ maybe [] pure tailStmt
  cutShort stmts tailStmt
  declared <- traverse robtarget [ s | s@(_, x) <- stmts, "robtarget" `elem` words (lower (map sep x)) ]
  -- RAPID names are case-insensitive; a name declared twice is ambiguous
  targets <- M.traverseWithKey (\name -> \case
                 [(_, pose)] -> Right pose
                 lns -> Left ("RAPID lines " ++ joinLines (reverse (map fst lns)) ++ ": robtarget " ++ name
                              ++ " is declared " ++ show (length lns) ++ " times (RAPID names ignore case); which one is meant?"))
               (M.fromListWith (++) [ (lower name, [(ln, pose)]) | (ln, name, pose) <- declared ])
  let moves = [ s | s@(_, x) <- stmts, isMove x ]
      -- the procedure each statement belongs to (the last PROC before it)
      procs = [ (ln, takeWhile (\c -> isAlphaNum c || c == '_') n) | (ln, x) <- stmts, ("proc" : n : _) <- [dropLocal (words (lower x))] ]
      procOf ln = case [ n | (l, n) <- procs, l <= ln ] of
        [] -> "(outside any PROC)"
        ns -> last ns
      moveProcs = M.toList (M.fromListWith min [ (procOf ln, ln) | (ln, _) <- moves ])
      control = [ (ln, w) | (ln, x) <- stmts, (w : _) <- [words x], lower w `elem` controlWords ]
      -- a move vprof cannot turn into straight timed moves changes the path: refuse it
      -- (MoveAbsJ, a move in joint space, is left out as documented)
      unsupported = [ (ln, w) | (ln, x) <- stmts, (w : _) <- [words x], let lw = lower w
                              , any (`isPrefixOf` lw) ["move", "paint", "search", "trigg"]
                              , lw `notElem` ["movel", "paintl", "movej", "moveabsj"] ]
  case control of
    (ln, w) : _ -> Left ("RAPID line " ++ show ln ++ ": " ++ w ++ " is not followed: vprof reads the moves in the order they are"
                         ++ " written, so a module with loops, branches or jumps would give another path; write its moves out in order")
    [] -> Right ()
  case moveProcs of
    _ : _ : _ -> Left ("RAPID: moves in more than one procedure (" ++ commaList [ n ++ " from line " ++ show l | (n, l) <- sortOnSnd moveProcs ]
                       ++ "): vprof reads the moves of one procedure in the order written and cannot tell the order the procedures run in")
    _ -> Right ()
  case unsupported of
    (ln, w) : _ -> Left ("RAPID line " ++ show ln ++ ": " ++ w ++ " is not supported (vprof reads MoveL, PaintL and MoveJ"
                         ++ " with \\T:= times; a circular or searching move would change the path)")
    [] -> Right ()
  if null moves then Left "RAPID: no MoveL/PaintL/MoveJ instruction found" else Right ()
  steps <- traverse (move targets) (zip [0 :: Int ..] moves)
  let times = scanl1 (+) (maybe 0 id startT : map fst (tail steps))
  pure [ Sample ln t p q | ((ln, _), t, (_, (p, q))) <- zip3 moves times steps ]
  where
    sep c = if c == ':' || c == '=' then ' ' else c
    isMove x = case words x of
      (w : _) -> lower w `elem` ["movel", "paintl", "movej"]
      _ -> False
    robtarget (ln, x) = do
      let (lhs, rhs) = breakOn ":=" x
          name = case reverse (words lhs) of
            (n : _) -> n
            [] -> ""
      if null rhs then Left ("RAPID line " ++ show ln ++ ": robtarget " ++ name ++ " has no value") else Right ()
      let groups = innerGroups (drop 2 rhs)
          shape = "needs [[x,y,z],[q1,q2,q3,q4],...]"
      case map numbersIn (take 2 groups) of
        [Right [x1, y1, z1], Right [q1, q2, q3, q4]] ->
          Right (ln, name, (P3 (x1 * 1e-3) (y1 * 1e-3) (z1 * 1e-3), Q4 q1 q2 q3 q4))
        [Left bad, _] -> Left ("RAPID line " ++ show ln ++ ": robtarget " ++ name ++ ": not a number: " ++ show bad)
        [_, Left bad] -> Left ("RAPID line " ++ show ln ++ ": robtarget " ++ name ++ ": not a number: " ++ show bad)
        [Right ps, Right qs] -> Left ("RAPID line " ++ show ln ++ ": robtarget " ++ name ++ " " ++ shape ++ ", found "
                                      ++ show (length ps) ++ " numbers in the position and " ++ show (length qs) ++ " in the orientation")
        _ -> Left ("RAPID line " ++ show ln ++ ": robtarget " ++ name ++ " " ++ shape ++ ", found " ++ show (length groups) ++ " bracketed groups")
    move targets (k, (ln, x)) = do
      let afterInstr = dropWhile isSpace (dropWhile (not . isSpace) x)
          name = trim (takeWhile (/= ',') afterInstr)
      pose <- maybe (Left ("RAPID line " ++ show ln ++ ": move to " ++ show name ++ ", which is not a declared robtarget")) Right
                    (M.lookup (lower name) targets)
      dt <- case breakOn "\\t:=" (lower x) of
        (_, "") | k == 0 -> Right 0
                | otherwise -> Left ("RAPID line " ++ show ln ++ ": move to " ++ name
                                     ++ " has no \\T:= time; every move after the first needs one")
        (pre, rest) ->
          let numTxt = takeWhile (\c -> not (isSpace c) && c /= ',' && c /= '\\') (drop 4 rest)
              _ = pre
          in case readDouble (B.pack numTxt) of
               Just d | d > 0 || k == 0 -> Right d
               _ -> Left ("RAPID line " ++ show ln ++ ": move to " ++ name ++ ": \\T:= " ++ show numTxt
                          ++ " is not a positive time")
      Right (dt, pose)

-- | A module that ends before its ENDMODULE, a procedure before its ENDPROC, or a last
-- statement without its ';' was cut short (a copy or a transfer that stopped): its last moves
-- would be lost without a word, so it is refused. A text without MODULE (a procedure alone) needs
-- no ENDMODULE.
cutShort :: [(Int, String)] -> Maybe (Int, String) -> Either String ()
cutShort stmts tailStmt = do
  let firstWords = [ (ln, ws) | (ln, x) <- stmts, let ws = dropLocal (words (lower x)), not (null ws) ]
      opened open close = go' [] firstWords
        where
          go' stack [] = stack
          go' stack ((ln, w : rest) : more)
            | w == open = go' ((ln, takeWhile (\c -> isAlphaNum c || c == '_') (concat (take 1 rest))) : stack) more
            | w == close = go' (drop 1 stack) more
          go' stack (_ : more) = go' stack more
  case tailStmt of
    Just (ln, x) | take 1 (dropLocal (words (lower x))) `notElem` map pure blockWords ->
      Left ("RAPID line " ++ show ln ++ ": the statement is not ended by ';': is the file cut short?")
    _ -> Right ()
  case opened "proc" "endproc" of
    (ln, n) : _ -> Left ("RAPID line " ++ show ln ++ ": PROC " ++ n ++ " has no ENDPROC: is the file cut short?")
    [] -> Right ()
  case opened "module" "endmodule" of
    (ln, n) : _ -> Left ("RAPID line " ++ show ln ++ ": MODULE " ++ n ++ " has no ENDMODULE: is the file cut short?")
    [] -> Right ()

-- | The words that open or close a block: their lines need no ';'.
blockWords :: [String]
blockWords = ["module", "endmodule", "proc", "endproc", "func", "endfunc", "trap", "endtrap"]

joinLines :: [Int] -> String
joinLines = commaList . map show

commaList :: [String] -> String
commaList [] = ""
commaList [a] = a
commaList xs = foldr1 (\a b -> a ++ ", " ++ b) (init xs) ++ " and " ++ last xs

sortOnSnd :: Ord b => [(a, b)] -> [(a, b)]
sortOnSnd = sortBy (comparing snd)

dropLocal :: [String] -> [String]
dropLocal ("local" : r) = r
dropLocal r = r

breakOn :: String -> String -> (String, String)
breakOn pat = go ""
  where
    go acc s | pat `isPrefixOf` map toLower s = (reverse acc, s)
             | otherwise = case s of
                 [] -> (reverse acc, [])
                 (c : cs) -> go (c : acc) cs

-- | The texts of the groups one bracket level inside the outermost, in order:
-- @[[1,2,3],[4,5,6,7],[0,0,0,0]]@ gives @["1,2,3", "4,5,6,7", "0,0,0,0"]@.
innerGroups :: String -> [String]
innerGroups = go (0 :: Int) "" []
  where
    go _ _ acc [] = reverse acc
    go d cur acc (c : cs)
      | c == '[' = go (d + 1) (if d >= 2 then c : cur else "") acc cs
      | c == ']' = if d == 2 then go (d - 1) "" (reverse cur : acc) cs
                   else go (d - 1) (if d > 2 then c : cur else cur) acc cs
      | d >= 2 = go d (c : cur) acc cs
      | otherwise = go d cur acc cs

-- | All numbers in a bracketed RAPID value (commas, brackets and whitespace separate).
numbersIn :: String -> Either String [Double]
numbersIn s = traverse num (wordsBy (\c -> c `elem` ",[]" || isSpace c) s)
  where
    num w = maybe (Left w) Right (readDouble (B.pack w))
    wordsBy p str = case dropWhile p str of
      "" -> []
      str' -> let (w, rest) = break p str' in w : wordsBy p rest

-- | Decimals of a segment time: 6 (1 µs), or as many as show three significant digits of a
-- shorter one (0.000000 would be read back as no time at all).
segmentDecimals :: Double -> Int
segmentDecimals d
  | d >= 1e-6 || d <= 0 = 6
  | otherwise = min 20 (ceiling (negate (logBase 10 d)) + 2)

-- | A module with one robtarget a waypoint (mm) and timed MoveL instructions.
renderRapid :: RapidOptions -> Track -> String
renderRapid o (Track ts ps qs) = unlines $
  [ "MODULE " ++ roModule o
  , "  ! generated by vprof compress: " ++ show k ++ " waypoints"
  , "  ! positions in mm, orientation quaternion [q1,q2,q3,q4] = [w,x,y,z]"
  , "  ! vprof start time: " ++ fixed 6 (U.head ts)
  ] ++
  [ "  CONST robtarget " ++ nm j ++ " := [[" ++ commas (map (fixed 4 . (* 1000)) [x, y, z]) ++ "],["
      ++ commas (map (fixed 9) [w, a, b, c]) ++ "],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];"
  | (j, P3 x y z, Q4 w a b c) <- zip3 [0 :: Int ..] (ptoList ps) (ptoList qs) ] ++
  [ ""
  , "  PROC main()"
  ] ++
  [ "    MoveL " ++ nm j ++ ", " ++ roSpeed o ++ timing j ++ ", " ++ roZone o ++ ", " ++ roTool o
      ++ "\\WObj:=" ++ roWobj o ++ ";"
  | j <- [0 .. k - 1] ] ++
  [ "  ENDPROC"
  , "ENDMODULE"
  ]
  where
    k = U.length ts
    nm j = "p" ++ show j
    timing j | j == 0 = ""
             | otherwise = "\\T:=" ++ fixed (segmentDecimals (ts U.! j - ts U.! (j - 1))) (ts U.! j - ts U.! (j - 1))
    commas = foldr1 (\a b -> a ++ "," ++ b)
    fixed d v = showFFloat (Just d) v ""
    _ = isAlphaNum
