"""One design point of a mechanism run as ``feeder analyze --motion`` runs it: the URDF edited
with the variables' values (:mod:`~feeder.design.mechanism.urdf_edit`), read by the chain's
readers from a temporary file, then :func:`feeder.study.analyze.analyze` on every motion table
(the mechanism mounted on its assembled pose, the motion tracked by continuation, inverse
dynamics with every reaction).

The temporary URDF is written in a new temporary folder, or, when the model names meshes, beside
the model (a hidden name, removed after the run): the readers resolve mesh paths against the
model's folder and read none outside it (:mod:`feeder.chain.readers.model_files`).

**The peaks.** Of each run: ``tau_<joint>`` of each actuated joint, ``<joint>_force`` and
``<joint>_moment`` of each joint, ``<closure>_force`` and ``<closure>_moment`` (the magnitudes of
each closure's wrench), ``<element>_force`` of each force element (the column names of
``loads.csv``, :func:`~feeder.study.mechanism_table.load_columns`) and ``velocity_gain``: each
as its series over the samples, whose largest magnitude is the peak.

Points run on the sweep's executor (:func:`~feeder.study.sweep.run_cases`): every local core or
a Dask cluster. A point whose motion does not assemble (a sample unreachable, a singular pose)
is not a crash: its outcome is the reason.
"""

from __future__ import annotations

import os
import tempfile
import warnings
from collections.abc import Iterator, Sequence
from concurrent.futures import Executor
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from ...chain.kinematics.joints import kind_of
from ...chain.kinematics.tree import reach
from ...exceptions import FeederError, FeederWarning
from ...study.analyze import Analysis, analyze
from ...study.mechanism_table import (
    ROUND_OFF,
    column_stem,
    element_units,
    load_scale,
    load_unit,
)
from ...study.sweep import run_cases
from .urdf_edit import Target, edited

GAIN = "velocity_gain"


@dataclass(frozen=True)
class Mechanism:
    """The files of a mechanism.

    Attributes:
        model: The URDF file.
        closures: The mechanism file (its model overridden by each point's URDF).
        motions: The motion tables, (M,).
        urdf: The model's text.
    """

    model: Path
    closures: Path
    motions: tuple[Path, ...]
    urdf: str

    @property
    def meshes(self) -> bool:
        """Whether the model names mesh files (then its edits are written beside it)."""
        return "<mesh" in self.urdf

    def point_urdf(self, targets: Sequence[Target], values) -> str:
        """The URDF with the targets set to ``values`` [their units]."""
        return edited(self.urdf, targets, values)


@dataclass(frozen=True)
class PointCase:
    """One point to run (picklable, for the workers).

    Attributes:
        key: Its key in the batch.
        mechanism: The mechanism's files.
        urdf: The point's URDF text; None: the files as they are (the mechanism file's own
            model, as ``feeder analyze`` reads a written optimum).
    """

    key: bytes
    mechanism: Mechanism
    urdf: str | None


@dataclass(frozen=True)
class Run:
    """A point's runs, one per motion table.

    Attributes:
        series: Peak name → its values over each table's samples, one (N_m,) array per table.
        units: Peak name → its SI unit.
        coordinates: One-coordinate joint → its coordinate over each table's samples [m or
            rad], one (N_m,) array per table.
        times: The samples' times of each table [s].
        joint_units: One-coordinate joint → its coordinate's unit (``m`` or ``rad``).
        scales: Unit (``N``, ``N·m``) → the loads' scale over every table
            (:func:`~feeder.study.mechanism_table.load_scale`): a peak within
            :data:`~feeder.study.mechanism_table.ROUND_OFF` of it is zero to round-off.
    """

    series: dict[str, tuple[np.ndarray, ...]]
    units: dict[str, str]
    coordinates: dict[str, tuple[np.ndarray, ...]]
    times: tuple[np.ndarray, ...]
    joint_units: dict[str, str]
    scales: dict[str, float]

    def round_off(self, name: str) -> bool:
        """Whether the peak of ``name`` is zero to round-off (``feeder analyze`` prints it 0)."""
        unit = self.units[name]
        return unit in self.scales and self.peaks(name).max() <= ROUND_OFF * self.scales[unit]

    def peaks(self, name: str) -> np.ndarray:
        """max |value| of ``name`` over each table's samples, (M,)."""
        return np.array([float(np.max(np.abs(s))) for s in self.series[name]])

    def values(self, name: str) -> np.ndarray:
        """|value| of ``name`` at every sample of every table, in order, (Σ N_m,)."""
        return np.abs(np.concatenate(self.series[name]))

    def labels(self) -> list[str]:
        """``<table index>#<sample>`` of every sample of every table, in order."""
        return [f"{m}#{k}" for m, t in enumerate(self.times) for k in range(t.size)]

    def signed_peak(self, name: str) -> tuple[float, int, float]:
        """The value of largest magnitude over every table, its table's index and time [s]."""
        best = (0.0, 0, float(self.times[0][0]))
        for m, s in enumerate(self.series[name]):
            k = int(np.argmax(np.abs(s)))
            if m == 0 or abs(s[k]) > abs(best[0]):
                best = (float(s[k]), m, float(self.times[m][k]))
        return best


Outcome = Run | str
"""A point's runs, or why they failed."""


@contextmanager
def model_file(mechanism: Mechanism, text: str) -> Iterator[Path]:
    """A temporary URDF file holding ``text`` (module docstring), removed on leaving."""
    if mechanism.meshes:
        handle, name = tempfile.mkstemp(
            suffix=".urdf", prefix=".feeder-design-", dir=mechanism.model.parent
        )
        try:
            with os.fdopen(handle, "w", encoding="utf-8") as stream:
                stream.write(text)
            yield Path(name)
        finally:
            Path(name).unlink(missing_ok=True)
        return
    with tempfile.TemporaryDirectory(prefix="feeder-design-") as folder:
        path = Path(folder) / mechanism.model.name
        path.write_text(text, encoding="utf-8")
        yield path


@contextmanager
def _model(mechanism: Mechanism, text: str | None) -> Iterator[Path | None]:
    """The model file to override the mechanism file's with: a temporary one holding ``text``,
    or None (the mechanism file's own) when ``text`` is None."""
    if text is None:
        yield None
        return
    with model_file(mechanism, text) as path:
        yield path


def loads_series(analysis: Analysis) -> tuple[dict[str, np.ndarray], dict[str, str]]:
    """The peaks' series of one run (module docstring), (N,) each, and their units."""
    loads, model = analysis.loads, analysis.chain.model
    series: dict[str, np.ndarray] = {}
    units: dict[str, str] = {}
    for joint, values in loads.actuators.items():
        series[f"tau_{column_stem(joint)}"] = values
        units[f"tau_{column_stem(joint)}"] = load_unit(model, joint)
    for joint, wrench in loads.joints.items():
        for what, vector, unit in (("force", wrench.force, "N"), ("moment", wrench.moment, "N·m")):
            series[f"{column_stem(joint)}_{what}"] = np.linalg.norm(vector, axis=1)
            units[f"{column_stem(joint)}_{what}"] = unit
    for label, wrench in loads.closures.items():
        for what, vector, unit in (("force", wrench.force, "N"), ("moment", wrench.moment, "N·m")):
            series[f"{column_stem(label)}_{what}"] = np.linalg.norm(vector, axis=1)
            units[f"{column_stem(label)}_{what}"] = unit
    element = element_units(model, analysis.spec.forces)
    for name, values in loads.elements.items():
        series[f"{column_stem(name)}_force"] = values
        units[f"{column_stem(name)}_force"] = element[name]
    series[GAIN], units[GAIN] = analysis.gain, "-"
    return series, units


UNITS = {"revolute": "rad", "prismatic": "m"}
"""The coordinate's unit of the one-coordinate joints whose range a stroke may bound."""


def _coordinates(analysis: Analysis) -> dict[str, tuple[np.ndarray, str]]:
    """Each revolute or prismatic joint's coordinate over the samples, (N,), and its unit."""
    model = analysis.chain.model
    found = {}
    for j in range(1, model.njoints):
        kind = kind_of(model.joints[j])
        if kind in UNITS:
            found[model.names[j]] = (analysis.q[:, model.joints[j].idx_q], UNITS[kind])
    return found


def run_point(case: PointCase) -> tuple[bytes, Outcome]:
    """Run one point on every motion table (in a worker): its key and outcome."""
    mechanism = case.mechanism
    series: dict[str, list[np.ndarray]] = {}
    coordinates: dict[str, list[np.ndarray]] = {}
    times, units, joint_units, force_scale, size = [], {}, {}, 0.0, 0.0
    try:
        with _model(mechanism, case.urdf) as path, warnings.catch_warnings():
            warnings.simplefilter("ignore", FeederWarning)  # the model's warnings: analyze's
            for motion in mechanism.motions:
                analysis = analyze(mechanism.closures, motion, model=path)
                found, units = loads_series(analysis)
                for name, values in found.items():
                    series.setdefault(name, []).append(np.asarray(values, dtype=float))
                for name, (values, unit) in _coordinates(analysis).items():
                    coordinates.setdefault(name, []).append(values)
                    joint_units[name] = unit
                times.append(analysis.motion.t)
                model = analysis.chain.model
                scale = load_scale(model, analysis.loads, analysis.spec.forces)
                force_scale = max(force_scale, scale)
                size = reach(model, pin.neutral(model)[None])
    except FeederError as exc:
        return case.key, str(exc)
    return case.key, Run(
        {k: tuple(v) for k, v in series.items()},
        units,
        {k: tuple(v) for k, v in coordinates.items()},
        tuple(times),
        joint_units,
        {"N": force_scale, "N·m": force_scale * size},
    )


def run_points(
    cases: Sequence[PointCase], executor: Executor | None, slots: int, progress: bool = False
) -> dict[bytes, Outcome]:
    """Every case's outcome, by key, run on ``executor`` (None: here)."""
    return dict(
        run_cases(cases, executor, slots, progress, work=run_point, unit="run", desc="design")
    )
