"""Initial rates from the rates of some joints (feeder.chain.initial_rates): the rate of an
independent joint gives the closure's velocity (finite differences of the assembled pose along
the motion); rates that contradict the closure are projected, by the least-squares fit that a
hand computation on the four-bar's tangent gives; bad names and values are refused in one line."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from feeder.chain import initial_rates
from feeder.exceptions import InputError
from feeder.study.analyze import mount_mechanism

from ...conftest import REPO

FOUR_BAR = REPO / "examples" / "four_bar" / "closures.toml"
SLIDER_CRANK = REPO / "examples" / "slider_crank" / "closures.toml"

STEP = 1e-5
"""[rad or m] Step of the central differences: truncation ~STEP² × the third derivative
(~1e-10), assembly's 1e-13 residual over 2 STEP ~5e-9: both below :data:`DIFFERENCE`."""

DIFFERENCE = 1e-7
"""[rad/s] Agreement of a rate with the central difference (of ~1 rad/s rates)."""


def tangent(path, rate: float) -> tuple[np.ndarray, np.ndarray, object]:
    """The assembled pose q (nq,), the central difference of the closed poses along the
    independent joint (q(x + h) ⊖ q(x − h)) / 2h times ``rate`` (nv,), and the chain."""
    spec, chain, partition, _, q = mount_mechanism(path, None, None)
    x = partition.independent_values(q)
    ahead = partition.assemble(partition.with_independent(q, x + STEP))
    behind = partition.assemble(partition.with_independent(q, x - STEP))
    return q, pin.difference(chain.model, behind, ahead) / (2 * STEP) * rate, chain


@pytest.mark.parametrize(
    ("path", "joint"), [(FOUR_BAR, "crank_joint"), (SLIDER_CRANK, "crank_joint")]
)
def test_an_independent_joint_s_rate_gives_the_closure_s_velocity(path, joint):
    q, expected, chain = tangent(path, 2.5)
    start = initial_rates(chain, q, {joint: 2.5})
    np.testing.assert_allclose(start.v, expected, rtol=0.0, atol=DIFFERENCE)
    assert start.used == pytest.approx({joint: 2.5}, abs=1e-12)
    assert not start.projected() and (start.fixed, start.freedoms) == (1, 1)
    assert np.abs(chain.jacobian(q) @ start.v).max() <= 1e-12  # closed to round-off


def test_the_slider_s_rate_drives_the_slider_crank_except_at_its_dead_centre():
    """A prismatic joint's rate [m/s] given: met exactly, the crank follows the closure. At the
    assembled pose (crank at 0, the slider at its end) no closed motion moves the slider: its
    rate cannot be honoured, it is projected to 0 and said so, and it fixes no freedom."""
    spec, chain, partition, _, dead = mount_mechanism(SLIDER_CRANK, None, None)
    q = partition.assemble(partition.with_independent(dead, np.array([0.7])))
    start = initial_rates(chain, q, {"slider_joint": 0.3})
    assert start.units == {"slider_joint": "m/s"}
    assert start.used["slider_joint"] == pytest.approx(0.3, abs=1e-12)
    assert np.abs(chain.jacobian(q) @ start.v).max() <= 1e-12
    stuck = initial_rates(chain, dead, {"slider_joint": 0.3})
    assert stuck.projected() and stuck.fixed == 0
    assert abs(stuck.used["slider_joint"]) <= 1e-9 and not np.any(np.abs(stuck.v) > 1e-9)
    assert "they fix 0 of the mechanism's 1 freedoms" in "\n".join(stuck.lines())


def test_rates_that_contradict_the_closure_are_projected_as_by_hand():
    """Crank 3 rad/s and rocker 1 rad/s: the four-bar moves along its tangent t (the finite
    differences per unit crank rate), so the closed rates are α t with α minimising
    (α t_c − 3)² + (α t_r − 1)²: α = (3 t_c + t_r) / (t_c² + t_r²), by hand."""
    q, t, chain = tangent(FOUR_BAR, 1.0)
    crank, rocker = (chain.joint_slice(name).start for name in ("crank_joint", "rocker_joint"))
    alpha = (3.0 * t[crank] + 1.0 * t[rocker]) / (t[crank] ** 2 + t[rocker] ** 2)
    start = initial_rates(chain, q, {"crank_joint": 3.0, "rocker_joint": 1.0})
    np.testing.assert_allclose(start.v, alpha * t, rtol=0.0, atol=3 * DIFFERENCE)
    change = start.change()
    assert change["crank_joint"] == pytest.approx(alpha * t[crank] - 3.0, abs=3 * DIFFERENCE)
    assert change["rocker_joint"] == pytest.approx(alpha * t[rocker] - 1.0, abs=3 * DIFFERENCE)
    assert start.projected()
    text = "\n".join(start.lines())
    assert "contradict the closure: projected" in text
    assert f"largest change {max(abs(x) for x in change.values()):.3g} rad/s" in text
    # consistent rates of both (taken from the closure itself) are met as given
    consistent = {"crank_joint": 2 * t[crank], "rocker_joint": 2 * t[rocker]}
    assert not initial_rates(chain, q, consistent).projected()


def test_no_rate_is_rest_and_bad_rates_are_refused_in_one_line():
    spec, chain, _, _, q = mount_mechanism(FOUR_BAR, None, None)
    start = initial_rates(chain, q, {})
    assert not start.v.any() and start.lines() == [
        "initial rates: none given, the run starts at rest"
    ]
    for rates, message in (
        ({"crank": 1.0}, r"no joint 'crank' in model .*; did you mean 'crank_joint'\?"),
        ({"crank_joint": float("nan")}, "the rate of 'crank_joint' must be .*finite"),
        ({"crank_joint": "1"}, "the rate of 'crank_joint'"),
        ([("crank_joint", 1.0)], "rates must map joint names"),
    ):
        with pytest.raises(InputError, match=message) as info:
            initial_rates(chain, q, rates)
        assert "\n" not in str(info.value)
