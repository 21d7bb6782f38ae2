-- | The one vocabulary of input errors, shared by every capability: a 'FieldError' names
-- the field as the user wrote it, the value in the user's unit, and the rule it breaks.
-- Validators return every error at once (a list), never the first only. The check
-- combinators keep a field's checks in order: a value that is not a finite number gets
-- that error alone, not a cascade of comparisons with NaN.
module VProf.Validation
  ( FieldError (..)
  , FieldValue (..)
  , renderFieldError
  , renderFieldErrors
  , renderValue
  , showNumber
  , roundSignificant
  , roundSignificantTo
  , showBound
    -- * Checks
  , fieldError
  , literalError
  , ensure
  , finite
  , ensureFinite
  , validated
  , maxCoordinate
  , maxTime
  , tooLateRule
  , tooFarRule
  , tooLongRule
  , maxAngleDeg
  , tooWideRule
  , tooWideInRule
  , minTimeStep
  , maxTimeStep
  , timeStepRule
    -- * Speaking the user's language
  , UserField (..)
  , inUserTerms
  ) where

import Data.List (intercalate)
import Numeric (showEFloat, showFFloat)

-- | The farthest a coordinate may lie from the origin (m; an OBJ scene's file units): a
-- billion metres holds any work cell, a vehicle's UTM coordinates or a GPS track's, and keeps
-- every square of a fit or a distance finite (coordinates of 1e150 m gave infinite errors, a
-- NaN report, and a target "Infinity mm too far"). Beyond it a value is taken for a wrong unit
-- or a corrupt file.
maxCoordinate :: Double
maxCoordinate = 1e9

-- | The latest time a recorded sample may have, either side of 0 (s): 10^19 holds any clock's
-- count since 1970 even in nanoseconds (1.8e18) read as seconds, which a recording keeps with a
-- warning; beyond it no clock counts, in any unit (1e300 s was written back as a 300-digit time
-- no reader took, and a span of -1e308 to 1.7e308 s is infinite).
maxTime :: Double
maxTime = 1e19

-- | The rule a time beyond 'maxTime' breaks.
tooLateRule :: String
tooLateRule = "is more than " ++ showBound maxTime ++ " s from 0, more than any clock counts in any unit (is the number right?)"

-- | The rule a position beyond 'maxCoordinate' breaks, in the words every reader uses.
tooFarRule :: String
tooFarRule = "is more than " ++ showBound maxCoordinate ++ " m from the origin (is the unit right?)"

-- | The rule a length beyond 'maxCoordinate' breaks (a radius, a clearance, a link).
tooLongRule :: String
tooLongRule = "is more than " ++ showBound maxCoordinate ++ " m (is the unit right?)"

-- | The range of a controller's time step (s), the same for a profile and a plan: below a
-- microsecond no controller samples, above a second the profile says nothing between samples.
minTimeStep, maxTimeStep :: Double
minTimeStep = 1e-6
maxTimeStep = 1

-- | The rule a time step outside ['minTimeStep', 'maxTimeStep'] breaks.
timeStepRule :: String
timeStepRule = "must be from 1e-6 s (1 µs) to 1 s"  -- 'minTimeStep' and 'maxTimeStep' in words

-- | The largest angle taken in degrees (a pose's roll, pitch or yaw): a million degrees is
-- some 2,800 turns; beyond, the angle is taken for a wrong unit (the sine of 1e300 is noise).
maxAngleDeg :: Double
maxAngleDeg = 1e6

-- | The rule an angle beyond 'maxAngleDeg' breaks; 'tooWideInRule' for a triple holding one.
tooWideRule, tooWideInRule :: String
tooWideRule = "is more than " ++ showBound maxAngleDeg ++ " degrees (is the unit right?)"
tooWideInRule = "holds an angle beyond " ++ showBound maxAngleDeg ++ " degrees (is the unit right?)"

-- | A value as the user gave it: a number (rendered in full precision) or any text.
data FieldValue
  = Number !Double
  | Literal !String
  deriving (Eq, Show)

-- | One problem with one field: "max_jerk = -1.0 m/s³: must be > 0".
data FieldError = FieldError
  { feField :: !String      -- ^ the field or option, as the user writes it
  , feValue :: !FieldValue  -- ^ the offending value, in 'feUnit'
  , feUnit  :: !String      -- ^ the unit of the value ("" for none)
  , feRule  :: !String      -- ^ what is wrong
  } deriving (Eq, Show)

-- | Every digit of a double, without an exponent where that stays short: from 1e-12 to below
-- 1e15 in magnitude (and 0); outside that range with one (1.0e300, not 301 digits).
showNumber :: Double -> String
showNumber x
  | x == 0 || (a >= 1e-12 && a < 1e15) || isNaN x || isInfinite x = showFFloat Nothing x ""
  | otherwise = showEFloat Nothing x ""
  where a = abs x

-- | A number rounded to 12 significant digits, for showing a value computed from read ones
-- (a time step of 210.52 - 0.01 s is 210.51, not 210.51000000000002; 165° read and shown
-- again is not 165.00000000000003°).
roundSignificant :: Double -> Double
roundSignificant = roundSignificantTo 12

-- | A number rounded to n significant digits (1 to 17).
roundSignificantTo :: Int -> Double -> Double
roundSignificantTo n x
  | isNaN x || isInfinite x || x == 0 = x
  | otherwise = read (showEFloat (Just (max 0 (min 16 (n - 1)))) x "")

-- | A bound as people write it: a power of ten from 1e5 up as "1e9" (showNumber writes
-- "1000000000.0"), any other number as 'showNumber' does.
showBound :: Double -> String
showBound x
  | x >= 1e5, x < 1e300, let e = round (logBase 10 x) :: Int, 10 ^^ e == x = "1e" ++ show e
  | otherwise = showNumber x

renderValue :: FieldValue -> String
renderValue = \case
  Number x -> showNumber x
  Literal s -> s

-- | Every problem as 'renderFieldError' says it, joined by "; ", the first 20 of them and
-- then how many more (2000 bad meshes made a message of 230 kB; the list of errors keeps them
-- all).
renderFieldErrors :: [FieldError] -> String
renderFieldErrors es = case splitAt 20 es of
  (shown, []) -> intercalate "; " (map renderFieldError shown)
  (shown, rest) -> intercalate "; " (map renderFieldError shown) ++ "; and " ++ show (length rest) ++ " more"

-- | "field = value unit: rule", or "field: rule" when the rule is about the field as a
-- whole (an empty literal value).
renderFieldError :: FieldError -> String
renderFieldError (FieldError f v u r) = case v of
  Literal "" -> f ++ ": " ++ r
  _ -> f ++ " = " ++ renderValue v ++ (if null u then "" else ' ' : u) ++ ": " ++ r

-- | An error about a numeric field.
fieldError :: String -> Double -> String -> String -> FieldError
fieldError f x = FieldError f (Number x)

-- | An error about a field whose value is not a number.
literalError :: String -> String -> String -> FieldError
literalError f v = FieldError f (Literal v) ""

-- | The error, unless the condition holds.
ensure :: Bool -> FieldError -> [FieldError]
ensure ok e = if ok then [] else [e]

finite :: Double -> Bool
finite x = not (isNaN x || isInfinite x)

-- | A finite number goes on to the further checks; anything else is that one error.
ensureFinite :: String -> Double -> String -> [FieldError] -> [FieldError]
ensureFinite f x unit further
  | finite x = further
  | otherwise = [fieldError f x unit "must be a finite number"]

-- | The value when there is no error, every error otherwise.
validated :: [[FieldError]] -> a -> Either [FieldError] a
validated checks x = case concat checks of
  [] -> Right x
  es -> Left es

-- | How an interface names a field of the core's vocabulary: the name the user typed,
-- the unit the user works in, and how many of that unit make one SI unit of the core.
data UserField = UserField
  { ufName  :: !String
  , ufUnit  :: !String
  , ufScale :: !Double
  } deriving (Eq, Show)

-- | Re-express errors in an interface's terms: fields it names differently get its name,
-- and numeric values its unit. Fields it does not name stay as they are.
inUserTerms :: (String -> Maybe UserField) -> [FieldError] -> [FieldError]
inUserTerms lookupField = map $ \e -> case lookupField (feField e) of
  Nothing -> e
  Just (UserField n u k) -> e
    { feField = n
    , feValue = case feValue e of Number x -> Number (x * k); v -> v
    , feUnit = if null u then feUnit e else u }
