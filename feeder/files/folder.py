"""The output folder of one run, with its manifest, and a run's output read back as it was left.

An output folder (:class:`OutputFolder`) holds the outputs of one run:

* It is checked before anything is computed, and nothing is created then: not empty, not a
  file, and a new folder, an empty one, or one that an earlier feeder run wrote (it has a
  manifest). Any other folder is refused: its files could pass for this run's.
* For the run it is created and locked: a second run on the same folder is refused at once. A
  run that fails or is interrupted removes the folder if it created it (a resumable run, the
  sweep, keeps what it wrote, for the next run to resume).
* An output is a file of the folder, or of a subfolder inside it (``meshes/part.stl``: file
  names joined by ``/``, never ``..``, nor a link leading out), which the run creates and
  removes with its last file.
* The manifest :data:`MANIFEST` says which command, feeder version and parameters made the
  outputs, when, and the SHA-256 of each output. It is written first marked incomplete (listing
  the previous run's files with their hashes), updated as each output lands, and marked complete
  once every output is in place; then the previous run's outputs that this run did not rewrite
  are removed, each only if its SHA-256 is still the one its manifest recorded. A folder whose
  earlier output changed since (or whose manifest names a file it did not write) is refused
  before the run, as the run could write over it; a resumable folder keeps such a file, with a
  warning. So the folder never mixes two runs without its manifest saying so, and an edit is
  never lost.

A command that reads a run's output back (``feeder view --run``) takes it only as its run left
it, by the same manifest (:func:`verified_output`): a run that completed, and a file whose
SHA-256 is the one recorded, not one edited since.
"""

from __future__ import annotations

import hashlib
import importlib.metadata
import json
import warnings
from collections.abc import Callable, Mapping
from datetime import UTC, datetime
from pathlib import Path

from ..exceptions import FeederWarning, InputError
from ..validation import check_path
from .atomic import is_plain_name, write_text
from .lock import exclusive_lock

MANIFEST = "feeder-run.json"
"""The manifest of the run that wrote an output folder (JSON)."""

LOCK = ".feeder-run.lock"
"""The lock file of an output folder while a run writes it (removed when the run ends)."""

Writer = Callable[[Path], object]
"""Writes one output file, atomically, at the path it is given."""


class OutputFolder:
    """The output folder of one run: checked now, created and locked in a ``with`` block, and
    written through :meth:`write` (or :meth:`begin`, :meth:`put` for each output, :meth:`finish`).

    Args:
        path: The folder.
        resumable: Keep the outputs written so far (and the incomplete manifest) when the run
            fails or is interrupted, for the next run to resume (default: a failed run removes
            the folder it created).

    Raises:
        InputError: An empty path, a path that is a file or lies under one, a folder that holds
            files but no feeder manifest (or a manifest that cannot be read), or (not
            resumable) an earlier output changed since its run.
    """

    def __init__(self, path: str | Path, resumable: bool = False):
        self.path = check_path("the output folder", path)
        self.resumable = resumable
        self.previous: dict[str, str | None] = self._previous_files()  # the checks, first
        """The outputs the earlier run's manifest lists: name → SHA-256 it recorded."""
        self._created = False
        self._lock = None
        self._manifest: dict[str, object] | None = None
        self._files: dict[str, str] = {}
        self._tried: set[str] = set()

    def __enter__(self) -> OutputFolder:
        try:
            self.path.mkdir(parents=True)  # raises if it exists: of two runs, one created it
            self._created = True
        except FileExistsError:
            self._created = False
        except OSError as exc:
            raise InputError(
                f"cannot create the output folder {self.path}: {exc.strerror or exc}"
            ) from exc
        lock = exclusive_lock(self.path / LOCK, f"the output folder {self.path}")
        try:
            lock.__enter__()
        except BaseException:
            self._remove_if_created()
            raise
        self._lock = lock
        try:
            self.previous = self._previous_files()  # again, now that no other run can change it
        except BaseException as error:
            self.__exit__(type(error), error, error.__traceback__)  # unlock, then clean up
            raise
        return self

    def __exit__(self, kind, error, traceback) -> None:
        self._lock.__exit__(None, None, None)
        self._lock = None
        if kind is not None and not (self.resumable and self._files):
            self._remove_if_created()

    def write(self, outputs: Mapping[str, Writer], record: Mapping[str, object]) -> list[Path]:
        """Write every output (name → writer) and the manifest; remove the previous run's
        outputs that were not rewritten. Returns the paths, in the order of ``outputs``.

        Args:
            outputs: File name (in this folder) → function writing that file atomically.
            record: What the run computed and from what (JSON-serialisable), for the manifest.

        Raises:
            InputError: Not inside the ``with`` block, or a file cannot be written.
        """
        self.begin(record)
        paths = [self.put(name, writer) for name, writer in outputs.items()]
        self.finish()
        return paths

    def begin(self, record: Mapping[str, object]) -> None:
        """Start the run: the manifest, marked incomplete, lists the previous run's outputs.

        Raises:
            InputError: Not inside the ``with`` block.
        """
        if self._lock is None:
            raise InputError(f"write into the output folder {self.path} inside its with block")
        self._manifest = {
            "complete": False,
            **record,
            "feeder_version": importlib.metadata.version("feeder"),
            "started": _now(),
            "finished": None,
        }
        self._files = {}
        self._write_manifest(self.previous)

    def put(self, name: str, writer: Writer) -> Path:
        """Write (or rewrite) the output ``name`` with ``writer`` and record its SHA-256 in the
        incomplete manifest; returns its path.

        Raises:
            InputError: Not begun, a name that is not a file name (or ``/``-separated file
                names: a file in a subfolder, created here, which must lie inside this folder),
                or a file that cannot be written.
        """
        if self._manifest is None or self._lock is None:
            raise InputError(f"begin the run in the output folder {self.path} before writing")
        path = self._output_path(name)
        if name in (MANIFEST, LOCK):
            raise InputError(f"the output {name!r} is the output folder's own file: rename it")
        self._tried.add(name)  # removed after a failure even if written but not yet recorded
        writer(path)
        self._files[name] = _sha256(path)
        left = {n: h for n, h in self.previous.items() if n not in self._files}
        self._write_manifest(self._files | left)
        return path

    def finish(self) -> None:
        """Mark the manifest complete, listing this run's outputs only; then remove each of the
        previous run's outputs that this run did not rewrite, if it is still the file that run
        wrote (its SHA-256 is the one recorded), else keep it and warn."""
        if self._manifest is None or self._lock is None:
            raise InputError(f"begin the run in the output folder {self.path} before finishing")
        self._manifest |= {"complete": True, "finished": _now()}
        self._write_manifest(self._files)
        for name, recorded in self.previous.items():
            path = self.path / name
            if name in self._files or not path.is_file():
                continue
            if not path.resolve().is_relative_to(self.path.resolve()):
                continue  # a link made since leads out of the folder: not this run's to remove
            if recorded is not None and _sha256(path) == recorded:
                path.unlink(missing_ok=True)
                self._prune(name)
            else:
                warnings.warn(
                    f"kept {path}: an earlier run's manifest lists it, but not with its present "
                    "SHA-256 (changed since, or not feeder's); delete it if it is not yours",
                    FeederWarning,
                    stacklevel=2,
                )
        self.previous = dict(self._files)  # for a second write in the same block

    def _output_path(self, name: str) -> Path:
        """The path of the output ``name``: a file name, or file names joined by ``/`` (its
        subfolders created, each a folder inside this one, not a link leading out of it)."""
        if not _is_output_name(name):
            raise InputError(f"the output {name!r} is not a file name in {self.path}: rename it")
        path = self.path / name
        if "/" in name:
            try:
                path.parent.mkdir(parents=True, exist_ok=True)
            except OSError as exc:
                raise InputError(f"cannot write {path}: {exc.strerror or exc}") from exc
            if not path.parent.resolve().is_relative_to(self.path.resolve()):
                raise InputError(f"the output {name!r} would lie outside {self.path}: not written")
        return path

    def _prune(self, name: str) -> None:
        """Remove the subfolders of the output ``name`` (removed) that are now empty."""
        for parent in (self.path / name).parents:
            if parent == self.path or not parent.is_relative_to(self.path):
                return
            try:
                parent.rmdir()
            except OSError:
                return  # not empty (or gone): its parents are not empty either

    def _previous_files(self) -> dict[str, str | None]:
        """The outputs an earlier run listed in this folder's manifest, with their SHA-256
        ({} for a new or empty folder); raises if the folder is not an output folder."""
        if not self.path.exists():
            parent = next(p for p in self.path.parents if p.exists())
            if not parent.is_dir():
                raise InputError(
                    f"cannot create the output folder {self.path}: {parent} is a file"
                )
            return {}
        if not self.path.is_dir():
            raise InputError(f"the output folder {self.path} is a file")
        manifest = self.path / MANIFEST
        if not manifest.is_file():
            others = sorted(p.name for p in self.path.iterdir() if p.name != LOCK)
            if others:
                raise InputError(
                    f"the output folder {self.path} holds files that no feeder run wrote "
                    f"({', '.join(others[:3])}{', …' if len(others) > 3 else ''}): choose a new "
                    "or empty folder"
                )
            return {}
        remedy = "choose a new or empty folder"
        files = _read_manifest(manifest, f"the output folder {self.path}", remedy)["files"]
        if not self.resumable:  # a resumable run checks its own rows
            changed = _changed(self.path, files)
            if changed:
                raise InputError(
                    f"the output folder {self.path} holds {', '.join(changed)}, changed "
                    "since the run that wrote it (or not feeder's): this run could overwrite "
                    "it; move it away, or choose a new folder"
                )
        return files

    def _write_manifest(self, files: Mapping[str, str | None]) -> None:
        manifest = {**self._manifest, "files": dict(files)}
        write_text(self.path / MANIFEST, json.dumps(manifest, indent=2, ensure_ascii=False) + "\n")

    def _remove_if_created(self) -> None:
        """After a failed run: remove the folder if this run created it (its files only)."""
        if not self._created:
            return
        for name in [*self._tried, MANIFEST]:
            (self.path / name).unlink(missing_ok=True)
            self._prune(name)
        try:
            self.path.rmdir()
        except OSError:
            pass  # something else was put there meanwhile: leave it
        self._created = False


def _is_output_name(name: object) -> bool:
    """Whether ``name`` names a file in an output folder: a plain file name, or plain names
    joined by ``/`` (a file in a subfolder; no ``..``, no absolute path)."""
    return isinstance(name, str) and all(is_plain_name(part) for part in name.split("/"))


def verified_output(folder: str | Path, name: str) -> Path:
    """``folder / name`` as the feeder run that wrote ``folder`` left it: the folder's manifest
    (:data:`MANIFEST`) is feeder's, marks the run complete and records the file's present
    SHA-256 (the check an output folder makes before a run writes over it).

    Raises:
        InputError: A folder without a manifest, a manifest that is not feeder's, a run that
            did not complete, or a file that the manifest does not list or that changed since
            (edited): the message names the file and the remedy.
    """
    folder = Path(folder)
    manifest = folder / MANIFEST
    if not manifest.is_file():
        raise InputError(
            f"{folder} has no {MANIFEST}: not the output folder of a feeder run, whose files "
            "could have been edited; run it again into a new folder"
        )
    remedy = "run it again into a new folder"
    record = _read_manifest(manifest, f"the run folder {folder}", remedy)
    if record.get("complete") is not True:
        raise InputError(
            f"{manifest} marks its run incomplete (it failed, was interrupted or is still "
            f"writing): {remedy}"
        )
    path = folder / name
    if name not in record["files"]:
        raise InputError(f"{path} is not an output that {manifest} lists: {remedy}")
    if not path.is_file():
        raise InputError(f"{path}, an output that {manifest} lists, is missing: {remedy}")
    if _changed(folder, {name: record["files"][name]}):
        raise InputError(
            f"{path} changed since the run that wrote it (its SHA-256 is not the one {manifest} "
            f"records): {remedy}"
        )
    return path


def _read_manifest(manifest: Path, what: str, remedy: str) -> dict[str, object]:
    """The manifest ``manifest`` of ``what`` (a folder, for messages), checked: a JSON object
    whose ``files`` map output names (:func:`_is_output_name`) to SHA-256 texts (or None).

    Raises:
        InputError: Anything else, with ``remedy``.
    """
    try:
        record = json.loads(manifest.read_text(encoding="utf-8"))
        files = record["files"]
        if not isinstance(files, dict):
            raise TypeError(f"its files are {files!r}, not a table of names")
        if not all(h is None or isinstance(h, str) for h in files.values()):
            raise TypeError("its hashes are not text")
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise InputError(
            f"{what} has a {MANIFEST} that is not a feeder manifest ({exc}): {remedy}"
        ) from exc
    if not all(_is_output_name(name) and name not in (MANIFEST, LOCK) for name in files):
        raise InputError(
            f"the manifest {manifest} lists files outside its folder: {list(files)}; {remedy}"
        )
    return record


def _changed(folder: Path, files: Mapping[str, str | None]) -> list[str]:
    """The names, sorted, of the files in ``folder`` whose SHA-256 is not the one ``files``
    records (a file that is not there has not changed: it is not there to overwrite)."""
    return sorted(
        name
        for name, recorded in files.items()
        if (folder / name).is_file() and _sha256(folder / name) != recorded
    )


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _now() -> str:
    return datetime.now(UTC).isoformat(timespec="seconds")
