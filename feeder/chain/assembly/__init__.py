"""Closed poses: assembly, velocities, accelerations and continuation along a motion."""
