"""The one scene builder and the one page writer, as any client gets them: an overlay (the
device's barrel axis is one) drawn and framed with a user's mechanism, a link held while it
waits (the device's payload is one) on a user's mechanism, and one page writer whose pages
replace each other, the device's and a mechanism's alike."""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path

import numpy as np
import pytest

from feeder.exceptions import InputError
from feeder.motion import feeding_cycle
from feeder.study.analyze import analyze
from feeder.study.view import analysis_view, pose_view
from feeder.viz.device_scene import device_scene
from feeder.viz.model_scene import model_scene
from feeder.viz.nodes import BASE
from feeder.viz.overlays import Rod
from feeder.viz.viewer import PAGE_MARKER, scene_html, write_html
from tests.viz.test_viewer import decode_commands, legend_colours, tracks

FOUR_BAR = Path(__file__).resolve().parents[2] / "examples" / "four_bar"
POSITION_ROUND_OFF = 1e-12
"""[m] A transform sent as float64 from sums of a few ~1 m terms."""


def _grid_step(page: str) -> float:
    """The floor grid's square [m] the page's legend states."""
    return float(re.search(r"floor grid, ([0-9.e-]+) m squares", page).group(1))


def test_an_overlay_is_drawn_and_framed_with_any_mechanism():
    """A rod given to the four-bar's scene (4 m long, far beyond its 0.2 m links) is drawn
    between its ends under the base's node, named in the legend in its colour, and framed: the
    floor grid grows to the rod's size."""
    scene = model_scene(pose_view(FOUR_BAR / "closures.toml"))
    ends = np.array([[-2.0, 0.5, 0.0], [2.0, 0.5, 0.0]])
    rod = Rod("guide", ends, 0.01, 0x123456, "a guide rail")
    page = scene_html(dataclasses.replace(scene, overlays=(*scene.overlays, rod)))
    (placed,) = [
        c
        for c in decode_commands(page)
        if c["type"] == "set_transform" and c["path"] == f"/meshcat/{BASE}/guide"
    ]
    matrix = np.array(placed["matrix"]).reshape(4, 4).T  # three.js: column-major
    np.testing.assert_allclose(matrix[:3, 3], ends.mean(axis=0), atol=POSITION_ROUND_OFF)
    np.testing.assert_allclose(matrix[:3, 1], [1.0, 0.0, 0.0], atol=POSITION_ROUND_OFF)
    assert legend_colours(page)["#123456"] == "a guide rail"
    assert _grid_step(page) > 10.0 * _grid_step(scene_html(scene))


def test_a_waiting_link_is_held_on_any_mechanism():
    """The four-bar's rocker told to wait over the first half of its motion: its visuals stay
    where they are at the first sample after, then follow the rocker; the crank moves on."""
    analysis = analyze(FOUR_BAR / "closures.toml", FOUR_BAR / "motion.csv")
    scene = model_scene(analysis_view(analysis))
    waiting = analysis.motion.t < 0.5
    animated = tracks(
        decode_commands(scene_html(dataclasses.replace(scene, waiting={"rocker": waiting})))
    )
    first = int(np.argmin(waiting))  # the first sample after the wait
    for link, held in (("rocker", True), ("crank", False)):
        (path,) = [p for p in animated if re.search(f"/mechanism/visuals/{link}_", p)]
        values = np.array([key["value"] for key in animated[path]["position"]])
        assert len(values) == waiting.size  # a key frame per sample (101 samples, 121 frames)
        spread = np.abs(values[:first] - values[first]).max()
        assert bool(spread == 0.0) == held, (link, spread)
        assert np.abs(values[first:] - values[first]).max() > 1e-3  # then it moves


def test_one_page_writer_for_the_device_and_any_mechanism(feeder, tmp_path):
    """The device's page and a mechanism's, written by the one writer to the same file, replace
    each other (the viewer's marker in the head); each carries the legend; a file the viewer did
    not write is refused."""
    device = device_scene(feeder, feeding_cycle(feeder, math.radians(30.0)))
    mechanism = model_scene(pose_view(FOUR_BAR / "closures.toml"))
    path = tmp_path / "view.html"
    for scene, title in (
        (device, "projectile feeder"),
        (mechanism, "four_bar.urdf"),
        (device, "projectile feeder"),
    ):
        page = write_html(scene, path).read_text(encoding="utf-8")
        assert PAGE_MARKER in page[:4096]
        assert (
            re.search(r'<details id="feeder-legend" open>\s*<summary>([^<]*)<', page)
            .group(1)
            .startswith(title)
        )
    other = tmp_path / "notes.html"
    other.write_text("<html>mine</html>", encoding="utf-8")
    with pytest.raises(InputError, match="is not an HTML page that feeder view wrote"):
        write_html(mechanism, other)
    assert other.read_text(encoding="utf-8") == "<html>mine</html>"
