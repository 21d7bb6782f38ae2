-- | Why a file could not be read or written, in words and without the file's name (the
-- message that names the file says it once; 'show' of an 'IOException' repeats it and
-- the system call: "x.json: openBinaryFile: does not exist (No such file or directory)").
module VProf.Format.IOError
  ( ioReason
  , ioWriteReason
  ) where

import GHC.IO.Exception (IOException (..))
import System.IO.Error (isDoesNotExistError, isFullError, isPermissionError, isUserError)

-- | "no such file", "permission denied", "the disk is full", or the error's kind and
-- description, e.g. "inappropriate type (is a directory)".
ioReason :: IOException -> String
ioReason e
  | isDoesNotExistError e = "no such file"
  | isPermissionError e = "permission denied"
  | isFullError e = "the disk is full"
  -- (a library's own failure, e.g. Cairo's "error while writing to output stream")
  | isUserError e, not (null (ioe_description e)) = ioe_description e
  | otherwise = show (ioe_type e) ++ (if null (ioe_description e) then "" else " (" ++ ioe_description e ++ ")")

-- | 'ioReason' for a file being written: one that does not exist there is a missing
-- directory.
ioWriteReason :: IOException -> String
ioWriteReason e
  | isDoesNotExistError e = "no such directory"
  | otherwise = ioReason e
