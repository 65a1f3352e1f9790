"""``feeder design sensitivities MODEL --design FILE``: every peak's derivative against central
differences of full runs of models written independently (the lever of lever.py with its
numbers changed, not the URDF editor's output)."""

from __future__ import annotations

import numpy as np
import pytest

from feeder.design.differences import STEP_FACTOR
from feeder.design.mechanism.inputs import check_inputs
from feeder.design.mechanism.outputs import run_mechanism_sensitivities
from feeder.design.mechanism.sensitivities import mechanism_sensitivities
from feeder.study.analyze import analyze

from .lever import Lever

DESIGN = """\
[variables]
cylinder_pivot.x = {lower = 0.9, upper = 1.6}   # a: the ground pivot
body_pin.x = {lower = 0.6, upper = 1.0}         # b: the lever pin
body.mass = {lower = 300.0, upper = 700.0}      # m: the lever's mass (I_c scaled with it)

[objective]
peak = "tau_cylinder_slide"
"""

RELATIVE = 1e-4
"""The independent differences' relative step: truncation ~ (1e-4)² = 1e-8 of peak/p, and the
peaks' round-off (1e-12 of the peak, :data:`feeder.design.differences.NOISE`) over the step
1e-8 too."""

TOLERANCE = 1e-6
"""Agreement asked of the two derivatives, relative to peak/p: a hundred times the independent
differences' error above; the module's own estimate is ~1e-10 (ε^(2/3))."""


def _lever(name: str, value: float) -> Lever:
    base = Lever()
    if name == "cylinder_pivot.x":
        return Lever(a=value)
    if name == "body_pin.x":
        return Lever(b=value)
    return Lever(m=value, inertia=base.inertia * value / base.m)


def _peaks(lever: Lever, folder) -> dict[str, float]:
    """Every peak of the run of ``lever``: the loads.csv columns' largest |value|, a closure's
    force and moment as the magnitude of its x, y, z columns."""
    folder.mkdir()
    _, closures, motion, _ = lever.write(folder, DESIGN)
    columns = analyze(closures, motion).columns()
    peaks = {name: float(np.abs(values).max()) for name, values in columns.items()}
    for what in ("force", "moment"):
        parts = [columns[f"rod_body_pin_{what}_{axis}"] for axis in "xyz"]
        peaks[f"rod_body_pin_{what}"] = float(np.linalg.norm(parts, axis=0).max())
    return peaks


def test_every_derivative_agrees_with_central_differences_of_full_runs(tmp_path):
    lever = Lever()
    model, closures, motion, design = lever.write(tmp_path, DESIGN)
    inputs = check_inputs(model, closures, design, [motion])
    result = mechanism_sensitivities(inputs.design, inputs.mechanism, STEP_FACTOR, workers=1,
                                     progress=False)  # fmt: skip
    (scope,) = result.scopes
    values = {"cylinder_pivot.x": lever.a, "body_pin.x": lever.b, "body.mass": lever.m}
    assert {p.name for p in scope.peaks} >= {"tau_cylinder_slide", "body_hinge_force",
                                             "rod_body_pin_force", "velocity_gain"}  # fmt: skip
    for name, p in values.items():
        h = RELATIVE * p
        up = _peaks(_lever(name, p + h), tmp_path / f"{name}+")
        down = _peaks(_lever(name, p - h), tmp_path / f"{name}-")
        for peak in scope.peaks:
            entry = scope.entries[(peak.name, name)]
            assert entry.status == "ok", (peak.name, name)
            expected = (up[peak.name] - down[peak.name]) / (2.0 * h)
            scale = abs(peak.value) / p
            assert entry.derivative == pytest.approx(expected, abs=TOLERANCE * scale), (
                peak.name,
                name,
            )


def test_the_output_folder_holds_the_tables_and_the_summary(tmp_path):
    model, closures, motion, design = Lever().write(tmp_path, DESIGN)
    result, paths = run_mechanism_sensitivities(
        model, closures, design, [motion], tmp_path / "out", workers=1, progress=False,
        figure=False,
    )  # fmt: skip
    names = [path.name for path in paths]
    assert names == ["sensitivities.csv", "sensitivity_details.csv", "summary.txt"]
    header = (tmp_path / "out" / "sensitivities.csv").read_text().splitlines()[0].split(",")
    assert header[:5] == ["peak", "unit", "value", "motion", "time_s"]
    assert "d_cylinder_pivot.x" in header and "elasticity_body.mass" in header
