"""The inputs of ``feeder design sensitivities|optimize MODEL --closures F --design D --motion
M``, checked before any folder is made: the model (a URDF), the mechanism file, the motion
tables and the design file, and the peaks its objective and limits name, which a run of the
model at the variables' starts lists (:func:`~.evaluation.run_point`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...chain.readers.mechanism import read_spec
from ...chain.readers.urdf import read_urdf
from ...exceptions import InputError
from ...validation import check_file, check_path
from .design_file import MechanismDesign, check_peaks, read_mechanism_design
from .evaluation import Mechanism, PointCase, run_point


@dataclass(frozen=True)
class MechanismInputs:
    """The checked inputs.

    Attributes:
        design: The design file.
        mechanism: The mechanism's files.
    """

    design: MechanismDesign
    mechanism: Mechanism


def check_inputs(
    model: str | Path, closures: str | Path, design: str | Path, motions: Sequence[str | Path]
) -> MechanismInputs:
    """Every input checked (module docstring).

    Raises:
        InputError: A model that is not a URDF; a missing file; no motion table; a bad design
            file (:func:`~.design_file.mechanism_design`); an objective or limit naming no
            peak; a model that fails to run at the variables' starts (the reason).
    """
    model = check_path("the model file", model)
    if model.suffix.lower() != ".urdf":
        raise InputError(
            f"{model}: the design of a mechanism edits a URDF model, not {model.suffix}"
        )
    closures = check_path("the closure file", closures)
    read_spec(closures, model)  # the mechanism file, checked as feeder analyze does
    if isinstance(motions, (str, Path)) or not motions:
        raise InputError("give at least one motion table: --motion FILE")
    tables = tuple(check_file("motion table", m) for m in motions)
    if len({t.name for t in tables}) != len(tables):
        raise InputError(f"the motion tables must have distinct file names, got {list(tables)}")
    urdf = read_urdf(model)
    found = read_mechanism_design(check_path("the design file", design), urdf, str(model))
    mechanism = Mechanism(model, closures, tables, urdf)
    start = np.array([v.start for v in found.variables])
    targets = [v.target for v in found.variables]
    _, run = run_point(PointCase(b"", mechanism, mechanism.point_urdf(targets, start)))
    if isinstance(run, str):
        raise InputError(f"the model as given (the variables' starts) fails: {run}")
    check_peaks(found, run.units)
    return MechanismInputs(found, mechanism)
