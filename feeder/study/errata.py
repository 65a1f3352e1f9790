"""The errata table of the paper measured on its reference cycle (``ERRATA.md``)."""

from __future__ import annotations

import math

from ..device.feeder import load_feeder
from ..device.parameters import FeederParameters
from ..motion.cycle import feeding_cycle
from ..paper.errata import ReferenceMotion, errata_markdown

REFERENCE_ELEVATION = math.radians(-4.0)
"""Elevation [rad] of the reference cycle: the longest arm travel (94°), paper Fig. 4."""


def paper_errata(device: str | FeederParameters = "projectile") -> str:
    """The published errata table as Markdown, measured on a device's cycle at −4° with the
    default timing (:func:`feeder.paper.errata.errata_markdown`): by default the projectile
    feeder (``ERRATA.md``), or a built-in device's name or a parameter set."""
    feeder = load_feeder(device)
    cycle = feeding_cycle(feeder, REFERENCE_ELEVATION)
    caption = (
        f"the {feeder.params.name} feeder, elevation {math.degrees(cycle.elevation):g}°, stage "
        f"durations {tuple(float(x) for x in cycle.spec.durations)} s"
    )
    motion = ReferenceMotion(cycle.t, cycle.q, cycle.v, cycle.a, cycle.gripped, caption)
    return errata_markdown(feeder.params, motion)
