"""A pose given by the user: a CSV table ``joint,value`` (header row, then one row per joint,
SI units: rad for revolute and continuous joints, m for prismatic ones). The joints not listed
keep their reference value (0, or the identity rotation). It picks the assembly branch: the
mechanism is mounted onto the closed pose nearest to it. A TOML mechanism file may give the same
as ``pose = {joint = value, …}`` in its ``[mechanism]`` table."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin

from ...exceptions import InputError
from ...validation import check_file, check_number


def read_pose(path: str | Path, model: pin.Model) -> np.ndarray:
    """The configuration (nq,) the pose file gives (module docstring).

    Raises:
        InputError: Missing or malformed file, an unknown or multi-coordinate joint, a value
            that is not a finite number, a joint given twice.
    """
    path = check_file("pose file", path)
    if not isinstance(model, pin.Model):
        raise InputError(f"model must be a pinocchio.Model, got {model!r}")
    try:
        lines = [line.strip() for line in path.read_text(encoding="utf-8-sig").splitlines()]
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read the pose file {path}: {exc}") from exc
    rows = [line.split(",") for line in lines if line]
    if not rows or [x.strip() for x in rows[0]] != ["joint", "value"]:
        raise InputError(f"{path}: the header row must be 'joint,value'")
    values, seen = [], set()
    for number, row in enumerate(rows[1:], start=2):
        if len(row) != 2:
            raise InputError(f"{path}, row {number}: expected 'joint,value', got {row!r}")
        name, text = row[0].strip(), row[1].strip()
        try:
            value = float(text)
        except ValueError:
            raise InputError(
                f"{path}, row {number}: the value of {name!r} must be a number [rad or m], got "
                f"{text!r}"
            ) from None
        if name in seen:
            raise InputError(f"{path}, row {number}: joint {name!r} given twice")
        seen.add(name)
        values.append((name, value, f"{path}, row {number}"))
    return pose_from_values(values, model)


def pose_from_values(values: list[tuple[str, float, str]], model: pin.Model) -> np.ndarray:
    """The configuration (nq,) with the given joints at the given values, the others at their
    reference value (module docstring); ``values`` are (joint, value, where it was read).

    Raises:
        InputError: An unknown or multi-coordinate joint, a value that is not a finite number.
    """
    q = pin.neutral(model)
    for name, value, where in values:
        value = check_number(f"{where}: the value", value)  # a TOML true is no 1 rad
        if not model.existJointName(name):
            raise InputError(
                f"{where}: {name!r} is not a joint of the model; joints: {list(model.names)[1:]}"
            )
        joint = model.joints[model.getJointId(name)]
        if joint.nv != 1:
            raise InputError(
                f"{where}: joint {name!r} has {joint.nv} coordinates; a pose gives revolute, "
                "continuous and prismatic joints"
            )
        if joint.nq == 2:
            q[joint.idx_q : joint.idx_q + 2] = np.cos(value), np.sin(value)
        else:
            q[joint.idx_q] = value
    return q
