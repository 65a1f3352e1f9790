"""Kinematics: at every sample at once, the tree's motion (:mod:`.tree`) and the closure rows
along it (:mod:`.rows`); at one configuration, the chain's pose with its kinematics run once
(:mod:`.pose`)."""
