"""The errata table (feeder.paper.errata): its rows and Markdown on a reference motion, and
Table I's printed moments. The published ERRATA.md is checked in tests/study/test_errata.py;
the printed equations the rows quote in tests/paper/test_printed.py."""

from __future__ import annotations

from dataclasses import replace

import pytest

from feeder.exceptions import InertiaError
from feeder.motion.cycle import feeding_cycle
from feeder.paper.errata import (
    TABLE_I_PRINTED_MOMENTS,
    ReferenceMotion,
    errata_markdown,
    errata_rows,
)
from feeder.study.errata import REFERENCE_ELEVATION

ERRATA_ROWS = 15
"""The errata the package documents: Table I and eqs. (30)–(46), rows 1–15 (rows 13–15 are
eq. (46)'s, see tests/paper/test_printed.py)."""
CAPTION = "a test caption for the reference motion"
HEADER_LINES = 2
"""The Markdown table's header row and its |---| separator."""


@pytest.fixture(scope="module")
def motion(feeder):
    """The reference cycle (projectile feeder at −4°) as the errata's ReferenceMotion."""
    k = feeding_cycle(feeder, REFERENCE_ELEVATION)
    return ReferenceMotion(k.t, k.q, k.v, k.a, k.gripped, CAPTION)


@pytest.fixture(scope="module")
def rows(feeder, motion):
    return errata_rows(feeder.params, motion)


def test_every_row_is_complete(rows):
    assert len(rows) >= ERRATA_ROWS
    for row in rows:
        assert all(
            text.strip()
            for text in (row.equation, row.printed, row.corrected, row.why, row.consequence)
        )


def test_markdown_lists_every_row_on_the_motion_it_names(feeder, motion, rows):
    text = errata_markdown(feeder.params, motion)
    assert CAPTION in text
    assert f"{motion.t.size} samples" in text
    table = [line for line in text.splitlines() if line.startswith("|")]
    assert len(table) == len(rows) + HEADER_LINES
    for number, (line, row) in enumerate(zip(table[HEADER_LINES:], rows, strict=True), 1):
        escaped = row.equation.replace("|", "\\|")
        assert line.startswith(f"| {number} | {escaped} |")


def test_table_i_printed_moments_are_not_physical(feeder):
    p = feeder.params
    for link, moments in TABLE_I_PRINTED_MOMENTS.items():
        with pytest.raises(InertiaError, match=link):
            replace(getattr(p, link), moments=moments).check(link)
