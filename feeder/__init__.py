"""feeder: rigid-body analysis of the 152 mm SPH M77 ammunition feeding device, on Pinocchio.

The package is layered in the order of the data (each layer imports only the ones above it;
tests/test_layers.py checks it):

* :mod:`feeder.chain` — any URDF with loop closures: strict reading, closures, assembly;
* :mod:`feeder.device` — the feeding device: parameters → URDF → Pinocchio model with the
  rod-eye pin closure, and the loop in closed form;
* :mod:`feeder.motion` — the feeding cycle and the payload's workspace;
* :mod:`feeder.dynamics` — inverse dynamics, every joint reaction, drives, forward run;
* :mod:`feeder.paper` — the paper's hand-derived equations (numpy only): the cross-check;
* :mod:`feeder.study` — a cycle cross-checked, the ``cycle.csv`` contract, sweeps, retrofit;
* :mod:`feeder.viz` — figures (matplotlib Figures) and the MeshCat viewer;
* :mod:`feeder.outputs` — the files a study writes.

The names below are the device's workflow, the public API that the README, the notebooks and
the command line use: load a feeder (:func:`load_feeder`, :class:`FeederParameters`), its loop
and workspace, a cycle study (:class:`CycleSpec` → :func:`run_cycle_study` →
:class:`CycleStudy`, :func:`write_cycle_outputs`, :func:`read_csv`), sweeps over elevation and
variants (:func:`elevation_sweep`, :func:`run_sweep`, :func:`retrofit`) and the paper's errata.
Names for any mechanism (:class:`~feeder.chain.ClosedChain`, :class:`~feeder.chain.Partition`,
:func:`~feeder.chain.load_mechanism`, :class:`~feeder.chain.BaseMotion` and its profiles, …)
are in :mod:`feeder.chain` only; the rest of a layer is reached through it (e.g.
:class:`feeder.device.LinkInertia`, :data:`feeder.device.parameters.VEHICLE_FORWARD`). Errors are
:class:`FeederError` and its subclasses in :mod:`feeder.exceptions`.

Each name (and each layer, e.g. ``feeder.viz``) is imported when it is first used, not by
``import feeder``: Pinocchio, and matplotlib above all, take most of a short command's time,
and ``feeder parameters`` needs neither.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .lazy import lazy_names

if TYPE_CHECKING:  # the names for type checkers; at run time they load on first use
    from .device import DEVICES, Feeder, FeederParameters, load_feeder, loop_state
    from .device.loop import required_stroke, transmission_angle
    from .exceptions import FeederError, FeederWarning
    from .motion import CycleSpec, feeding_cycle, workspace
    from .outputs import write_cycle_outputs
    from .study import (
        CycleStudy,
        elevation_sweep,
        paper_errata,
        read_csv,
        retrofit,
        run_cycle_study,
    )
    from .study.sweep_folder import run_sweep

__version__ = "0.1.0"

__all__ = [
    "DEVICES",
    "CycleSpec",
    "CycleStudy",
    "Feeder",
    "FeederError",
    "FeederParameters",
    "FeederWarning",
    "elevation_sweep",
    "feeding_cycle",
    "load_feeder",
    "loop_state",
    "paper_errata",
    "read_csv",
    "required_stroke",
    "retrofit",
    "run_cycle_study",
    "run_sweep",
    "transmission_angle",
    "workspace",
    "write_cycle_outputs",
]

_SOURCES = {
    "DEVICES": ".device",
    "Feeder": ".device",
    "FeederParameters": ".device",
    "load_feeder": ".device",
    "loop_state": ".device",
    "required_stroke": ".device.loop",
    "transmission_angle": ".device.loop",
    "FeederError": ".exceptions",
    "FeederWarning": ".exceptions",
    "CycleSpec": ".motion",
    "feeding_cycle": ".motion",
    "workspace": ".motion",
    "write_cycle_outputs": ".outputs",
    "CycleStudy": ".study",
    "elevation_sweep": ".study",
    "paper_errata": ".study",
    "read_csv": ".study",
    "retrofit": ".study",
    "run_cycle_study": ".study",
    "run_sweep": ".study.sweep_folder",
}
"""Public name → the module that defines it (every name of :data:`__all__`)."""

_SUBMODULES = frozenset(
    {"chain", "device", "motion", "dynamics", "paper", "study", "viz", "outputs"}
)


__getattr__, __dir__ = lazy_names(__name__, _SOURCES, __all__, submodules=_SUBMODULES)
