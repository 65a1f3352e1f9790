"""What a forward run may cost: the caps on its output samples and integration steps, its
progress line, and the message of a run stopped at the cap.

A run's work is its integration steps (each a dozen right-hand sides, a check of the singular
pose) and its output samples (each projected onto the constraints, its accelerations and loads
evaluated, written to the table). Both are bounded, so that every run answers: a request that
exceeds a cap for certain (more samples than the memory allows, a step limit that cannot cover
the span) is refused before the run, with the numbers and the remedy; the steps, which only the
run knows, are counted and the run stops at :data:`MAX_STEPS` with the time it reached.
"""

from __future__ import annotations

import time

from tqdm import tqdm

from ...exceptions import InputError

MAX_STEPS = 200_000
"""Accepted integration steps after which a run stops, naming the time reached: a budget of a
few minutes. Measured: 0.4–0.65 ms per DOP853 or Radau step for the examples of 3 to 19
coordinates (four-bar, slider-crank, Bricard, Andrews' squeezer, cassie_like: 80–130 s at the
cap), 2.1 ms for the 48 of battobot_6d (7 min). The four-bar swinging under gravity takes ~90
DOP853 steps per second of motion (2 000 s of it fit), Andrews' squeezer ~2 500 (80 s)."""

SAMPLE_BYTES = 2_000
"""[B] Memory per output sample and velocity coordinate while a run's results are computed and
written (states, the inverse dynamics' batched arrays, the table's columns): measured growth of
the process's peak 1.4 kB for the four-bar (3 coordinates, 4.3 kB per sample), 0.9 kB for
cassie_like (19), 1.2 kB for battobot_6d (48)."""

SAMPLE_MEMORY = 1_000_000_000
"""[B] Memory a run's output samples may take (1 GB): at most SAMPLE_MEMORY / (SAMPLE_BYTES nv)
samples, 166 666 for the four-bar, 10 416 for battobot_6d. Their projection, loads and table take
0.03–0.09 ms per sample and coordinate (measured on the same three): under a minute at the cap."""

PROGRESS_DELAY = 3.0
"""[s] Wall-clock time after which a run shows its progress line (on a terminal): a shorter run
ends without one."""

PROGRESS_INTERVAL = 0.5
"""[s] Wall-clock time between two updates of the progress line's estimate."""


def max_samples(nv: int) -> int:
    """The most output samples a run of a chain of ``nv`` velocity coordinates may have
    (:data:`SAMPLE_MEMORY`)."""
    return max(2, SAMPLE_MEMORY // (SAMPLE_BYTES * max(nv, 1)))


def check_sample_count(name: str, count: int, nv: int) -> None:
    """Refuse ``count`` output samples beyond :func:`max_samples` (``name``: the argument that
    gives them, for the message)."""
    cap = max_samples(nv)
    if count > cap:
        need = count * SAMPLE_BYTES * max(nv, 1)
        raise InputError(
            f"{count} output samples ({name}) are more than the {cap} a run of this "
            f"{nv}-coordinate mechanism may have (about {need / 1e9:.3g} GB at "
            f"{SAMPLE_BYTES / 1e3:g} kB per sample and coordinate, for a budget of "
            f"{SAMPLE_MEMORY / 1e9:g} GB): ask for at most {cap}, or split the run"
        )


def check_step_count(span: float, max_step: float) -> None:
    """Refuse a run of ``span`` [s] whose longest step ``max_step`` [s] needs more than
    :data:`MAX_STEPS` steps for certain."""
    if span / max_step > MAX_STEPS:
        raise InputError(
            f"max_step {max_step:g} s needs at least {span / max_step:.3g} steps for the run's "
            f"{span:g} s, more than the cap of {MAX_STEPS}: a longer max_step, or a run of at "
            f"most {MAX_STEPS * max_step:.3g} s"
        )


def step_cap_message(reached: float, end: float, advice: str) -> str:
    """The one line of a run stopped at :data:`MAX_STEPS` at the time ``reached`` [s] of the
    ``end`` [s] it was asked for; ``advice``: what holds its steps (empty: nothing known)."""
    return (
        f"the run stopped at t = {reached:.6g} s of {end:.6g} s: it reached the cap of "
        f"{MAX_STEPS} integration steps (a few minutes of computing); end it by "
        f"t = {reached:.6g} s{advice}"
    )


def sample_progress(count: int, enabled: bool) -> tqdm:
    """The progress line of the ``count`` output samples' evaluation, after the integration
    (shown as :class:`Progress` is)."""
    quiet = None if enabled else True
    return tqdm(total=count, desc="samples", unit="sample", delay=PROGRESS_DELAY, disable=quiet)


class Progress:
    """The run's progress line on stderr (tqdm, as the sweep and the cycle show theirs): the
    simulated time [s] done of the run's span, the steps of at most :data:`MAX_STEPS`, and an
    estimate of the time left (to the end, or to the cap when it comes first). Shown only on a
    terminal, and only once the run has lasted :data:`PROGRESS_DELAY`::

        simulate:  17%|███▍                | 0.06099 of 0.4 s, 2429 of at most 200000 steps,
        ~00:19 left

    Args:
        start, end: The run's first and last times [s].
        enabled: False: no line at all.
    """

    def __init__(self, start: float, end: float, enabled: bool):
        self.start, self.span = start, end - start
        quiet = None if enabled else True  # None: tqdm shows the bar only on a terminal
        self.bar = tqdm(
            total=self.span,
            desc="simulate",
            delay=PROGRESS_DELAY,
            disable=quiet,
            bar_format="{desc}: {percentage:3.0f}%|{bar:20}| {n:.4g} of {total:.4g} s{postfix}",
        )
        self.began = self.shown = time.monotonic()

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc) -> None:
        self.bar.close()

    def update(self, t: float, steps: int) -> None:
        """The run has reached time ``t`` [s] in ``steps`` accepted steps."""
        if self.bar.disable:
            return
        now = time.monotonic()
        if now - self.shown >= PROGRESS_INTERVAL:
            self.shown = now
            self.bar.set_postfix_str(self._text(t, steps, now - self.began), refresh=False)
        self.bar.update(t - self.start - self.bar.n)

    def _text(self, t: float, steps: int, elapsed: float) -> str:
        """The line's end after the simulated time: the steps and the time left [s] (to the end
        of the run or to the step cap, whichever the pace so far reaches first)."""
        share = (t - self.start) / self.span
        capped = steps / MAX_STEPS > share
        share = max(share, steps / MAX_STEPS)
        left = tqdm.format_interval(elapsed * (1.0 - share) / share) if share > 0.0 else "?"
        ending = " (the step cap comes first)" if capped else ""
        return f"{steps} of at most {MAX_STEPS} steps, ~{left} left{ending}"
