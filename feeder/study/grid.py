"""The grid of a sweep: elevations × parameter variants × devices, and its cases.

A grid is made here (:func:`make_grid`), or read from a TOML file
(:func:`~feeder.study.grid_file.read_grid`, which gives the file's format). Each variant applies
to every device; each (device, variant, elevation) is one :class:`SweepCase`. Every number is
checked when the grid is built, and every variant of every device is checked to assemble over
its travel (:func:`~feeder.device.loop.check_device`), so a bad grid fails before any cycle is
computed.
"""

from __future__ import annotations

import hashlib
import json
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, fields, replace

import numpy as np

from ..chain import BaseMotion, HullTable
from ..device.builtin import DEVICES
from ..device.loop import check_device
from ..device.parameters import VEHICLE_FORWARD, FeederParameters
from ..dynamics.servo import ServoGains
from ..exceptions import FeederError, InputError
from ..motion.laws import CycleSpec
from ..validation import check_elevations_deg, check_number
from .retrofit import retrofit

DEFAULT_ELEVATIONS_DEG = (-4.0, 70.0, 1.0)
"""Default elevation range (start, stop, step) [deg]: the device's whole range, every degree."""

NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.+-]*")
"""Variant names: a letter or digit, then letters, digits and ``_ . + -`` (they become table
cells and file names, so no commas, quotes, spaces or slashes)."""

RETROFIT_KEYS = ("mass_factor", "length_factor")
"""Variant keys that change the payload as a whole (:func:`~feeder.study.retrofit.retrofit`)."""

MAX_CASES = 100_000
"""Most cases a grid may have. Measured at 1 kHz: ~42 ms a case, so 100 000 cases take ~70 min
on 2 cores, and their table (~40 MB) ~2 s to rewrite at each checkpoint; a step of 0.0001°
(740 001 cases: ~4.3 h, a 300 MB table rewritten in ~15 s) is a typo, refused before any work."""


def _numeric_fields() -> tuple[str, ...]:
    return tuple(f.name for f in fields(FeederParameters) if f.type == "float")


PARAMETER_KEYS = _numeric_fields()
"""Variant keys that set one number of :class:`~feeder.device.parameters.FeederParameters`."""


@dataclass(frozen=True)
class Variant:
    """One change of the devices' parameters, or of their vehicle's motion.

    Attributes:
        name: Its name in the table and the figures.
        changes: Parameter name → value (SI, as in PARAMETERS.md), and/or the retrofit factors
            ``mass_factor``, ``length_factor``; empty for the unchanged device. Given as a
            mapping or as (name, value) pairs; kept as pairs of floats.
        base: The vehicle's motion (forward axis
            :data:`~feeder.device.parameters.VEHICLE_FORWARD`), None for standing level.
        servo: The drives' position loops of the controlled forward run
            (:mod:`feeder.dynamics.loading`: the loading pose against the rammer's line), None
            for no forward run.
    """

    name: str
    changes: tuple[tuple[str, float], ...] = ()
    base: BaseMotion | None = None
    servo: ServoGains | None = None

    def __post_init__(self) -> None:
        """Check the name and every change, and keep the values as floats.

        Raises:
            InputError: A name that is not :data:`NAME`, an unknown key, a value that is not
                one finite number.
        """
        if not isinstance(self.name, str) or not NAME.fullmatch(self.name):
            raise InputError(
                f"variant name {self.name!r}: use letters, digits and _ . + - (no spaces, "
                "commas or slashes)"
            )
        pairs = self.changes.items() if isinstance(self.changes, Mapping) else self.changes
        checked = []
        for key, value in pairs:
            if key not in PARAMETER_KEYS and key not in RETROFIT_KEYS:
                raise InputError(
                    f"variant {self.name!r}: unknown key {key!r}; use "
                    f"{', '.join(RETROFIT_KEYS)} or a parameter name: {', '.join(PARAMETER_KEYS)}"
                )
            checked.append((key, check_number(f"variant {self.name!r}: {key}", value)))
        object.__setattr__(self, "changes", tuple(checked))
        if self.base is not None and (
            not isinstance(self.base, BaseMotion) or self.base.forward != VEHICLE_FORWARD
        ):
            raise InputError(
                f"variant {self.name!r}: base must be a BaseMotion with the device's forward "
                f"axis {list(VEHICLE_FORWARD)}"
            )
        if self.servo is not None and not isinstance(self.servo, ServoGains):
            raise InputError(f"variant {self.name!r}: servo must be a ServoGains or None")

    def apply(self, params: FeederParameters) -> FeederParameters:
        """``params`` with this variant's changes (retrofit first, then the named numbers)."""
        changes = dict(self.changes)
        factors = [changes.pop(key, 1.0) for key in RETROFIT_KEYS]
        if factors != [1.0, 1.0]:
            params = retrofit(params, *factors)
        return replace(params, **changes) if changes else params


@dataclass(frozen=True)
class SweepCase:
    """One cycle of a sweep.

    Attributes:
        device: Built-in device name, or the parameter set's name.
        variant: Variant name.
        elevation_deg: ε [deg], as given (the table's key and column).
        elevation: ε [rad] of the cycle.
        params: The device's parameters with the variant applied.
        spec: Stage durations and sample rate.
        base: The variant's vehicle motion, None for standing level.
        servo: The variant's controlled forward run, None for none.
    """

    device: str
    variant: str
    elevation_deg: float
    elevation: float
    params: FeederParameters
    spec: CycleSpec
    base: BaseMotion | None = None
    servo: ServoGains | None = None

    @property
    def key(self) -> tuple[str, str, float]:
        """(device, variant, elevation [deg]): what identifies the case in a table."""
        return (self.device, self.variant, self.elevation_deg)

    @property
    def sha256(self) -> str:
        """SHA-256 of what defines the case's computation: its key, its elevation [rad], and
        its parameters and timing (:func:`fingerprint`), its vehicle's motion, and its
        controlled run's settings if it has one (a case without keeps its earlier hash). A table
        row of this case carries it."""
        parts = [
            self.device,
            self.variant,
            repr(self.elevation_deg),
            repr(self.elevation),
            fingerprint(self.params, self.spec),
            base_fingerprint(self.base),
        ]
        if self.servo is not None:
            parts.append(repr(self.servo))
        text = json.dumps(parts)
        return hashlib.sha256(text.encode("utf-8")).hexdigest()


def fingerprint(params: FeederParameters, spec: CycleSpec) -> str:
    """A short hash of every number of a case but its elevation: a table row computed with other
    parameters or timing has another one."""
    text = repr((params, spec.durations, spec.rate))
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def base_fingerprint(base: BaseMotion | None) -> str:
    """A short hash of a vehicle's motion (every profile's numbers; a hull table's values)."""
    digest = hashlib.sha256()
    for profile in () if base is None else base.profiles:
        if isinstance(profile, HullTable):
            digest.update(profile.table.t.tobytes() + profile.table.values.tobytes())
        else:
            digest.update(repr(profile).encode("utf-8"))
    return digest.hexdigest()[:16]


def _too_many(what: str) -> str:
    """The message refusing a grid larger than :data:`MAX_CASES`."""
    return (
        f"{what}: a sweep has at most {MAX_CASES} cases (~70 min on 2 cores); use a larger "
        "elevation step, or fewer variants or devices"
    )


def elevation_range(start: float, stop: float, step: float) -> np.ndarray:
    """Elevations [deg] from ``start`` to ``stop`` inclusive in steps of ``step`` (> 0).

    Computed as start + k·step (no accumulated rounding) and rounded to 1e-12°, so whole-degree
    steps give whole numbers and 0.1° steps read 0.3, not 0.30000000000000004; ``stop`` is
    included when it lies on the grid within 1e-9 of a step.

    Raises:
        InputError: A bound or step that is not a finite number, a step ≤ 0, stop < start, or
            more than :data:`MAX_CASES` elevations.
    """
    start = check_number("elevation start [deg]", start)
    stop = check_number("elevation stop [deg]", stop)
    step = check_number("elevation step [deg]", step)
    if step <= 0.0 or stop < start:
        raise InputError(
            f"elevations must run from start to stop ≥ start in steps > 0 [deg], got start "
            f"{start:g}, stop {stop:g}, step {step:g}"
        )
    count = math.floor((stop - start) / step + 1e-9) + 1
    if count > MAX_CASES:
        raise InputError(_too_many(f"{count} elevations ({start:g}° to {stop:g}° by {step:g}°)"))
    return np.round(start + step * np.arange(count), 12)


@dataclass(frozen=True)
class SweepGrid:
    """Elevations × variants × devices, checked.

    Attributes:
        devices: Device name → its parameters (built-in devices by name).
        elevations_deg: Elevations ε [deg], shape (K,), each inside every device's range.
        variants: The parameter variants (names unique).
        spec: Stage durations and sample rate of every cycle.
    """

    devices: Mapping[str, FeederParameters]
    elevations_deg: np.ndarray
    variants: tuple[Variant, ...]
    spec: CycleSpec

    def cases(self) -> list[SweepCase]:
        """Every case, by device, then variant, then elevation."""
        cases = []
        for device, params in self.devices.items():
            for variant in self.variants:
                changed = variant.apply(params)
                for elevation in self.elevations_deg:
                    deg = float(elevation)
                    cases.append(
                        SweepCase(
                            device,
                            variant.name,
                            deg,
                            math.radians(deg),
                            changed,
                            self.spec,
                            variant.base,
                            variant.servo,
                        )
                    )
        return cases


def make_grid(
    devices: Sequence[str] | Mapping[str, FeederParameters] = ("projectile",),
    elevations_deg: Sequence[float] | np.ndarray | None = None,
    variants: Sequence[Variant] = (Variant("reference"),),
    spec: CycleSpec | None = None,
) -> SweepGrid:
    """A checked grid.

    Args:
        devices: Built-in device names, or name → parameters.
        elevations_deg: Elevations [deg]; default every degree of −4° … 70°.
        variants: Parameter variants; default the unchanged devices.
        spec: Timing; default :class:`~feeder.motion.laws.CycleSpec`.

    Raises:
        InputError: Unknown device, no device or variant or elevation, a repeated name, a bad
            variant name or key or value, an elevation outside a device's range.
        FeederError: A variant whose parameters are not physical or whose loop does not
            assemble (:func:`~feeder.device.loop.check_device`'s error, naming the device and
            the variant).
    """
    if isinstance(devices, Mapping):
        chosen = dict(devices)
    else:
        if isinstance(devices, str) or not isinstance(devices, Sequence):
            raise InputError(f"devices must be a list of device names, got {devices!r}")
        unknown = [d for d in devices if not isinstance(d, str) or d not in DEVICES]
        if unknown:
            raise InputError(f"unknown devices {unknown!r}; choose from {sorted(DEVICES)}")
        chosen = {name: DEVICES[name] for name in devices}
    if not chosen:
        raise InputError("a sweep needs at least one device")
    if elevations_deg is None:
        elevations_deg = elevation_range(*DEFAULT_ELEVATIONS_DEG)
    elevations = np.array(check_elevations_deg(elevations_deg, None))
    variants = tuple(variants)
    if not variants:
        raise InputError("a sweep needs at least one variant (e.g. 'reference', no change)")
    count = elevations.size * len(chosen) * len(variants)
    if count > MAX_CASES:
        raise InputError(
            _too_many(
                f"{count} cases ({elevations.size} elevations × {len(variants)} variants × "
                f"{len(chosen)} devices)"
            )
        )
    names = [v.name for v in variants]
    if len(set(names)) != len(names):
        raise InputError(f"variant names must be unique, got {names}")
    for device, params in chosen.items():
        check_elevations_deg(elevations, params.elevation_limits)
        for variant in variants:
            try:
                check_device(variant.apply(params))
            except FeederError as exc:  # the same error, told where it comes from
                raise type(exc)(f"device {device!r}, variant {variant.name!r}: {exc}") from exc
    return SweepGrid(chosen, elevations, variants, spec or CycleSpec())
