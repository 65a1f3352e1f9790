"""The feeding cycle (paper Fig. 7, REFERENCE.md): prescribed motion of φ3, φ4 and its samples.

Stage 1 (0 … T1): the forearm swings by ``swing`` about its hinge (vertical at loading) to the
conveyor, empty. Stage 2 (T1 … T1+T2): it swings back with the payload, gripped at the end of
stage 1, into the barrel plane. Stage 3 (… T1+T2+T3): the cylinder turns the arm up by 90° − ε,
laying the payload axis along the barrel at elevation ε. Every stage follows the quintic
rest-to-rest law h(s) = 10 s³ − 15 s⁴ + 6 s⁵ (zero velocity and acceleration at both ends).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ..device.loop import arm_travel
from ..device.parameters import FeederParameters
from ..exceptions import FeederWarning, InputError
from ..validation import check_finite

MAX_SAMPLES = 1_000_000
"""Most samples a cycle may have. Measured per sample: the kinematics take ~0.5 kB (peak) and
7 µs, the whole cycle dynamics ~2 kB and 27 µs, so a million samples need ~2 GB and ~30 s (ten
million would need 20 GB); that is 250 kHz over the default 4 s cycle, far finer than any result
needs (1 kHz gives 4001 samples)."""


PEAK_TOLERANCE = 1e-3
"""Largest relative miss of a load's peak that a sampling may cause without a warning. A peak
can fall half a step h from the nearest sample; a load that turns like a sine over a stage of
duration T then misses its peak by at most 1 − cos(π h / T): below 0.1 % when a stage holds at
least 71 samples (measured at −4°: 3.6e-5 for the piston force at 71 Hz against 1 kHz; 5.2 %
at 1 Hz)."""


def peak_miss_bound(rate: float, shortest_stage: float) -> float:
    """The bound 1 − cos(π h / T) on a peak's relative miss at ``rate`` [Hz] (h = 1/rate) for
    the shortest stage T [s] (:data:`PEAK_TOLERANCE`); 1 when a stage holds a single step."""
    phase = math.pi / (rate * shortest_stage)
    return 1.0 - math.cos(phase) if phase < math.pi / 2.0 else 1.0


@dataclass(frozen=True)
class CycleSpec:
    """Timing of a feeding cycle; the numbers are checked and stored as floats.

    Attributes:
        durations: Durations (T1, T2, T3) [s] of stages 1–3. Default (1, 1, 2) s: Fig. 7 and
            section V give stage boundaries at 1 s and 2 s; T3 = 2 s is assumed.
        rate: Sample rate [Hz] (default 1 kHz).

    Raises:
        InputError: Durations that are not three finite positive times, a rate that is not
            finite and positive, or more than :data:`MAX_SAMPLES` samples.
    """

    durations: tuple[float, float, float] = (1.0, 1.0, 2.0)
    rate: float = 1000.0

    def __post_init__(self) -> None:
        durations = check_finite("stage durations", self.durations)
        if durations.shape != (3,) or np.any(durations <= 0.0):
            raise InputError(
                f"stage durations must be three positive times [s], got {self.durations!r}"
            )
        rate = check_finite("sample rate", self.rate)
        if rate.shape != () or rate <= 0.0:
            raise InputError(f"sample rate must be one positive number [Hz], got {self.rate!r}")
        period, rate = float(durations.sum()), float(rate)
        steps = period * rate
        if steps + 1 > MAX_SAMPLES:
            raise InputError(
                f"sample rate {rate:g} Hz over a {period:g} s cycle gives {steps + 1:.0f} "
                f"samples, more than the {MAX_SAMPLES} allowed"
            )
        # The samples run from 0 to the cycle's end, both included, at one step 1/rate (the
        # force-rule run integrates with that step): the cycle must hold a whole number of steps,
        # to round-off (1e-9 relative).
        whole = max(round(steps), 1)
        if abs(steps - whole) > 1e-9 * max(steps, 1.0):
            fitting = ", ".join(
                f"{n / period:g} Hz" for n in sorted({math.floor(steps) or 1, math.ceil(steps)})
            )
            raise InputError(
                f"sample rate {rate:g} Hz does not divide the {period:g} s cycle into whole "
                f"steps ({steps:g}): the last sample would miss the cycle's end; use e.g. "
                f"{fitting}"
            )
        object.__setattr__(self, "durations", tuple(float(d) for d in durations))
        object.__setattr__(self, "rate", rate)
        miss = peak_miss_bound(self.rate, min(self.durations))
        if miss > PEAK_TOLERANCE:
            needed = math.ceil(math.pi / math.acos(1.0 - PEAK_TOLERANCE) / min(self.durations))
            warnings.warn(
                f"sampling at {self.rate:g} Hz is too coarse for the {min(self.durations):g} s "
                f"stage: a load's peak may be missed by up to {miss:.1%} (it can fall between "
                f"samples); sample at {needed} Hz or more for {PEAK_TOLERANCE:.1%}",
                FeederWarning,
                stacklevel=3,
            )

    @property
    def boundaries(self) -> np.ndarray:
        """Stage start and end times [0, T1, T1+T2, T1+T2+T3] [s], shape (4,)."""
        return np.concatenate([[0.0], np.cumsum(self.durations)])

    def times(self) -> np.ndarray:
        """Sample times [s], shape (N,), from 0 to the cycle's end inclusive, one step 1/rate
        apart (the last one exactly at the end)."""
        count = round(self.boundaries[-1] * self.rate)
        t = np.arange(count + 1) / self.rate
        t[-1] = self.boundaries[-1]  # not a round-off beyond the last stage
        return t


def rest_to_rest(s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Quintic law h(s) = 10s³ − 15s⁴ + 6s⁵ and its derivatives h′, h″ for s in [0, 1]."""
    s = np.clip(s, 0.0, 1.0)
    h = s**3 * (10.0 - 15.0 * s + 6.0 * s**2)
    dh = 30.0 * s**2 * (1.0 - s) ** 2
    ddh = 60.0 * s * (1.0 - s) * (1.0 - 2.0 * s)
    return h, dh, ddh


def prescribed_motion(
    p: FeederParameters, elevation: float, spec: CycleSpec
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Times and the independent coordinates' laws at ``elevation`` ε [rad] (checked).

    Returns:
        t [s] (N,), and (N, 2) arrays of [φ3, φ4] [rad], their rates [rad/s] and accelerations
        [rad/s²].
    """
    t = spec.times()
    ends = spec.boundaries
    x = np.zeros((t.size, 2))
    dx, ddx = np.zeros_like(x), np.zeros_like(x)
    stages = (
        (1, 1, 0.0, p.swing),  # (stage, coordinate: 0 = φ3, 1 = φ4, start, change)
        (2, 1, p.swing, -p.swing),
        (3, 0, p.phi3_load, arm_travel(elevation)),
    )
    x[:, 0] = p.phi3_load
    for stage, k, start, change in stages:
        duration = ends[stage] - ends[stage - 1]
        inside = (t >= ends[stage - 1]) & (t <= ends[stage])
        h, dh, ddh = rest_to_rest((t[inside] - ends[stage - 1]) / duration)
        x[inside, k] = start + change * h
        dx[inside, k] = change * dh / duration
        ddx[inside, k] = change * ddh / duration**2
    return t, x, dx, ddx
