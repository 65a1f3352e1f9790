"""A user mechanism's figures drawn into PNG bytes from their panels (:mod:`feeder.viz.panels`),
in this process or in a process forked before the run (:func:`figure_process`): the panels are
sent to it, and it imports matplotlib (lean: :func:`~feeder.viz.forked.import_matplotlib`) while
the run computes. This module imports matplotlib only to draw."""

from __future__ import annotations

from collections.abc import Mapping

from .forked import FigureProcess, import_matplotlib
from .panels import Stack


def stack_pngs(stacks: Mapping[str, Stack]) -> dict[str, bytes]:
    """Each stack of panels drawn (:func:`~feeder.viz.analysis.stacked_figure`) as a PNG file's
    bytes, by file name."""
    from .analysis import stacked_figure
    from .png import png_bytes

    return {name: png_bytes(stacked_figure(t, panels)) for name, (t, panels) in stacks.items()}


def figure_process(figures: bool = True) -> FigureProcess:
    """The process that draws a mechanism's figures (:func:`stack_pngs`), forked on entering it
    if ``figures`` and forking is safe here: it imports matplotlib while the run computes."""
    return FigureProcess(_prepare, "drawing the figures", fork=figures)


def _prepare() -> None:
    """Import what drawing needs: matplotlib lean
    (:func:`~feeder.viz.forked.import_matplotlib`) and the figures' module."""
    import_matplotlib()
    from . import analysis  # noqa: F401
