"""``feeder design optimize MODEL --closures F --design D --motion M``: the design variables of a
mechanism that minimise the objective of its design file within the bounds and constraints,
written into an output folder (:class:`~feeder.files.OutputFolder`, resumable).

The search is the device's (:mod:`feeder.design.search`: the Latin-hypercube global start where
the design file asks for samples, then SciPy's SLSQP on the epigraph form, the history that a
run on the same folder resumes, Ctrl-C writing the best feasible point so far, status
:data:`~feeder.design.report.INTERRUPTED`), on the problem of
:mod:`~feeder.design.mechanism.problem`.

Files: :data:`MODEL_FILE` and :data:`MECHANISM_FILE` (the optimum as a URDF and the mechanism
file naming it, which ``feeder analyze`` and the other commands read), the model's mesh files
copied into ``meshes/`` for them (:mod:`~feeder.design.mechanism.meshes`), ``optimum.csv`` and
``summary.txt`` (:mod:`~feeder.design.mechanism.report`), ``history.csv``, ``optimum.png``
(:mod:`~feeder.design.mechanism.figure`), ``report.html`` (the summary, the table and the
figure on one static page) and the manifest. The optimum's peaks are those of the written
files, run as ``feeder analyze`` runs them.
"""

from __future__ import annotations

import hashlib
import json
import re
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from ...exceptions import InputError
from ...files import OutputFolder, Writer, write_text
from ...study.sweep import sweep_executor
from ..history import HISTORY, History
from ..optimize import earlier_history, found_optimum
from ..report import INTERRUPTED, Optimum
from ..search import Search
from ..tables import write_rows
from .design_file import MechanismDesign
from .evaluation import Mechanism, PointCase, run_point
from .inputs import MechanismInputs, check_inputs
from .meshes import MESH_FOLDER, MESH_LIMIT, MeshCopies, mesh_copies
from .problem import MechanismEvaluation, MechanismProblem
from .report import optimum_rows, summary

MODEL_FILE, MECHANISM_FILE = "optimum.urdf", "optimum_mechanism.toml"
TABLE, SUMMARY, FIGURE, PAGE = "optimum.csv", "summary.txt", "optimum.png", "report.html"

_MODEL_KEY = re.compile(r"""^(\s*urdf\s*=\s*)("[^"\n]*"|'[^'\n]*')""", re.MULTILINE)
"""The ``urdf = "…"`` line of a TOML mechanism file (the only key of that name in one)."""


@dataclass(frozen=True)
class MechanismSetup:
    """The checked inputs of a run and the hash that tells its history from another's.

    Attributes:
        inputs: The design, the mechanism's files, the run at the starts.
        space: The design (the name the device's history check reads).
        fingerprint: SHA-256 of the files' contents.
        meshes: The model's mesh files to copy beside the optimum.
    """

    inputs: MechanismInputs
    space: MechanismDesign
    fingerprint: str
    meshes: MeshCopies


def mechanism_text(closures: Path, urdf_name: str) -> str:
    """The TOML mechanism file ``closures`` naming the model ``urdf_name`` (beside it)."""
    text = closures.read_text(encoding="utf-8-sig")
    if len(_MODEL_KEY.findall(text)) != 1:
        raise InputError(
            f"{closures}: optimize writes the optimum's mechanism file from this one, which must "
            'name its model in one line urdf = "FILE"'
        )
    return _MODEL_KEY.sub(lambda m: f'{m.group(1)}"{urdf_name}"', text)


def check_setup(model, closures, design, motions, mesh_limit: int = MESH_LIMIT) -> MechanismSetup:
    """Every input checked (:func:`~.inputs.check_inputs`, and what writing the optimum needs)
    before any folder is made.

    Raises:
        InputError: As :func:`~.inputs.check_inputs`; a mechanism file that is not TOML or
            does not name its model in one ``urdf =`` line; mesh files totalling more than
            ``mesh_limit`` bytes (:func:`~.meshes.mesh_copies`).
    """
    inputs = check_inputs(model, closures, design, motions)
    m = inputs.mechanism
    if m.closures.suffix.lower() != ".toml":
        raise InputError(f"{m.closures}: optimize writes a TOML mechanism file: give a TOML one")
    mechanism_text(m.closures, MODEL_FILE)
    meshes = mesh_copies(m.model, m.urdf, mesh_limit)
    files = [m.model, m.closures, inputs.design.path, *m.motions]
    text = json.dumps([hashlib.sha256(Path(f).read_bytes()).hexdigest() for f in files])
    fingerprint = hashlib.sha256(text.encode("utf-8")).hexdigest()
    return MechanismSetup(inputs, inputs.design, fingerprint, meshes)


def written(
    problem: MechanismProblem, candidates: Sequence[MechanismEvaluation], meshes: MeshCopies
) -> tuple[MechanismEvaluation | None, str]:
    """The first candidate whose model, written as :data:`MODEL_FILE` (its meshes named as
    ``meshes`` copies them) and :data:`MECHANISM_FILE`, runs as ``feeder analyze`` runs it: (its
    evaluation as written, the mechanism file's text); (None, "") when none does. The meshes
    are not copied for this run: the loads read none."""
    m = problem.mechanism
    text = mechanism_text(m.closures, MODEL_FILE)
    with tempfile.TemporaryDirectory(prefix="feeder-optimum-") as folder:
        for e in candidates:
            urdf, closures = Path(folder) / MODEL_FILE, Path(folder) / MECHANISM_FILE
            model = meshes.rewritten(e.urdf)
            write_text(urdf, model)
            write_text(closures, text)
            _, run = run_point(PointCase(b"", Mechanism(urdf, closures, m.motions, model), None))
            problem.cycles += len(m.motions)
            if not isinstance(run, str):
                return MechanismEvaluation(e.x, model, run, ""), text
    return None, ""


def _record(setup: MechanismSetup, command: str | None, status: str, runs: int) -> dict:
    from .outputs import files_record

    return {
        "command": command or "Python API (feeder.design.mechanism.run_mechanism_optimization)",
        "status": status,
        "problem_sha256": setup.fingerprint,
        "objective": setup.space.objective.text,
        **files_record(setup.inputs),
        "runs": runs,
    }


def _figure(opt: Optimum) -> bytes:
    from ...viz.png import png_bytes
    from .figure import mechanism_optimum_figure

    return png_bytes(mechanism_optimum_figure(opt))


def _write(
    folder: OutputFolder,
    setup: MechanismSetup,
    optimum: Optimum,
    history: History,
    model_text: tuple[str, str],
    figure: bool,
    command: str | None,
) -> list[Path]:
    """Every output and the manifest (marked with the status); the history first."""
    from ...viz.png import write_png
    from ...viz.report_page import report_page

    urdf, closures = model_text
    copies = len(setup.meshes.files)
    meshes = f" (its {copies} mesh file(s) copied into {MESH_FOLDER}/)" if copies else ""
    names = f"{MODEL_FILE}{meshes} and {MECHANISM_FILE}" if urdf else ""
    report = summary(optimum, names) + "\n"
    rows = optimum_rows(optimum)
    outputs: dict[str, Writer] = {HISTORY: history.write}
    if urdf:
        outputs |= setup.meshes.writers()  # before the model that names them
        outputs[MODEL_FILE] = lambda path: write_text(path, urdf)
        outputs[MECHANISM_FILE] = lambda path: write_text(path, closures)
    outputs[TABLE] = lambda path: write_rows(path, rows)
    outputs[SUMMARY] = lambda path: write_text(path, report)
    pngs = {FIGURE: _figure(optimum)} if figure else {}
    if figure:
        outputs[FIGURE] = lambda path: write_png(path, pngs[FIGURE])
    title = f"{setup.inputs.mechanism.model.stem}: feeder design optimize"
    page = report_page(title, command or "", report, None, pngs, "Summary", {TABLE: rows})
    outputs[PAGE] = lambda path: write_text(path, page)
    record = _record(setup, command, optimum.status, optimum.problem.cycles)
    return folder.write(outputs, record)


def run_mechanism_optimization(
    model: str | Path,
    closures: str | Path,
    design: str | Path,
    motions: Sequence[str | Path],
    out_dir: str | Path,
    *,
    samples: int | None = None,
    starts: int | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
    figure: bool = True,
    command: str | None = None,
) -> tuple[Optimum, list[Path]]:
    """Optimise the mechanism's design variables and write the outputs (module docstring) into
    ``out_dir``; returns the optimum and the paths written.

    Args:
        model, closures, design, motions: The URDF, the mechanism file, the design file and the
            motion tables.
        samples, starts: Override the design file's ``[search]``.
        workers, scheduler: Where the runs go (:func:`~feeder.study.sweep.sweep_executor`).
        progress: Progress bars on a terminal.
        figure: Also write ``optimum.png`` (and show it on ``report.html``).
        command: The command line, for the manifest.

    Raises:
        InputError: Any refusal of :func:`check_setup`; another problem's history in the
            folder.
        KeyboardInterrupt: After writing the best feasible point so far.
    """
    setup = check_setup(model, closures, design, motions)
    space = setup.space
    samples = space.samples if samples is None else samples
    starts = space.starts if starts is None else starts
    folder = OutputFolder(out_dir, resumable=True)
    began = time.monotonic()
    with folder:
        history = History([v.name for v in space.variables], earlier_history(folder, setup),
                          save=lambda h: folder.put(HISTORY, h.write))  # fmt: skip
        folder.begin(_record(setup, command, "running", 0))
        search = None
        try:
            with sweep_executor(workers, scheduler) as (executor, slots):
                problem = MechanismProblem(space, setup.inputs.mechanism, executor, slots)
                search = Search(problem, history, progress)
                found = search.run(samples, starts)
                best, text = written(problem, search.feasible(), setup.meshes)
            optimum = found_optimum(found, best, time.monotonic() - began)
        except KeyboardInterrupt:
            if search is None or search.reference_point is None:
                raise
            best = search.best()
            text = (
                "" if best is None else mechanism_text(setup.inputs.mechanism.closures, MODEL_FILE)
            )
            optimum = Optimum(INTERRUPTED, (), search.problem, search.reference_point, best, {},
                              time.monotonic() - began)  # fmt: skip
            model_text = ("", "") if best is None else (setup.meshes.rewritten(best.urdf), text)
            _write(folder, setup, optimum, history, model_text, figure, command)
            raise
        model_text = (best.urdf, text) if best is not None else ("", "")
        paths = _write(folder, setup, optimum, history, model_text, figure, command)
    return optimum, paths
