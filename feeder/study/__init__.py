"""Studies on the device: one loading cycle cross-checked by the hand-derived equations, the
``cycle.csv`` contract, peaks, elevation sweeps, the retrofit payload and the paper's errata."""

from .columns import COLUMNS, KINEMATIC_COLUMNS, Column, cycle_columns, kinematic_columns
from .csv import read_csv, write_csv
from .cycle_study import CycleStudy, run_cycle_study
from .elevation_sweeps import ElevationSweep, elevation_sweep
from .errata import paper_errata
from .peaks import Peak, cycle_peaks
from .retrofit import retrofit

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
