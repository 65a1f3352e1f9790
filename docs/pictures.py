"""Regenerate the README's pictures: ``python docs/pictures.py [NAME ...]`` (all by default).

Each picture is made by the commands a user runs (``feeder cycle``, ``feeder sweep``, ``feeder
design optimize``, ``feeder view``; the viewer's pages photographed by headless Debian
Chromium, 1000 × 800, software WebGL) and carries, in a PNG text chunk ``feeder-fingerprint``,
the SHA-256 of the files that draw it (:data:`PICTURES`: this script, the drawing code, the
model and the inputs).
``tests/test_docs.py`` recomputes the fingerprints: a picture whose sources changed since it was
made fails the test until this script is run again.
"""

from __future__ import annotations

import hashlib
import shutil
import subprocess
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
KEY = "feeder-fingerprint"
CASSIE = ROOT / "examples" / "cad" / "cassie_like"
CHROMIUM_FLAGS = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--use-angle=swiftshader",  # software WebGL
    "--enable-unsafe-swiftshader",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--window-size=1000,800",
    "--virtual-time-budget=6000",  # [ms] page load, then the player seeks to #t=
)
GRID = """devices = ["projectile"]
elevations = {start = -4, stop = 70, step = 1}   # [deg]
[[variants]]
name = "reference"
[[variants]]
name = "retrofit"        # the payload 20 % heavier and 15 % longer
mass_factor = 1.2
length_factor = 1.15
"""
"""The grid of the README's sweep (its text, as the README shows it)."""

_DEVICE = ("feeder/device/*.py", "feeder/motion/*.py", "urdf/*.urdf")
_DYNAMICS = (*_DEVICE, "feeder/dynamics/*.py", "feeder/chain/**/*.py")
_FIGURES = ("feeder/viz/figures.py", "feeder/viz/axes.py", "feeder/viz/catalog.py",
            "feeder/viz/report.py")  # fmt: skip
_VIEWER = tuple(
    f"feeder/viz/{name}.py"
    for name in ("scene", "nodes", "legend", "placements", "arrows", "framing", "overlays",
                 "_page", "viewer")
)  # fmt: skip
PICTURES: dict[str, tuple[str, ...]] = {
    "device_side_view.png": (*_DEVICE, *_FIGURES, "feeder/viz/drawings.py"),
    "fig14_piston_force.png": (*_DYNAMICS, *_FIGURES),
    "sweep_projectile.png": (
        *_DYNAMICS,
        *_FIGURES,
        "feeder/viz/comparisons.py",
        "feeder/study/sweep*.py",
        "feeder/study/elevation_sweeps.py",
        "feeder/study/grid*.py",
    ),  # fmt: skip
    "design_optimum.png": (
        *_DYNAMICS,
        *_FIGURES,
        "feeder/design/*.py",
        "feeder/study/sweep*.py",
        "feeder/study/grid.py",
        "feeder/study/peaks.py",
    ),  # fmt: skip
    "viewer.png": (*_DEVICE, *_VIEWER, "feeder/viz/device_scene.py"),
    "cad_viewer.png": (
        *_VIEWER,
        "feeder/viz/model_scene.py",
        "feeder/viz/model_visuals.py",
        "feeder/study/view.py",
        "feeder/chain/**/*.py",
        "examples/cad/cassie_like/*",
        "examples/cad/cassie_like_motion.csv",
    ),  # fmt: skip
}
"""Each picture and the files (globs under the repository) that make it, besides this script."""


def fingerprint(name: str) -> str:
    """SHA-256 of this script and of every file that makes the picture ``name``."""
    digest = hashlib.sha256(Path(__file__).read_bytes())
    files = sorted({path for pattern in PICTURES[name] for path in ROOT.glob(pattern)})
    for path in files:
        digest.update(path.relative_to(ROOT).as_posix().encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()


def stamped(name: str) -> str | None:
    """The fingerprint the picture ``name`` in docs/ carries (None without one)."""
    from PIL import Image

    with Image.open(DOCS / name) as image:
        return image.text.get(KEY)


def _feeder(*args: str) -> None:
    subprocess.run([sys.executable, "-m", "feeder", *args], check=True, cwd=ROOT)


def _photograph(page: Path, time: float, png: Path) -> None:
    """Headless Chromium's screenshot of the viewer's ``page`` paused at ``time`` [s]."""
    chromium = shutil.which("chromium")
    if chromium is None:
        raise SystemExit("the viewer pictures need Debian's chromium (apt-get install chromium)")
    profile = png.with_suffix(".profile")
    subprocess.run(
        [chromium, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", f"--screenshot={png}",
         f"{page.as_uri()}#t={time:g}"],
        check=True, capture_output=True, timeout=120,
    )  # fmt: skip


def _cycle(work: Path, name: str) -> Path:
    if not (work / "cycle" / "feeder-run.json").is_file():  # one run for its two figures
        _feeder("cycle", "--elevation", "-4", "--no-forward", "--out", str(work / "cycle"))
    return work / "cycle" / name


def _sweep(work: Path, name: str) -> Path:
    (work / "grid.toml").write_text(GRID, encoding="utf-8")
    _feeder("sweep", "--grid", str(work / "grid.toml"), "--out", str(work / "sweep"))
    return work / "sweep" / name


def _optimum(work: Path, name: str) -> Path:
    _feeder("design", "optimize", "--out", str(work / "optimum"))
    return work / "optimum" / "optimum.png"


def _viewer(work: Path, name: str) -> Path:
    _feeder("view", "--elevation", "-4", "--html", str(work / "cycle.html"))
    _photograph(work / "cycle.html", 4.0, work / name)
    return work / name


def _cad_viewer(work: Path, name: str) -> Path:
    _feeder(
        "view", str(CASSIE / "robot.urdf"), "--closures", str(CASSIE / "robot.yaml"),
        "--motion", str(CASSIE.parent / "cassie_like_motion.csv"), "--html",
        str(work / "cad.html"),
    )  # fmt: skip
    _photograph(work / "cad.html", 0.5, work / name)
    return work / name


MAKERS: dict[str, Callable[[Path, str], Path]] = {
    "device_side_view.png": _cycle,
    "fig14_piston_force.png": _cycle,
    "sweep_projectile.png": _sweep,
    "design_optimum.png": _optimum,
    "viewer.png": _viewer,
    "cad_viewer.png": _cad_viewer,
}


def make(name: str, work: Path) -> Path:
    """Make the picture ``name`` in ``work`` and write it, stamped, into docs/ (atomically)."""
    from PIL import Image, PngImagePlugin

    made = MAKERS[name](work, name)
    info = PngImagePlugin.PngInfo()
    info.add_text(KEY, fingerprint(name))
    temporary = DOCS / f".{name}.tmp"
    with Image.open(made) as image:
        image.save(temporary, format="PNG", pnginfo=info, optimize=True)
    temporary.replace(DOCS / name)
    return DOCS / name


def main(names: list[str]) -> None:
    unknown = sorted(set(names) - set(PICTURES))
    if unknown:
        raise SystemExit(f"unknown pictures {unknown}; known: {sorted(PICTURES)}")
    with tempfile.TemporaryDirectory() as folder:
        for name in names or PICTURES:
            print(f"wrote {make(name, Path(folder))}", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
