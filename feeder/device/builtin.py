"""The built-in devices: the projectile feeder of the paper and the mirrored charge feeder.

Masses and moments from Table I (two moments corrected, see :mod:`feeder.device.parameters`);
lengths assumed, as each field's source says; Table I's centre-of-gravity coordinates place the
forearm and the payload.
"""

from __future__ import annotations

from dataclasses import replace

from .parameters import FeederParameters, LinkInertia

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


DEVICES: dict[str, FeederParameters] = {"projectile": PROJECTILE_FEEDER, "charge": CHARGE_FEEDER}
"""The built-in devices by name."""
