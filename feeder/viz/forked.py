"""Processes forked from this one to draw figures, and the lean import of matplotlib they use.

A :class:`ForkedDrawing` is a process forked from this single-threaded one (it has every module
and every object of this process already): it prepares (imports what drawing needs, while this
process goes on computing), then waits for one piece of work, a picklable callable, sent
through a pipe (:meth:`~ForkedDrawing.send`) unless it was given before forking, and answers
with its result, or the error it met, through another (:meth:`~ForkedDrawing.result`). The
figure worker's extra processes and the sweep's figure process (:mod:`feeder.viz.report`)
and a mechanism's figure process (:mod:`feeder.viz.mechanism_figures`, through
:class:`FigureProcess`) are all such processes.

Such a process (and the figure worker of :class:`~feeder.viz.report.FigureWorkers`, a pool's
forked worker) runs nothing but feeder's drawing, and ends without returning into the caller's
code: it imports matplotlib lean (:func:`import_matplotlib`), without the text of the ``set``
docstrings that matplotlib builds for every artist class as it is defined (a third of importing
it: 0.1 s of CPU), which nobody reads there, and keeps the objects of its imports out of the
garbage collector's passes (:func:`freeze_imports`).
"""

from __future__ import annotations

import contextlib
import gc
import os
import pickle
import signal
import sys
from collections.abc import Callable
from typing import TypeVar

from ..workers import fork_safe, interrupts_held, worker_signals

T = TypeVar("T")


def import_matplotlib() -> None:
    """Import matplotlib's figure and its Agg canvas without building the artists' ``set``
    docstrings: matplotlib writes each from the properties of its class, as it defines the
    class (:func:`matplotlib.artist.kwdoc`, 0.1 s of CPU over its 100 classes). Meant for a
    process that only draws (:class:`ForkedDrawing`): there ``kwdoc`` gives an empty text while
    the modules load, and is restored after; the docstrings, nothing else, are left short. A
    process that has matplotlib loaded already, or a matplotlib without ``kwdoc``, imports as
    usual."""
    if "matplotlib.figure" in sys.modules:
        return
    import matplotlib.artist

    kwdoc = getattr(matplotlib.artist, "kwdoc", None)
    if kwdoc is not None:
        matplotlib.artist.kwdoc = _no_kwdoc
    try:
        import matplotlib.backends.backend_agg
        import matplotlib.figure  # noqa: F401
    finally:
        if kwdoc is not None:
            matplotlib.artist.kwdoc = kwdoc


def freeze_imports() -> None:
    """Keep every object this process holds now out of the garbage collector's later passes
    (:func:`gc.freeze`): in a process that only draws, once its imports are done (matplotlib,
    Pinocchio, feeder: some 80 000 objects), the collector's passes over them were 5 % of
    drawing the figures; it still collects the figures' own garbage."""
    gc.freeze()


def _no_kwdoc(artist: object) -> str:
    """The empty list of an artist's properties (:func:`import_matplotlib`)."""
    return ""


class ForkedDrawing:
    """A process forked from this single-threaded one (the caller checks
    :func:`feeder.workers.fork_safe`) that runs ``prepare`` (its errors are met again, and
    sent, by the work), then waits for one piece of work (:meth:`send`) and answers with its
    result (:meth:`result`); a process never sent any ends at :meth:`close`, one whose answer
    nobody will read at :meth:`stop`. It leaves Ctrl-C to this process and ends on SIGTERM
    (:func:`feeder.workers.worker_signals`).

    Args:
        prepare: What to do before the work arrives (e.g. imports).
        what: What the process does, for the text of an error that does not pickle.
        work: The work, known before forking: the process inherits it (nothing is sent through
            the pipe; :meth:`send` is not called) and starts on it at once.
    """

    def __init__(
        self,
        prepare: Callable[[], None] | None = None,
        what: str = "drawing",
        work: Callable[[], object] | None = None,
    ):
        request_read, request_write = os.pipe()
        answer_read, answer_write = os.pipe()
        try:
            with interrupts_held():  # a Ctrl-C now is this process's, not the child's
                pid = os.fork()
                if pid == 0:
                    os.close(request_write)
                    os.close(answer_read)
                    _serve(request_read, answer_write, prepare, what, work)  # never returns
        except BaseException:  # no process: no pipes
            for fd in (request_read, request_write, answer_read, answer_write):
                os.close(fd)
            raise
        os.close(request_read)
        os.close(answer_write)
        self.pid = pid
        self._request: int | None = request_write
        self._answer: int | None = answer_read
        self._answered: tuple[bool, object] | None = None
        if work is not None:
            self._close_request()

    def send(self, work: Callable[[], object]) -> None:
        """Send the work (a picklable callable, e.g. a :func:`functools.partial` of a module's
        function); the process starts on it at once."""
        request, self._request = self._request, None
        with os.fdopen(request, "wb") as pipe:
            pipe.write(pickle.dumps(work))

    def result(self) -> object:
        """The work's result, once the process has ended.

        Raises:
            Exception: The error the work met (or a RuntimeError if the process ended without
                an answer).
        """
        done, value = self.answer()
        if not done:
            raise value
        return value

    def answer(self) -> tuple[bool, object]:
        """``(True, the work's result)`` or ``(False, the error it met)``, once the process
        has ended (:meth:`result` raises the error); read once, the same answer after."""
        if self._answered is None:
            answer, self._answer = self._answer, None
            with os.fdopen(answer, "rb") as stream:
                data = stream.read()
            _, status = os.waitpid(self.pid, 0)
            if data:
                self._answered = pickle.loads(data)
            else:
                code = os.waitstatus_to_exitcode(status)
                error = RuntimeError(f"a figure process ended with status {code} and no answer")
                self._answered = (False, error)
        return self._answered

    def close(self) -> None:
        """End a process never sent any work (it ends at its request's end) and reap it; one
        sent work is left to finish and its answer read (:meth:`answer`)."""
        self._close_request()
        if self._answer is not None:
            self.answer()

    def stop(self) -> None:
        """End the process at once if its answer was not read (SIGTERM: a process whose answer
        nobody reads would wait forever to write it), close its pipes and reap it."""
        if self._answer is None:
            return
        with contextlib.suppress(ProcessLookupError):
            os.kill(self.pid, signal.SIGTERM)
        self._close_request()
        os.close(self._answer)
        self._answer = None
        os.waitpid(self.pid, 0)
        self._answered = (False, RuntimeError("a figure process was stopped before it answered"))

    def _close_request(self) -> None:
        if self._request is not None:
            os.close(self._request)
            self._request = None


def _serve(
    request: int,
    answer: int,
    prepare: Callable[[], None] | None,
    what: str,
    work: Callable[[], object] | None,
) -> None:
    """The forked process of :class:`ForkedDrawing`: prepare, read the work (unless it has it
    already), write ``(True, its result)`` or ``(False, the error it met)``, pickled, and end
    (never returning into the parent's code)."""
    status = 1
    try:
        worker_signals()  # Ctrl-C is the parent's; SIGTERM ends it (feeder.workers)
        if prepare is not None:
            with contextlib.suppress(Exception):  # an import error is met again, and sent
                prepare()
        freeze_imports()
        with os.fdopen(request, "rb") as pipe:
            sent = None if work is not None else pipe.read()
        if sent == b"":  # the pipe closed unasked, or an interruption
            status = 0
            return
        try:
            reply = pickle.dumps((True, (work if sent is None else pickle.loads(sent))()))
        except Exception as exc:  # sent to the parent, which raises it
            try:
                reply = pickle.dumps((False, exc))
            except Exception:  # an error that does not pickle: its text
                reply = pickle.dumps((False, RuntimeError(f"{what}: {exc!r}")))
        with os.fdopen(answer, "wb") as pipe:
            pipe.write(reply)
        status = 0
    finally:
        os._exit(status)


class FigureProcess:
    """Figures drawn in a process forked on entering this context (a :class:`ForkedDrawing`
    that runs ``prepare`` while this process computes), or in this process where forking is not
    safe (:func:`feeder.workers.fork_safe`: a threaded process) or not asked for.

    Args:
        prepare: What the forked process does before its work arrives (the imports).
        what: What it does, for the text of an error that does not pickle.
        fork: Whether to fork at all (False: every work is done here).
    """

    def __init__(
        self, prepare: Callable[[], None] | None = None, what: str = "drawing", fork: bool = True
    ):
        self._prepare, self._what, self._fork = prepare, what, fork
        self._child: ForkedDrawing | None = None
        self._sent: list[ForkedDrawing] = []

    def __enter__(self) -> FigureProcess:
        if self._fork and fork_safe():
            self._child = ForkedDrawing(self._prepare, self._what)
        return self

    def __exit__(self, kind, error, traceback) -> None:
        """End the process: one never asked ends at its request's end; one whose answer was not
        read (an error came first) is stopped (:meth:`ForkedDrawing.stop`); both are reaped."""
        if self._child is not None:
            self._child.close()
            self._child = None
        while self._sent:
            self._sent.pop().stop()

    def submit(self, work: Callable[[], T]) -> Callable[[], T]:
        """Start ``work`` (picklable) in the forked process, and return what waits for its
        result (raising the error it met; once the context is left unread, a RuntimeError).
        The process takes one work: the next, or any outside the context or without a process,
        is done here when its result is asked for."""
        if self._child is None:
            return work
        child, self._child = self._child, None
        self._sent.append(child)  # stopped at the context's end if its answer is unread
        child.send(work)
        return child.result  # type: ignore[return-value]
