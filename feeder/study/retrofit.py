"""Retrofit study: the device with a heavier and longer payload of the same calibre."""

from __future__ import annotations

from dataclasses import replace

from ..device.parameters import FeederParameters, LinkInertia
from ..exceptions import InputError
from ..validation import check_number

FACTORS = (1e-3, 1e3)
"""Accepted range of the retrofit factors: a payload a thousand times heavier, lighter, longer or
shorter is another device, not a retrofit (and 1e306 overflows the inertias)."""


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
        InputError: A factor that is not finite or outside :data:`FACTORS`.
    """
    mass_factor = check_number("retrofit mass factor", mass_factor)
    length_factor = check_number("retrofit length factor", length_factor)
    low, high = FACTORS
    if not (low <= mass_factor <= high and low <= length_factor <= high):
        raise InputError(
            f"retrofit factors must be positive, within {low:g}…{high:g}, got "
            f"mass ×{mass_factor:g}, length ×{length_factor:g}"
        )
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
