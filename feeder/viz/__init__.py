"""Figures and the 3-D viewer. Every figure function returns a
:class:`matplotlib.figure.Figure`; :mod:`feeder.viz.report` draws a study's figures in worker
processes and writes them. The MeshCat viewer, served on 127.0.0.1 only, is
:mod:`feeder.viz.viewer` (imported on demand: it pulls in MeshCat); it draws one kind of scene,
:class:`feeder.viz.scene.MechanismScene`, for the device (:mod:`feeder.viz.device_scene`) and
for any mechanism (:mod:`feeder.viz.model_scene`).

The names below load on first use, so that importing :mod:`feeder.viz.report` (the figures'
writers) does not import matplotlib in a process that only ships data to the workers.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..lazy import lazy_names

if TYPE_CHECKING:  # the names for type checkers; at run time they load on first use
    from .catalog import CYCLE_FIGURES
    from .comparisons import cross_check_figure, cycles_figure, sweep_figure
    from .drawings import loop_figure, side_view_figure, workspace_figure
    from .figures import cycle_figures, mark_stages, position_figure, time_history
    from .report import kinematics_figures, study_figures

_SOURCES = {
    "cross_check_figure": ".comparisons",
    "cycles_figure": ".comparisons",
    "sweep_figure": ".comparisons",
    "loop_figure": ".drawings",
    "side_view_figure": ".drawings",
    "workspace_figure": ".drawings",
    "CYCLE_FIGURES": ".catalog",
    "cycle_figures": ".figures",
    "mark_stages": ".figures",
    "position_figure": ".figures",
    "time_history": ".figures",
    "kinematics_figures": ".report",
    "study_figures": ".report",
}
"""Public name → the module that defines it."""

__all__ = [
    "CYCLE_FIGURES",
    "cross_check_figure",
    "cycle_figures",
    "cycles_figure",
    "kinematics_figures",
    "loop_figure",
    "mark_stages",
    "position_figure",
    "side_view_figure",
    "study_figures",
    "sweep_figure",
    "time_history",
    "workspace_figure",
]


__getattr__, __dir__ = lazy_names(__name__, _SOURCES, __all__)
