"""The Extended-URDF side-file (YAML) of CAD exports: loop frames, their type, the motors and
joint-type overrides, beside a ``robot.urdf``::

    closed_loop: [['closedloop1_A', 'closedloop1_B']]   # frame pairs that coincide, assembled
    type: ['6d']                   # '6d' weld (placements coincide), '3d' ball (origins
                                   # coincide), 'revolute' hinge about the frames' z (default 6d)
    name_mot: ['mot1', 'mot2']     # the actuated joints, and the independent ones
    joint_name: ['ankle_1']        # optional: joints whose URDF type is replaced by
    joint_type: ['UJOINT_ZY']      # these types (:mod:`~feeder.chain.readers.joint_types`)

The model is the URDF given beside it (``feeder analyze robot.urdf --closures robot.yaml``), or
else the ``.urdf`` of the same name in the side-file's folder. Keys this reader does not use are
reported by a :class:`~feeder.exceptions.FeederWarning` and ignored. Read with PyYAML's safe
loader (no object construction from the file) within the side-file limits
(:mod:`~feeder.chain.readers.spec`: its size and nesting depth) and :data:`YAML_MAX_VALUES`:
aliases (``*name``) may repeat a value, but not expand the file beyond that many values (the
"billion laughs", 9 levels of 9 aliases, would be 9⁹).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import yaml

from ...exceptions import FeederWarning, InputError
from ...validation import check_file, check_path
from ..model.closure import Closure, repeated_cut
from .joint_types import joint_model
from .spec import SIDE_FILE_MAX_DEPTH, MechanismSpec, read_side_text, too_deep

CUT_TYPES = {"3d": "point", "6d": "weld", "revolute": "revolute"}
"""The side-file's closure types (any case) and the closure kinds they are."""

KEYS = {"closed_loop", "type", "name_mot", "joint_name", "joint_type"}

YAML_MAX_VALUES = 100_000
"""Most values (names, numbers, lists, mappings) a YAML side-file may hold once its aliases are
expanded: twice what :data:`~feeder.chain.readers.spec.SIDE_FILE_MAX_BYTES` holds without them.
A loop takes 4 (the shipped side-files 13–71 in all); checking or printing a value takes
~0.1 µs, so every use of the document stays within milliseconds (9 levels of 9 aliases would
make 9⁹ ≈ 4·10⁸ values, and an error message printing them would run out of memory)."""


class _LimitedLoader(yaml.SafeLoader):
    """PyYAML's safe loader of the ``text`` of the side-file ``path`` that refuses, while it
    composes the document (before any value is built), nesting deeper than
    :data:`~feeder.chain.readers.spec.SIDE_FILE_MAX_DEPTH`, more than :data:`YAML_MAX_VALUES`
    values with the aliases expanded, and an alias inside its own anchor (a value that contains
    itself)."""

    def __init__(self, text: str, path: Path):
        super().__init__(text)
        self._path = path
        self._depth = 0
        self._values: dict[int, int] = {}  # id(node) → its values, aliases expanded

    def compose_node(self, parent, index):
        line = self.peek_event().start_mark.line + 1
        if self.check_event(yaml.AliasEvent):
            node = super().compose_node(parent, index)
            if id(node) not in self._values:
                raise InputError(f"{self._path}: the alias at line {line} is inside its anchor")
            return node
        self._depth += 1
        if self._depth > SIDE_FILE_MAX_DEPTH:
            raise InputError(too_deep(self._path, f" at line {line}"))
        node = super().compose_node(parent, index)
        self._depth -= 1
        children = node.value if isinstance(node, yaml.SequenceNode) else ()
        if isinstance(node, yaml.MappingNode):
            children = [child for pair in node.value for child in pair]
        count = 1 + sum(self._values[id(child)] for child in children)
        if count > YAML_MAX_VALUES:
            raise InputError(
                f"{self._path}: aliases expand the value at line {line} to more than "
                f"{YAML_MAX_VALUES} values, the limit of a side-file (a loop takes 4)"
            )
        self._values[id(node)] = count
        return node


def _load(path: Path) -> object:
    """The YAML document of the side-file at ``path``, read within the limits (module
    docstring).

    Raises:
        InputError: Unreadable or malformed YAML, or a limit passed (named).
    """
    text = read_side_text(path, "YAML")
    try:
        loader = _LimitedLoader(text, path)  # its reader refuses control characters here
        try:
            return loader.get_single_data()
        finally:
            loader.dispose()
    except yaml.YAMLError as exc:
        detail = " ".join(str(exc).split())  # PyYAML's message spans lines
        raise InputError(f"{path}: not a readable YAML file: {detail}") from exc


def _names(value: object, key: str, where: str, pairs: bool = False) -> list:
    ok = isinstance(value, list) and all(
        (isinstance(item, list) and len(item) == 2 and all(isinstance(x, str) and x for x in item))
        if pairs
        else (isinstance(item, str) and item)
        for item in value
    )
    if not ok:
        shape = "pairs of frame names" if pairs else "names"
        raise InputError(f"{where}: '{key}' must be a list of {shape}, got {value!r}")
    return value


def read_extended_urdf(path: Path, model: Path | None = None) -> MechanismSpec:
    """Read and check an Extended-URDF side-file (module docstring).

    Raises:
        InputError: Unreadable YAML, one beyond the limits (module docstring), a missing or
            mistyped key (named), lists of different lengths, an unknown closure or joint type,
            the same loop twice, no model file, a path that is not text or a path.
    """
    path = check_file("closure file", path)
    model = None if model is None else check_path("the model file", model)
    document = _load(path)
    if not isinstance(document, dict):
        raise InputError(f"{path}: expected a mapping with closed_loop, type, name_mot")
    unknown = sorted(set(map(str, document)) - KEYS)
    if unknown:
        warnings.warn(f"{path}: keys {unknown} are not used", FeederWarning, stacklevel=3)
    where = str(path)
    loops = _names(document.get("closed_loop", []), "closed_loop", where, pairs=True)
    repeated = repeated_cut(loops)
    if repeated is not None:
        i, j = repeated
        raise InputError(
            f"{where}: closed_loop entries #{i + 1} {loops[i]} and #{j + 1} {loops[j]} join the "
            "same frames: one loop listed twice is not two cuts; list it once"
        )
    types = document.get("type", ["6d"] * len(loops))
    if not isinstance(types, list) or len(types) != len(loops):
        raise InputError(f"{where}: 'type' must give one type per closed_loop pair, got {types!r}")
    closures = []
    for (frame_a, frame_b), kind in zip(loops, types, strict=True):
        if str(kind).lower() not in CUT_TYPES:
            raise InputError(
                f"{where}: closure type {kind!r} of ({frame_a}, {frame_b}) is not one of "
                f"{sorted(CUT_TYPES)}"
            )
        closures.append(Closure(frame_a, frame_b, CUT_TYPES[str(kind).lower()]))
    if "name_mot" not in document:
        raise InputError(f"{where}: 'name_mot' (the motors) is required")
    motors = _names(document["name_mot"], "name_mot", where)
    if not motors or len(set(motors)) != len(motors):
        raise InputError(f"{where}: 'name_mot' must name distinct joints, got {motors!r}")
    joint_names = _names(document.get("joint_name", []) or [], "joint_name", where)
    joint_kinds = _names(document.get("joint_type", []) or [], "joint_type", where)
    if len(joint_names) != len(joint_kinds) or len(set(joint_names)) != len(joint_names):
        raise InputError(
            f"{where}: 'joint_name' and 'joint_type' must be lists of one length, names distinct"
        )
    for kind in joint_kinds:
        try:
            joint_model(kind)
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
    if model is None:
        model = path.with_suffix(".urdf")
        if not model.is_file():
            raise InputError(
                f"{where}: give the model file (the side-file names none, and {model} does not "
                "exist)"
            )
    return MechanismSpec(
        model=model,
        model_format="urdf",
        closures=tuple(closures),
        actuated=tuple(motors),
        independent=tuple(motors),
        joint_types=dict(zip(joint_names, joint_kinds, strict=True)),
    )
