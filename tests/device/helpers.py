"""Loop quantities that only the tests use, moved here from :mod:`feeder.device.loop`."""

from __future__ import annotations

import numpy as np

from feeder.device.parameters import FeederParameters


def stroke_ratio(p: FeederParameters, q: np.ndarray) -> np.ndarray:
    """dr2/dφ3 = d3 sin(φ1 − φ3) [m/rad]: piston travel per radian of arm, q (..., 4)."""
    return p.d3 * np.sin(q[..., 0] - q[..., 2])
