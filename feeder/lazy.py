"""Public names that load on first use (PEP 562), for the packages' ``__init__`` modules: a
command imports only the modules it uses (``tests/test_lazy_imports.py``), while
``from feeder.chain import simulate`` works as with an eager package."""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Iterable, Mapping


def lazy_names(
    module: str,
    sources: Mapping[str, str],
    names: Iterable[str] = (),
    *,
    anchor: str | None = None,
    submodules: Iterable[str] = (),
) -> tuple[Callable[[str], object], Callable[[], list[str]]]:
    """The ``__getattr__`` and ``__dir__`` of ``module``.

    Args:
        module: The module's ``__name__``.
        sources: Public name → the module that defines it, relative to ``anchor``.
        names: The module's ``__all__`` (``dir()`` lists them before their first use).
        anchor: The package the relative names start from (default: ``module``, a package).
        submodules: Names that are the package's own submodules, imported as modules.

    Returns:
        The two functions, to assign as ``__getattr__, __dir__``: a name of ``sources`` or
        ``submodules`` is imported on first use and kept in the module; any other name raises
        :class:`AttributeError`.
    """
    anchor = module if anchor is None else anchor
    submodules = frozenset(submodules)
    listed = set(names) | set(sources) | submodules

    def __getattr__(name: str) -> object:
        if name in sources:
            value = getattr(importlib.import_module(sources[name], anchor), name)
        elif name in submodules:
            value = importlib.import_module(f".{name}", module)
        else:
            raise AttributeError(f"module {module!r} has no attribute {name!r}")
        setattr(sys.modules[module], name, value)
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[module])) | listed)

    return __getattr__, __dir__
