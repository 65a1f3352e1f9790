"""Kinematics at every sample at once: the tree's motion (:mod:`.tree`) and the closure rows
along it (:mod:`.rows`)."""
