-- | Validation returns every problem at once, each naming the field and the value.
module VProf.Profile.RequestSpec (spec) where

import Data.List (isInfixOf)
import Test.Hspec
import Test.QuickCheck

import VProf.Profile.Request
import VProf.Units
import VProf.Validation (fieldError, renderFieldErrors)

fields :: Request -> [String]
fields rq = either (map feField) (const []) (validate rq)

messages :: Request -> [String]
messages rq = either (map renderFieldError) (const []) (validate rq)

spec :: Spec
spec = do
  it "accepts the default request" $ fields defaultRequest `shouldBe` []

  it "names the field and the value: max_jerk = -1.0 m/s³ must be > 0" $
    messages defaultRequest { rqMaxJerk = (-1) *~ mps3 } `shouldBe` ["max_jerk = -1.0 m/s³: must be > 0"]

  it "names the cause of a degenerate request, not a default it set (route_length 5e-324 named end_tolerance, a zone at 5e-324 m/s route_length)" $ do
    fields defaultRequest { rqRouteLength = 5e-324 *~ meter } `shouldBe` ["route_length"]
    fields defaultRequest { rqZones = [SpeedZone (0 *~ meter) (5e-324 *~ mps)] } `shouldBe` ["speed_limits[0].velocity"]
    fields defaultRequest { rqTimeStep = Just (1e-7 *~ second) } `shouldBe` ["time_step"]

  it "says at most 20 problems and how many more (2000 bad meshes made a 230 kB message)" $ do
    let es = [ fieldError ("x[" ++ show i ++ "]") 1 "m" "bad" | i <- [0 .. 99 :: Int] ]
        m = renderFieldErrors es
    length (filter (== ';') m) `shouldBe` 20
    m `shouldSatisfy` ("and 80 more" `isInfixOf`)
    renderFieldErrors (take 3 es) `shouldBe` "x[0] = 1.0 m: bad; x[1] = 1.0 m: bad; x[2] = 1.0 m: bad"

  it "reports every problem at once" $ do
    let rq = defaultRequest
          { rqRouteLength = (-5) *~ meter
          , rqMinAcceleration = 0.5 *~ mps2
          , rqMaxAcceleration = 0 *~ mps2
          , rqMinJerk = 1 *~ mps3
          , rqTimeStep = Just (0 *~ second) }
    -- and what follows from them: the zone at 0 lies beyond a negative route end; the
    -- start and end accelerations (0) lie outside [0.5, 0]
    fields rq `shouldMatchList` [ "route_length", "speed_limits[0].start_distance", "min_acceleration", "max_acceleration"
                                , "min_jerk", "start_acceleration", "end_acceleration", "time_step" ]

  it "rejects non-finite numbers by name" $ do
    let nan = 0 / 0 :: Double
    fields defaultRequest { rqStartVelocity = nan *~ mps } `shouldBe` ["start_velocity"]
    messages defaultRequest { rqMaxAcceleration = (1 / 0) *~ mps2 } `shouldSatisfy` any ("Infinity" `isInfixOf`)

  it "checks the zones: empty, first not at 0, unsorted, overlapping, beyond the route, non-positive" $ do
    fields defaultRequest { rqZones = [] } `shouldBe` ["speed_limits"]
    fields defaultRequest { rqZones = [SpeedZone (1 *~ meter) (1 *~ mps)] } `shouldBe` ["speed_limits[0].start_distance"]
    fields defaultRequest { rqZones = [SpeedZone (0 *~ meter) (1 *~ mps), SpeedZone (5 *~ meter) (1 *~ mps), SpeedZone (3 *~ meter) (1 *~ mps)] }
      `shouldBe` ["speed_limits[2].start_distance"]
    fields defaultRequest { rqZones = [SpeedZone (0 *~ meter) (1 *~ mps), SpeedZone (0 *~ meter) (2 *~ mps)] }
      `shouldBe` ["speed_limits[1].start_distance"]
    fields defaultRequest { rqZones = [SpeedZone (0 *~ meter) (1 *~ mps), SpeedZone (12 *~ meter) (2 *~ mps)] }
      `shouldBe` ["speed_limits[1].start_distance"]
    fields defaultRequest { rqZones = [SpeedZone (0 *~ meter) (0 *~ mps)] } `shouldBe` ["speed_limits[0].velocity"]

  it "checks start and end velocity against the zone they lie in" $ do
    fields defaultRequest { rqStartVelocity = 1.5 *~ mps } `shouldBe` ["start_velocity"]
    fields defaultRequest { rqEndVelocity = (-0.1) *~ mps } `shouldBe` ["end_velocity"]
    fields defaultRequest { rqZones = [SpeedZone (0 *~ meter) (3 *~ mps), SpeedZone (5 *~ meter) (1 *~ mps)], rqEndVelocity = 2 *~ mps }
      `shouldBe` ["end_velocity"]

  it "checks start and end acceleration against the acceleration range" $ do
    fields defaultRequest { rqStartAcceleration = 2 *~ mps2 } `shouldBe` ["start_acceleration"]
    fields defaultRequest { rqEndAcceleration = (-1.5) *~ mps2 } `shouldBe` ["end_acceleration"]

  it "refuses a velocity step that cannot fit inside the jerk range, suggesting one" $ do
    let ms = messages defaultRequest { rqVelocityStep = Just (0.5 *~ mps) }
    ms `shouldSatisfy` any ("velocity_step = 0.5 m/s: is too coarse" `isInfixOf`)
    ms `shouldSatisfy` any ("suggested" `isInfixOf`)

  it "refuses a velocity step with which a single sample cannot rise: above |j|·dt²/2" $ do
    -- the default request: |j| = 1 m/s³, dt = 0.125 s, so |j|·dt²/2 = 0.0078125 m/s
    fields defaultRequest { rqVelocityStep = Just (0.0079 *~ mps) } `shouldBe` ["velocity_step"]
    fields defaultRequest { rqVelocityStep = Just (0.0078125 *~ mps) } `shouldBe` []

  it "thesis mode takes the largest power-of-two step with which a single sample can rise" $
    property $ \(Positive a1) (Positive a2) (Positive j1) (Positive j2) ->
      let rq = defaultRequest { rqAlgorithm = Thesis
                              , rqMinAcceleration = negate (a1 + 0.1) *~ mps2, rqMaxAcceleration = (a2 + 0.1) *~ mps2
                              , rqMinJerk = negate (j1 + 0.1) *~ mps3, rqMaxJerk = (j2 + 0.1) *~ mps3 }
          bound = largestVelocityStep 0.125 (negate (a1 + 0.1)) (a2 + 0.1) (negate (j1 + 0.1)) (j2 + 0.1)
      in case validate rq of
           Right pb -> isPowerOfTwo (pbDv pb) .&&. pbDv pb <= bound .&&. 2 * pbDv pb > bound
           Left es -> counterexample (show es) False

  it "refuses a request above the sample cap" $
    fields defaultRequest { rqRouteLength = 1e7 *~ meter } `shouldBe` ["route_length"]

  it "chooses a power-of-two velocity step inside the jerk and acceleration ranges" $
    property $ \(Positive a1) (Positive a2) (Positive j1) (Positive j2) ->
      let dt = 0.125
          dv = autoVelocityStep dt (negate (a1 + 0.1)) (a2 + 0.1) (negate (j1 + 0.1)) (j2 + 0.1)
          quarter = minimum [j1 + 0.1, j2 + 0.1, (a1 + 0.1) / dt, (a2 + 0.1) / dt] * dt * dt / 4
      -- the largest power of two that is at most a quarter of min(|j|·dt², |a|·dt)
      in counterexample (show (dv, quarter)) $ isPowerOfTwo dv .&&. dv <= quarter .&&. 2 * dv > quarter
