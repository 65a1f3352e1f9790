"""Parameter sets of the two feeding devices: every number, its unit and its source, in one place.

The world frame has its origin at the cylinder pivot B, x horizontal in the barrel's vertical
plane (the muzzle is towards −x), y vertical up, z along the pivot axes (REFERENCE.md).

Link frames (so that the joint positions equal the paper's coordinates of eq. 29):

* ``cylinder``: origin at B, x along the cylinder axis (angle φ1 from world x about z).
* ``piston``: origin at the piston's centre of gravity S, a distance r2 from B along the axis.
* ``arm``: origin at the arm pivot (L1, L2), x along the arm (angle φ3 from world x about z).
* ``forearm``: origin on the forearm hinge at (a + b, −f, c) in the arm frame; it turns by φ4
  about the arm's y axis, which is perpendicular to the arm in its vertical plane (eq. 30).
* ``projectile``: origin at the payload's centre of gravity, fixed in the forearm frame at
  (e5, h5, z5); its y axis is the payload axis, nose first (nose up at loading).

Table I gives moments of inertia about axes through each centre of gravity parallel to the global
axes, in the pose drawn in the paper. Its projectile has its smallest moment about y, so that pose
is our loading pose (arm along x, forearm in the barrel plane, projectile axis vertical), in which
the arm, forearm and projectile frames are parallel to the world axes: their moments are used as
printed. The cylinder and piston moments are smallest about the table's y axis, i.e. their axis of
symmetry is y there; in our link frames that axis is x, so their x and y moments are exchanged
(z, the pivot axis, is common). That is a relabelling, not a change of values.

Two printed tensors are not physical (one moment exceeds the sum of the other two): the piston's
I2yy = 4.160e-2 and the arm's I3yy = 5.036e-2 kg·m². The smallest edit of the printed numbers that
makes them valid is one digit of the exponent, e-2 → e-3 (a factor ten, a typesetting slip);
clamping them to the triangle bound instead would describe bodies of zero thickness (singular
pseudo-inertia), which the loader rightly refuses. Other Table I moments are physically valid but
implausibly small for the parts' sizes (the 43.5 kg projectile has 1.312e-2 kg·m² about a
transverse axis where a solid 152 mm × 0.70 m cylinder has ≈ 1.8 kg·m²); as REFERENCE.md asks they
are kept as printed. Their effect is small: the payload's moments about the arm pivot are dominated
by m·r² (43.5 kg at 0.65 m: 18 kg·m²).

The lengths are not in the paper. They are chosen so that the loop assembles over the whole arm
travel of 94° with the transmission angle inside [43°, 137°] (the best achievable band for a lever
on the arm line sweeping 94°, found by a grid search over L1, L2, d3), with a cylinder of 0.28 m
stroke and 0.41 m retracted pin-to-pin length; offsets between the arm, forearm and payload centres
of gravity are Table I's coordinate differences.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace

import numpy as np

from .exceptions import InertiaError, InputError, check_finite


@dataclass(frozen=True)
class LinkInertia:
    """Mass and central moments of inertia of one link.

    Attributes:
        mass: Mass [kg].
        moments: (Ixx, Iyy, Izz) [kg·m²] about axes through the centre of gravity, parallel to
            the link frame's axes (products of inertia are zero).
        source: Where the numbers come from.
    """

    mass: float
    moments: tuple[float, float, float]
    source: str

    def check(self, link: str) -> None:
        """Raise :class:`InertiaError` naming ``link`` unless the inertia is physical.

        Physical means: finite, positive mass; positive moments; each moment strictly smaller
        than the sum of the other two (a body of non-zero thickness).
        """
        check_inertia(link, self.mass, np.diag(self.moments))


def check_inertia(link: str, mass: float, inertia: np.ndarray) -> None:
    """Raise :class:`InertiaError` naming ``link`` unless ``mass`` and ``inertia`` are physical.

    Args:
        link: Link name, for the message.
        mass: Mass [kg].
        inertia: (3, 3) rotational inertia about the centre of gravity [kg·m²].
    """
    values = np.append(np.ravel(inertia), mass)
    if not np.all(np.isfinite(values)):
        raise InertiaError(link, f"mass or inertia is not finite (mass={mass!r})")
    if mass <= 0.0:
        raise InertiaError(link, f"mass must be positive, got {mass!r} kg")
    inertia = np.asarray(inertia, dtype=float)
    if not np.allclose(inertia, inertia.T, rtol=0.0, atol=1e-12 * max(1.0, np.abs(inertia).max())):
        raise InertiaError(link, "inertia tensor is not symmetric")
    principal = np.linalg.eigvalsh(inertia)
    if principal[0] <= 0.0:
        raise InertiaError(
            link, f"inertia tensor is not positive definite (principal moments {principal})"
        )
    total = principal.sum()
    for moment in principal:
        if moment >= total - moment:
            raise InertiaError(
                link,
                f"principal moment {moment:.6g} kg·m² is not smaller than the sum of the other "
                f"two ({total - moment:.6g} kg·m²): no rigid body has this inertia "
                "(triangle inequality)",
            )


POSITIVE_LENGTHS = (
    "d2",
    "d3",
    "a",
    "e5",
    "r2_min",
    "payload_length",
    "payload_diameter",
    "bore_diameter",
    "rod_diameter",
    "pinion_radius",
)
"""Lengths [m] that :meth:`FeederParameters.check` requires positive: the rod-eye pin beyond the
piston's centre of gravity (d2) and the piston ahead of the cylinder pivot (r2_min); the arm's
lever to the pin (d3 = 0 puts the pin on the arm pivot: no moment, a singular loop); the arm
beam (a); the payload's centre of gravity ahead of the forearm hinge (e5: the tray's length);
the payload's and the drives' sizes."""


def _length(unit: str, source: str):
    return field(metadata={"unit": unit, "source": source})


@dataclass(frozen=True, kw_only=True)
class FeederParameters:
    """Geometry, inertia, drives and limits of one feeding device.

    Lengths [m] and angles [rad]. Field metadata hold each number's unit and source;
    :func:`parameter_table` lists them.
    """

    name: str = field(metadata={"unit": "", "source": "device name"})
    # Loop geometry (eq. 30, 44; world frame, origin at the cylinder pivot B).
    L1: float = _length("m", "assumed: arm pivot x from B; grid search for the transmission band")
    L2: float = _length("m", "assumed: arm pivot y from B; grid search for the transmission band")
    l1: float = _length("m", "assumed: cylinder CG from B along its axis, mid-barrel")
    d2: float = _length("m", "assumed: piston CG S to the rod-eye pin along the axis")
    l3: float = _length("m", "assumed: arm CG from its pivot along the arm")
    d3: float = _length("m", "assumed: arm pivot to the rod-eye pin; grid search")
    a: float = _length("m", "assumed: arm beam length, pivot to the forearm bearing boss")
    b: float = _length("m", "assumed: boss to the forearm hinge axis along the arm (a + b = a1)")
    c: float = _length("m", "Table I: Z4 − Z3, forearm hinge offset along z from the arm plane")
    d: float = _length("m", "Table I: Y3 − Y4 − f, forearm CG below the hinge origin")
    e: float = _length("m", "Table I: X4 − X3 + l3 − a1, forearm CG from the hinge axis")
    f: float = _length("m", "assumed: forearm hinge origin below the arm axis")
    # Payload placement in the forearm frame.
    e5: float = _length("m", "Table I: X5 − X4 + e, payload CG from the hinge axis")
    h5: float = _length("m", "Table I: Y5 − Y4 − d, payload CG above the hinge origin")
    z5: float = _length("m", "Table I: Z5 − Z4, payload CG offset along z")
    payload_length: float = _length("m", "payload overall length (visual and retrofit studies)")
    payload_diameter: float = _length("m", "payload calibre (visual)")
    payload_name: str = field(default="projectile", metadata={"unit": "", "source": "-"})
    # Inertia (Table I).
    cylinder: LinkInertia
    piston: LinkInertia
    arm: LinkInertia
    forearm: LinkInertia
    payload: LinkInertia
    # Motion (REFERENCE.md, section "The feeding cycle").
    phi3_load: float = field(
        default=0.0, metadata={"unit": "rad", "source": "REFERENCE.md: arm horizontal at loading"}
    )
    swing: float = field(
        default=math.radians(90.0),
        metadata={"unit": "rad", "source": "assumed: forearm swing to the conveyor, Δφ52"},
    )
    elevation_min: float = field(
        default=math.radians(-4.0), metadata={"unit": "rad", "source": "paper, section I"}
    )
    elevation_max: float = field(
        default=math.radians(70.0), metadata={"unit": "rad", "source": "REFERENCE.md"}
    )
    # Joint limits (the URDF's; the loop is unreachable outside them).
    r2_min: float = _length("m", "assumed: piston end stop, 10 mm before the loading pose")
    r2_max: float = _length("m", "assumed: piston end stop, 10 mm past the −4° pose")
    phi3_min: float = field(
        default=math.radians(-5.0), metadata={"unit": "rad", "source": "assumed: arm end stop"}
    )
    phi3_max: float = field(
        default=math.radians(100.0), metadata={"unit": "rad", "source": "assumed: arm end stop"}
    )
    phi1_min: float = field(
        default=math.radians(100.0), metadata={"unit": "rad", "source": "assumed: cylinder swing"}
    )
    phi1_max: float = field(
        default=math.radians(170.0), metadata={"unit": "rad", "source": "assumed: cylinder swing"}
    )
    phi4_limit: float = field(
        default=math.radians(100.0),
        metadata={"unit": "rad", "source": "assumed: forearm end stops ±100°"},
    )
    # Drives (issue 3: hydraulics).
    bore_diameter: float = _length("m", "assumed: cylinder bore, ISO 3320 size 50 mm")
    rod_diameter: float = _length("m", "assumed: piston rod, ISO 3320 size 28 mm")
    pinion_radius: float = _length("m", "assumed: forearm rack pinion pitch radius")

    @property
    def a1(self) -> float:
        """Arm pivot to the forearm hinge axis along the arm, a1 = a + b [m] (eq. 30)."""
        return self.a + self.b

    @property
    def elevation_limits(self) -> tuple[float, float]:
        """Elevation range (min, max) [rad]."""
        return (self.elevation_min, self.elevation_max)

    def links(self) -> dict[str, LinkInertia]:
        """Inertia of each link by URDF link name."""
        return {
            "cylinder": self.cylinder,
            "piston": self.piston,
            "arm": self.arm,
            "forearm": self.forearm,
            "projectile": self.payload,
        }

    def check(self) -> None:
        """Raise unless every number is usable and the feeding cycle can be assembled.

        Checked, in this order: every number finite; every link inertia physical; the lengths
        in :data:`POSITIVE_LENGTHS` positive and the CG distances l1, l3 not negative (c, d,
        e, f, h5, z5 are offsets of either sign, L1, L2 a position); 0 < rod diameter < bore
        diameter; each range (r2, φ1, φ3, elevation) with min < max; 0 < φ4 limit and
        |swing| ≤ φ4 limit; then the geometry over the whole arm travel
        (:func:`~feeder.kinematics.check_travel`): every pose from loading to the lowest
        elevation reachable, its transmission angle away from the toggle.

        Raises:
            InputError: A non-finite or out-of-range number, an empty range, a pose near the
                toggle.
            InertiaError: A non-physical link inertia (names the link).
            UnreachablePoseError: A pose of the travel outside the joint limits.
        """
        for f_ in fields(self):
            value = getattr(self, f_.name)
            if isinstance(value, float):
                check_finite(f_.name, value)
        for link, inertia in self.links().items():
            inertia.check(link)
        for name in POSITIVE_LENGTHS:
            if not getattr(self, name) > 0.0:
                raise InputError(
                    f"parameters {self.name!r}: {name} must be positive, got "
                    f"{getattr(self, name)!r} m"
                )
        if not self.a1 > 0.0:
            raise InputError(
                f"parameters {self.name!r}: a1 = a + b must be positive, got {self.a1!r} m"
            )
        for name in ("l1", "l3"):
            if getattr(self, name) < 0.0:
                raise InputError(
                    f"parameters {self.name!r}: {name} (a centre of gravity along its link "
                    f"from the pivot) must not be negative, got {getattr(self, name)!r} m"
                )
        if not self.rod_diameter < self.bore_diameter:
            raise InputError(
                f"parameters {self.name!r}: the rod diameter {self.rod_diameter!r} m must be "
                f"smaller than the bore diameter {self.bore_diameter!r} m"
            )
        for low, high in (
            ("r2_min", "r2_max"),
            ("phi1_min", "phi1_max"),
            ("phi3_min", "phi3_max"),
            ("elevation_min", "elevation_max"),
        ):
            if not getattr(self, low) < getattr(self, high):
                raise InputError(
                    f"parameters {self.name!r}: {low} = {getattr(self, low)!r} must be smaller "
                    f"than {high} = {getattr(self, high)!r}"
                )
        if not self.phi4_limit > 0.0:
            raise InputError(
                f"parameters {self.name!r}: phi4_limit must be positive, got "
                f"{self.phi4_limit!r} rad"
            )
        if not abs(self.swing) <= self.phi4_limit:
            raise InputError(
                f"parameters {self.name!r}: the swing {math.degrees(self.swing):.3f}° is outside "
                f"the forearm's end stops ±{math.degrees(self.phi4_limit):.3f}°"
            )
        from .kinematics import check_travel  # kinematics imports this module

        check_travel(self)

    def mirrored(self, name: str) -> FeederParameters:
        """The same device mirrored through the barrel's vertical plane (z → −z)."""
        return replace(self, name=name, c=-self.c, z5=-self.z5, swing=-self.swing)


def parameter_table(params: FeederParameters) -> list[tuple[str, str, str, str]]:
    """Every number of ``params`` as rows (name, value, unit, source)."""
    rows = []
    for f_ in fields(params):
        value = getattr(params, f_.name)
        if isinstance(value, LinkInertia):
            rows.append((f"{f_.name}.mass", f"{value.mass:g}", "kg", value.source))
            for axis, moment in zip("xyz", value.moments, strict=True):
                rows.append((f"{f_.name}.I{axis}{axis}", f"{moment:g}", "kg·m²", value.source))
        elif isinstance(value, float):
            unit = f_.metadata["unit"]
            shown = f"{math.degrees(value):g}°" if unit == "rad" else f"{value:g}"
            rows.append((f_.name, shown, unit, f_.metadata["source"]))
    return rows


def parameters_markdown() -> str:
    """Every number of the built-in devices as a Markdown table (the published PARAMETERS.md)."""
    lines = [
        "# Parameters of the built-in devices",
        "",
        "Generated by `feeder parameters --out PARAMETERS.md` from `feeder/parameters.py`; do not "
        "edit by hand. SI units (angles shown in degrees). Source: “Table I” of the paper, an "
        "equation, or “assumed” with the reason. Table I's moments are about axes through each "
        "centre of gravity, here in the link frame (see the module docstring).",
    ]
    for name, params in DEVICES.items():
        lines += [
            "",
            f"## {name} feeder",
            "",
            "| name | value | unit | source |",
            "|---|---|---|---|",
        ]
        lines += [f"| {n} | {v} | {u} | {s} |" for n, v, u, s in parameter_table(params)]
    return "\n".join(lines) + "\n"


_TABLE_I = "Table I"
_SWAPPED = "Table I; table x/y exchanged into the link frame (axis of symmetry = link x)"

TABLE_I_CG: dict[int, tuple[float, float, float]] = {
    1: (-0.134, -0.257, 3.425e-2),
    2: (-6.999e-2, -0.181, 3.425e-2),
    3: (7.620e-2, -0.140, 3.115e-2),
    4: (0.423, -0.169, 1.710e-2),
    5: (0.53, -0.129, 8.425e-2),
}
"""Table I centre-of-gravity coordinates (X, Y, Z) [m] of links 1–4 and the projectile (5), in
the paper's pose (our loading pose). Their differences place the forearm and the payload."""

_X, _Y, _Z = 0, 1, 2
_A1, _L3, _F = 0.45, 0.20, 0.020  # a + b, l3, f: assumed (see the field sources)
_D = TABLE_I_CG[3][_Y] - TABLE_I_CG[4][_Y] - _F
_E = TABLE_I_CG[4][_X] - TABLE_I_CG[3][_X] + _L3 - _A1

PROJECTILE_FEEDER = FeederParameters(
    name="projectile",
    L1=-0.49,
    L2=0.28,
    l1=0.18,
    d2=0.17,
    l3=_L3,
    d3=0.19,
    a=0.40,
    b=_A1 - 0.40,
    c=TABLE_I_CG[4][_Z] - TABLE_I_CG[3][_Z],
    d=_D,
    e=_E,
    f=_F,
    e5=TABLE_I_CG[5][_X] - TABLE_I_CG[4][_X] + _E,
    h5=TABLE_I_CG[5][_Y] - TABLE_I_CG[4][_Y] - _D,
    z5=TABLE_I_CG[5][_Z] - TABLE_I_CG[4][_Z],
    payload_length=0.70,
    payload_diameter=0.152,
    cylinder=LinkInertia(4.117, (2.391e-2, 3.504e-2, 3.511e-2), _SWAPPED),
    piston=LinkInertia(
        2.092,
        (4.160e-3, 1.054e-2, 1.058e-2),
        _SWAPPED + "; I2yy printed 4.160e-2 violates the triangle inequality: read 4.160e-3",
    ),
    arm=LinkInertia(
        18.663,
        (0.238e-2, 5.036e-3, 0.278e-2),
        _TABLE_I + "; I3yy printed 5.036e-2 violates the triangle inequality: read 5.036e-3",
    ),
    forearm=LinkInertia(16.077, (0.262e-2, 0.284e-2, 0.531e-2), _TABLE_I),
    payload=LinkInertia(43.5, (1.312e-2, 0.143e-2, 1.312e-2), _TABLE_I),
    r2_min=0.2304,  # r2 at φ3 = 0 is 0.24037 m
    r2_max=0.5283,  # r2 at φ3 = 94° is 0.51828 m
    bore_diameter=0.050,
    rod_diameter=0.028,
    pinion_radius=0.040,
)
"""The right-hand (projectile) feeder of the 152 mm SPH M77 (paper, Fig. 3 item 7)."""


def _charge_case_inertia(mass: float, length: float, diameter: float) -> LinkInertia:
    """Uniform solid cylinder along y: Iyy = m r²/2, Ixx = Izz = m (3 r² + L²)/12."""
    r = diameter / 2.0
    transverse = mass * (3.0 * r**2 + length**2) / 12.0
    return LinkInertia(
        mass,
        (transverse, mass * r**2 / 2.0, transverse),
        "assumed: 16 kg charge in case, uniform solid cylinder 0.17 m × 0.60 m",
    )


CHARGE_FEEDER = replace(
    PROJECTILE_FEEDER.mirrored("charge"),
    payload_name="charge",
    payload_length=0.60,
    payload_diameter=0.17,
    payload=_charge_case_inertia(16.0, 0.60, 0.17),
)
"""The left-hand (propellant-charge) feeder: the projectile feeder mirrored through the barrel
plane (paper, Fig. 3 item 4), with an assumed charge case as payload (data not in the paper)."""


def retrofit(
    params: FeederParameters, mass_factor: float, length_factor: float
) -> FeederParameters:
    """The device with a heavier and longer payload of the same calibre.

    Assumptions: the payload's base stays where the tray holds it and its centre of gravity stays
    at 40 % of its length from the base, so the CG moves along the payload axis (forearm y) by
    0.4 ΔL; its transverse moments scale as m L², its axial moment as m (same calibre).

    Args:
        params: The original device.
        mass_factor: New mass / old mass (e.g. 1.2 for +20 %).
        length_factor: New length / old length (e.g. 1.15 for +15 %).

    Raises:
        InputError: A factor that is not finite and positive.
    """
    factors = check_finite("retrofit factors", (mass_factor, length_factor))
    if np.any(factors <= 0.0):
        raise InputError(f"retrofit factors must be positive, got {tuple(factors)}")
    old = params.payload
    ixx, iyy, izz = old.moments
    transverse = mass_factor * length_factor**2
    payload = LinkInertia(
        old.mass * mass_factor,
        (ixx * transverse, iyy * mass_factor, izz * transverse),
        f"retrofit of ({old.source}): mass ×{mass_factor:g}, length ×{length_factor:g}",
    )
    length = params.payload_length * length_factor
    return replace(
        params,
        name=f"{params.name} (retrofit)",
        payload=payload,
        payload_length=length,
        h5=params.h5 + 0.4 * (length - params.payload_length),
    )


DEVICES: dict[str, FeederParameters] = {"projectile": PROJECTILE_FEEDER, "charge": CHARGE_FEEDER}
"""The built-in devices by name."""
