"""Physical rigid-body inertia (feeder.inertia, also exported by feeder.chain.readers): what no
rigid body can have is refused, whatever the frame the tensor is written in."""

from __future__ import annotations

import math

import numpy as np
import pytest

from feeder.chain import readers
from feeder.exceptions import InertiaError
from feeder.inertia import check_inertia


def rotation_z(angle: float) -> np.ndarray:
    """Rotation matrix about z by ``angle`` [rad]."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


@pytest.mark.parametrize(
    "mass, moments, reason",
    [
        (-1.0, (1.0, 1.0, 1.0), "negative"),
        (0.0, (1.0, 1.0, 1.0), "without mass"),
        (1.0, (1.0, 1.0, -0.1), "positive semi-definite"),
        (1.0, (1.0, 1.0, 2.0 + 1e-6), "triangle"),
        (float("nan"), (1.0, 1.0, 1.0), "finite"),
        (1.0, (1.0, float("inf"), 1.0), "finite"),
    ],
)
def test_check_inertia_refuses_non_physical(mass, moments, reason):
    with pytest.raises(InertiaError, match=reason) as info:
        check_inertia("some_link", mass, np.diag(moments))
    assert info.value.link == "some_link"
    assert "link 'some_link'" in str(info.value)


def test_check_inertia_sees_rotated_tensors():
    """The checks use the principal moments, not the diagonal of the given frame."""
    rotation = rotation_z(math.pi / 6)
    # A valid rod rotated by 30° about z keeps its principal moments: still valid.
    rod = rotation @ np.diag([0.01, 1.0, 1.0]) @ rotation.T
    check_inertia("rod", 1.0, rod)
    # (0.1, 0.1, 1.0) breaks the triangle inequality in any frame.
    with pytest.raises(InertiaError, match="triangle"):
        check_inertia("bad", 1.0, rotation @ np.diag([0.1, 0.1, 1.0]) @ rotation.T)
    # A negative principal moment can hide behind a positive diagonal: it is found.
    hidden = rotation @ np.diag([-0.05, 1.0, 1.0]) @ rotation.T
    assert np.all(np.diag(hidden) > 0.0)
    with pytest.raises(InertiaError, match="positive semi-definite"):
        check_inertia("hidden", 1.0, hidden)


def test_check_inertia_refuses_an_asymmetric_tensor():
    """A product of inertia given on one side of the diagonal only is not a tensor."""
    lopsided = np.diag([1.0, 1.0, 1.0])
    lopsided[0, 1] = 0.1
    with pytest.raises(InertiaError, match="not symmetric"):
        check_inertia("lopsided", 1.0, lopsided)
    symmetric = lopsided.copy()
    symmetric[1, 0] = 0.1
    check_inertia("symmetric", 1.0, symmetric)


@pytest.mark.parametrize(
    "mass, moments",
    [
        (0.0, (0.0, 0.0, 0.0)),  # a CAD frame link: no mass, no inertia
        (1e-9, (0.0, 0.0, 0.0)),  # the same, exported as 1e-9 kg
        (2.0, (0.5, 0.5, 0.0)),  # a thin rod: one moment zero, I₁ = I₂
        (2.0, (0.3, 0.2, 0.5)),  # a lamina: I₃ = I₁ + I₂
        (2.0, (0.3, 0.2, 0.5 * (1.0 + 1e-12))),  # the same, rounded up by the export
    ],
)
def test_idealised_bodies_are_accepted(mass, moments):
    """Real exports: frame links, and the triangle inequality's limiting cases in any frame."""
    rotation = rotation_z(0.7)
    check_inertia("ideal", mass, rotation @ np.diag(moments) @ rotation.T)


def test_the_readers_export_the_same_check():
    """feeder.chain.readers gives the check of feeder.inertia (numpy only), not a copy."""
    assert readers.check_inertia is check_inertia
