"""``feeder design optimize`` of a model that names mesh files: the meshes copied into the
output folder's ``meshes/``, the written optimum naming them, ``feeder analyze`` of it reading
them (no missing-mesh warning) with the optimiser's peaks; the size limit; meshes the model's
readers refuse left as they are."""

from __future__ import annotations

import csv
import json
import shutil
import xml.etree.ElementTree as ET

import pytest

from feeder.cli import main
from feeder.design import run_mechanism_optimization
from feeder.design.mechanism.meshes import mesh_copies
from feeder.design.mechanism.optimize import check_setup
from feeder.exceptions import InputError
from feeder.files import MANIFEST

from .lever import Lever
from .test_optimize import DESIGN

STL = """solid part
facet normal 0 0 1
outer loop
vertex 0 0 0
vertex 0.5 0 0
vertex 0 0.5 0
endloop
endfacet
endsolid part
"""
OBJ = "mtllib body.mtl\nv 0 0 0\nv 0.8 0 0\nv 0 0.2 0\nusemtl red\nf 1 2 3\n"
MTL = "newmtl red\nKd 0.8 0.1 0.1\n"
VISUALS = """<link name="body">
    <visual><geometry><mesh filename="package:///parts/body.obj"/></geometry></visual>
    <collision><geometry><mesh filename="package://lever/barrel.stl"/></geometry></collision>
"""


def meshed_lever(tmp_path, extra: str = ""):
    """The lever of lever.py whose body names an OBJ (with its material file, in a subfolder)
    and an STL (the ``package://PKG/NAME`` form), and ``extra`` visuals; its files."""
    tmp_path.mkdir(exist_ok=True)
    model, closures, motion, design = Lever().write(tmp_path, DESIGN)
    text = model.read_text(encoding="utf-8").replace('<link name="body">', VISUALS + extra)
    model.write_text(text, encoding="utf-8")
    (tmp_path / "parts").mkdir()
    (tmp_path / "parts" / "body.obj").write_text(OBJ, encoding="utf-8")
    (tmp_path / "parts" / "body.mtl").write_text(MTL, encoding="utf-8")
    (tmp_path / "barrel.stl").write_text(STL, encoding="utf-8")
    return model, closures, motion, design


def _analyze(out, motion, check, capsys) -> tuple[dict[str, float], list[str]]:
    """``feeder analyze`` of the written optimum: each loads.csv column's peak, and feeder's
    warnings about meshes."""
    capsys.readouterr()
    assert main(["analyze", str(out / "optimum.urdf"), "--closures",
                 str(out / "optimum_mechanism.toml"), "--motion", str(motion), "--out",
                 str(check)]) == 0  # fmt: skip
    with open(check / "loads.csv", encoding="utf-8", newline="") as handle:
        rows = list(csv.DictReader(handle))
    peaks = {name: max(abs(float(row[name])) for row in rows) for name in rows[0]}
    lines = capsys.readouterr().err.splitlines()
    return peaks, [line for line in lines if line.startswith("feeder: warning") and "mesh" in line]


def test_the_written_optimum_reads_its_copied_meshes_in_feeder_analyze(tmp_path, capsys):
    model, closures, motion, design = meshed_lever(tmp_path / "model")
    out = tmp_path / "out"
    run_mechanism_optimization(
        model, closures, design, [motion], out, workers=1, progress=False, figure=False
    )
    copies = {"meshes/parts/body.obj", "meshes/parts/body.mtl", "meshes/barrel.stl"}
    for name in copies:  # byte for byte the model's files, listed with their hashes
        assert (out / name).read_bytes() == (tmp_path / "model" / name[7:]).read_bytes()
    assert copies <= set(json.loads((out / MANIFEST).read_text(encoding="utf-8"))["files"])
    written = ET.parse(out / "optimum.urdf").getroot()
    assert sorted(m.get("filename") for m in written.iter("mesh")) == [
        "meshes/barrel.stl",
        "meshes/parts/body.obj",
    ]
    peaks, errors = _analyze(out, motion, tmp_path / "check", capsys)
    assert errors == []  # every visual drawn: no mesh missing, outside or unreadable
    with open(out / "optimum.csv", encoding="utf-8", newline="") as handle:
        table = [r for r in csv.DictReader(handle) if r["kind"] == "peak" and r["name"] in peaks]
    assert table
    for row in table:  # the same pipeline on the same numbers: equal to round-off
        assert abs(float(row["after"])) == pytest.approx(peaks[row["name"]], rel=1e-12, abs=1e-9)
    # The check above can fail: without the copies, analyze warns of the missing visual.
    shutil.rmtree(out / "meshes")
    _, errors = _analyze(out, motion, tmp_path / "check2", capsys)
    assert len(errors) == 1 and "not found" in errors[0] and "meshes/parts/body.obj" in errors[0]


def test_meshes_beyond_the_size_limit_are_refused_in_one_line(tmp_path):
    model, closures, motion, design = meshed_lever(tmp_path)
    total = sum(len(text) for text in (OBJ, MTL, STL))  # ASCII: one byte per character
    assert len(check_setup(model, closures, design, [motion], total).meshes.files) == 3
    with pytest.raises(InputError, match=r"3 mesh files total .* MiB") as caught:
        check_setup(model, closures, design, [motion], total - 1)
    assert "\n" not in str(caught.value)


def test_a_mesh_the_readers_refuse_is_neither_copied_nor_renamed(tmp_path):
    (tmp_path / "secret.stl").write_text(STL, encoding="utf-8")
    extra = """<visual><geometry><mesh filename="package:///../secret.stl"/></geometry></visual>
    <visual><geometry><mesh filename="package:///absent.stl"/></geometry></visual>
"""
    model, *_ = meshed_lever(tmp_path / "model", extra)
    copies = mesh_copies(model, model.read_text(encoding="utf-8"))
    assert all(source.is_relative_to(tmp_path / "model") for source in copies.files.values())
    assert len(copies.files) == 3
    names = [
        m.get("filename") for m in ET.fromstring(copies.rewritten(model.read_text())).iter("mesh")
    ]
    assert "package:///../secret.stl" in names and "package:///absent.stl" in names
