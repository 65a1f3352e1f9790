"""Figures and the 3-D viewer. Every figure function returns a
:class:`matplotlib.figure.Figure` (saving is the caller's: :func:`feeder.outputs.save_figure`);
the MeshCat viewer, served on 127.0.0.1 only, is :mod:`feeder.viz.viewer` (imported on demand:
it pulls in MeshCat)."""

from .comparisons import cross_check_figure, cycles_figure, sweep_figure
from .drawings import loop_figure, side_view_figure, workspace_figure
from .figures import CYCLE_FIGURES, cycle_figures, mark_stages, position_figure, time_history
from .report import kinematics_figures, study_figures

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
