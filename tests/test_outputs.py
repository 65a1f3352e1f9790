"""The output folder: checked before anything is created, one run at a time, a manifest that
says which run wrote which file (each with its SHA-256), and no outputs of an earlier run left
beside a new one."""

from __future__ import annotations

import hashlib
import json
import math

import pytest

import feeder as api
from feeder.exceptions import FeederWarning, InputError, OutputBusyError
from feeder.files import verified_output, write_text
from feeder.outputs import LOCK, MANIFEST, OutputFolder, write_kinematics_outputs

RECORD = {"command": "test", "device": "none"}


def writers(**texts: str):
    """Writers of small text files, by name."""
    return {name: (lambda path, text=text: write_text(path, text)) for name, text in texts.items()}


def manifest(folder):
    return json.loads((folder / MANIFEST).read_text(encoding="utf-8"))


def sha256(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.mark.parametrize("path", ["", "  "])
def test_empty_path_is_refused(path):
    with pytest.raises(InputError, match="empty path"):
        OutputFolder(path)


def test_checks_create_nothing(tmp_path):
    OutputFolder(tmp_path / "new" / "deeper")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "where, message",
    [("file", "is a file"), ("under_file", "file is a file"), ("foreign", "no feeder run wrote")],
)
def test_refused_folders(tmp_path, where, message):
    (tmp_path / "file").write_text("x")
    (tmp_path / "foreign").mkdir()
    (tmp_path / "foreign" / "notes.txt").write_text("mine")
    path = {
        "file": tmp_path / "file",
        "under_file": tmp_path / "file" / "out",
        "foreign": tmp_path / "foreign",
    }[where]
    with pytest.raises(InputError, match=message):
        OutputFolder(path)
    assert (tmp_path / "foreign" / "notes.txt").read_text() == "mine"


def test_manifest_lists_every_output_with_its_hash(tmp_path):
    folder = tmp_path / "out"
    with OutputFolder(folder) as out:
        paths = out.write(writers(a="1", b="2"), RECORD)
    assert paths == [folder / "a", folder / "b"]
    record = manifest(folder)
    assert record["complete"] is True
    assert record["command"] == "test" and record["feeder_version"] == api.__version__
    assert record["files"] == {"a": sha256(folder / "a"), "b": sha256(folder / "b")}
    assert record["started"] <= record["finished"]
    assert sorted(p.name for p in folder.iterdir()) == ["a", "b", MANIFEST]  # lock removed


def test_a_new_run_removes_the_outputs_of_the_previous_one(tmp_path):
    with OutputFolder(tmp_path) as out:
        out.write(writers(a="old", b="old", c="old"), RECORD)
    (tmp_path / "notes.txt").write_text("mine")  # added by the user after the run: kept
    with OutputFolder(tmp_path) as out:
        out.write(writers(a="new"), RECORD)
    assert (tmp_path / "a").read_text() == "new"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a", MANIFEST, "notes.txt"]
    assert list(manifest(tmp_path)["files"]) == ["a"]


def test_a_failed_run_removes_the_folder_it_created(tmp_path):
    folder = tmp_path / "new" / "out"
    with pytest.raises(RuntimeError), OutputFolder(folder):
        raise RuntimeError("the computation failed")
    assert not folder.exists()


def test_ctrl_c_while_locking_removes_the_folder_it_created(tmp_path, monkeypatch):
    """Ctrl-C as the new folder is locked and checked again (the lock file already exists):
    the lock is released first, so the folder it created is removed, not left empty."""
    folder = tmp_path / "out"
    out = OutputFolder(folder)

    def interrupted(self):
        assert (folder / LOCK).exists()
        raise KeyboardInterrupt

    monkeypatch.setattr(OutputFolder, "_previous_files", interrupted)
    with pytest.raises(KeyboardInterrupt), out:
        pass
    assert not folder.exists()


def test_an_interrupted_write_is_marked_incomplete_and_cleaned_up_next_time(tmp_path):
    """Ctrl-C after the first output of a run into an earlier run's folder: the manifest says
    the folder is incomplete and lists both runs' files; the next run removes the leftovers."""
    with OutputFolder(tmp_path) as out:
        out.write(writers(a="old", b="old", c="old"), RECORD)

    def interrupted(path):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt), OutputFolder(tmp_path) as out:
        out.write({**writers(x="new"), "y": interrupted}, RECORD)
    record = manifest(tmp_path)
    assert record["complete"] is False and record["finished"] is None
    assert record["files"] == {"x": sha256(tmp_path / "x")} | {
        name: sha256(tmp_path / name) for name in "abc"
    }
    assert (tmp_path / "x").read_text() == "new" and not (tmp_path / LOCK).exists()
    with OutputFolder(tmp_path) as out:
        out.write(writers(z="newest"), RECORD)
    assert sorted(p.name for p in tmp_path.iterdir()) == [MANIFEST, "z"]


def _forged_folder(tmp_path):
    """A run's folder where the user edited output b since, and a forged manifest lists the
    user's own files (under a wrong SHA-256, or none)."""
    with OutputFolder(tmp_path) as out:
        out.write(writers(a="old", b="old"), RECORD)
    (tmp_path / "b").write_text("edited by the user")
    (tmp_path / "thesis.tex").write_text("mine")
    (tmp_path / "notes.txt").write_text("mine too")
    forged = manifest(tmp_path)
    forged["files"] |= {"thesis.tex": "0" * 64, "notes.txt": None}
    (tmp_path / MANIFEST).write_text(json.dumps(forged))
    return sorted(p.name for p in tmp_path.iterdir())


def test_a_folder_with_an_edited_output_is_refused_before_the_run(tmp_path):
    """An output changed since its run (the same name would be written over), or a forged
    manifest: refused before anything is computed, naming the files; nothing is touched."""
    before = _forged_folder(tmp_path)
    with pytest.raises(InputError, match=r"holds b, notes.txt, thesis.tex, changed since"):
        OutputFolder(tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == before
    assert (tmp_path / "b").read_text() == "edited by the user"


def test_a_resumable_run_keeps_a_file_whose_hash_does_not_match_its_manifest(tmp_path):
    """The sweep's folder (it checks its own rows): the next run keeps such files, with a
    warning, and removes only its own."""
    _forged_folder(tmp_path)
    with pytest.warns(FeederWarning) as caught, OutputFolder(tmp_path, resumable=True) as out:
        out.write(writers(z="new"), RECORD)
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "b",
        MANIFEST,
        "notes.txt",
        "thesis.tex",
        "z",
    ]
    assert (tmp_path / "thesis.tex").read_text() == "mine"
    assert (tmp_path / "b").read_text() == "edited by the user"
    assert sorted(str(w.message).split(":")[0] for w in caught) == [
        f"kept {tmp_path / name}" for name in ("b", "notes.txt", "thesis.tex")
    ]
    assert list(manifest(tmp_path)["files"]) == ["z"]


def test_a_resumable_run_keeps_what_it_wrote_when_interrupted(tmp_path):
    """The sweep's folder: an interrupted run leaves its outputs and an incomplete manifest
    with their hashes (a later run resumes them), not an emptied folder."""
    folder = tmp_path / "sweep"
    with pytest.raises(KeyboardInterrupt), OutputFolder(folder, resumable=True) as out:
        out.begin(RECORD)
        out.put("table", lambda path: write_text(path, "rows"))
        raise KeyboardInterrupt
    record = manifest(folder)
    assert record["complete"] is False and record["files"] == {"table": sha256(folder / "table")}
    assert OutputFolder(folder).previous == record["files"]


def test_a_second_run_on_the_folder_is_refused(tmp_path):
    with OutputFolder(tmp_path) as out:
        with pytest.raises(OutputBusyError, match=str(tmp_path)):
            with OutputFolder(tmp_path):
                pass
        out.write(writers(a="1"), RECORD)
    assert manifest(tmp_path)["complete"] is True


def test_write_needs_the_with_block(tmp_path):
    with pytest.raises(InputError, match="with block"):
        OutputFolder(tmp_path).write(writers(a="1"), RECORD)


@pytest.mark.parametrize(
    "files",
    [
        {"../escape": None},
        {"sub/../a": None},
        {"/abs": None},
        {MANIFEST: None},
        {"..": None},
        {"": None},
        "abc",
        [],
    ],
)
def test_a_manifest_that_points_outside_is_refused(tmp_path, files):
    (tmp_path / MANIFEST).write_text(json.dumps({"files": files}))
    with pytest.raises(InputError):
        OutputFolder(tmp_path)


def test_a_corrupt_manifest_is_refused(tmp_path):
    (tmp_path / MANIFEST).write_text("{half")
    with pytest.raises(InputError, match="not a feeder manifest"):
        OutputFolder(tmp_path)


def _run(folder):
    """A folder that a complete run wrote: outputs a and b."""
    with OutputFolder(folder) as out:
        out.write(writers(a="1\n", b="2\n"), RECORD)
    return folder


def test_verified_output_is_the_file_as_its_run_wrote_it(tmp_path):
    assert verified_output(_run(tmp_path / "run"), "a") == tmp_path / "run" / "a"


@pytest.mark.parametrize(
    ("spoil", "name", "match"),
    [
        (lambda f: (f / "a").write_text("9\n"), "a", r"/run/a changed since the run that wrote"),
        (lambda f: (f / "a").write_bytes(b"1\r\n"), "a", r"/run/a changed since"),
        (lambda f: (f / MANIFEST).unlink(), "a", r"/run has no feeder-run.json: not the output"),
        (lambda f: (f / MANIFEST).write_text("{half"), "a", r"/run has a feeder-run.json that is"),
        (
            lambda f: (f / MANIFEST).write_text(json.dumps(manifest(f) | {"complete": False})),
            "a",
            r"/run/feeder-run.json marks its run incomplete",
        ),
        (lambda f: (f / "c").write_text("3\n"), "c", r"/run/c is not an output that .* lists"),
        (lambda f: (f / "a").unlink(), "a", r"/run/a, an output that .* lists, is missing"),
    ],
    ids=["edited", "line-ends", "no-manifest", "corrupt", "incomplete", "unlisted", "missing"],
)
def test_verified_output_refuses_what_its_run_did_not_leave(tmp_path, spoil, name, match):
    """One line naming the file or manifest and the remedy (run it again)."""
    folder = _run(tmp_path / "run")
    spoil(folder)
    with pytest.raises(InputError, match=match) as caught:
        verified_output(folder, name)
    assert "\n" not in str(caught.value) and "run it again" in str(caught.value)


def test_kinematics_outputs_record_the_run(tmp_path, feeder):
    cycle = api.feeding_cycle(feeder, math.radians(30.0), api.CycleSpec(rate=100.0))
    paths = write_kinematics_outputs(feeder, cycle, tmp_path / "k", command="feeder kinematics")
    record = manifest(tmp_path / "k")
    assert list(record["files"]) == [p.name for p in paths]
    assert record["device"] == "projectile" and record["elevation_deg"] == 30.0  # as typed
    assert record["sample_rate_hz"] == 100.0 and record["command"] == "feeder kinematics"
