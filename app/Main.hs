module Main where
main :: IO ()
main = pure ()
