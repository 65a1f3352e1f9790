"""Pinocchio's MeshCat visualizer, :class:`MeshcatVisualizer`, imported without trimesh.

``pinocchio.visualize`` imports every viewer it has; its viser viewer imports trimesh (with
``scipy.spatial``: 0.35 s, longer than drawing the squeezer's whole report page) and then viser,
and is given up when viser is not installed. Where viser is not installed, trimesh is hidden
during that import (:func:`hidden`): the viser viewer is given up at once, as it would have been
after loading trimesh, and nothing else changes; trimesh imports as usual afterwards.
"""

from __future__ import annotations

import contextlib
import importlib.util
import sys
from collections.abc import Iterator


@contextlib.contextmanager
def hidden(name: str) -> Iterator[None]:
    """While the block runs, ``import name`` raises ImportError (unless the module is imported
    already: then nothing changes); afterwards it imports as usual."""
    hide = name not in sys.modules
    if hide:
        sys.modules[name] = None  # the import system's mark of a module that cannot be imported
    try:
        yield
    finally:
        if hide and name in sys.modules and sys.modules[name] is None:
            del sys.modules[name]


with hidden("trimesh") if importlib.util.find_spec("viser") is None else contextlib.nullcontext():
    from pinocchio.visualize import MeshcatVisualizer

__all__ = ["MeshcatVisualizer", "hidden"]
