"""The public API stays small and says one thing per name: ``feeder`` is the device's workflow
(at most 20 names), ``feeder.chain`` any mechanism's (at most 27), every listed name resolves,
and no two public functions of the package's public ``__all__``s share a name while being
different objects (a re-export of the same object is fine)."""

from __future__ import annotations

import importlib
import inspect

import pytest

import feeder
import feeder.chain

DEVICE_NAMES = 20
"""The device's workflow: load, loop, cycle, study, sweeps, errata, outputs, errors."""

CHAIN_NAMES = 27
"""Any mechanism's workflow: read, close, assemble, track, mobility, dynamics, base, forces."""

PUBLIC = (
    "feeder",
    "feeder.chain",
    "feeder.chain.readers",
    "feeder.chain.results",
    "feeder.device",
    "feeder.motion",
    "feeder.dynamics",
    "feeder.paper",
    "feeder.study",
    "feeder.viz",
    "feeder.design",
    "feeder.files",
)
"""The modules whose ``__all__`` is public API."""


def test_the_top_levels_are_small():
    assert len(feeder.__all__) <= DEVICE_NAMES, sorted(feeder.__all__)
    assert len(feeder.chain.__all__) <= CHAIN_NAMES, sorted(feeder.chain.__all__)


def test_mechanism_names_are_not_repeated_in_feeder():
    assert not set(feeder.__all__) & set(feeder.chain.__all__)


@pytest.mark.parametrize("module", PUBLIC)
def test_every_listed_name_resolves(module):
    public = importlib.import_module(module)
    assert len(set(public.__all__)) == len(public.__all__), module
    for name in public.__all__:
        assert getattr(public, name) is not None, f"{module}.{name}"


def test_one_name_one_function():
    seen: dict[str, tuple[str, object]] = {}
    clashes = []
    for module in PUBLIC:
        public = importlib.import_module(module)
        for name in public.__all__:
            value = getattr(public, name)
            if not (inspect.isfunction(value) or inspect.isclass(value)):
                continue
            first = seen.setdefault(name, (module, value))
            if first[1] is not value:
                clashes.append(f"{name}: {first[0]} and {module}")
    assert not clashes, clashes
