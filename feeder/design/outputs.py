"""The files of ``feeder design sensitivities``: the tables, the summary, the figure and the
manifest, written into an output folder by the rule of every feeder run
(:class:`~feeder.files.OutputFolder`: checked before the work, locked, every file atomic, a
manifest with the SHA-256 of each)."""

from __future__ import annotations

import importlib
from collections.abc import Sequence
from pathlib import Path

from ..device.parameter_file import parameters_sha256
from ..device.parameters import FeederParameters
from ..files import OutputFolder, Writer, write_text
from ..motion.laws import CycleSpec
from .differences import STEP_FACTOR
from .sensitivities import Sensitivities, check_inputs, design_sensitivities
from .tables import detail_rows, summary, wide_rows, write_rows

TABLE = "sensitivities.csv"
DETAILS = "sensitivity_details.csv"
SUMMARY = "summary.txt"
FIGURE = "sensitivities.png"


def figure_writer(module: str, function: str, data: object) -> Writer:
    """The writer of the PNG that ``function`` of the figure module ``module`` (relative to
    :mod:`feeder.design`: ``.figure``, ``.optimum_figure``) draws of ``data``: the module, and
    matplotlib with it, is imported only when the file is written."""

    def write(path: Path) -> Path:
        from ..viz.png import png_bytes, write_png

        draw = getattr(importlib.import_module(module, __package__), function)
        return write_png(path, png_bytes(draw(data)))

    return write


def sensitivity_writers(result: Sensitivities) -> dict[str, Writer]:
    """The writers of the tables :data:`TABLE` and :data:`DETAILS`, in that order (also the
    sensitivities at the optimum of ``feeder design optimize``)."""
    return {
        TABLE: lambda path: write_rows(path, wide_rows(result)),
        DETAILS: lambda path: write_rows(path, detail_rows(result)),
    }


def record(result: Sensitivities, params: FeederParameters, command: str | None) -> dict:
    """The manifest's description of the study: what was differentiated, where, how."""
    scopes = {scope.name: list(scope.elevations_deg) for scope in result.scopes}
    return {
        "command": command or "Python API (feeder.design.run_sensitivities)",
        "device": result.device,
        "parameters_sha256": parameters_sha256(params),
        "elevation_deg": scopes.get("elevation", [None])[0],
        "envelope_elevations_deg": scopes.get("envelope", []),
        "stage_durations_s": list(result.spec.durations),
        "sample_rate_hz": result.spec.rate,
        "relative_step": result.factor,
        "parameters": [p.name for p in result.parameters],
        "cycles": result.cycles,
    }


def write_sensitivity_outputs(
    result: Sensitivities,
    params: FeederParameters,
    folder: OutputFolder,
    command: str | None = None,
    figure: bool = True,
) -> list[Path]:
    """Write :data:`TABLE`, :data:`DETAILS`, :data:`SUMMARY`, :data:`FIGURE` (unless
    ``figure`` is False) and the manifest into ``folder`` (entered); returns the paths, the
    table first."""
    text = summary(result) + "\n"
    outputs = sensitivity_writers(result)
    outputs[SUMMARY] = lambda path: write_text(path, text)
    if figure:
        outputs[FIGURE] = figure_writer(".figure", "sensitivity_figure", result)
    return folder.write(outputs, record(result, params, command))


def run_sensitivities(
    params: FeederParameters,
    out_dir: str | Path,
    *,
    elevations_deg: Sequence[float] | None = None,
    elevation_deg: float | None = None,
    parameters: Sequence[str] | None = None,
    spec: CycleSpec | None = None,
    factor: float = STEP_FACTOR,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
    figure: bool = True,
    command: str | None = None,
) -> tuple[Sensitivities, list[Path]]:
    """Compute the sensitivities (:func:`~feeder.design.sensitivities.design_sensitivities`,
    whose arguments these are) and write them into the output folder ``out_dir``, checked
    before any cycle runs; returns the result and the paths written.

    Raises:
        InputError: Any error of ``design_sensitivities``; an output folder that cannot be
            written or holds files no feeder run wrote.
        OutputBusyError: Another run is writing into the folder.
    """
    check_inputs(params, elevations_deg, elevation_deg, parameters, factor)
    folder = OutputFolder(out_dir)
    with folder:
        result = design_sensitivities(
            params,
            elevations_deg=elevations_deg,
            elevation_deg=elevation_deg,
            parameters=parameters,
            spec=spec,
            factor=factor,
            workers=workers,
            scheduler=scheduler,
            progress=progress,
        )
        paths = write_sensitivity_outputs(result, params, folder, command, figure)
    return result, paths
