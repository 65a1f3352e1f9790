"""Points of a mechanism whose motion its tables report (``[[point]]`` of a mechanism file): a
named frame's origin, or a point fixed on a body at an offset in the body's frame."""

from __future__ import annotations

from dataclasses import dataclass

import pinocchio as pin

from ...exceptions import InputError
from .closure import ClosedChain


@dataclass(frozen=True)
class Point:
    """A point fixed on one body of the tree.

    Attributes:
        name: Its name (the tables' columns ``point_<name>_…``).
        frame: The frame it is given in: a frame of the model (``frame = "…"``), or a body's own
            frame (``body = "…"``, a link of a URDF, a body of an MJCF or SDF).
        offset: Its position in that frame [m], (3,).
        body: Whether ``frame`` names a body (True) or any frame (False), for the messages.
    """

    name: str
    frame: str
    offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    body: bool = False


def check_points(chain: ClosedChain, points: tuple[Point, ...], where: str) -> None:
    """Refuse a point whose frame or body is not the model's (the nearest name given; ``where``:
    the file, for the message).

    Raises:
        InputError: An unknown frame, or a body name that is a frame of the model but not a body.
    """
    for point in points:
        what = "body" if point.body else "frame"
        try:
            frame = chain.frame_id(point.frame)
        except InputError as exc:
            raise InputError(f"{where} [[point]] {point.name!r}: {what}: {exc}") from None
        if point.body and chain.model.frames[frame].type != pin.FrameType.BODY:
            raise InputError(
                f"{where} [[point]] {point.name!r}: {point.frame!r} is a frame of the model but "
                "not a body (a link): give it as frame = …"
            )
