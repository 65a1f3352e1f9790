"""The viewer of a user's mechanism (``feeder view MODEL``): the scene it sends (decoded from its
static page) against Pinocchio's kinematics and the run's own table, what headless Chromium draws
of a shared CAD export (with its meshes) and of the four-bar, its loopback-only, silent server,
the command line, and the report page of ``feeder analyze`` / ``feeder simulate``."""

from __future__ import annotations

import base64
import hashlib
import json
import re
import shutil
import urllib.error
import urllib.request
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from lxml import etree

from feeder.chain import read_spec
from feeder.cli import main
from feeder.exceptions import FeederWarning, InputError
from feeder.outputs import MANIFEST, write_analysis_outputs
from feeder.study.analyze import analyze
from feeder.study.csv import read_csv, write_csv
from feeder.study.mechanism_table import joint_columns, q_from_columns
from feeder.study.view import analysis_view, pose_view, run_view
from feeder.viz._meshcat_server import LOOPBACK
from feeder.viz.arrows import ARROW_LENGTH, HEAD_LENGTH
from feeder.viz.model_scene import DEFAULT_REACTIONS, MOUNT_FORCE, model_scene
from feeder.viz.nodes import BASE
from feeder.viz.scene import FRAME_RATE
from feeder.viz.viewer import SceneViewer, mechanism_html
from tests.viz.test_viewer import (
    FLOAT32_POSITION,
    HIDE_LEGEND,
    arrow_keys,
    changed,
    decode_commands,
    legend_colours,
    listening,
    needs_chromium,
    rotation,
    scene_colours,
    screenshot,
    tracks,
)

ROOT_DIR = Path(__file__).resolve().parents[2]
FOUR_BAR = ROOT_DIR / "examples" / "four_bar"
CASSIE = ROOT_DIR.parent / "shared" / "mechanisms" / "cassie_like"
if not CASSIE.is_dir():  # the repository's own copy of the shared export
    CASSIE = ROOT_DIR / "examples" / "cad" / "cassie_like"
MIN_BODY_SHARE = 0.005
"""The mechanism's bodies cover more than 0.5 % of the 1000 × 800 window (measured: the four-bar
~4 %, the Cassie-like leg ~3 %): a blank scene covers none."""
MIN_MOTION_SHARE = 0.002
"""Between two times of the four-bar's motion more than 0.2 % of the window changes (its crank
turns by ~40°; measured ~1.5 %); an animation that does not move changes 0 (the software
renderer draws one scene identically)."""
PLAYER_ROWS = 700
"""[px] Rows of the window above the player, whose clock and slider change with the time."""


@pytest.fixture(scope="module")
def four_bar():
    return analyze(FOUR_BAR / "closures.toml", FOUR_BAR / "motion.csv")


@pytest.fixture(scope="module")
def four_bar_page(four_bar):
    return mechanism_html(analysis_view(four_bar))


@pytest.fixture(scope="module")
def cassie_page():
    return mechanism_html(pose_view(CASSIE / "robot.yaml"))


def test_coordinate_columns_give_the_configurations_back():
    """joint_columns → q_from_columns on every joint type of the Cassie-like leg (ball joints
    among them) and the four-bar, at random closed or open poses: exactly (the quaternion and
    the plain coordinates are written as they are; a continuous angle goes through atan2)."""
    from feeder.chain import load_mechanism

    for path in (CASSIE / "robot.yaml", FOUR_BAR / "closures.toml"):
        model = load_mechanism(read_spec(path)).model
        q = np.array([pin.randomConfiguration(model, -np.ones(model.nq), np.ones(model.nq))
                      for _ in range(5)])  # fmt: skip
        zero = np.zeros((5, model.nv))
        back = q_from_columns(model, joint_columns(model, q, zero, zero))
        np.testing.assert_allclose(back, q, rtol=0.0, atol=4e-16)  # cos(atan2(s, c)): 2 ulp


def test_a_table_of_another_model_is_refused(four_bar):
    with pytest.raises(InputError, match="no column 'q_crank_joint'"):
        q_from_columns(four_bar.chain.model, {"t": np.zeros(2)})


def test_meshes_are_embedded_and_every_body_drawn(cassie_page):
    """The Cassie-like leg's STL meshes, read beside its URDF, travel inside the page: it needs
    no file and no network."""
    commands = decode_commands(cassie_page)
    meshes = [
        c for c in commands
        if c["type"] == "set_object" and "/mechanism/visuals/" in c["path"]
    ]  # fmt: skip
    urdf_meshes = etree.parse(str(CASSIE / "robot.urdf")).findall(".//visual//mesh")
    assert len(meshes) == len(urdf_meshes) > 0
    for command in meshes:
        (geometry,) = command["object"]["geometries"]
        assert geometry["type"] == "_meshfile" and geometry["format"] == "stl"
        assert len(geometry["data"].data) > 1000  # the file's bytes (msgpack ext), no reference
    assert not re.search(r'(src|href)="https?://', cassie_page)


def test_a_pose_has_no_animation_and_says_so(cassie_page):
    commands = decode_commands(cassie_page)
    assert not [c for c in commands if c["type"] == "set_animation"]
    assert "(no motion)" in cassie_page and 'id="feeder-play"' not in cassie_page


def test_legend_names_every_colour_of_the_scene(four_bar_page, cassie_page):
    """Read from the scene's own commands, not from the legend's code."""
    for page in (four_bar_page, cassie_page):
        missing = scene_colours(decode_commands(page)) - set(legend_colours(page))
        assert not missing, f"colours without a legend entry: {missing}"


def key_samples(track: dict, t: np.ndarray) -> np.ndarray:
    """The motion sample (index into t) of each key frame of a track: the animation plays the
    motion from t[0] to t[-1] over its key frames' span (slowed down, if at all, uniformly)."""
    played = np.array([key["time"] for key in track["position"]]) / track["fps"]
    assert played[0] == 0.0 and track["fps"] == FRAME_RATE
    motion = t[0] + played / played[-1] * (t[-1] - t[0])
    samples = np.abs(t[None, :] - motion[:, None]).argmin(axis=1)
    np.testing.assert_allclose(t[samples], motion, atol=1e-12)  # keys sit on samples
    return samples


def test_cut_marker_follows_pinocchio(four_bar, four_bar_page):
    """The animated placement of the closure's cut marker equals Pinocchio's placement of the
    cut's first frame at every key frame (to MeshCat's float32 key frames)."""
    model = four_bar.chain.model
    data = model.createData()
    animated = tracks(decode_commands(four_bar_page))
    closure = four_bar.chain.closures[0]
    cut = animated[f"/meshcat/{BASE}/cuts/{closure.label}"]
    frame = model.getFrameId(closure.frame_a)
    samples = key_samples(cut, four_bar.motion.t)
    assert samples[-1] == four_bar.motion.t.size - 1
    for key, k in zip(cut["position"], samples, strict=True):
        pin.framesForwardKinematics(model, data, four_bar.q[k])
        np.testing.assert_allclose(
            key["value"], data.oMf[frame].translation, atol=FLOAT32_POSITION
        )


def test_default_arrows_are_the_drive_and_the_largest_reactions(four_bar, four_bar_page):
    """Ranked here from the loads themselves (ChainLoads), not from the viewer's table."""
    peaks = {
        name: float(np.linalg.norm(wrench.force, axis=1).max())
        for name, wrench in four_bar.loads.joints.items()
    }
    largest = sorted(peaks, key=peaks.get, reverse=True)[:DEFAULT_REACTIONS]
    legend = legend_colours(four_bar_page).values()
    for name in largest:
        assert f"reaction force in {name} [N]" in legend
    for name in four_bar.loads.actuators:
        assert any(f"drive moment of {name}" in label for label in legend)


def page_scale(page: str) -> tuple[float, float]:
    """The force arrows' scale the page prints: a length [m] and the force [N] drawn so long."""
    found = re.search(r"force arrows to one scale: ([0-9.e-]+) m long = ([0-9.e+-]+) N", page)
    return float(found.group(1)), float(found.group(2))


def test_arrows_to_one_scale(four_bar, four_bar_page):
    """Every drawn reaction arrow is |F| / scale long at every key frame, F the analysis' own
    reaction at that sample, the scale the page's (largest force drawn, the mount's among them,
    = the page's length)."""
    animated = tracks(decode_commands(four_bar_page))
    length, newtons = page_scale(four_bar_page)
    peaks = {n: np.linalg.norm(w.force, axis=1).max() for n, w in four_bar.loads.joints.items()}
    mount = np.linalg.norm(four_bar.loads.mount.force, axis=1).max()
    assert newtons == pytest.approx(max(*peaks.values(), mount), rel=1e-3)  # 4 printed digits
    head_length = HEAD_LENGTH * length / ARROW_LENGTH  # the head's cone, scaled with the arrow
    for name in sorted(peaks, key=peaks.get, reverse=True)[:DEFAULT_REACTIONS]:
        node = f"/meshcat/{BASE}/forces/reaction force in {name} [N]"
        shaft, head = animated[f"{node}/shaft"], animated[f"{node}/head"]
        drawn = np.array(
            [s["value"][1] + h["value"][1] * head_length
             for s, h in zip(shaft["scale"], head["scale"], strict=True)]
        )  # fmt: skip
        force = np.linalg.norm(four_bar.loads.joints[name].force, axis=1)
        expected = force[key_samples(shaft, four_bar.motion.t)] / newtons * length
        # float32 scales (1e-7 relative) and the 4 printed digits of the scale (5e-4)
        np.testing.assert_allclose(drawn, expected, rtol=1e-3, atol=1e-6)


def test_run_folder_shows_the_run(four_bar, tmp_path):
    """An analysis written to a folder and read back: the same poses (the CSV keeps every
    digit) and a refused folder of another mechanism or without a table."""
    write_analysis_outputs(four_bar, tmp_path / "run")
    view = run_view(FOUR_BAR / "closures.toml", tmp_path / "run")
    np.testing.assert_array_equal(view.q, four_bar.q)
    np.testing.assert_array_equal(view.t, four_bar.motion.t)
    assert "report.html" in {p.name for p in (tmp_path / "run").iterdir()}
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputError, match="holds no loads.csv or states.csv"):
        run_view(FOUR_BAR / "closures.toml", tmp_path / "empty")
    with pytest.raises(InputError, match="run folder not found"):
        run_view(FOUR_BAR / "closures.toml", tmp_path / "nowhere")


def _edit_loads(folder: Path, edit, rehash: bool = False) -> None:
    """Rewrite the run's loads.csv with ``edit(columns)`` applied; with ``rehash``, its manifest
    records the edited file's SHA-256 (a forged run)."""
    table = folder / "loads.csv"
    columns = read_csv(table)
    edit(columns)
    write_csv(table, columns)
    if rehash:
        record = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
        record["files"]["loads.csv"] = hashlib.sha256(table.read_bytes()).hexdigest()
        (folder / MANIFEST).write_text(json.dumps(record), encoding="utf-8")


def _open_loop(columns):
    columns["q_rocker_joint"][40] += 0.3  # [rad] the loop opened at one row


def _drive(columns):
    columns["tau_crank_joint"][60] = 1e6  # [N·m]


def _reverse(columns):
    for name in columns:
        columns[name] = columns[name][::-1].copy()


@pytest.mark.parametrize(
    ("edit", "rehash", "match"),
    [
        (_open_loop, False, r"/run/loads.csv changed since the run that wrote it \(its SHA-256"),
        (_drive, False, r"/run/loads.csv changed since the run that wrote it"),
        (_reverse, False, r"/run/loads.csv changed since the run that wrote it"),
        # motion.csv ends at t = 0.99 s and 1 s: reversed, its first two rows
        (_reverse, True, r"/run/loads.csv: times must increase strictly from row to row, but "
         r"t = 0.99 s follows t = 1 s \(data rows 1 and 2\)"),
    ],
    ids=["loop-opened", "drive-1e6", "reversed", "reversed-and-rehashed"],
)  # fmt: skip
def test_an_edited_run_is_refused(four_bar, tmp_path, edit, rehash, match):
    """A loads.csv edited since its run (its manifest's SHA-256 no longer matches), or whose
    times run backwards even under a matching manifest: refused in one line naming the file."""
    write_analysis_outputs(four_bar, tmp_path / "run")
    _edit_loads(tmp_path / "run", edit, rehash)
    with pytest.raises(InputError, match=match) as caught:
        run_view(FOUR_BAR / "closures.toml", tmp_path / "run")
    assert "\n" not in str(caught.value)


def test_an_incomplete_or_unrecorded_run_is_refused(four_bar, tmp_path):
    """A run whose manifest says it did not complete, or a folder without a manifest."""
    write_analysis_outputs(four_bar, tmp_path / "run")
    manifest = tmp_path / "run" / MANIFEST
    record = json.loads(manifest.read_text(encoding="utf-8"))
    manifest.write_text(json.dumps(record | {"complete": False}), encoding="utf-8")
    with pytest.raises(InputError, match=r"feeder-run.json marks its run incomplete"):
        run_view(FOUR_BAR / "closures.toml", tmp_path / "run")
    manifest.unlink()
    with pytest.raises(InputError, match=r"/run has no feeder-run.json"):
        run_view(FOUR_BAR / "closures.toml", tmp_path / "run")


def test_view_command_refuses_an_edited_run(four_bar, tmp_path, capsys):
    write_analysis_outputs(four_bar, tmp_path / "run")
    _edit_loads(tmp_path / "run", _drive)
    page = tmp_path / "view.html"
    args = [str(FOUR_BAR / "four_bar.urdf"), "--closures", str(FOUR_BAR / "closures.toml")]
    assert main(["view", *args, "--run", str(tmp_path / "run"), "--html", str(page)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"{tmp_path / 'run' / 'loads.csv'} changed since" in err[0]
    assert not page.exists()


def test_bad_reaction_is_refused():
    view = pose_view(FOUR_BAR / "closures.toml")
    with pytest.raises(InputError, match="no reaction of joint"):
        model_scene(view, ["no_such_joint"])


def test_a_missing_mesh_is_left_out_with_a_warning(tmp_path):
    """The loads need no meshes: a visual whose mesh file is not found is not drawn (the crank's
    here; the coupler and rocker are), one warning names the file and the legend the body (a
    missing collision mesh is not drawn anyway: left out silently); with every mesh missing the
    bodies are a stick figure that says why."""
    urdf = (FOUR_BAR / "four_bar.urdf").read_text(encoding="utf-8")
    crank_box = '<box size="0.04 0.02 0.01"/>'
    broken = urdf.replace(crank_box, '<mesh filename="package://four_bar/missing.stl"/>', 1)
    collision = '<collision><geometry><mesh filename="collision.stl"/></geometry></collision>'
    broken = broken.replace("</visual>", f"</visual>{collision}", 2)
    with pytest.warns(FeederWarning, match=r"1 mesh file\(s\) not found") as caught:
        page = mechanism_html(pose_view(_four_bar_copy(tmp_path, broken)))
    (message,) = [str(w.message) for w in caught if w.category is FeederWarning]
    assert message.endswith(": package://four_bar/missing.stl")
    visuals = [
        c["path"].rsplit("/", 1)[1]
        for c in decode_commands(page)
        if c["type"] == "set_object" and "/mechanism/visuals/" in c["path"]
    ]
    assert sorted(name.split("_")[0] for name in visuals) == ["coupler", "rocker"]
    assert "not drawn (mesh files missing or unusable): crank" in page
    boxes = iter(range(3))
    meshes_only = re.sub(r"<box [^>]*/>", lambda _: f'<mesh filename="m{next(boxes)}.stl"/>', urdf)
    with pytest.warns(FeederWarning, match=r"3 mesh file\(s\) .*: m0.stl, m1.stl, m2.stl$"):
        page = mechanism_html(pose_view(_four_bar_copy(tmp_path, meshes_only)))
    assert "bodies as a stick figure (their mesh files are missing or unusable)" in page


def test_server_is_on_loopback_and_silent(capfd):
    """MeshCat's own server prints "opened:" per tab, "Port: 6000 in use" per busy ZMQ port
    and tornado's "404 GET /favicon.ico": none of it reaches the terminal."""
    with SceneViewer(model_scene(pose_view(FOUR_BAR / "closures.toml"))) as viewer:
        assert set(listening(viewer.port)) == {LOOPBACK}
        zmq_port = int(viewer._server.zmq_url.rsplit(":", 1)[1])
        assert set(listening(zmq_port)) == {LOOPBACK}
        with pytest.raises(urllib.error.HTTPError):
            urllib.request.urlopen(viewer.url.replace("static/", "favicon.ico"), timeout=10)
        with urllib.request.urlopen(viewer.url, timeout=10) as response:
            assert 'id="feeder-legend"' in response.read().decode("utf-8")
    out, err = capfd.readouterr()
    assert out == "" and err == ""


def test_view_command(tmp_path, capsys):
    page = tmp_path / "view.html"
    args = [str(FOUR_BAR / "four_bar.urdf"), "--closures", str(FOUR_BAR / "closures.toml")]
    assert (
        main(["view", *args, "--motion", str(FOUR_BAR / "motion.csv"), "--html", str(page)]) == 0
    )
    assert f"wrote {page}" in capsys.readouterr().out
    assert "set_animation" in str(decode_commands(page.read_text(encoding="utf-8")))
    assert main(["view", *args, "--elevation", "30", "--html", str(page)]) == 2
    assert "not of a MODEL's" in capsys.readouterr().err
    assert main(["view", "--run", str(tmp_path), "--html", str(page)]) == 2
    assert "give MODEL" in capsys.readouterr().err
    assert main(["view", *args, "--reactions", "nope", "--html", str(page)]) == 2
    assert main(["view", *args, "--slope", "0", "15", "--html", str(page)]) == 2
    assert "its file's [base]" in capsys.readouterr().err


def test_report_page(four_bar, tmp_path):
    """One file that opens offline: the summary, the viewer's page in an iframe, every figure
    the folder holds (the same PNG bytes)."""
    paths = write_analysis_outputs(four_bar, tmp_path / "run", "feeder analyze (test)")
    page = (tmp_path / "run" / "report.html").read_text(encoding="utf-8")
    assert four_bar.summary().splitlines()[0] in page
    assert 'iframe id="view"' in page and "feeder-legend" in page
    images = re.findall(r'<img alt="([^"]+)" src="data:image/png;base64,([^"]+)"', page)
    pngs = {p.name for p in paths if p.suffix == ".png"}
    assert {name for name, _ in images} == pngs
    for name, data in images:
        assert base64.b64decode(data) == (tmp_path / "run" / name).read_bytes()
    assert not re.search(r'(src|href)="https?://', page)


@pytest.fixture(scope="module")
def four_bar_shots(four_bar_page, tmp_path_factory):
    """Screenshots of the four-bar's page at two times, and without its bodies."""
    folder = tmp_path_factory.mktemp("four_bar_shots")
    page = folder / "page.html"
    page.write_text(four_bar_page.replace("</body>", HIDE_LEGEND + "</body>"), encoding="utf-8")
    hidden = folder / "hidden.html"
    hide = "<style>#feeder-legend { display: none; }</style>"
    script = (
        "<script>viewer.scene_tree.find(['meshcat', 'feeder', 'base', 'mechanism'])"
        ".set_property('visible', false);</script>"
    )
    hidden.write_text(
        four_bar_page.replace("</body>", hide + script + "</body>"), encoding="utf-8"
    )
    return {
        "start": screenshot(page.as_uri() + "#t=0", folder / "start.png"),
        "later": screenshot(page.as_uri() + "#t=0.5", folder / "later.png"),
        "hidden": screenshot(hidden.as_uri() + "#t=0", folder / "hidden.png"),
    }


@needs_chromium
def test_browser_draws_the_four_bar_and_plays_it(four_bar_shots):
    bodies = changed(four_bar_shots["start"], four_bar_shots["hidden"])
    assert bodies.mean() > MIN_BODY_SHARE, f"bodies cover {bodies.mean():.2%}"
    moved = changed(four_bar_shots["start"], four_bar_shots["later"])[:PLAYER_ROWS]
    assert moved.mean() > MIN_MOTION_SHARE, f"{moved.mean():.3%} of the window moved"


@needs_chromium
def test_browser_draws_the_cad_export_with_its_meshes(cassie_page, tmp_path):
    """The Cassie-like leg, live on 127.0.0.1 and offline: its meshes cover the window's share."""
    with SceneViewer(model_scene(pose_view(CASSIE / "robot.yaml"))) as viewer:
        live = screenshot(viewer.url, tmp_path / "live.png")
        viewer.visualizer.viewer[f"{BASE}/mechanism"].set_property("visible", False)
        hidden = screenshot(viewer.url, tmp_path / "hidden.png")
    page = tmp_path / "page.html"
    page.write_text(cassie_page, encoding="utf-8")
    offline = screenshot(page.as_uri(), tmp_path / "offline.png")
    for image in (live, offline):
        bodies = changed(image, hidden)
        assert bodies.mean() > MIN_BODY_SHARE, f"bodies cover {bodies.mean():.2%}"


def _four_bar_copy(folder: Path, urdf: str) -> Path:
    """The four-bar's mechanism file beside a URDF of ``urdf``'s text in ``folder``."""
    (folder / "four_bar.urdf").write_text(urdf, encoding="utf-8")
    shutil.copy(FOUR_BAR / "closures.toml", folder / "closures.toml")
    return folder / "closures.toml"


def test_a_model_without_visuals_is_a_stick_figure(tmp_path):
    """No <visual> at all: a ball at every joint, a rod to every child joint and closure frame,
    all animated with the joints; the legend says it."""
    urdf = (FOUR_BAR / "four_bar.urdf").read_text(encoding="utf-8")
    bare = re.sub(r"<visual>.*?</visual>", "", urdf, flags=re.S)
    view = pose_view(_four_bar_copy(tmp_path, bare))
    page = mechanism_html(view)
    commands = decode_commands(page)
    drawn = {c["path"].rsplit("/", 1)[1] for c in commands if c["type"] == "set_object"}
    model = view.chain.model
    assert {f"joint_{name}" for name in list(model.names)[1:]} <= drawn
    closure = view.chain.closures[0]
    assert {f"rod_{closure.frame_a}", f"rod_{closure.frame_b}"} <= drawn
    assert "stick figure" in page


def test_obj_meshes_resolved_beside_the_model(tmp_path):
    """A relative OBJ path, resolved beside the URDF and embedded in the page."""
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "crank.obj").write_text(
        "v 0 0 0\nv 0.04 0 0\nv 0 0.02 0\nv 0 0 0.01\nf 1 2 3\nf 1 2 4\nf 1 3 4\nf 2 3 4\n",
        encoding="utf-8",
    )
    urdf = (FOUR_BAR / "four_bar.urdf").read_text(encoding="utf-8")
    meshed = urdf.replace('<box size="0.04 0.02 0.01"/>', '<mesh filename="meshes/crank.obj"/>', 1)
    page = mechanism_html(pose_view(_four_bar_copy(tmp_path, meshed)))
    meshes = [
        g
        for c in decode_commands(page)
        if c["type"] == "set_object"
        for g in c["object"].get("geometries", [])
        if g["type"] == "_meshfile"
    ]
    assert [m["format"] for m in meshes] == ["obj"]
    assert "v 0.04 0 0" in meshes[0]["data"]  # the file's text, not a reference to it


SECRET = "SECRET_outside"
"""A marker in the files outside the model's folder: it must not reach the page."""
TRIANGLE_STL = f"solid {SECRET}\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0.04 0 0\n"
TRIANGLE_STL += f"vertex 0 0.02 0\nendloop\nendfacet\nendsolid {SECRET}\n"
TRIANGLE_OBJ = "v 0 0 0\nv 0.04 0 0\nv 0 0.02 0\nf 1 2 3\n"
TEXTURED_DAE = """<?xml version="1.0"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <library_images><image id="skin"><init_from>../texture.png</init_from></image></library_images>
  <library_geometries><geometry id="g"><mesh>
    <source id="p"><float_array id="pa" count="9">0 0 0 0.04 0 0 0 0.02 0</float_array>
      <technique_common><accessor source="#pa" count="3" stride="3"><param name="X" type="float"/>
      <param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common>
    </source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n">
    <instance_geometry url="#g"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
"""
"""A triangle whose image lies above the mesh's folder (Pinocchio's viewer embeds images)."""


def _with_crank_mesh(folder: Path, uri: str) -> Path:
    """The four-bar in ``folder`` (created), its crank's box replaced by the mesh ``uri``."""
    folder.mkdir(exist_ok=True)
    urdf = (FOUR_BAR / "four_bar.urdf").read_text(encoding="utf-8")
    meshed = urdf.replace('<box size="0.04 0.02 0.01"/>', f'<mesh filename="{uri}"/>', 1)
    return _four_bar_copy(folder, meshed)


def _embeds_secret(page: str) -> bool:
    """Whether the page's MeshCat commands hold :data:`SECRET`, as bytes or in base64 (a
    texture's data URL)."""
    secret = SECRET.encode()
    blobs = re.findall(r"data:application/octet-binary;base64,([A-Za-z0-9+/=]*)", page)
    decoded = [base64.b64decode(blob) for blob in blobs]
    return any(secret in blob or base64.b64encode(secret) in blob for blob in decoded)


def _drawn_visuals(page: str) -> list[str]:
    """The links whose visuals the page draws."""
    return sorted(
        c["path"].rsplit("/", 1)[1].split("_")[0]
        for c in decode_commands(page)
        if c["type"] == "set_object" and "/mechanism/visuals/" in c["path"]
    )


@pytest.mark.parametrize(
    "uri", ["package:///../secret.stl", "../secret.stl", "file://{outside}/secret.stl", "link.stl"]
)
def test_a_mesh_outside_the_model_folder_is_never_read(tmp_path, uri):
    """A mesh named above the model's folder, by ``..``, an absolute path or a symbolic link, is
    left out like a missing one (one warning naming it; the loads need no meshes), and its
    bytes never reach the page."""
    (tmp_path / "secret.stl").write_text(TRIANGLE_STL)
    model = tmp_path / "model"
    model.mkdir()
    (model / "link.stl").symlink_to(tmp_path / "secret.stl")
    uri = uri.format(outside=tmp_path)
    outside = r"1 mesh file\(s\) outside the model's folder"
    with pytest.warns(FeederWarning, match=outside) as caught:
        page = mechanism_html(pose_view(_with_crank_mesh(model, uri)))
    (message,) = [str(w.message) for w in caught if w.category is FeederWarning]
    assert message.endswith(f": {uri}")
    assert _drawn_visuals(page) == ["coupler", "rocker"]
    assert not _embeds_secret(page)
    assert "not drawn (mesh files missing or unusable): crank" in page


@pytest.mark.parametrize(
    "mesh, text",
    [("crank.dae", TEXTURED_DAE), ("crank.obj", f"mtllib ../texture.png\n{TRIANGLE_OBJ}")],
    ids=["dae-image", "obj-materials"],
)
def test_a_mesh_naming_a_file_outside_the_model_folder_is_left_out(tmp_path, mesh, text):
    """A mesh inside the folder whose image (embedded by Pinocchio's viewer) or material library
    (read by assimp) lies above it: left out, its file never read."""
    (tmp_path / "texture.png").write_text(SECRET)
    model = tmp_path / "model"
    model.mkdir()
    (model / mesh).write_text(text)
    with pytest.warns(FeederWarning, match=f"outside the model's folder.*: {mesh}$"):
        page = mechanism_html(pose_view(_with_crank_mesh(model, mesh)))
    assert _drawn_visuals(page) == ["coupler", "rocker"]
    assert not _embeds_secret(page)


@pytest.mark.parametrize(
    "mesh, data",
    [
        ("crank.stl", bytes(range(256)) * 2),
        ("crank.stl", b""),
        ("crank.dae", b"<COLLADA><broken"),
        ("crank.obj", b"not a mesh\n"),
    ],
    ids=["garbage-stl", "empty-stl", "malformed-dae", "text-obj"],
)
def test_a_corrupt_mesh_is_left_out_with_a_warning(tmp_path, mesh, data):
    """A mesh file beside the model that does not load is handled like a missing one."""
    (tmp_path / mesh).write_bytes(data)
    with pytest.warns(
        FeederWarning, match=rf"1 mesh file\(s\) not readable as meshes .*: {mesh}$"
    ):
        page = mechanism_html(pose_view(_with_crank_mesh(tmp_path, mesh)))
    assert _drawn_visuals(page) == ["coupler", "rocker"]


def test_view_draws_a_model_with_a_corrupt_mesh(tmp_path, capsys):
    """``feeder view --html``: exit 0, the page written, one warning line, no traceback."""
    (tmp_path / "crank.stl").write_bytes(bytes(range(256)) * 2)
    side = _with_crank_mesh(tmp_path, "crank.stl")
    page = tmp_path / "page.html"
    args = [str(tmp_path / "four_bar.urdf"), "--closures", str(side), "--html", str(page)]
    assert main(["view", *args]) == 0
    err = capsys.readouterr().err
    assert err.splitlines() == [
        f"feeder: warning: {tmp_path / 'four_bar.urdf'}: 1 mesh file(s) not readable as meshes "
        "(STL, DAE, OBJ), their visuals not drawn (the loads need no meshes): crank.stl"
    ]
    assert _drawn_visuals(page.read_text(encoding="utf-8")) == ["coupler", "rocker"]


# -- a mechanism on a vehicle (its file's [base]): it rides on the base; the mount's arrow --

BASE_TABLE = """
[base]
roll_deg = 10.0

[[base.profile]]
type = "terrain"
"""
"""The four-bar's vehicle: a 10° roll slope and the terrain profile (±40 mm heave, ±3° pitch,
±1.5° roll at 1.2 Hz) over its 1 s motion."""
ROTATION_ROUND_OFF = 1e-12
"""A placement sent as a float64 position and quaternion, read back as a matrix: round-off."""
POSITION_ROUND_OFF = 1e-12
"""[m] The base's position (≤ 0.04 m), sent as float64."""


@pytest.fixture(scope="module")
def on_terrain(tmp_path_factory):
    """The four-bar's mechanism file with :data:`BASE_TABLE`: its motion analysed, and the
    viewer's page of the analysis."""
    folder = tmp_path_factory.mktemp("four_bar_on_terrain")
    for name in ("four_bar.urdf", "motion.csv"):
        shutil.copy(FOUR_BAR / name, folder / name)
    spec = (FOUR_BAR / "closures.toml").read_text(encoding="utf-8") + BASE_TABLE
    (folder / "closures.toml").write_text(spec, encoding="utf-8")
    analysis = analyze(folder / "closures.toml", folder / "motion.csv")
    return analysis, mechanism_html(analysis_view(analysis))


def test_mechanism_rides_on_its_base(on_terrain):
    """The base's node is placed, at every key frame, where the analysis' base state puts the
    model's axes (rotation, origin) in the level ones, and moves; the bodies and cuts are in
    it, over the hull; every colour has a legend entry."""
    analysis, page = on_terrain
    commands = decode_commands(page)
    animated = tracks(commands)
    base, state = animated[f"/meshcat/{BASE}"], analysis.loads.base
    samples = key_samples(base, analysis.motion.t)
    turns = np.array([rotation(key["value"]) for key in base["quaternion"]])
    np.testing.assert_allclose(turns, state.rotation[samples], rtol=0.0, atol=ROTATION_ROUND_OFF)
    origins = np.array([key["value"] for key in base["position"]])
    np.testing.assert_allclose(origins, state.position[samples], rtol=0.0, atol=POSITION_ROUND_OFF)
    assert np.ptp(origins, axis=0).max() > 0.01  # the terrain's heave
    assert any(path.startswith(f"/meshcat/{BASE}/mechanism/visuals/") for path in animated)
    assert any(path.startswith(f"/meshcat/{BASE}/cuts/") for path in animated)
    assert any(
        c["type"] == "set_object" and c["path"] == f"/meshcat/{BASE}/hull" for c in commands
    )
    assert not scene_colours(commands) - set(legend_colours(page))


def test_a_pose_on_a_base_is_placed(on_terrain):
    """The assembled pose of the mechanism on its base (no motion): the base's node is placed
    once, where the base stands at t = 0 (the slope with the terrain's pitch there)."""
    analysis, _ = on_terrain
    view = pose_view(analysis.spec.model.parent / "closures.toml")
    state = analysis.spec.base.state(np.zeros(1), analysis.chain.model.gravity.linear)
    np.testing.assert_array_equal(view.base.rotation, state.rotation)
    (placed,) = [
        c
        for c in decode_commands(mechanism_html(view))
        if c["type"] == "set_transform" and c["path"] == f"/meshcat/{BASE}"
    ]
    matrix = np.array(placed["matrix"]).reshape(4, 4).T  # three.js: column-major
    np.testing.assert_allclose(matrix[:3, :3], state.rotation[0], rtol=0.0, atol=1e-15)
    np.testing.assert_allclose(matrix[:3, 3], state.position[0], rtol=0.0, atol=1e-15)


def test_standing_mechanism_has_no_moving_base(four_bar_page):
    """Without [base] the base's node keeps MeshCat's identity and no hull is drawn."""
    commands = decode_commands(four_bar_page)
    assert not [c for c in commands if c["path"] in (f"/meshcat/{BASE}", f"/meshcat/{BASE}/hull")]
    assert f"/meshcat/{BASE}" not in tracks(commands)


@pytest.mark.parametrize("case", ["standing", "on terrain"])
def test_mount_arrow(four_bar, four_bar_page, on_terrain, case):
    """The mount's arrow starts at the model's origin and is, at every key frame, the analysis'
    mount force in the model's moving axes (not the level ones) over the page's scale; the
    legend names it."""
    analysis, page = (four_bar, four_bar_page) if case == "standing" else on_terrain
    commands = decode_commands(page)
    node = f"/meshcat/{BASE}/forces/{MOUNT_FORCE}"
    _, tail, tip = arrow_keys(commands, node)
    samples = key_samples(tracks(commands)[f"{node}/shaft"], analysis.motion.t)
    length, newtons = page_scale(page)
    mount = analysis.loads.mount
    assert np.abs(tail).max() <= POSITION_ROUND_OFF
    # the scale printed to 4 digits (5e-4)
    np.testing.assert_allclose(
        tip - tail, mount.force[samples] / newtons * length, rtol=0.0, atol=1e-3 * length
    )
    if case == "on terrain":  # the arrow tells the moving axes from the level ones
        assert np.abs(mount.level_force - mount.force).max() / newtons > 3e-3
    assert MOUNT_FORCE in legend_colours(page).values()
