"""The TOML closure side-file: the model (URDF, MJCF or SDF), the actuated and independent joints,
gravity and the cut joints.

The side-file (TOML, read with the standard library's ``tomllib``: no extra dependency)::

    [mechanism]
    urdf = "four_bar.urdf"          # the model, relative to this file (or "mjcf" / "sdf")
    actuated = ["crank_joint"]      # joints whose generalized forces are the unknown loads
                                    # (may be empty for a forward run: a passive mechanism)
    independent = ["crank_joint"]   # joints whose motion the motion table prescribes
    gravity = [0.0, -9.81, 0.0]     # [m/s²] world frame (optional: the model's, −z for URDF;
                                    # the summary and the manifest say when it was assumed)
    pose = {crank_joint = 0.7}      # optional: the reference pose [rad, m] that picks the branch
    rates = {crank_joint = 2.0}     # optional: the initial rates [rad/s, m/s] of a forward run
                                    # (any joints: projected onto the closure,
                                    # :mod:`feeder.chain.assembly.rates`); default at rest
    joint_types = {ankle = "UJOINT_ZY"}   # optional: URDF joints replaced by a joint URDF cannot
                                    # write (ball, universal; :mod:`.joint_types`)

    [[closure]]                     # one per cut joint (none for an MJCF with equality
    frames = ["coupler_tip", "rocker_tip"]   # constraints: those are read from the model)
    type = "revolute"               # required: point | weld | revolute
    axis = [0.0, 0.0, 1.0]          # revolute: hinge axis in the frames' axes
    stiffness = [1, 1, 1, 1, 1]     # optional, per row: the split of indeterminate forces

    [base]                          # optional: the base moves (feeder.chain.readers.base_motion)
    roll_deg = 15.0                 # e.g. a side slope

    [[point]]                       # optional: points whose motion the tables report
    name = "P1"                     # (feeder.chain.readers.points)
    frame = "rocker_tip"

    [[control]]                     # optional: a joint under control (readers.control)
    joint = "crank_joint"
    reference = "motion.csv"
    kp = 400.0                      # [1/s²]
    kd = 40.0                       # [1/s]

    [[force]]                       # optional: force elements (feeder.chain.readers.forces)
    type = "spring"
    frames = ["coupler_tip", "ground_pin"]
    stiffness = 400.0               # [N/m]
    rest_length = 0.1               # [m]
"""

from __future__ import annotations

import tomllib
from pathlib import Path

from ...exceptions import InputError
from ...validation import check_file, check_finite, check_number, check_path
from ..model.closure import Closure, repeated_cut
from ..model.cuts import KINDS
from .base_motion import read_base
from .control import read_control
from .forces import read_forces
from .joint_types import joint_model
from .points import read_points
from .spec import (
    MechanismSpec,
    check_depth,
    format_of,
    read_side_text,
    table_entries,
    too_deep,
)

MODEL_KEYS = ("urdf", "mjcf", "sdf")
"""Keys of ``[mechanism]`` that name the model file, one of them."""

CLOSURE_KEYS = {"frames", "type", "axis", "axis_b", "name", "stiffness"}
"""Keys a ``[[closure]]`` table may have."""


def _names(table: dict, key: str, where: str, empty: bool = False) -> tuple[str, ...]:
    """The joint names of ``key``: a list of distinct names, non-empty unless ``empty``."""
    value = table.get(key)
    if (
        not isinstance(value, list)
        or not (value or empty)
        or not all(isinstance(x, str) and x for x in value)
        or len(set(value)) != len(value)
    ):
        kind = "a list" if empty else "a non-empty list"
        raise InputError(f"{where}: '{key}' must be {kind} of distinct joint names, got {value!r}")
    return tuple(value)


def _axis(entry: dict, key: str, where: str) -> tuple[float, ...] | None:
    if key not in entry:
        return None
    value = entry[key]
    if not isinstance(value, list) or len(value) != 3:
        raise InputError(f"{where}: '{key}' must be 3 numbers, got {value!r}")
    return tuple(float(x) for x in check_finite(f"{where} {key}", value))


def _joint_types(table: object, model_format: str, where: str) -> dict[str, str]:
    """``joint_types = {joint = "TYPE", …}``: checked types (:func:`.joint_types.joint_model`),
    for a URDF only (an MJCF or SDF writes ball and universal joints itself)."""
    if not isinstance(table, dict) or not all(
        isinstance(name, str) and isinstance(kind, str) for name, kind in table.items()
    ):
        raise InputError(
            f'{where}: joint_types must be a table {{joint = "TYPE", …}}, got {table!r}'
        )
    if table and model_format != "urdf":
        raise InputError(
            f"{where}: joint_types replaces URDF joints; an {model_format.upper()} model writes "
            "its ball and universal joints itself"
        )
    for name, kind in table.items():
        try:
            joint_model(kind)
        except InputError as exc:
            raise InputError(f"{where} joint_types.{name}: {exc}") from None
    return dict(table)


def _rates(table: object, where: str) -> tuple[tuple[str, float, str], ...]:
    """``rates = {joint = value, …}``: (joint, rate [rad/s, m/s], where it was read), each a
    finite number (the joints are checked against the model by
    :func:`~feeder.chain.readers.mechanism.load_mechanism`)."""
    if not isinstance(table, dict):
        raise InputError(f"{where}: rates must be a table {{joint = rate, …}}, got {table!r}")
    return tuple(
        (name, check_number(f"{where} rates.{name} [rad/s or m/s]", value), f"{where} rates")
        for name, value in table.items()
    )


def read_toml(path: Path, model: str | Path | None = None) -> MechanismSpec:
    """Read and check a TOML closure side-file (module docstring).

    Args:
        path: The TOML side-file.
        model: The model file, overriding the side-file's (e.g. given on the command line).

    Raises:
        InputError: Missing or malformed file, one beyond the side-file limits
            (:data:`~feeder.chain.readers.spec.SIDE_FILE_MAX_BYTES`, ``SIDE_FILE_MAX_DEPTH``), a
            missing or mistyped key (named; a closure's ``type`` is required), an unknown
            closure type, the same cut twice, a path that is not text or a path.
    """
    path = check_file("closure file", path)
    text = read_side_text(path, "TOML")
    try:
        document = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path}: not a readable TOML file: {exc}") from exc
    except RecursionError:  # tomllib parses nested arrays and tables by recursion
        raise InputError(too_deep(path)) from None
    check_depth(document, path)
    unknown = set(document) - {"mechanism", "closure", "force", "base", "point", "control"}
    if unknown:
        raise InputError(
            f"{path}: unknown sections {sorted(unknown)} (expected [mechanism], [[closure]], "
            "[[force]], [base], [[point]], [[control]])"
        )
    mechanism = document.get("mechanism")
    if not isinstance(mechanism, dict):
        raise InputError(f"{path}: a [mechanism] table is required")
    where = f"{path} [mechanism]"
    known = {"actuated", "independent", "gravity", "pose", "rates", "joint_types", *MODEL_KEYS}
    if set(mechanism) - known:
        raise InputError(f"{where}: unknown keys {sorted(set(mechanism) - known)}")
    if model is not None:
        model_path = check_path("the model file", model)
        model_format = format_of(model_path)
    else:
        given = [key for key in MODEL_KEYS if key in mechanism]
        if len(given) != 1 or not isinstance(mechanism[given[0]], str):
            raise InputError(f'{where}: name the model with one of {list(MODEL_KEYS)} = "file"')
        model_path, model_format = path.parent / mechanism[given[0]], given[0]
    gravity = None
    if "gravity" in mechanism:
        gravity = check_finite(f"{where} gravity [m/s²]", mechanism["gravity"])
        if gravity.shape != (3,):
            raise InputError(
                f"{where}: gravity must be 3 numbers [m/s²], got {mechanism['gravity']!r}"
            )
    pose = mechanism.get("pose", {})
    if not isinstance(pose, dict):
        raise InputError(f"{where}: pose must be a table {{joint = value, …}}, got {pose!r}")
    rates = _rates(mechanism.get("rates", {}), where)
    joint_types = _joint_types(mechanism.get("joint_types", {}), model_format, where)
    closures, stiffness = [], {}
    for here, entry in table_entries(
        document.get("closure", []), "closure", CLOSURE_KEYS, str(path)
    ):
        frames = entry.get("frames")
        if (
            not isinstance(frames, list)
            or len(frames) != 2
            or not all(isinstance(f, str) for f in frames)
        ):
            raise InputError(f"{here}: 'frames' must be two frame names, got {frames!r}")
        if "type" not in entry:
            raise InputError(
                f"{here}: 'type' is required: one of {sorted(KINDS)} (point: a ball, or a pin in "
                "a planar loop)"
            )
        kind = entry["type"]
        if kind not in KINDS:
            raise InputError(f"{here}: 'type' must be one of {sorted(KINDS)}, got {kind!r}")
        closure = Closure(
            frames[0],
            frames[1],
            kind,
            _axis(entry, "axis", here) or (0.0, 0.0, 1.0),
            _axis(entry, "axis_b", here),
            str(entry.get("name", "")),
        )
        closures.append(closure)
        if "stiffness" in entry:
            stiffness[closure.label] = tuple(check_finite(f"{here} stiffness", entry["stiffness"]))
    repeated = repeated_cut([(c.frame_a, c.frame_b) for c in closures])
    if repeated is not None:
        i, j = repeated
        raise InputError(
            f"{path}: [[closure]] #{i + 1} and #{j + 1} both join {closures[i].frame_a!r} and "
            f"{closures[i].frame_b!r}: one loop listed twice is not two cuts; list it once"
        )
    return MechanismSpec(
        model=model_path,
        model_format=model_format,
        closures=tuple(closures),
        actuated=_names(mechanism, "actuated", where, empty=True),
        independent=_names(mechanism, "independent", where),
        gravity=gravity,
        stiffness=stiffness,
        joint_types=joint_types,
        forces=read_forces(document.get("force", []), path.parent, str(path)),
        pose=tuple((name, value, f"{where} pose") for name, value in pose.items()),
        rates=rates,
        points=read_points(document.get("point", []), str(path)),
        control=read_control(document.get("control", []), path.parent, str(path)),
        base=read_base(document["base"], path.parent, str(path)) if "base" in document else None,
    )
