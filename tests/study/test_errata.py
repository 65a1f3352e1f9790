"""The published errata table ERRATA.md (feeder.study.errata.paper_errata).

``feeder errata --out FILE`` writing this table is tested in tests/test_cli.py.
"""

from __future__ import annotations

import math

import pytest

from feeder.study.errata import REFERENCE_ELEVATION, paper_errata

from ..conftest import REPO

ERRATA_MD = REPO / "ERRATA.md"


@pytest.fixture(scope="module")
def table():
    return paper_errata()


def test_published_table_is_current(table):
    """Regenerate with ``feeder errata --out ERRATA.md`` if this fails after a change."""
    assert ERRATA_MD.read_text(encoding="utf-8") == table


def test_reference_cycle_is_the_longest_arm_travel(feeder, table):
    """The errata are measured at the projectile feeder's lowest elevation (−4°, Fig. 4), where
    the arm turns furthest, and the table says so."""
    assert math.isclose(REFERENCE_ELEVATION, feeder.params.elevation_min)
    assert math.isclose(REFERENCE_ELEVATION, math.radians(-4.0))
    assert f"elevation {math.degrees(REFERENCE_ELEVATION):g}°" in table
    assert feeder.params.name in table
