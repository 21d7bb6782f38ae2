-- | What every text input format shares before its own parsing: the text without the UTF-8
-- byte-order mark that spreadsheets and Windows editors write before the first line.
module VProf.Format.Text
  ( dropBom
  , dropBomLazy
  ) where

import qualified Data.ByteString.Char8 as B
import qualified Data.ByteString.Lazy.Char8 as BL

-- | The text without a UTF-8 byte-order mark at its start.
dropBom :: B.ByteString -> B.ByteString
dropBom s = if B.pack "\xEF\xBB\xBF" `B.isPrefixOf` s then B.drop 3 s else s

-- | 'dropBom' for a lazy string.
dropBomLazy :: BL.ByteString -> BL.ByteString
dropBomLazy s = if BL.pack "\xEF\xBB\xBF" `BL.isPrefixOf` s then BL.drop 3 s else s
