"""feeder.lazy: a package's public names load on first use, are kept, and listed; any other
name is an AttributeError (as for an eager module)."""

from __future__ import annotations

import sys
import types

import pytest

from feeder.lazy import lazy_names


@pytest.fixture
def package(monkeypatch):
    """A module ``lazy_test`` whose public name ``dumps`` comes from the ``json`` package."""
    module = types.ModuleType("lazy_test")
    monkeypatch.setitem(sys.modules, "lazy_test", module)
    module.__getattr__, module.__dir__ = lazy_names(
        "lazy_test", {"dumps": "json"}, ["dumps"], anchor="json"
    )
    return module


def test_a_name_loads_on_first_use_and_is_kept(package):
    import json

    assert "dumps" not in vars(package) and "dumps" in dir(package)
    assert package.dumps is json.dumps
    assert vars(package)["dumps"] is json.dumps  # kept: __getattr__ is not asked again


def test_another_name_is_an_attribute_error(package):
    with pytest.raises(AttributeError, match="module 'lazy_test' has no attribute 'loads'"):
        package.loads  # noqa: B018
