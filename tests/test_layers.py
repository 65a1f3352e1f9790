"""The package's layers: the data flows one way, the paper's equations stay independent, and no
module imports itself through others.

The contracts live in ``pyproject.toml`` ([tool.importlinter]) and are checked with
import-linter (which also gives ``lint-imports`` on the command line): chain → device → motion
→ dynamics → paper → study → viz → outputs → CLI, over the leaf modules files, validation, inertia
and exceptions; inside chain, model → readers | kinematics → assembly → mobility → dynamics;
``feeder.paper`` reaches neither Pinocchio nor the pipeline, directly or not; the device's layers
(device, motion, dynamics, paper, the device's studies) import ``feeder.chain``'s public names
only: those of ``feeder.chain``, ``feeder.chain.readers`` and ``feeder.chain.results`` (never
the modules inside them).
"""

from __future__ import annotations

import grimp
from importlinter.cli import lint_imports

from .conftest import REPO


def test_contracts_are_kept(monkeypatch, capsys):
    monkeypatch.chdir(REPO)
    status = lint_imports(config_filename=str(REPO / "pyproject.toml"))
    report = capsys.readouterr().out
    assert status == 0, report
    assert "4 kept, 0 broken" in report


def test_no_import_cycles():
    graph = grimp.build_graph("feeder")
    modules = sorted(graph.modules)
    state: dict[str, int] = {}  # 1: on the current path, 2: done

    def visit(module: str, path: list[str]) -> None:
        state[module] = 1
        for imported in sorted(graph.find_modules_directly_imported_by(module)):
            if state.get(imported) == 1:
                raise AssertionError(" → ".join([*path, module, imported]))
            if imported not in state:
                visit(imported, [*path, module])
        state[module] = 2

    for module in modules:
        if module not in state:
            visit(module, [])


def test_chain_imports_nothing_of_the_device():
    graph = grimp.build_graph("feeder")
    allowed = ("feeder.chain", "feeder.exceptions", "feeder.validation", "feeder.inertia")
    allowed += ("feeder.hermite",)  # numpy and SciPy's polynomials only
    allowed += (
        "feeder.lazy",
    )  # the packages' lazy public names: generic, imports no feeder module
    for module in graph.find_descendants("feeder.chain") | {"feeder.chain"}:
        for imported in graph.find_modules_directly_imported_by(module):
            assert imported.startswith(allowed), f"{module} imports {imported}"
