"""PNG files of drawn figures: matplotlib's pixels encoded here with :mod:`zlib`, written
atomically (:func:`png_bytes`, :func:`write_png`; matplotlib is imported only to draw).

Matplotlib hands its pixels to Pillow's PNG encoder, which tries every PNG row filter on every
row and keeps the best: three quarters of the encoding time, for line art on white that
compresses as well unfiltered (the 13 figures of ``feeder cycle``: 1.25 MB unfiltered against
1.20 MB, in a third of the time: 0.12 s against 0.35 s). :func:`png_file` writes the pixels
unfiltered (filter type 0 on every row) in the same chunks matplotlib's files have: the header,
the text (``Software``), the resolution and the image data.
"""

from __future__ import annotations

import io
import struct
import zlib
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..files import atomic_path

if TYPE_CHECKING:
    from matplotlib.figure import Figure

FIGURE_DPI = 150
"""Resolution of the written figures [dots per inch]: an 8 × 4.2 in time history is 1200 × 630."""

PNG_COMPRESSION = 1
"""zlib level of the PNG files (0–9): 1 encodes a figure three times faster than the default 6
for a file 4 % larger: line art compresses well at any level."""

SIGNATURE = b"\x89PNG\r\n\x1a\n"
"""The first eight bytes of every PNG file."""

_RGBA = 6
"""The PNG colour type of 8-bit red, green, blue and alpha samples."""


def png_file(pixels: np.ndarray, dpi: float, text: Mapping[str, str] | None = None) -> bytes:
    """A PNG file's bytes of an image.

    Args:
        pixels: RGBA samples, (height, width, 4) uint8, the top row first.
        dpi: Resolution [dots per inch], written in pixels per metre as Pillow writes it.
        text: Latin-1 keyword → text, written as ``tEXt`` chunks (e.g. ``Software``).
    """
    height, width, _ = pixels.shape
    rows = np.empty((height, 1 + 4 * width), dtype=np.uint8)
    rows[:, 0] = 0  # each row's filter byte: 0, none
    rows[:, 1:] = pixels.reshape(height, 4 * width)
    per_metre = int(dpi / 0.0254 + 0.5)
    chunks = [(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, _RGBA, 0, 0, 0))]
    for key, value in (text or {}).items():
        chunks.append((b"tEXt", f"{key}\0{value}".encode("latin-1")))
    chunks += [
        (b"pHYs", struct.pack(">IIB", per_metre, per_metre, 1)),  # 1: the unit is the metre
        (b"IDAT", zlib.compress(rows, PNG_COMPRESSION)),
        (b"IEND", b""),
    ]
    return SIGNATURE + b"".join(
        struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
        for kind, data in chunks
    )


def png_bytes(fig: Figure, dpi: int = FIGURE_DPI) -> bytes:
    """The figure as a PNG file's bytes: the pixels of ``savefig`` at ``dpi``, and its
    ``Software`` text, encoded by :func:`~feeder.viz.png.png_file`."""
    import matplotlib

    buffer = io.BytesIO()
    fig.savefig(buffer, format="rgba", dpi=dpi)
    width = int(fig.get_figwidth() * dpi)  # matplotlib's canvas: whole pixels, truncated
    pixels = np.frombuffer(buffer.getbuffer(), dtype=np.uint8).reshape(-1, width, 4)
    software = f"Matplotlib version{matplotlib.__version__}, https://matplotlib.org/"
    return png_file(pixels, dpi, {"Software": software})


def write_png(path: str | Path, png: bytes) -> Path:
    """Write PNG bytes to ``path`` atomically."""
    path = Path(path)
    with atomic_path(path) as temporary:
        temporary.write_bytes(png)
    return path
