"""A user's mechanism from its files: the side-file (TOML or Extended-URDF YAML, by its suffix)
and the model it names (URDF, MJCF or SDF), read strictly into a
:class:`~feeder.chain.model.closure.ClosedChain`."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin

from ...exceptions import InputError
from ...validation import check_file, check_path
from ..model.closure import ClosedChain
from ..model.points import check_points
from .extended_urdf import read_extended_urdf
from .joint_types import replace_joints
from .mjcf import read_mjcf
from .side_file import read_toml
from .spec import MechanismSpec
from .urdf import build_model, read_urdf


def read_spec(path: str | Path, model: str | Path | None = None) -> MechanismSpec:
    """Read and check a closure side-file: TOML (``.toml``, :mod:`.side_file`) or Extended-URDF
    YAML (``.yaml``/``.yml``, :mod:`.extended_urdf`).

    Args:
        path: The side-file.
        model: The model file, overriding the side-file's (e.g. given on the command line).

    Raises:
        InputError: A path that is not text or a path, missing or malformed file, a missing or
            mistyped key (named), an unknown closure or joint type.
    """
    path = check_file("closure file", path)
    model = None if model is None else check_path("the model file", model)
    if path.suffix.lower() in (".yaml", ".yml"):
        return read_extended_urdf(path, model)
    return read_toml(path, model)


def load_mechanism(spec: MechanismSpec) -> ClosedChain:
    """The closed chain the side-file describes (model read strictly, closures attached).

    An MJCF's ``<equality><connect>`` and ``<weld>`` constraints become point and weld closures
    (Pinocchio's MJCF parser reads them; frames ``mjcf_constraint_<i>_a|b`` are added at their
    anchors), before the side-file's closures. As in MuJoCo, an anchor is given in its first
    body's frame and sits on the second body where it is at ``qpos0``: build the model assembled
    at qpos0. Pinocchio's parser reads only the first body under ``<worldbody>``: put the whole
    mechanism under one (jointless) body.

    Raises:
        UrdfError: Missing or malformed model file, or one Pinocchio cannot read.
        InertiaError: A non-physical body.
        ClosureFrameError, InputError: Bad closures; an actuated or independent joint, or one
            given a rate, that is not a one-coordinate joint of the model; a point on a frame
            or body the model lacks; ``spec`` not a :class:`MechanismSpec`.
    """
    if not isinstance(spec, MechanismSpec):
        raise InputError(f"spec must be a MechanismSpec (from read_spec(path)), got {spec!r}")
    closures = list(spec.closures)
    if spec.model_format == "urdf":
        model = build_model(read_urdf(spec.model), str(spec.model))
        model = replace_joints(model, spec.joint_types, str(spec.model))
    elif spec.model_format == "sdf":
        from .sdf import read_sdf

        xml, cuts = read_sdf(spec.model)
        model = build_model(xml, str(spec.model))
        closures = cuts + closures
    else:
        model, extra = read_mjcf(spec.model)
        closures = extra + closures
    if spec.gravity is not None:
        model.gravity = pin.Motion(spec.gravity, np.zeros(3))
    chain = ClosedChain(model, closures)
    for name, _, where in spec.rates:
        try:
            chain.coordinate_columns([name], "rated")
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
    check_points(chain, spec.points, "the mechanism file's")
    for role, names in (("actuated", spec.actuated), ("independent", spec.independent)):
        try:
            chain.coordinate_columns(names, role)
        except InputError as exc:
            raise InputError(
                f"the mechanism file's {role} joints: {exc}: correct them there"
            ) from None
    return chain
