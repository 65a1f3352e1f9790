"""The figures of a study, by file name: what ``feeder cycle`` and ``feeder kinematics`` write."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from ..device.feeder import Feeder
from ..motion.cycle import CycleKinematics
from ..motion.workspace import workspace
from ..study.cycle_study import CycleStudy
from .comparisons import cross_check_figure
from .drawings import side_view_figure, workspace_figure
from .figures import cycle_figures, position_figure

WORKSPACE_STEP_DEG = 10.0
"""Elevation step [deg] of the ramming poses drawn in the workspace figure (Fig. 4)."""


def kinematics_figures(feeder: Feeder, cycle: CycleKinematics) -> dict[str, Figure]:
    """Fig. 4 (the workspace, ramming poses every 10°) and Fig. 10 (payload position)."""
    low, high = np.degrees(feeder.params.elevation_limits)
    space = workspace(feeder, np.radians(np.arange(low, high + 1.0, WORKSPACE_STEP_DEG)))
    return {
        "fig04_workspace.png": workspace_figure(space, feeder.params.name),
        "fig10_projectile_position.png": position_figure(cycle),
    }


def study_figures(study: CycleStudy) -> dict[str, Figure]:
    """Every figure of the standard study: the side view, Figs. 4, 8, 10–15, the arm-pivot
    reaction, the cylinder pressures, the rack force and the cross-check."""
    feeder, cycle = study.feeder, study.dynamics.kinematics
    return {
        "device_side_view.png": side_view_figure(feeder, cycle),
        **kinematics_figures(feeder, cycle),
        **cycle_figures(study),
        "lagrange_cross_check.png": cross_check_figure(study),
    }
