"""Sweeps (feeder.study.sweep, sweep_folder, elevation_sweeps): the peaks of each case's cycle,
in memory and as a resumable table, on local worker processes and on a Dask cluster
(LocalCluster on 127.0.0.1)."""

from __future__ import annotations

import csv
import hashlib
import json
import math
import signal
import socket
from concurrent.futures import Executor, Future
from functools import partial

import numpy as np
import pytest

from feeder.chain import BaseMotion, Recoil
from feeder.device.feeder import load_feeder
from feeder.device.parameters import VEHICLE_FORWARD
from feeder.dynamics.cycle import cycle_dynamics
from feeder.dynamics.servo import ServoGains
from feeder.exceptions import ElevationError, InputError, OutputBusyError
from feeder.files import LOCK, MANIFEST, OutputFolder, exclusive_lock
from feeder.motion.laws import CycleSpec
from feeder.study import sweep as sweep_module
from feeder.study import sweep_folder
from feeder.study.elevation_sweeps import elevation_sweep, sweeps_of
from feeder.study.grid import Variant, elevation_range, make_grid
from feeder.study.peaks import cycle_peaks
from feeder.study.sweep_folder import run_sweep
from feeder.study.sweep_table import (
    LOADING_COLUMNS,
    PARQUET,
    QUANTITIES,
    TABLE,
    TABLE_COLUMNS,
    read_sweep_table,
    row_sha256,
)
from feeder.viz.png import write_png
from feeder.viz.report import sweep_pngs

SWEEP_SPEC = CycleSpec(rate=100.0)
"""100 Hz: below the forward run's minimum rate, which a sweep does not need; fast."""

ELEVATIONS = (-4.0, 20.0, 70.0)
REFERENCE = (Variant("reference"),)


def sha256(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _grid(elevations=ELEVATIONS, variants=REFERENCE, spec=SWEEP_SPEC):
    return make_grid(("projectile", "charge"), elevations, variants, spec)


def test_sweep_peaks_are_the_cycles_peaks(feeder, capsys):
    """The sweep needs no forward run (so no minimum rate), and is quiet off a terminal."""
    elevations = np.radians([-4.0, 50.0])
    sweep = elevation_sweep(feeder, elevations, SWEEP_SPEC)
    assert capsys.readouterr().err == ""
    np.testing.assert_array_equal(sweep.elevations, elevations)
    for k, elevation in enumerate(elevations):
        peaks = cycle_peaks(cycle_dynamics(feeder, elevation, SWEEP_SPEC, forward=False))
        assert list(sweep.peaks) == [peak.name for peak in peaks]
        for peak in peaks:
            assert sweep.peaks[peak.name][k] == peak.value
            assert sweep.times[peak.name][k] == peak.time
            assert sweep.units[peak.name] == peak.unit


def test_worker_processes_give_the_same_numbers(feeder):
    elevations = np.radians(ELEVATIONS)
    here = elevation_sweep(feeder, elevations, SWEEP_SPEC, progress=False, workers=1)
    pool = elevation_sweep(feeder, elevations, SWEEP_SPEC, progress=False, workers=2)
    for name in here.peaks:
        np.testing.assert_array_equal(pool.peaks[name], here.peaks[name], err_msg=name)


@pytest.mark.parametrize("bad", [[], np.zeros((2, 2)), 0.1, [0.1, float("nan")]])
def test_sweep_needs_a_list_of_finite_elevations(feeder, bad):
    with pytest.raises(InputError, match="elevations"):
        elevation_sweep(feeder, bad)


def test_sweep_checks_every_elevation_first(feeder):
    with pytest.raises(ElevationError, match="elevation 80° is outside"):
        elevation_sweep(feeder, np.radians([10.0, 80.0]))


@pytest.mark.parametrize("workers", [0, -1, 1.5, True, "2"])
def test_workers_must_be_a_positive_whole_number(feeder, workers):
    with pytest.raises(InputError, match="workers"):
        elevation_sweep(feeder, np.radians([10.0]), SWEEP_SPEC, workers=workers)


def test_table_has_one_row_per_case_with_its_peaks(tmp_path):
    """Each row is the case's own cycle reduced to its peaks; a heavier payload needs a larger
    piston force at every elevation (the physics, not the code, says so)."""
    grid = _grid(variants=(Variant("reference"), Variant("heavier", {"mass_factor": 1.2})))
    path = run_sweep(grid, tmp_path, progress=False).table
    assert path == tmp_path / TABLE
    rows, rejected = read_sweep_table(path)
    assert rejected == []
    assert path.read_text(encoding="utf-8").splitlines()[0].split(",") == list(TABLE_COLUMNS)
    assert [(r["device"], r["variant"], r["elevation_deg"]) for r in rows] == [
        case.key for case in grid.cases()
    ]
    case = grid.cases()[4]  # the projectile, heavier, at 20°
    peaks = cycle_peaks(
        cycle_dynamics(
            sweep_module.cached_feeder(case.params), case.elevation, SWEEP_SPEC, forward=False
        )
    )
    assert [peak.name for peak in peaks] == list(QUANTITIES)  # the table's columns
    for peak in peaks:
        assert rows[4][peak.name] == peak.value and rows[4][f"{peak.name}_time"] == peak.time
    sweeps = sweeps_of(rows)
    for device in ("projectile", "charge"):
        heavier, reference = sweeps[(device, "heavier")], sweeps[(device, "reference")]
        np.testing.assert_array_equal(np.degrees(reference.elevations), ELEVATIONS)
        assert np.all(
            np.abs(heavier.peaks["piston_force"]) > np.abs(reference.peaks["piston_force"])
        )
        assert reference.units["piston_force"] == "N"


def test_resumes_computing_only_the_missing_cases(tmp_path, monkeypatch):
    first = run_sweep(_grid(elevations=(-4.0, 20.0)), tmp_path, progress=False, workers=1).table
    before = first.read_text(encoding="utf-8").splitlines()
    computed = []
    original = sweep_module.case_peaks

    def counting(case):
        computed.append(case.key)
        return original(case)

    monkeypatch.setattr(sweep_module, "case_peaks", counting)
    outputs = run_sweep(_grid(), tmp_path, progress=False, workers=1)
    assert computed == [("projectile", "reference", 70.0), ("charge", "reference", 70.0)]
    assert (outputs.kept, outputs.computed) == (4, 2)
    after = first.read_text(encoding="utf-8").splitlines()
    assert len(after) == 1 + 6
    assert set(before) <= set(after)  # the earlier rows, untouched to the last digit
    computed.clear()
    outputs = run_sweep(_grid(), tmp_path, progress=False, workers=1)
    assert computed == [] and (outputs.kept, outputs.computed) == (6, 0)
    assert json.loads((tmp_path / MANIFEST).read_text())["files"] == {TABLE: sha256(first)}


def test_an_interrupted_sweep_keeps_what_it_finished(tmp_path, monkeypatch):
    original = sweep_module.case_peaks
    calls = []

    def interrupted(case):
        calls.append(case.key)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return original(case)

    monkeypatch.setattr(sweep_module, "case_peaks", interrupted)
    monkeypatch.setattr(sweep_folder, "CHECKPOINT_SECONDS", 3600.0)  # only the final save
    with pytest.raises(KeyboardInterrupt):
        run_sweep(_grid(), tmp_path, progress=False, workers=1)
    rows, _ = read_sweep_table(tmp_path / TABLE)
    assert len(rows) == 2
    record = json.loads((tmp_path / MANIFEST).read_text())
    assert record["complete"] is False and record["files"] == {TABLE: sha256(tmp_path / TABLE)}
    monkeypatch.setattr(sweep_module, "case_peaks", original)
    outputs = run_sweep(_grid(), tmp_path, progress=False, workers=1)
    rows, _ = read_sweep_table(outputs.table)
    assert len(rows) == 6 and (outputs.kept, outputs.computed) == (2, 4)


def test_refuses_a_folder_of_another_sweep(tmp_path):
    run_sweep(_grid(elevations=(20.0,)), tmp_path, progress=False, workers=1)
    with pytest.raises(InputError, match="other parameters or timing"):
        run_sweep(_grid(elevations=(20.0,), spec=CycleSpec(rate=50.0)), tmp_path, workers=1)
    with pytest.raises(InputError, match="not in this sweep"):
        run_sweep(_grid(elevations=(30.0,)), tmp_path, progress=False, workers=1)


def test_one_sweep_at_a_time_per_folder(tmp_path):
    with exclusive_lock(tmp_path / LOCK, "a sweep folder"):
        with pytest.raises(OutputBusyError, match="another feeder run"):
            run_sweep(_grid(), tmp_path, progress=False, workers=1)
    assert not (tmp_path / TABLE).exists()
    run_sweep(_grid(elevations=(0.0,)), tmp_path, progress=False, workers=1)
    assert not (tmp_path / LOCK).exists()


def test_refuses_an_unwritable_folder(tmp_path):
    blocker = tmp_path / "a_file"
    blocker.write_text("")
    with pytest.raises(InputError, match="cannot create the output folder"):
        run_sweep(_grid(), blocker / "sub", progress=False)


def test_overrides_of_devices_and_elevations(tmp_path):
    outputs = run_sweep(
        None, tmp_path, devices=["charge"], elevations=[0.0, 10.0], workers=1, progress=False
    )
    rows, _ = read_sweep_table(outputs.table)
    assert [(r["device"], r["elevation_deg"]) for r in rows] == [("charge", 0.0), ("charge", 10.0)]


def test_parquet_copy_holds_the_same_table(tmp_path):
    pq = pytest.importorskip("pyarrow.parquet", reason="pyarrow (the parquet extra) not installed")
    run_sweep(_grid(), tmp_path, progress=False, parquet=True)
    rows, _ = read_sweep_table(tmp_path / TABLE)
    table = pq.read_table(tmp_path / PARQUET).to_pydict()
    assert list(table) == list(TABLE_COLUMNS)
    for name in TABLE_COLUMNS[:-1]:  # nan: the controlled run's columns, none in this grid
        same = [
            a == b or (a != a and b != b)
            for a, b in zip(table[name], [r[name] for r in rows], strict=True)
        ]
        assert len(table[name]) == len(rows) and all(same), name
    written = list(csv.reader((tmp_path / TABLE).open(encoding="utf-8")))[1:]
    assert table["row_sha256"] == [cells[-1] for cells in written]


def figure_writers(table):
    """What ``feeder sweep`` passes: the figures of the finished table."""
    return {name: partial(write_png, png=png) for name, png in sweep_pngs(table).items()}


def test_the_table_and_a_figure_per_device_with_their_manifest(tmp_path):
    outputs = run_sweep(_grid(), tmp_path, progress=False, figures=figure_writers, command="x")
    paths = outputs.files[1:]
    assert sorted(p.name for p in paths) == ["sweep_charge.png", "sweep_projectile.png"]
    for path in paths:
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > 20_000
    record = json.loads((tmp_path / MANIFEST).read_text())
    assert record["complete"] is True and record["command"] == "x"
    assert record["files"] == {path.name: sha256(path) for path in outputs.files}
    assert record["sweep"]["devices"] == ["projectile", "charge"]
    assert record["sweep"]["elevations_deg"] == list(ELEVATIONS)
    assert OutputFolder(tmp_path).previous == record["files"]  # any run takes the folder over


def test_refuses_a_folder_of_other_files_and_leaves_them(tmp_path):
    """A folder that no feeder run wrote, e.g. docs/ holding a tracked sweep_projectile.png."""
    (tmp_path / "sweep_projectile.png").write_text("the user's picture")
    with pytest.raises(InputError, match="no feeder run wrote"):
        run_sweep(_grid(), tmp_path, progress=False, figures=figure_writers)
    assert [p.name for p in tmp_path.iterdir()] == ["sweep_projectile.png"]
    assert (tmp_path / "sweep_projectile.png").read_text() == "the user's picture"


def test_a_sweep_replaces_another_runs_outputs(tmp_path):
    """The folder of an earlier feeder run (not a sweep): its outputs are replaced."""
    with OutputFolder(tmp_path) as out:
        out.write({"cycle.csv": lambda path: path.write_text("t\n0\n")}, {"command": "c"})
    outputs = run_sweep(_grid(elevations=(20.0,)), tmp_path, progress=False, workers=1)
    assert outputs.kept == 0 and sorted(p.name for p in tmp_path.iterdir()) == [MANIFEST, TABLE]


@pytest.mark.parametrize("address", ["127.0.0.1:8786", "http://127.0.0.1:8786", "tcp://host"])
def test_scheduler_address_must_be_tcp_host_port(tmp_path, address):
    with pytest.raises(InputError, match="tcp://HOST:PORT"):
        run_sweep(_grid(), tmp_path, scheduler=address)


def test_no_scheduler_at_the_address(tmp_path, monkeypatch):
    pytest.importorskip("distributed", reason="dask.distributed (the cluster extra) not installed")
    with socket.socket() as probe:  # a port on which nothing listens
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    monkeypatch.setattr(sweep_module, "SCHEDULER_TIMEOUT", 1.0)
    with pytest.raises(InputError, match="no Dask scheduler answers"):
        run_sweep(_grid(), tmp_path, scheduler=f"tcp://127.0.0.1:{port}", progress=False)


def test_dask_cluster_gives_the_table_of_the_local_run(tmp_path, dask_scheduler):
    """The same cases through a Dask LocalCluster (two worker processes on 127.0.0.1) give the
    same table, to the last digit, as the local process pool."""
    grid = _grid(variants=(Variant("reference"), Variant("longer", {"length_factor": 1.15})))
    local = run_sweep(grid, tmp_path / "local", progress=False)
    remote = run_sweep(grid, tmp_path / "dask", scheduler=dask_scheduler, progress=False)
    assert remote.table.read_text(encoding="utf-8") == local.table.read_text(encoding="utf-8")


def test_peak_times_lie_in_the_cycle(tmp_path):
    rows, _ = read_sweep_table(run_sweep(_grid(), tmp_path, progress=False).table)
    end = float(SWEEP_SPEC.boundaries[-1])
    for row in rows:
        times = [value for name, value in row.items() if name.endswith("_time")]
        assert all(0.0 <= t <= end for t in times)
        assert math.isfinite(row["piston_force"])


def _edit_table(path, edit) -> None:
    """Rewrite the table's lines (header first, each a list of cells) through ``edit``."""
    with path.open(encoding="utf-8", newline="") as handle:
        lines = edit(list(csv.reader(handle)))
    with path.open("w", encoding="utf-8", newline="") as handle:
        csv.writer(handle, lineterminator="\n").writerows(lines)


@pytest.mark.parametrize("figures", [figure_writers, None])
@pytest.mark.parametrize("edit", ["missing", "unknown"])
def test_a_table_of_other_columns_is_refused_not_resumed(tmp_path, figures, edit):
    """A table without ``grip_force`` (or with a foreign column) is another version's or was
    edited as a whole: refused before any work, naming the column and the remedy, and left as
    it was (recomputing every row would discard the user's file without asking)."""
    run_sweep(_grid(elevations=(20.0,)), tmp_path, progress=False, workers=1)

    def change(lines):
        if edit == "unknown":
            return [[*cells, "note" if k == 0 else "1.0"] for k, cells in enumerate(lines)]
        dropped = lines[0].index("grip_force")
        return [cells[:dropped] + cells[dropped + 1 :] for cells in lines]

    _edit_table(tmp_path / TABLE, change)
    before = sha256(tmp_path / TABLE)
    named = "no column grip_force" if edit == "missing" else "unknown column note"
    with pytest.raises(InputError, match=f"{named}\\): delete it to start afresh"):
        run_sweep(_grid(elevations=(20.0,)), tmp_path, progress=False, workers=1, figures=figures)
    assert sha256(tmp_path / TABLE) == before


def test_the_command_refuses_a_table_of_other_columns_in_one_line(tmp_path, capsys):
    from feeder.__main__ import main

    arguments = ["sweep", "--elevations", "20", "20", "1", "--workers", "1", "--out"]
    assert main([*arguments, str(tmp_path), "--no-figures"]) == 0
    _edit_table(tmp_path / TABLE, lambda lines: [cells[:-2] for cells in lines])
    capsys.readouterr()
    assert main([*arguments, str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no columns" in err and "delete it" in err, err


def test_rows_that_fail_their_checks_are_recomputed(tmp_path, monkeypatch):
    """A half-finished table with a NaN peak (its checksum redone, as a buggy run would write
    it), a duplicated case row and an edited value: those rows are dropped, their cases computed
    again, the summary says how many and why, and the table ends as a fresh run writes it."""
    grid = _grid()
    fresh = run_sweep(grid, tmp_path / "fresh", progress=False, workers=1).table
    out = tmp_path / "resumed"
    run_sweep(grid, out, progress=False, workers=1)

    def damage(lines):
        header = lines[0]
        force = header.index("piston_force")
        nan = lines[1][:-1]
        nan[force] = "nan"
        lines[1] = [*nan, row_sha256(nan)]
        lines[5][force] = str(float(lines[5][force]) * 1.01)  # the checksum left as it was
        return [*lines, lines[3]]  # line 3's case twice

    _edit_table(out / TABLE, damage)
    computed = []
    original = sweep_module.case_peaks

    def counting(case):
        computed.append(case.key)
        return original(case)

    monkeypatch.setattr(sweep_module, "case_peaks", counting)
    outputs = run_sweep(grid, out, progress=False, workers=1)
    cases = grid.cases()
    assert sorted(computed) == sorted([cases[0].key, cases[2].key, cases[4].key])
    assert (outputs.kept, outputs.computed) == (3, 3)
    assert outputs.dropped == {"non-finite value": 1, "duplicated": 2, "checksum mismatch": 1}
    assert outputs.summary() == (
        "6 cases: 3 kept from the earlier table, 3 computed (4 earlier rows recomputed: "
        "1 non-finite value, 2 duplicated, 1 checksum mismatch)"
    )
    assert outputs.table.read_text(encoding="utf-8") == fresh.read_text(encoding="utf-8")
    record = json.loads((out / MANIFEST).read_text())
    assert record["earlier_rows_dropped"] == outputs.dropped


def test_a_row_moved_to_another_case_fails_its_checksum(tmp_path):
    """A row whose elevation was changed to another case of the sweep is not taken for that
    case: its checksum (row_sha256) no longer matches its cells."""
    run_sweep(_grid(), tmp_path, progress=False, workers=1)

    def move(lines):
        lines[1][lines[0].index("elevation_deg")] = "70.0"
        return lines

    _edit_table(tmp_path / TABLE, move)
    rows, rejected = read_sweep_table(tmp_path / TABLE)
    assert rejected == [(2, "checksum mismatch")] and len(rows) == 5


def test_a_typo_of_a_step_is_refused_before_any_work():
    """−4° … 70° by 0.0001° is 740 001 cases (~4 h on 2 cores): refused, saying what to do."""
    with pytest.raises(InputError, match=r"740001 elevations .*use a larger elevation step"):
        elevation_range(-4.0, 70.0, 0.0001)
    with pytest.raises(InputError, match=r"100002 cases \(50001 elevations × 1 variants × 2"):
        make_grid(("projectile", "charge"), elevation_range(0.0, 50.0, 0.001), REFERENCE)


class _InterruptedExecutor(Executor):
    """An executor whose third submit meets a Ctrl-C; its futures never run."""

    def __init__(self):
        self.futures = []

    def submit(self, fn, /, *args, **kwargs):
        if len(self.futures) == 2:
            raise KeyboardInterrupt
        self.futures.append(Future())
        return self.futures[-1]


def test_ctrl_c_while_submitting_cancels_what_was_submitted():
    """A large sweep takes seconds to submit its batches: a Ctrl-C meanwhile must cancel the
    ones already submitted (once, they all ran before the sweep could end)."""
    executor = _InterruptedExecutor()
    with pytest.raises(KeyboardInterrupt):
        list(sweep_module.run_cases(_grid().cases(), executor, slots=1, progress=False))
    assert len(executor.futures) == 2 and all(f.cancelled() for f in executor.futures)


def test_workers_leave_ctrl_c_to_the_sweep():
    """Workers ignore SIGINT (the terminal sends it to them too; the sweep stops them), and do
    not keep it blocked from the fork, where it was held back."""
    with sweep_module.sweep_executor(workers=2) as (executor, _):
        assert executor.submit(signal.getsignal, signal.SIGINT).result() == signal.SIG_IGN
        held = executor.submit(signal.pthread_sigmask, signal.SIG_BLOCK, set()).result()
        assert signal.SIGINT not in held


def test_a_controlled_variant_adds_its_loading_pose_on_every_executor(tmp_path, dask_scheduler):
    """A variant with the controlled run (the hull rocking after a shot at t = 3 s): its rows
    hold the loading pose, settling, peaks and saturation of that run (the numbers of the run
    made directly), the other variant's rows nan there; the Dask cluster gives the same table,
    to the last digit."""
    spec = CycleSpec(rate=100.0)
    servo = ServoGains(bandwidth_hz=8.0)
    base = BaseMotion((Recoil(start=3.0),), VEHICLE_FORWARD)
    grid = make_grid(
        ("projectile",),
        (70.0,),
        (Variant("reference"), Variant("loop", base=base, servo=servo)),
        spec,
    )
    local = run_sweep(grid, tmp_path / "local", workers=1, progress=False)
    rows = {
        row["variant"]: row
        for row in read_sweep_table(local.table)[0]
        if row["device"] == "projectile"
    }
    assert all(math.isnan(rows["reference"][name]) for name in LOADING_COLUMNS)
    direct = cycle_dynamics(
        load_feeder(), math.radians(70.0), spec, base=base, forward=False, controlled=servo
    )
    run = direct.controlled
    pose = run.loading_pose()
    expected = {
        "loading_off_line": pose.off_line,
        "loading_along_line": pose.along_line,
        "loading_angle": pose.angle,
        "loading_settling": pose.settle_time,
        "controlled_peak_pressure": run.pressures.peak()[: run.cycle_samples].max(),
        "controlled_peak_rack_force": np.abs(run.rack_force[: run.cycle_samples]).max(),
    }
    for name, value in expected.items():
        assert rows["loop"][name] == value, name
    assert pose.off_line > 1e-6  # the hull moves the payload: the numbers are not round-off
    assert rows["loop"]["controlled_saturated_duration"] == 0.0
    remote = run_sweep(grid, tmp_path / "dask", scheduler=dask_scheduler, progress=False)
    assert remote.table.read_text(encoding="utf-8") == local.table.read_text(encoding="utf-8")


def _finish_spread(sizes: list[int], slots: int) -> int:
    """How many cases apart the slots finish when each takes the next batch as it frees up
    (equal cases: a batch's time is its size)."""
    free = [0] * slots
    for size in sizes:
        k = free.index(min(free))
        free[k] += size
    return max(free) - min(free)


@pytest.mark.parametrize(("count", "slots"), [(75, 2), (1000, 2), (75, 8), (7, 4), (1, 2)])
def test_batches_shrink_so_the_slots_finish_together(count, slots):
    """Guided batches: every case once, in order, none larger than MAX_BATCH, non-increasing;
    the slots finish within one case of each other (equal batches of ⌈75/16⌉ = 5 cases left two
    slots five apart)."""
    sizes = sweep_module.batch_sizes(count, slots)
    assert sum(sizes) == count
    assert all(1 <= size <= sweep_module.MAX_BATCH for size in sizes)
    assert sizes == sorted(sizes, reverse=True)
    assert _finish_spread(sizes, slots) <= 1
    if (count, slots) == (75, 2):
        assert _finish_spread([5] * 15, 2) == 5  # the equal batches this replaced


class _RecordingExecutor(Executor):
    """Runs each batch at once and keeps the cases it was given."""

    def __init__(self):
        self.batches = []

    def submit(self, fn, /, *args, **kwargs):
        self.batches.append(args[1])
        future = Future()
        future.set_result([case.key for case in args[1]])
        return future


def test_every_case_is_submitted_once_in_order():
    cases = _grid().cases()
    executor = _RecordingExecutor()
    keys = list(sweep_module.run_cases(cases, executor, slots=2, progress=False))
    assert [case for batch in executor.batches for case in batch] == cases
    assert [len(batch) for batch in executor.batches] == sweep_module.batch_sizes(len(cases), 2)
    assert sorted(keys) == sorted(case.key for case in cases)
