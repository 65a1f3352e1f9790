"""``[[control]]`` tables: joints driven toward a reference motion by a computed-torque
controller (:mod:`feeder.chain.dynamics.control`), through their own actuators or a force
element's push, in a TOML mechanism file or a file of their own (``feeder simulate --control
FILE``, :func:`read_control_file`)::

    [[control]]
    joint = "crank_joint"           # required: an actuated joint, or the joint element moves
    # element = "boom_cylinder"     # optional: a [[force]] spring or cylinder whose push [N]
                                    #   drives the joint (not actuated) instead of its actuator
    reference = "motion.csv"        # required: a motion table (t, q_<joint>, optional v_, a_;
                                    # as feeder analyze --motion reads it), relative to the file
    kp = 400.0                      # position gain K_p [1/s²] and rate gain K_d [1/s] …
    kd = 40.0
    # omega = 20.0                  # … or the closed loop's natural frequency ω [rad/s] and
    # zeta = 1.0                    #   damping ratio ζ [-] (default 1): K_p = ω², K_d = 2ζω
    force_limit = 500.0             # optional: |u| ≤ 500 [N or N·m], or [low, high]
    lag = 0.01                      # optional: first-order actuator lag T [s] (a servo-valve) …
    # bandwidth = 16.0              # … or its bandwidth f [Hz]: T = 1 / (2π f)
    rate_limit = 2e4                # optional, with a lag: |du/dt| ≤ 2e4 [N/s or N·m/s]
    area = 2.0e-3                   # optional, a prismatic joint driven itself: piston
                                    # area [m²]; the tables report the pressure u / area [Pa]

The gains are the closed loop's own (SI units, per second and per second squared): on the
controlled joint the law commands the acceleration q̈* = q̈_ref + K_d (q̇_ref − q̇) + K_p (q_ref − q),
so an error obeys ë + K_d ė + K_p e = 0 whatever the mechanism's inertia.

With ``element``, the law's force is the element's push P [N] (extending; force_limit and
rate_limit in N and N/s): the element's push law is the controller's, so a spring's ``force``
or a cylinder's ``pressure`` and ``rod_pressure`` must be left at 0 (its spring and damper act
as before), and for a cylinder the tables report the chamber pressures that give P (the cap's
P/A_cap when P ≥ 0, the rod side's −P/A_ann when P < 0, the other at zero gauge) [Pa]. Each
element drives one joint.
"""

from __future__ import annotations

import math
from pathlib import Path

from ...exceptions import InputError
from ...validation import check_file, check_number
from ..model.control import ControlSpec
from .motion_table import read_motion
from .spec import table_entries, tables_file

CONTROL_KEYS = (
    "joint",
    "element",
    "reference",
    "kp",
    "kd",
    "omega",
    "zeta",
    "force_limit",
    "rate_limit",
    "lag",
    "bandwidth",
    "area",
)
"""Keys a ``[[control]]`` table may have (module docstring)."""


def _positive(entry: dict, key: str, here: str, unit: str) -> float | None:
    """``entry[key]`` as a number > 0 [unit], or None when absent."""
    if key not in entry:
        return None
    value = check_number(f"{here} {key} [{unit}]", entry[key])
    if not value > 0.0:
        raise InputError(f"{here}: {key} must be > 0 [{unit}], got {entry[key]!r}")
    return value


def _gains(entry: dict, here: str) -> tuple[float, float]:
    """(K_p [1/s²], K_d [1/s]) from kp and kd, or omega and zeta."""
    pair, natural = {"kp", "kd"} & set(entry), {"omega", "zeta"} & set(entry)
    if pair and natural:
        raise InputError(
            f"{here}: give kp and kd [1/s², 1/s], or omega [rad/s] and zeta, not both "
            f"(got {sorted(pair | natural)})"
        )
    if natural:
        omega = _positive(entry, "omega", here, "rad/s")
        if omega is None:
            raise InputError(f"{here}: zeta needs omega [rad/s], the natural frequency")
        zeta = check_number(f"{here} zeta [-]", entry.get("zeta", 1.0))
        if not zeta >= 0.0:
            raise InputError(f"{here}: zeta must be ≥ 0, got {entry['zeta']!r}")
        return omega**2, 2.0 * zeta * omega
    if pair != {"kp", "kd"}:
        raise InputError(
            f"{here}: the gains are required: kp [1/s²] and kd [1/s], or omega [rad/s] "
            "(and zeta, default 1)"
        )
    kp = _positive(entry, "kp", here, "1/s²")
    kd = check_number(f"{here} kd [1/s]", entry["kd"])
    if not kd >= 0.0:
        raise InputError(f"{here}: kd must be ≥ 0 [1/s], got {entry['kd']!r}")
    return kp, kd


def _force_limit(entry: dict, here: str) -> tuple[float, float]:
    """(low, high) [N or N·m] from force_limit: one number L > 0 (±L) or [low, high]."""
    value = entry.get("force_limit")
    if value is None:
        return -math.inf, math.inf
    if isinstance(value, list):
        if len(value) != 2:
            raise InputError(f"{here}: force_limit must be L or [low, high] [N], got {value!r}")
        low, high = (check_number(f"{here} force_limit [N or N·m]", x) for x in value)
        if not low < high:
            raise InputError(f"{here}: force_limit [low, high] needs low < high, got {value!r}")
        return low, high
    limit = _positive(entry, "force_limit", here, "N or N·m")
    return -limit, limit


def _lag(entry: dict, here: str) -> float:
    """The time constant T [s] from lag or bandwidth (0: no lag)."""
    if "lag" in entry and "bandwidth" in entry:
        raise InputError(f"{here}: give lag [s] or bandwidth [Hz], not both")
    lag = _positive(entry, "lag", here, "s")
    bandwidth = _positive(entry, "bandwidth", here, "Hz")
    if bandwidth is not None:
        return 1.0 / (2.0 * math.pi * bandwidth)
    return lag or 0.0


def _entry(entry: dict, here: str) -> tuple[str, str, dict]:
    """The joint, the reference's name and the checked settings of one table."""
    joint, reference = entry.get("joint"), entry.get("reference")
    if not isinstance(joint, str) or not joint.strip():
        raise InputError(
            f'{here}: joint = "…" is required (an actuated joint, or the joint element = "…" '
            "drives)"
        )
    element = entry.get("element")
    if element is not None and (not isinstance(element, str) or not element.strip()):
        raise InputError(
            f'{here}: element = "…" names a spring or cylinder [[force]] element, got {element!r}'
        )
    if not isinstance(reference, str) or not reference.strip():
        raise InputError(
            f'{here}: reference = "motion.csv" is required (a motion table of {joint!r}, '
            "relative to this file)"
        )
    here = f"{here} ({joint!r})"
    if element is not None and "area" in entry:
        raise InputError(
            f"{here}: area is for a joint driven itself; the push of element {element!r} is in N "
            "(a cylinder's pressures follow from its bore and rod)"
        )
    kp, kd = _gains(entry, here)
    lag = _lag(entry, here)
    rate_limit = _positive(entry, "rate_limit", here, "N/s or N·m/s")
    if rate_limit is not None and lag == 0.0:
        raise InputError(
            f"{here}: rate_limit limits the actuator's force rate, a state of its lag: give "
            "lag [s] or bandwidth [Hz] too"
        )
    settings = {
        "kp": kp,
        "kd": kd,
        "force_limit": _force_limit(entry, here),
        "rate_limit": math.inf if rate_limit is None else rate_limit,
        "lag": lag,
        "area": _positive(entry, "area", here, "m²"),
        "where": here,
        "element": element,
    }
    return joint, reference, settings


def read_control(entries: object, folder: Path, where: str) -> tuple[ControlSpec, ...]:
    """The controlled joints of the ``[[control]]`` tables ``entries`` (module docstring);
    references relative to ``folder``; ``where``: the file, for the messages. Tables that name
    the same reference file read it once, for all their joints (:func:`~.read_motion`).

    Raises:
        InputError: Not a list of tables, an unknown key (with the nearest), a missing joint or
            reference, a joint or an element given twice, an element that is not a name or has
            an area, gains missing or mixed (kp/kd with omega/zeta), a value that is not a
            finite number in its range, a rate limit without a lag, a bad reference table
            (:func:`~.read_motion`).
    """
    tables = []
    for here, entry in table_entries(entries, "control", set(CONTROL_KEYS), where):
        joint, reference, settings = _entry(entry, here)
        if any(joint == other for other, _, _ in tables):
            raise InputError(f"{here}: joint {joint!r} is controlled twice: one table per joint")
        element = settings["element"]
        if element is not None and any(s["element"] == element for _, _, s in tables):
            raise InputError(f"{here}: element {element!r} drives two joints: one table each")
        tables.append((joint, folder / reference, settings))
    specs = []
    for path in dict.fromkeys(path for _, path, _ in tables):
        joints = tuple(joint for joint, other, _ in tables if other == path)
        try:
            motion = read_motion(path, joints)
        except InputError as exc:  # its message names the file; say which tables read it
            raise InputError(f"{where} [[control]] of {list(joints)}: {exc}") from None
        for i, joint in enumerate(joints):
            settings = next(s for name, _, s in tables if name == joint)
            columns = motion.x[:, i], motion.dx[:, i], motion.ddx[:, i]
            specs.append(ControlSpec(joint, path, motion.t, *columns, **settings))
    order = [joint for joint, _, _ in tables]
    return tuple(sorted(specs, key=lambda spec: order.index(spec.joint)))


def read_control_file(path: str | Path) -> tuple[ControlSpec, ...]:
    """The controlled joints of a TOML file holding only ``[[control]]`` tables (``feeder
    simulate --control FILE``), references relative to it.

    Raises:
        InputError: A path that is not text or a path, a missing or unreadable file, another
            section, no table, a bad table (:func:`read_control`).
    """
    path = check_file("control file", path)
    specs = read_control(tables_file(path, "control"), path.parent, str(path))
    if not specs:
        raise InputError(f"{path}: no [[control]] table")
    return specs
