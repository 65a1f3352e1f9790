"""The package's own modules import only what ``pip install .`` brings (issue 19): the runtime
dependencies of ``pyproject.toml`` and what they install. A command's extra (``cluster``,
``parquet``) may be imported only inside the function that needs it; the test extra's packages
(example-robot-data, yourdfpy and its trimesh stack) never.

Imports are read from the source with :mod:`ast` (nothing is executed); a module is traced to the
distributions that install it by the installed files (as
:func:`importlib.metadata.packages_distributions`, which misses Pinocchio's).
"""

from __future__ import annotations

import ast
import importlib.metadata
import sys
import tomllib
from functools import cache

import pytest
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

from .conftest import REPO

PROJECT = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))["project"]
SOURCES = sorted((REPO / "feeder").rglob("*.py"))
NOT_INSTALLED = "imported inside a function, not installed here"


def imports(source: str) -> dict[str, bool]:
    """Top-level names of the third-party modules ``source`` imports → whether every import of
    it runs only when a function is called (inside a ``def``)."""
    found: dict[str, bool] = {}

    def visit(node: ast.AST, lazy: bool) -> None:
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0:
            names = [node.module]
        else:
            names = []
        for name in names:
            top = name.split(".")[0]
            if top != "feeder" and top not in sys.stdlib_module_names:
                found[top] = found.get(top, True) and lazy
        inside = lazy or isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
        for child in ast.iter_child_nodes(node):
            visit(child, inside)

    visit(ast.parse(source), lazy=False)
    return found


@cache
def installed_closure(requirements: tuple[str, ...]) -> frozenset[str]:
    """The distributions pip installs for ``requirements``: them and, through the installed
    metadata, what they require in turn (canonical names)."""
    seen: set[tuple[str, str]] = set()
    todo = [Requirement(text) for text in requirements]
    while todo:
        requirement = todo.pop()
        name = canonicalize_name(requirement.name)
        for extra in ("", *requirement.extras):
            if (name, extra) in seen:
                continue
            seen.add((name, extra))
            try:
                needs = importlib.metadata.requires(name) or []
            except importlib.metadata.PackageNotFoundError:
                continue  # an extra not installed here: it brings nothing to trace
            for text in needs:
                need = Requirement(text)
                if need.marker is None or need.marker.evaluate({"extra": extra}):
                    todo.append(need)
    return frozenset(name for name, _ in seen)


@cache
def distributions_of() -> dict[str, frozenset[str]]:
    """Top-level module → the distributions that install it (canonical names).

    As :func:`importlib.metadata.packages_distributions`, from the first folder of each installed
    file, except that Pinocchio's wheels (cmeel) install ``pinocchio`` and ``coal`` under
    ``cmeel.prefix/lib/python3.X/site-packages/``: there the first folder after that one counts.
    """
    found: dict[str, set[str]] = {}
    for dist in importlib.metadata.distributions():
        name = canonicalize_name(dist.metadata["Name"])
        for file in dist.files or []:
            parts = file.parts
            if "site-packages" in parts[:-1]:
                parts = parts[parts.index("site-packages") + 1 :]
            module = parts[0].split(".")[0]  # a folder, name.py or name.cpython-311-….so
            found.setdefault(module, set()).add(name)
    return {module: frozenset(names) for module, names in found.items()}


def runtime() -> frozenset[str]:
    return installed_closure(tuple(PROJECT["dependencies"]))


def command_extras() -> frozenset[str]:
    """What the extras of the commands bring (every extra but ``test``)."""
    extras = PROJECT["optional-dependencies"]
    return installed_closure(
        tuple(text for name, group in extras.items() if name != "test" for text in group)
    )


def offenders(source: str) -> dict[str, str]:
    """Third-party modules of ``source`` that ``pip install .`` does not bring → why."""
    found = {}
    for module, lazy in imports(source).items():
        owners = distributions_of().get(module, frozenset())
        if not owners:
            found[module] = NOT_INSTALLED if lazy else "imported with the module, not installed"
        elif not owners & runtime():
            if not lazy:
                found[module] = f"imported with the module, from {sorted(owners)}"
            elif not owners & command_extras():
                found[module] = f"from {sorted(owners)}, in neither dependencies nor an extra"
    return found


def test_the_checker_finds_a_test_only_package_in_the_package():
    """yourdfpy is the test extra's: feeder/ may not import it, not even inside a function."""
    assert "yourdfpy" in offenders("import yourdfpy\n")
    assert "yourdfpy" in offenders("def f():\n    from yourdfpy import URDF\n")
    assert offenders("import numpy\nimport pinocchio\nfrom lxml import etree\n") == {}


def test_a_command_extra_is_imported_only_where_it_is_used():
    """pyarrow is the parquet extra's: inside a function, yes; with the module, never."""
    pytest.importorskip("pyarrow", reason="the parquet extra is not installed")
    assert offenders("def f():\n    import pyarrow\n") == {}
    assert "pyarrow" in offenders("import pyarrow\n")


def test_package_modules_import_only_what_pip_install_brings():
    found = {
        f"{path.relative_to(REPO)}: {module}": why
        for path in SOURCES
        for module, why in offenders(path.read_text(encoding="utf-8")).items()
    }
    assert {where: why for where, why in found.items() if why != NOT_INSTALLED} == {}
    if found:
        pytest.skip(f"{', '.join(found)}: {NOT_INSTALLED} (its extra could not be installed)")
