"""``[[point]]`` tables of a TOML mechanism file: points whose position, velocity and
acceleration the tables of ``feeder analyze`` and ``feeder simulate`` report::

    [[point]]
    name = "P1"                     # required: the columns point_P1_x, …
    frame = "rocker_tip"            # a frame of the model: its origin …
    # body = "rocker"               # … or a body (a link), with
    # offset = [0.08, 0.0, 0.0]     # the point in its frame [m] (default 0; also with frame)

Whether the frame or body is the model's is checked when the model is loaded
(:func:`~feeder.chain.model.points.check_points`).
"""

from __future__ import annotations

from ...exceptions import InputError
from ...validation import check_finite
from ..model.points import Point
from .spec import table_entries

POINT_KEYS = {"name", "frame", "body", "offset"}
"""Keys a ``[[point]]`` table may have."""


def read_points(entries: object, where: str) -> tuple[Point, ...]:
    """The points of the ``[[point]]`` tables ``entries`` (module docstring; ``where``: the
    file, for the messages).

    Raises:
        InputError: Not a list of tables, an unknown key, a missing or empty name, a name given
            twice, neither or both of ``frame`` and ``body``, an offset that is not 3 finite
            numbers [m].
    """
    points: list[Point] = []
    for here, entry in table_entries(entries, "point", POINT_KEYS, where):
        name = entry.get("name")
        if not isinstance(name, str) or not name.strip():
            raise InputError(f'{here}: name = "…" is required (the columns point_<name>_…)')
        if any(point.name == name for point in points):
            raise InputError(f"{here}: point {name!r} given twice: name each point once")
        given = [key for key in ("frame", "body") if key in entry]
        if len(given) != 1 or not isinstance(entry[given[0]], str):
            raise InputError(
                f'{here} ({name!r}): give one of frame = "…" (a frame of the model) or '
                'body = "…" (a body, with offset = [x, y, z] m in its frame)'
            )
        offset = entry.get("offset", [0.0, 0.0, 0.0])
        values = check_finite(f"{here} ({name!r}) offset [m]", offset)
        if values.shape != (3,):
            raise InputError(f"{here} ({name!r}): offset must be 3 numbers [m], got {offset!r}")
        points.append(Point(name, entry[given[0]], tuple(values.tolist()), given[0] == "body"))
    return tuple(points)
