"""Figures that say what they show (issue 17): every labelled axis has tick labels, no axis has
offset text, no drawn axis holds only zeros or round-off, log axes label at least two decades,
equal curves are drawn once and named together, legends are words; asserted on the figure
objects drawn with Agg, for the mechanism figures (four-bar, slider-crank, a trammel whose
reaction moments are all round-off, a forward run), the device's figures, the sweep, and the
charge feeder's file names."""

from __future__ import annotations

import math
import struct
import warnings

import numpy as np
import pytest
from matplotlib.axis import Axis
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from feeder.motion.cycle import feeding_cycle
from feeder.motion.laws import CycleSpec
from feeder.study.analyze import analyze
from feeder.study.cycle_study import run_cycle_study
from feeder.study.elevation_sweeps import elevation_sweep
from feeder.study.simulate import simulate_mechanism
from feeder.viz.analysis import stacked_figure
from feeder.viz.axes import ROUND_OFF, DecadeTicks, FullTicks, InView
from feeder.viz.comparisons import cross_check, cycles_figure, sweep_figure
from feeder.viz.panels import Panel, Stack, analysis_stacks, simulation_stacks
from feeder.viz.png import FIGURE_DPI, png_bytes
from feeder.viz.report import (
    FigureData,
    FigureWorkers,
    draw,
    kinematics_figures,
    study_figure_names,
)

from ..conftest import REPO

ROUND_OFF_CURVE = 1e-12
"""A drawn curve whose largest |value| is above zero but below this fraction of its axis's
largest is round-off drawn as data: five times the figures' own round-off level (ROUND_OFF,
2.2e-13), and eight decades below the smallest real curve here (a payload speed of mm/s)."""

TRAMMEL_URDF = """<?xml version="1.0"?>
<robot name="trammel">
  <link name="ground"/>
  {slider_a}{rod}{slider_b}
  <link name="rod_tip"/>
  <link name="slider_b_pin"/>
  <joint name="slider_a_joint" type="prismatic">
    <parent link="ground"/><child link="slider_a"/><axis xyz="1 0 0"/>
    <limit lower="-1" upper="1" effort="1000" velocity="100"/>
  </joint>
  <joint name="rod_joint" type="revolute">
    <parent link="slider_a"/><child link="rod"/><axis xyz="0 0 1"/>
    <limit lower="-7" upper="7" effort="1000" velocity="100"/>
  </joint>
  <joint name="rod_tip_joint" type="fixed">
    <origin xyz="0 0.2 0"/><parent link="rod"/><child link="rod_tip"/>
  </joint>
  <joint name="slider_b_joint" type="prismatic">
    <origin xyz="0 0.2 0"/><parent link="ground"/><child link="slider_b"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1000" velocity="100"/>
  </joint>
  <joint name="slider_b_pin_joint" type="fixed">
    <parent link="slider_b"/><child link="slider_b_pin"/>
  </joint>
</robot>
"""
"""A trammel (elliptic trammel): slider a driven along x, a 0.2 m rod pinned to it, its tip
pinned to slider b on y (the cut). The sliders' centres of gravity are at their pins and the
loads lie in the plane, so every reaction moment is zero in exact arithmetic."""

TRAMMEL_SIDE_FILE = """[mechanism]
urdf = "trammel.urdf"
actuated = ["slider_a_joint"]
independent = ["slider_a_joint"]
gravity = [0.0, -9.81, 0.0]

[[closure]]
frames = ["rod_tip", "slider_b_pin"]
type = "revolute"
axis = [0.0, 0.0, 1.0]
"""


def _link(name: str, mass: float, centre: str = "0 0 0") -> str:
    inertia = 'ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"'
    return (
        f'<link name="{name}"><inertial><origin xyz="{centre}"/><mass value="{mass}"/>'
        f"<inertia {inertia}/></inertial></link>\n"
    )


@pytest.fixture(scope="module")
def trammel(tmp_path_factory):
    folder = tmp_path_factory.mktemp("trammel")
    links = {
        "slider_a": _link("slider_a", 0.5),
        "rod": _link("rod", 0.3, "0 0.1 0"),
        "slider_b": _link("slider_b", 0.5),
    }
    (folder / "trammel.urdf").write_text(TRAMMEL_URDF.format(**links))
    (folder / "closures.toml").write_text(TRAMMEL_SIDE_FILE)
    t = np.linspace(0.0, 1.0, 101)
    w = 2.0 * math.pi
    x, v, a = 0.1 * np.sin(w * t), 0.1 * w * np.cos(w * t), -0.1 * w**2 * np.sin(w * t)
    table = np.column_stack([t, x, v, a])
    rows = "".join(",".join(f"{value:.17g}" for value in row) + "\n" for row in table)
    header = "t,q_slider_a_joint,v_slider_a_joint,a_slider_a_joint\n"
    (folder / "motion.csv").write_text(header + rows)
    return analyze(folder / "closures.toml", folder / "motion.csv")


@pytest.fixture(scope="module", params=("four_bar", "slider_crank"))
def example(request):
    folder = REPO / "examples" / request.param
    return analyze(folder / "closures.toml", folder / "motion.csv")


@pytest.fixture(scope="module")
def released_four_bar(tmp_path_factory):
    """The four-bar released under gravity, undriven: its reaction moments are all round-off."""
    forces = tmp_path_factory.mktemp("damper") / "damper.toml"
    forces.write_text('[[force]]\ntype = "joint_spring"\njoint = "rocker_joint"\ndamping = 0.01\n')
    spec = REPO / "examples" / "four_bar" / "closures.toml"
    return simulate_mechanism(spec, 1.0, forces=forces, samples=101)


@pytest.fixture(scope="module")
def study(feeder):
    return run_cycle_study(feeder, math.radians(-4.0), CycleSpec(rate=500.0))


@pytest.fixture(scope="module")
def sweep(feeder):
    return elevation_sweep(feeder, np.radians([0.0, 20.0, 40.0]), CycleSpec(rate=100.0), False)


def drawn(fig: Figure) -> Figure:
    FigureCanvasAgg(fig)
    fig.canvas.draw()
    return fig


def labelled_ticks(axis: Axis) -> list[str]:
    """The non-empty tick labels shown within the axis's view, after drawing."""
    low, high = sorted(axis.get_view_interval())
    slack = 1e-9 * (high - low)  # a tick at a limit, written with round-off
    return [
        tick.label1.get_text()
        for tick in axis.get_major_ticks()
        if low - slack <= tick.get_loc() <= high + slack
        and tick.label1.get_visible()
        and tick.label1.get_text()
    ]


def broken_rules(fig: Figure) -> list[str]:
    """What in ``fig`` breaks the rules (empty when nothing does)."""
    problems = []
    for ax in drawn(fig).axes:
        if not (ax.get_visible() and ax.axison):
            continue
        where = ax.get_title() or ax.get_ylabel()
        for axis, label in ((ax.xaxis, ax.get_xlabel()), (ax.yaxis, ax.get_ylabel())):
            ticks = labelled_ticks(axis)
            if label and not ticks:
                problems.append(f"{where}: {label!r} has no tick labels")
            if axis.get_offset_text().get_text():
                problems.append(f"{where}: offset text {axis.get_offset_text().get_text()!r}")
            if axis.get_scale() == "log" and len(ticks) < 2:
                problems.append(f"{where}: log axis with labels {ticks}")
        curves = [line.get_ydata() for line in ax.get_lines() if len(line.get_xdata()) > 2]
        if ax.get_yscale() != "linear" or not curves:
            continue
        peaks = [float(np.abs(y).max()) for y in curves]
        if max(peaks) == 0.0:
            problems.append(f"{where}: every curve is zero")
        problems += [
            f"{where}: a curve of round-off, {peak:.1e}"
            for peak in peaks
            if 0.0 < peak <= ROUND_OFF_CURVE * max(peaks)
        ]
    return problems


def stack_figures(stacks: dict[str, Stack]) -> dict[str, Figure]:
    """Each stack of panels drawn as the figure that
    :func:`~feeder.viz.mechanism_figures.stack_pngs` saves, by file name."""
    return {name: stacked_figure(t, panels) for name, (t, panels) in stacks.items()}


def notes(fig: Figure) -> str:
    return " | ".join(text.get_text() for ax in fig.axes for text in ax.texts)


def test_the_round_off_threshold():
    assert ROUND_OFF < ROUND_OFF_CURVE


def test_mechanism_figures_follow_the_rules(example):
    for name, fig in stack_figures(analysis_stacks(example)).items():
        assert broken_rules(fig) == [], name


def test_round_off_moments_are_drawn_as_one_zero_curve(example):
    """The four-bar's coupler and rocker joints carry moments of 2e-16 N·m, the slider-crank's
    rod 2e-16 and its slider 0: one zero curve naming both, below the crank's."""
    ax = stack_figures(analysis_stacks(example))["joint_reactions.png"].axes[1]
    lines = {line.get_label(): line for line in ax.get_lines()}
    assert list(lines)[0] == "crank_joint"
    (zero,) = [label for label in lines if label != "crank_joint"]
    assert " = " in zero and zero.split(" = ")[-1].startswith("0")
    assert not lines[zero].get_ydata().any()


def test_overlapping_curves_differ_in_line_style(example):
    ax = stack_figures(analysis_stacks(example))["joint_reactions.png"].axes[0]
    styles = [line.get_linestyle() for line in ax.get_lines()]
    assert len(styles) == 3 and len(set(styles)) == 3


def test_a_trammel_leaves_its_round_off_moments_out(trammel):
    figures = stack_figures(analysis_stacks(trammel))
    for name, fig in figures.items():
        assert broken_rules(fig) == [], name
    for name, what in (("joint_reactions.png", "round-off"), ("closure_forces.png", "exactly")):
        fig = figures[name]
        shown = [ax for ax in fig.axes if ax.axison]
        assert [ax.get_ylabel() for ax in shown] == ["|force| [N]"], name
        assert shown[0].get_xlabel() == "time t [s]"
        assert "moments" in notes(fig) and what in notes(fig), name


def test_the_velocity_gain_axis_shows_decades(example):
    """Whole decades, at least two: labels at powers of ten only (no "2×10⁰")."""
    ax = drawn(stack_figures(analysis_stacks(example))["actuator_loads.png"]).axes[1]
    low, high = np.log10(ax.get_ylim())
    assert high - low >= 2 and low == round(low) and high == round(high)
    assert len(labelled_ticks(ax.yaxis)) == high - low + 1
    assert not [label.get_text() for label in ax.yaxis.get_minorticklabels() if label.get_text()]


def test_only_the_lowest_panel_writes_the_time(example):
    fig = stack_figures(analysis_stacks(example))["actuator_loads.png"]
    assert [ax.get_xlabel() for ax in fig.axes] == ["", "time t [s]"]


def test_many_curves_keep_their_legends_inside_the_figure_beside_their_panels():
    """A mechanism with dozens of joints (battobot's 30 reactions, 18 joint rates): each panel's
    legend, its round-off group's long label wrapped, lies inside the figure, clear of every
    panel and of the other legend, and the layout needs no warning (tight_layout gave "Tight
    layout not applied" and legends that covered the panels and left the figure)."""
    t = np.linspace(0.0, 1.0, 11)
    many = tuple((f"joint_{k:02d}_of_a_long_leg", (k + 1.0) * (1.0 + t)) for k in range(30))
    zeros = tuple((f"spherical_joint_{k}", 1e-20 * t) for k in range(8))  # one round-off curve
    panels = [
        Panel("Forces", "|force| [N]", "N", many),
        Panel("Moments", "|moment| [N·m]", "N·m", many[:17] + zeros, scale=100.0),
    ]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fig = drawn(stacked_figure(t, panels))
    axes = [ax.get_window_extent() for ax in fig.axes]
    legends = [ax.get_legend().get_window_extent() for ax in fig.axes]
    assert [len(ax.get_legend().get_texts()) for ax in fig.axes] == [30, 18]
    for k, legend in enumerate(legends):
        assert fig.bbox.containsx(legend.x0) and fig.bbox.containsx(legend.x1), k
        assert fig.bbox.containsy(legend.y0) and fig.bbox.containsy(legend.y1), k
        assert not any(legend.overlaps(box) for box in axes), k
    assert not legends[0].overlaps(legends[1])
    assert broken_rules(fig) == []


def test_forward_run_figures_follow_the_rules(released_four_bar):
    figures = stack_figures(simulation_stacks(released_four_bar))
    for name, fig in figures.items():
        assert broken_rules(fig) == [], name
    assert "round-off" in notes(figures["joint_reactions.png"])  # nothing drives the crank


def test_device_figures_follow_the_rules(study):
    data = FigureData.of_study(study)
    for name in study_figure_names():
        assert broken_rules(draw(name, data)) == [], name


def test_the_cross_check_draws_pinocchio_and_the_corrected_equations_once(study):
    """They agree to round-off (1e-15 of the peak): one curve named for both, and a note where
    their difference would be plotted."""
    fig = draw("lagrange_cross_check.png", FigureData.of_study(study))
    legends = [text.get_text() for text in fig.axes[0].get_legend().get_texts()]
    assert legends == ["Pinocchio = Lagrange, corrected", "Lagrange, as printed"]
    assert notes(fig).count("zero at every sample (round-off") == 2


def test_a_real_difference_is_drawn_on_decades(study):
    """Corrected equations off by 1 N somewhere: the difference panel is drawn, on a log axis
    that follows the rules, its round-off floor named in the legend."""
    columns = dict(study.columns())
    columns["lagrange_piston_force"] = columns["lagrange_piston_force"] + np.where(
        columns["t"] > 3.0, 1.0, 0.0
    )
    k = study.dynamics.kinematics
    fig = cross_check(study.feeder.params, columns, k.spec.boundaries)
    assert broken_rules(fig) == []
    bottom = fig.axes[2]
    assert bottom.axison and bottom.get_yscale() == "log"
    assert "round-off below" in bottom.get_legend().get_texts()[0].get_text()


def test_equal_cycles_share_a_curve(study):
    fig = cycles_figure({"A": study, "B": study}, [("piston_force", "Piston force")])
    assert broken_rules(fig) == []
    assert [line.get_label() for line in fig.axes[0].get_lines()][:1] == ["A = B"]
    assert fig.axes[0].get_ylabel() == "piston force [kN]"


def test_sweep_legends_are_words_with_units(sweep):
    fig = sweep_figure({"reference": sweep, "again": sweep})
    assert broken_rules(fig) == []
    texts = [t.get_text() for legend in fig.legends for t in legend.get_texts()]
    for ax in fig.axes:
        if ax.get_legend() is not None:
            texts += [t.get_text() for t in ax.get_legend().get_texts()]
    assert "piston force [kN]" in texts and "cap-side pressure [bar]" in texts
    assert not [text for text in texts if "_" in text]


def test_the_charge_feeders_figures_are_named_for_the_charge(feeder, charge_feeder):
    cycle = feeding_cycle(charge_feeder, 0.2, CycleSpec(rate=100.0))
    assert "fig10_charge_position.png" in kinematics_figures(charge_feeder, cycle)
    charge = FigureData.of_cycle(charge_feeder, cycle)
    names = list(FigureWorkers(1).writers(charge, study_figure_names()))
    assert "fig08_charge_speed.png" in names and not [n for n in names if "projectile" in n]
    assert "payload" not in " ".join(names)
    projectile = FigureData.of_cycle(feeder, feeding_cycle(feeder, 0.2, CycleSpec(rate=100.0)))
    names = list(FigureWorkers(1).writers(projectile, study_figure_names()))
    assert {"fig08_projectile_speed.png", "fig10_projectile_position.png"} <= set(names)
    # a figure drawn by its file name is the one drawn by its catalogue name
    assert (
        draw("fig10_charge_position.png", charge).axes[0].get_title()
        == draw("fig10_{payload}_position.png", charge).axes[0].get_title()
    )


def test_figures_are_written_at_150_dpi_or_more():
    fig = Figure(figsize=(8.0, 4.0))
    fig.subplots().plot([0.0, 1.0])
    width, height = struct.unpack(">II", png_bytes(fig)[16:24])  # the PNG header's IHDR
    assert FIGURE_DPI >= 150 and (width, height) == (8 * FIGURE_DPI, 4 * FIGURE_DPI)


@pytest.mark.parametrize(
    "ticks, labels",
    [
        ([0.0, 0.5, 1.0], ["0", "0.5", "1.0"]),
        ([-2e-10, 0.0, 1e-10], ["−2×10⁻¹⁰", "0", "1×10⁻¹⁰"]),
        ([1000.0, 1000.5, 1001.0], ["1000.0", "1000.5", "1001.0"]),
        ([0.0, 2e5, 4e5], ["0", "2×10⁵", "4×10⁵"]),
    ],
)
def test_tick_labels_carry_their_whole_value(ticks, labels):
    assert FullTicks().format_ticks(ticks) == labels


@pytest.mark.parametrize(
    "ticks, labels",
    [([1e-12, 1.0, 100.0], ["10⁻¹²", "10⁰", "10²"]), ([0.002, 30.0], ["0.002", "30"])],
)
def test_log_axis_labels_are_powers_of_ten_in_plain_text(ticks, labels):
    """Decades as 10ⁿ (the ×10ⁿ of FullTicks, without matplotlib's math text); anything else as
    FullTicks writes it."""
    assert [DecadeTicks()(tick) for tick in ticks] == labels


def test_a_log_axis_makes_its_minor_ticks_within_its_view_only_and_draws_the_same():
    """The minor ticks of a log axis come from its minor locator filtered to the view
    (:class:`InView`): fewer tick objects than matplotlib's own locator gives, the same PNG."""
    t = np.linspace(0.0, 2.0, 201)
    panels = [Panel("Gain", "gain [–]", "", (("gain", 1.0 + 10.0 * t),), log=True)]  # 2 decades
    ours = stacked_figure(t, panels)
    plain = stacked_figure(t, panels)
    (axis,) = [ax.yaxis for ax in plain.axes]
    assert isinstance(axis.get_minor_locator(), InView)
    axis.set_minor_locator(axis.get_minor_locator().locator)  # matplotlib's LogLocator alone
    assert png_bytes(ours) == png_bytes(plain)
    low, high = ours.axes[0].get_ylim()
    inside = [x for x in axis.get_minorticklocs() if low <= x <= high]
    assert len(ours.axes[0].yaxis.get_minorticklocs()) == len(inside) == 16  # 2…9, 20…90
    assert len(ours.axes[0].yaxis.minorTicks) == 16 < len(axis.minorTicks)


def _panel_texts(ax) -> list:
    """The shown texts of a drawn panel: its title, notes, axis labels and the tick labels
    within its view (as :func:`labelled_ticks`)."""
    texts = [ax.title, *ax.texts]
    if ax.axison:
        texts += [ax.xaxis.label, ax.yaxis.label]
        for axis in (ax.xaxis, ax.yaxis):
            low, high = sorted(axis.get_view_interval())
            slack = 1e-9 * (high - low)
            texts += [
                t.label1
                for t in axis.get_major_ticks()
                if low - slack <= t.get_loc() <= high + slack
            ]
    return [text for text in texts if text.get_visible() and text.get_text()]


def test_stacked_panels_are_laid_out_clear_of_each_other():
    """The layout measured once (no layout engine: savefig draws the figure once): with wide
    tick labels (×10⁻⁷, −12000), long legend entries, a note between drawn panels and a note
    last (the time axis then under the panel above it), every text and legend lies inside the
    figure, no panel overlaps another, and no text of a panel reaches into another panel, its
    texts or a legend."""
    t = np.linspace(0.0, 2.0, 201)
    long = "a force of a joint with a long name, " * 2
    panels = [
        Panel("Forces", "|force| [N]", "N", ((long, 3e-7 + 1e-7 * np.sin(t)), ("B", 2e-7 * t))),
        Panel("Idle", "force [N]", "N", (("slider", 1e-20 * t),), scale=1.0),  # a note
        Panel("Moment", "moment [N·m]", "N·m", (("motor", -12345.0 * np.cos(3.0 * t)),)),
        Panel("Gain", "gain [–]", "", (("gain", 1.0 + 1e6 * t),), log=True),
        Panel("Idle too", "force [N]", "N", (("slider", 1e-20 * t),), scale=1.0),
    ]
    fig = stacked_figure(t, panels)
    assert fig.get_layout_engine() is None
    renderer = drawn(fig).canvas.get_renderer()
    boxes = [ax.get_window_extent(renderer) for ax in fig.axes]
    legends = [ax.get_legend() for ax in fig.axes]
    legend_boxes = [None if g is None else g.get_window_extent(renderer) for g in legends]
    texts = [[text.get_window_extent(renderer) for text in _panel_texts(ax)] for ax in fig.axes]
    for k in range(len(fig.axes)):
        later = [box for panel in texts[k + 1 :] for box in panel]
        assert not any(box.overlaps(other) for box in texts[k] for other in later), k
        for box in texts[k] + [b for b in legend_boxes[k : k + 1] if b is not None]:
            assert fig.bbox.containsx(box.x0) and fig.bbox.containsx(box.x1), k
            assert fig.bbox.containsy(box.y0) and fig.bbox.containsy(box.y1), k
        others = [b for m, b in enumerate(boxes) if m != k]
        others += [b for m, b in enumerate(legend_boxes) if m != k and b is not None]
        assert not any(box.overlaps(other) for box in texts[k] for other in others), k
        assert not any(boxes[k].overlaps(other) for other in boxes[k + 1 :]), k
    assert [ax.get_xlabel() for ax in fig.axes] == ["", "", "", "time t [s]", ""]
