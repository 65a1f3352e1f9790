"""The files of ``feeder design sensitivities MODEL --closures F --design D --motion M``: the
tables, the summary, the heat map and the manifest, written into an output folder
(:class:`~feeder.files.OutputFolder`: checked before the work, locked, every file atomic, a
manifest with the SHA-256 of each). The file names and the details' columns are the device's
(:mod:`feeder.design.outputs`, :mod:`feeder.design.tables`)."""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from pathlib import Path

from ...files import OutputFolder, write_text
from ..differences import STEP_FACTOR, check_step_factor
from ..outputs import DETAILS, FIGURE, SUMMARY, TABLE, figure_writer
from ..tables import detail_rows, write_rows
from .inputs import MechanismInputs, check_inputs
from .sensitivities import MechanismSensitivities, mechanism_sensitivities, summary, wide_rows


def files_record(inputs: MechanismInputs) -> dict:
    """The manifest's record of the mechanism's files: their paths and SHA-256."""
    m = inputs.mechanism
    files = [m.model, m.closures, inputs.design.path, *m.motions]
    return {
        "model": str(m.model),
        "closures": str(m.closures),
        "design": str(inputs.design.path),
        "motions": [str(path) for path in m.motions],
        "files_sha256": {
            str(path): hashlib.sha256(Path(path).read_bytes()).hexdigest() for path in files
        },
        "variables": [v.name for v in inputs.design.variables],
    }


def run_mechanism_sensitivities(
    model: str | Path,
    closures: str | Path,
    design: str | Path,
    motions: Sequence[str | Path],
    out_dir: str | Path,
    *,
    factor: float = STEP_FACTOR,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
    figure: bool = True,
    command: str | None = None,
) -> tuple[MechanismSensitivities, list[Path]]:
    """The sensitivities of every peak of a mechanism to its design variables
    (:func:`~.sensitivities.mechanism_sensitivities`), written into ``out_dir``: the tables
    ``sensitivities.csv`` and ``sensitivity_details.csv``, ``summary.txt``,
    ``sensitivities.png`` (unless ``figure`` is False) and the manifest; returns the result
    and the paths, the table first.

    Raises:
        InputError: Any refusal of :func:`~.inputs.check_inputs`; a step not in (0, 0.1];
            bad workers or scheduler; an output folder that cannot be written.
    """
    factor = check_step_factor(factor)
    inputs = check_inputs(model, closures, design, motions)
    folder = OutputFolder(out_dir)
    with folder:
        result = mechanism_sensitivities(
            inputs.design, inputs.mechanism, factor, workers, scheduler, progress
        )
        text = summary(result) + "\n"
        outputs = {
            TABLE: lambda path: write_rows(path, wide_rows(result)),
            DETAILS: lambda path: write_rows(path, detail_rows(result)),
            SUMMARY: lambda path: write_text(path, text),
        }
        if figure:
            outputs[FIGURE] = figure_writer(".figure", "sensitivity_figure", result)
        record = {
            "command": command
            or "Python API (feeder.design.mechanism.run_mechanism_sensitivities)",
            **files_record(inputs),
            "relative_step": factor,
            "runs": result.runs,
        }
        paths = folder.write(outputs, record)
    return result, paths
