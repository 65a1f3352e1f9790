"""The parameters of a feeding device: every number, its unit and its source (one dataclass).

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

from ..exceptions import InputError
from ..inertia import check_inertia
from ..validation import check_number, check_vector

GRAVITY = np.array([0.0, -9.81, 0.0])
"""Gravity [m/s²] in the world frame: −y, g = 9.81 m/s² (REFERENCE.md; Pinocchio's default is
−z, so :class:`~feeder.device.feeder.Feeder` sets its model's gravity to this)."""

VEHICLE_FORWARD = (-1.0, 0.0, 0.0)
"""The vehicle's forward axis in the world frame: the barrel points forward over the hull's front
(the muzzle towards −x); with up = +y the vehicle's left is +z (ISO 8855 axes:
:mod:`feeder.chain.model.base`)."""


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

        Raises:
            InputError: A mass that is not one number, moments that are not three numbers
                (text and truth values included).
            InertiaError: Numbers that no rigid body has.
        """
        mass = check_number(f"link '{link}': mass [kg]", self.mass)
        moments = check_vector(f"link '{link}': moments [kg·m²]", self.moments, 3)
        if any(isinstance(m, bool | np.bool_) for m in np.ravel(np.asarray(self.moments, object))):
            raise InputError(f"link '{link}': moments must be numbers, got {self.moments!r}")
        check_inertia(link, mass, np.diag(moments))


SINGULAR_TRANSMISSION_DEG = 5.0
"""Poses with |sin μ| < sin 5° (transmission angle μ within 5° of 0° or 180°) are refused: there
the piston force needed for a given arm moment is over 11× its value at μ = 90° and grows without
bound at the toggle. The reference device stays inside [43°, 137°]. The one toggle threshold of
the package: the pipeline (:mod:`feeder.device.loop`) and the hand-derived equations
(:mod:`feeder.paper`) both refuse with it."""

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

    def _shown(self, name: str) -> str:
        """``name = value`` for a message: an angle in degrees (under a parameter file's
        ``_deg`` key), a length in metres."""
        value = getattr(self, name)
        if self.__dataclass_fields__[name].metadata.get("unit") == "rad":
            return f"{name}_deg = {math.degrees(value):.6g}°"
        return f"{name} = {value!r} m"

    def check(self) -> None:
        """Raise unless every number is usable (the travel: :func:`~.loop.check_device`).

        Checked, in this order: every number finite; every link inertia physical; the lengths
        in :data:`POSITIVE_LENGTHS` positive and the CG distances l1, l3 not negative (c, d,
        e, f, h5, z5 are offsets of either sign, L1, L2 a position); 0 < rod diameter < bore
        diameter; each range (r2, φ1, φ3, elevation) with min < max; 0 < φ4 limit and
        |swing| ≤ φ4 limit. The geometry over the whole arm travel (every pose reachable, away
        from the toggle) is the loop's to check: :func:`feeder.device.loop.check_device` runs
        both.

        Raises:
            InputError: A non-finite or out-of-range number, an empty range.
            InertiaError: A non-physical link inertia (names the link).
        """
        for f_ in fields(self):
            if f_.type == "float":  # annotations are strings (from __future__ import annotations)
                check_number(f"parameters {self.name!r}: {f_.name}", getattr(self, f_.name))
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
                    f"parameters {self.name!r}: {self._shown(low)} must be smaller than "
                    f"{self._shown(high)}"
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

    def mirrored(self, name: str) -> FeederParameters:
        """The same device mirrored through the barrel's vertical plane (z → −z)."""
        return replace(self, name=name, c=-self.c, z5=-self.z5, swing=-self.swing)
