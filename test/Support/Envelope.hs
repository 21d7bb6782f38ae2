-- | A request through the daemon's whole envelope in process: encode the Request, check its
-- wire bytes strictly, decode and classify it as the server does, answer it with the
-- daemon's handler, and encode, check and decode the Response.
module Support.Envelope (viaEnvelope) where

import Test.Hspec

import VProf.Service (answer)
import VProf.Wire.Envelope
import VProf.Wire.Messages
import VProf.Wire.Validate (MsgType (..), validateWire)

viaEnvelope :: RequestMsg -> IO ResponseMsg
viaEnvelope req = do
  let bytes = encodeBare req
  validateWire TRequest bytes `shouldBe` Right ()
  decoded <- either fail pure (decodeBare bytes)
  inc <- either (fail . show) pure (classify decoded)
  rsp <- answer (requestIdOf decoded) inc
  let out = encodeBare rsp
  validateWire TResponse out `shouldBe` Right ()
  either fail pure (decodeBare out)
