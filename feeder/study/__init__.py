"""Studies on the device: one loading cycle cross-checked by the hand-derived equations, the
``cycle.csv`` contract, peaks, elevation sweeps, the retrofit payload and the paper's errata."""

from typing import TYPE_CHECKING

from ..lazy import lazy_names

# Bound here, not on first use: once the submodule ``retrofit`` is imported (by any module),
# the package's attribute ``retrofit`` would be that module, and __getattr__ never asked.
from .retrofit import retrofit

if TYPE_CHECKING:  # the names for type checkers; at run time they load on first use
    from .columns import COLUMNS, KINEMATIC_COLUMNS, Column, cycle_columns, kinematic_columns
    from .csv import read_csv, write_csv
    from .cycle_study import CycleStudy, run_cycle_study
    from .elevation_sweeps import ElevationSweep, elevation_sweep
    from .errata import paper_errata
    from .peaks import Peak, cycle_peaks


_SOURCES = {
    "COLUMNS": ".columns",
    "Column": ".columns",
    "CycleStudy": ".cycle_study",
    "ElevationSweep": ".elevation_sweeps",
    "KINEMATIC_COLUMNS": ".columns",
    "Peak": ".peaks",
    "cycle_columns": ".columns",
    "cycle_peaks": ".peaks",
    "elevation_sweep": ".elevation_sweeps",
    "kinematic_columns": ".columns",
    "paper_errata": ".errata",
    "read_csv": ".csv",
    "run_cycle_study": ".cycle_study",
    "write_csv": ".csv",
}
"""Public name → the module that defines it."""

__all__ = [
    "COLUMNS",
    "KINEMATIC_COLUMNS",
    "Column",
    "CycleStudy",
    "ElevationSweep",
    "Peak",
    "cycle_columns",
    "cycle_peaks",
    "elevation_sweep",
    "kinematic_columns",
    "paper_errata",
    "read_csv",
    "retrofit",
    "run_cycle_study",
    "write_csv",
]


__getattr__, __dir__ = lazy_names(__name__, _SOURCES, __all__)
