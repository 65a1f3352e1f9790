"""What a mechanism's side-file says, whatever its format (TOML, Extended-URDF YAML)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...exceptions import InputError
from ..model.base import BaseMotion
from ..model.closure import Closure
from ..model.forces import ForceElement


@dataclass(frozen=True)
class MechanismSpec:
    """What the side-file says.

    Attributes:
        model: Path of the model file (resolved against the side-file's folder).
        model_format: ``"urdf"``, ``"mjcf"`` or ``"sdf"``.
        closures: The cut joints.
        actuated: Actuated joint names.
        independent: Independent joint names.
        gravity: Gravity [m/s²], world frame, (3,), or None (the model's).
        stiffness: Closure label → per-row stiffness (indeterminate-force split).
        joint_types: Joint name → the type that replaces its URDF type
            (:mod:`~feeder.chain.readers.joint_types`).
        forces: The force elements (:mod:`~feeder.chain.model.forces`).
        pose: The reference pose the file gives: (joint, value [rad, m], where it was read)
            (:func:`~feeder.chain.readers.pose.pose_from_values`); empty: the model's zero.
        base: The base's motion (``[base]``), or None: the base stands still, level.
    """

    model: Path
    model_format: str
    closures: tuple[Closure, ...]
    actuated: tuple[str, ...]
    independent: tuple[str, ...]
    gravity: np.ndarray | None = None
    stiffness: dict[str, tuple[float, ...]] = field(default_factory=dict)
    joint_types: dict[str, str] = field(default_factory=dict)
    forces: tuple[ForceElement, ...] = ()
    pose: tuple[tuple[str, float, str], ...] = ()
    base: BaseMotion | None = None


def format_of(path: Path) -> str:
    suffix = path.suffix.lower()
    formats = {".urdf": "urdf", ".xml": "mjcf", ".mjcf": "mjcf", ".sdf": "sdf"}
    if suffix not in formats:
        raise InputError(f"model file {path}: unknown format {suffix!r} (.urdf, .xml/.mjcf, .sdf)")
    return formats[suffix]
