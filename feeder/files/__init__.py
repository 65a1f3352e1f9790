"""Writing files so that nothing half-written ever looks complete, one writer at a time, and
output folders that hold one run's files and say so.

* :mod:`~feeder.files.atomic` — every output written to a temporary name and renamed into place
  when complete (:func:`atomic_path`, :func:`write_text`), an output of one file replacing only
  the same command's own file (:func:`check_replaceable`);
* :mod:`~feeder.files.lock` — one writer at a time: a folder that a run fills is locked for that
  run (:func:`exclusive_lock`);
* :mod:`~feeder.files.folder` — the output folder of one run and its manifest
  (:class:`OutputFolder`), and a run's output read back only as its run left it
  (:func:`verified_output`).

Import these names from :mod:`feeder.files`. This package imports nothing from feeder but its
exceptions and input checks, so every layer may use it.
"""

from .atomic import HEAD, atomic_path, check_replaceable, path_in, write_text
from .folder import LOCK, MANIFEST, OutputFolder, Writer, verified_output
from .lock import exclusive_lock

__all__ = [
    "HEAD",
    "LOCK",
    "MANIFEST",
    "OutputFolder",
    "Writer",
    "atomic_path",
    "check_replaceable",
    "exclusive_lock",
    "path_in",
    "verified_output",
    "write_text",
]
