"""The figures' PNG files (feeder.viz.png): the pixels, size,
resolution and text of matplotlib's own PNG file of the same figure, read back by Pillow."""

from __future__ import annotations

import io

import numpy as np
import pytest
from matplotlib.figure import Figure
from PIL import Image  # matplotlib's own PNG writer, and an independent reader

from feeder.viz.png import FIGURE_DPI, png_bytes, png_file


def _figure(width: float, height: float) -> Figure:
    """Curves, text and a translucent patch: antialiased edges of every colour."""
    fig = Figure(figsize=(width, height))
    ax = fig.subplots()
    t = np.linspace(0.0, 3.0, 301)
    ax.plot(t, np.sin(4.0 * t), label="sin")
    ax.plot(t, np.cos(3.0 * t), "--", label="cos")
    ax.axvspan(1.0, 1.5, color="C2", alpha=0.3)
    ax.set_title("A title, and ε = 30°")
    ax.legend()
    return fig


@pytest.mark.parametrize("size", [(8.0, 4.2), (6.13, 3.37)])  # 3.37 × 150 = 505.5: truncated
def test_a_figures_png_is_matplotlibs_image(size):
    fig = _figure(*size)
    ours = Image.open(io.BytesIO(png_bytes(fig)))
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=FIGURE_DPI)  # matplotlib's file, through Pillow
    theirs = Image.open(buffer)
    assert ours.mode == theirs.mode == "RGBA" and ours.size == theirs.size
    np.testing.assert_array_equal(np.asarray(ours), np.asarray(theirs))
    assert ours.info == theirs.info  # the resolution and the Software text


def test_any_image_reads_back_as_written():
    rng = np.random.default_rng(29)
    pixels = rng.integers(0, 256, size=(7, 5, 4), dtype=np.uint8)  # nothing to compress
    image = Image.open(io.BytesIO(png_file(pixels, 300.0, {"Title": "noise"})))
    image.load()  # checks every chunk's CRC and the image data's length
    np.testing.assert_array_equal(np.asarray(image), pixels)
    assert image.info["Title"] == "noise"
    assert image.info["dpi"] == pytest.approx((300.0, 300.0), abs=0.01)  # whole pixels per m
