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

The names below are the public API that the README, the notebooks and the command line use.
Errors are :class:`FeederError` and its subclasses in :mod:`feeder.exceptions`.
"""

from .chain import ClosedChain, Partition, load_closed_chain
from .device import DEVICES, Feeder, FeederParameters, LinkInertia, load_feeder, loop_state
from .device.loop import required_stroke, transmission_angle
from .exceptions import FeederError
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

__version__ = "0.1.0"

__all__ = [
    "DEVICES",
    "ClosedChain",
    "CycleSpec",
    "CycleStudy",
    "Feeder",
    "FeederError",
    "FeederParameters",
    "LinkInertia",
    "Partition",
    "elevation_sweep",
    "feeding_cycle",
    "load_closed_chain",
    "load_feeder",
    "loop_state",
    "paper_errata",
    "read_csv",
    "required_stroke",
    "retrofit",
    "run_cycle_study",
    "transmission_angle",
    "workspace",
    "write_cycle_outputs",
]
