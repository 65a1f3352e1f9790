"""The design's cycles on a Dask cluster (``--scheduler``): the sensitivities computed on a
LocalCluster (two worker processes on 127.0.0.1) equal the local process pool's to the last
digit, as the sweep's table does (tests/study/test_sweep.py)."""

from __future__ import annotations

import numpy as np

from feeder.design import design_sensitivities
from feeder.device.builtin import PROJECTILE_FEEDER
from feeder.motion.laws import CycleSpec

SPEC = CycleSpec(rate=100.0)
"""100 Hz, as tests/design/test_sensitivities.py: each cycle ~15 ms."""


def _sensitivities(**where):
    return design_sensitivities(
        PROJECTILE_FEEDER,
        elevations_deg=(-4.0, 30.0),
        parameters=("d3", "payload.mass"),
        spec=SPEC,
        progress=False,
        **where,
    )


def test_a_dask_cluster_gives_the_local_derivatives(dask_scheduler):
    """The same cycles on the same parameters: a cluster may only change where they run, so
    every derivative and peak is bit-identical (no tolerance)."""
    local = _sensitivities(workers=2)
    remote = _sensitivities(scheduler=dask_scheduler)
    assert remote.cycles == local.cycles > 0
    for mine, theirs in zip(local.scopes, remote.scopes, strict=True):
        assert mine.peaks == theirs.peaks
        assert mine.entries.keys() == theirs.entries.keys()
        derivatives = [
            (e.derivative, theirs.entries[k].derivative) for k, e in mine.entries.items()
        ]
        np.testing.assert_array_equal(*zip(*derivatives, strict=True))
