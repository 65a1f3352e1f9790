"""The figures (feeder.viz): units an engineer reads, one unit per axis, one elevation format,
magnitudes over components, a side view whose nose is where the payload axis points, and the
figures drawn in worker processes the same as here."""

from __future__ import annotations

import math
import subprocess
import sys
import threading
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from feeder.exceptions import InputError
from feeder.motion.laws import CycleSpec
from feeder.study.cycle_study import run_cycle_study
from feeder.study.elevation_sweeps import elevation_sweep
from feeder.viz.catalog import CYCLE_FIGURES, UNITS, display_unit, elevation_text
from feeder.viz.comparisons import SWEEP_PANELS, sweep_figure
from feeder.viz.png import png_bytes
from feeder.viz.report import (
    KINEMATICS_FIGURES,
    TIME_HISTORIES,
    FigureData,
    FigureWorkers,
    draw,
    study_figure_names,
)

ELEVATION = math.radians(-4.0)
SPEC = CycleSpec(rate=500.0)
"""500 Hz: the forward run still tracks (a full study), and the figures stay quick."""

NOSE_ANGLE_DEG = 0.01
"""[deg] The drawn axis against the documented one: both exact up to round-off in mm."""

SCALED_LABEL = ("× 1e", "[m]", "[N]", "[Pa]", "[rad]")
"""What no axis label may show: a scale factor, or an SI unit that has an engineer's unit."""


@pytest.fixture(scope="module")
def data(feeder):
    return FigureData.of_study(run_cycle_study(feeder, ELEVATION, SPEC))


@pytest.fixture(scope="module")
def figures(data):
    return {name: draw(name, data) for name in study_figure_names()}


def write_figures(
    data: FigureData,
    names: Sequence[str],
    directory: str | Path,
    workers: int | None = None,
) -> list[Path]:
    """Draw ``names`` of a cycle and write them into ``directory`` (which must exist), each
    under its file name (:meth:`FigureData.file_name`)."""
    directory = Path(directory)
    with FigureWorkers(workers) as pool:
        return [writer(directory / name) for name, writer in pool.writers(data, names).items()]


def test_engineering_units():
    assert display_unit("m") == (1e3, "mm")
    assert display_unit("N") == (1e-3, "kN")
    assert display_unit("Pa") == (1e-5, "bar")
    assert display_unit("rad") == pytest.approx((180.0 / math.pi, "deg"))
    assert display_unit("N·m") == (1.0, "N·m")


def test_every_axis_label_names_an_engineers_unit(figures):
    for name, fig in figures.items():
        for ax in fig.axes:
            label = ax.get_ylabel() + " " + ax.get_xlabel()
            assert not any(bad in label for bad in SCALED_LABEL), (name, label)


def test_forces_are_drawn_in_kilonewtons(data, figures):
    """The curve on the piston-force figure is the column divided by 1000."""
    (line,) = figures["fig14_piston_force.png"].axes[0].get_lines()[:1]
    np.testing.assert_array_equal(line.get_ydata(), data.columns["piston_force"] * 1e-3)
    assert figures["fig14_piston_force.png"].axes[0].get_ylabel() == "piston force [kN]"


def test_one_unit_per_time_history():
    for spec in CYCLE_FIGURES:
        units = {UNITS[column] for _, column in spec.curves}
        assert len(units) == 1, spec.file


def test_newtons_and_newton_metres_never_share_a_sweep_axis(feeder):
    sweep = elevation_sweep(feeder, np.radians([0.0]), CycleSpec(rate=100.0), progress=False)
    with pytest.raises(InputError, match="mixes units"):
        sweep_figure({"x": sweep}, [("bad", ["piston_force", "forearm_torque"])])
    for title, names in SWEEP_PANELS:
        assert len({UNITS[name] for name in names}) == 1, title
    assert len(sweep_figure({"x": sweep}).axes) == len(SWEEP_PANELS)


def test_a_sweep_without_a_panels_quantity_is_refused_by_name(feeder):
    """Once a KeyError from deep in the drawing."""
    sweep = elevation_sweep(feeder, np.radians([0.0]), CycleSpec(rate=100.0), progress=False)
    del sweep.peaks["grip_force"]
    with pytest.raises(InputError, match=r"sweep 'x' has no peaks of \['grip_force'\]"):
        sweep_figure({"x": sweep})


@pytest.mark.parametrize(
    "degrees, text", [(-4.0, "ε = −4°"), (30.5, "ε = 30.5°"), (-0.001, "ε = 0°"), (70, "ε = 70°")]
)
def test_one_elevation_format(degrees, text):
    assert elevation_text(math.radians(degrees)) == text


def test_every_title_writes_the_elevation_one_way(figures):
    expected = elevation_text(ELEVATION)
    for name, fig in figures.items():
        titles = " ".join(ax.get_title() for ax in fig.axes)
        if "ε" in titles:
            assert expected in titles, name
            assert "ε = -" not in titles, name


def test_magnitude_is_drawn_over_its_components(figures):
    for spec in CYCLE_FIGURES:
        if spec.magnitude is None:
            continue
        lines = {line.get_label(): line for line in figures[spec.file].axes[0].get_lines()}
        top = lines[spec.magnitude]
        for label, line in lines.items():
            if label in ("x", "y", "z"):
                assert top.get_zorder() > line.get_zorder(), spec.file
                assert top.get_linewidth() > line.get_linewidth(), spec.file


def test_side_view_nose_is_where_the_payload_axis_points(figures):
    """REFERENCE.md: the payload's nose is up at loading and along the barrel, towards the
    muzzle (−x), at ramming. The drawn outline's pointed vertex (the third of base, shoulder,
    nose, shoulder, base) must lie that way from the middle of its base."""
    ax = figures["device_side_view.png"].axes[0]
    outlines = [line for line in ax.get_lines() if len(line.get_xdata()) == 6]
    assert "nose at the pointed end" in outlines[0].get_label()
    barrel = np.array([-math.cos(ELEVATION), math.sin(ELEVATION)])
    for outline, expected in ((outlines[0], np.array([0.0, 1.0])), (outlines[-1], barrel)):
        points = outline.get_xydata()
        direction = points[2] - points[[0, 4]].mean(axis=0)
        cosine = direction @ expected / np.linalg.norm(direction)
        assert cosine > math.cos(math.radians(NOSE_ANGLE_DEG))


def test_kinematics_data_draw_only_kinematic_figures(feeder):
    from feeder.motion.cycle import feeding_cycle

    data = FigureData.of_cycle(feeder, feeding_cycle(feeder, 0.2, CycleSpec(rate=100.0)))
    for name in KINEMATICS_FIGURES:
        assert draw(name, data).axes
    with pytest.raises(InputError, match="needs the column"):
        draw("fig14_piston_force.png", data)
    with pytest.raises(InputError, match="no figure named"):
        draw("fig99.png", data)


def test_workers_write_what_this_process_draws(data, tmp_path):
    """The files written by worker processes are byte for byte the ones drawn here."""
    names = ["fig14_piston_force.png", "device_side_view.png", "lagrange_cross_check.png"]
    here = write_figures(data, names, _folder(tmp_path / "here"), workers=1)
    with FigureWorkers(2) as pool:
        forked = pool._pool is not None
        writers = pool.writers(data, names)
        there = [writers[name](_folder(tmp_path / "there") / name) for name in names]
    if threading.active_count() == 1:
        assert forked  # a single-threaded process draws in forked workers
    for a, b in zip(here, there, strict=True):
        assert a.name == b.name and a.read_bytes() == b.read_bytes(), a.name
        assert a.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_time_history_drawn_on_anothers_figure_is_a_new_ones_byte_for_byte(data):
    """Each time history drawn on the one before's figure (as the workers draw them, their axes
    and ticks kept) gives the PNG of a new figure: after curves, after a note (a figure whose
    curves are all zero) and before one."""
    speed = "fig08_{payload}_speed.png"
    zero = replace(data, columns=data.columns | {"projectile_speed": 0.0 * data.columns["t"]})
    names = sorted(TIME_HISTORIES) + [speed, "fig14_piston_force.png"]
    datas = [data] * len(TIME_HISTORIES) + [zero, data]
    fresh = [png_bytes(draw(name, d)) for name, d in zip(names, datas, strict=True)]
    fig, reused, shown = None, [], []
    for name, d in zip(names, datas, strict=True):
        fig = draw(name, d, fig)
        reused.append(png_bytes(fig))
        shown.append(fig.axes[0].axison)
    assert shown == [True] * len(TIME_HISTORIES) + [False, True]  # the zero speed: a note
    for name, a, b in zip(names, fresh, reused, strict=True):
        assert a == b, name


FORKED = """
import sys
from feeder.device.feeder import load_feeder
from feeder.exceptions import InputError
from feeder.motion.cycle import feeding_cycle
from feeder.motion.laws import CycleSpec
from feeder.viz.report import FigureData, FigureWorkers
feeder = load_feeder()
data = FigureData.of_cycle(feeder, feeding_cycle(feeder, 0.5, CycleSpec(rate=100.0)))
with FigureWorkers(2) as pool:
    assert pool._pool is not None  # forked: this interpreter runs one thread
    writers = pool.writers(data, ["fig10_{payload}_position.png", "fig99.png"])
    png = writers["fig10_projectile_position.png"]
    try:
        png(sys.argv[1])
    except InputError as error:
        print(error)
"""


def test_an_error_in_a_forked_drawing_process_is_raised_by_its_writer(tmp_path):
    """The second share is drawn in a process forked from the figure worker (in a fresh,
    single-threaded interpreter: pytest runs threads): its error, an unknown figure, reaches the
    writers as the worker's own would, and nothing is written."""
    path = tmp_path / "fig10.png"
    done = subprocess.run(
        [sys.executable, "-c", FORKED, str(path)], capture_output=True, text=True, check=True
    )
    assert "no figure named 'fig99.png'" in done.stdout, done.stdout + done.stderr
    assert not path.exists()


SWEEP_FIGURES = """
import os, sys
from pathlib import Path
from feeder.exceptions import InputError
from feeder.motion.laws import CycleSpec
from feeder.study.grid import make_grid
from feeder.study.sweep_folder import run_sweep
from feeder.viz.report import SweepFigures, sweep_pngs
folder = Path(sys.argv[1])
with SweepFigures() as drawing:
    unasked = drawing._child.pid  # forked: this interpreter runs one thread
try:
    os.waitpid(unasked, os.WNOHANG)
except ChildProcessError:
    print("ended")
(folder / "bad.csv").write_text("not,a,sweep,table")
with SweepFigures() as drawing:
    try:
        drawing.pngs(folder / "bad.csv")
    except InputError as error:
        print("refused:", error)
grid = make_grid(("projectile",), (20.0, 40.0), spec=CycleSpec(rate=100.0))
with SweepFigures() as drawing:
    assert drawing._child is not None
    table = run_sweep(grid, folder / "sweep", progress=False, workers=1).table
    there = drawing.pngs(table)
print("same" if there == sweep_pngs(table) and there else "different")
"""


def test_a_sweeps_figures_are_drawn_in_a_process_forked_before_its_cases(tmp_path):
    """SweepFigures forks before the sweep's pool (in a fresh, single-threaded interpreter:
    pytest runs threads): its PNGs are the ones drawn here, byte for byte; a table it cannot
    read is refused by its error, raised here; a process never asked ends with the context."""
    argv = [sys.executable, "-c", SWEEP_FIGURES, str(tmp_path)]
    done = subprocess.run(argv, capture_output=True, text=True, check=True)
    lines = done.stdout.splitlines()
    assert lines[0] == "ended" and lines[1].startswith("refused:") and lines[2] == "same", lines


def test_figure_workers_count_is_checked():
    with pytest.raises(InputError, match="figure workers"):
        FigureWorkers(0)


def _folder(path):
    path.mkdir(parents=True, exist_ok=True)
    return path


def test_cycles_on_different_time_grids_each_keep_their_own(feeder):
    """Two studies sampled at 250 and 500 Hz on one figure: each curve is drawn against its own
    study's times (the two were once subtracted sample by sample, a broadcasting error)."""
    from feeder.viz.comparisons import cycles_figure

    fine = run_cycle_study(feeder, ELEVATION, SPEC, forward=False)
    coarse = run_cycle_study(feeder, ELEVATION, CycleSpec(rate=250.0), forward=False)
    fig = cycles_figure({"500 Hz": fine, "250 Hz": coarse}, [("piston_force", "Piston force")])
    lines = {
        line.get_label(): line for line in fig.axes[0].get_lines() if line.get_label()[0] != "_"
    }
    assert {label: len(line.get_xdata()) for label, line in lines.items()} == {
        "500 Hz": fine.columns()["t"].size,
        "250 Hz": coarse.columns()["t"].size,
    }


def test_cycle_figures_are_named_for_the_payload(charge_feeder):
    from feeder.viz.figures import cycle_figures

    study = run_cycle_study(charge_feeder, ELEVATION, CycleSpec(rate=100.0), forward=False)
    names = cycle_figures(study)
    assert "fig08_charge_speed.png" in names
    assert not [name for name in names if "{" in name or "projectile" in name]
