"""One piece of writing done in a forked child while the caller writes the rest.

A run folder's picture (~0.3 s of Matplotlib for Fig. 8) does not need its NetCDF and CSV
files (~0.25 s together). A forked child already holds the dataset and whatever the parent has
loaded, so nothing is pickled or imported again, and on a machine with a free core the
two take the time of the longer one (docs/performance.md).

:func:`beside` runs ``work`` in a child while the body of the ``with`` block runs, and
waits for it at the end of the block: when the block is left, the work is done, so a
folder moved into place afterwards is complete. If the child fails (or is killed), the
work is done again in this process, so its error is raised here as it would have been
without a child and no result is lost. If the block raises, the child is stopped.

Without ``os.fork`` (Windows), outside Linux (macOS's system libraries are not safe to
use in a forked child) or with other Python threads running (a Dask worker: a lock held
by another thread would stay locked in the child), or when no process can be made,
``work`` simply runs here at the end of the block, as before.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
import traceback
import warnings
from contextlib import contextmanager
from typing import Callable, Iterator, NoReturn

#: Characters of a child's traceback kept for the note printed when it failed.
REPORT_CHARS = 4000


def can_fork() -> bool:
    """Whether :func:`beside` uses a child here (Linux, no other Python thread)."""
    return hasattr(os, "fork") and sys.platform.startswith("linux") and \
        threading.active_count() == 1


def _child(work: Callable[[], object], parents_end: int, report: int) -> NoReturn:
    """In the child: do ``work``, write a traceback to ``report`` if it fails, leave.

    Never returns: the child must not run any of the parent's code after the fork
    (its ``finally`` blocks would remove the folder being written).
    """
    status = 1
    try:
        os.close(parents_end)
        # Stop signals are the parent's to act on; it waits for this child either way.
        for signum in (signal.SIGINT, signal.SIGTERM):
            signal.signal(signum, signal.SIG_IGN)
        work()
        status = 0
    except BaseException:  # noqa: BLE001 - reported to the parent, which does it again
        try:
            os.write(report, traceback.format_exc()[-REPORT_CHARS:].encode("utf-8", "replace"))
        except BaseException:  # noqa: BLE001
            pass
    finally:
        try:
            sys.stderr.flush()    # the child's own warnings (the parent flushed before)
        finally:
            os._exit(status)


def fork() -> int:
    """``os.fork`` without Python 3.12's warning about the numerical libraries' threads,
    the standard streams flushed first (else the child would print the parent's buffers)."""
    for stream in (sys.stdout, sys.stderr):
        if stream is not None:    # (None: closed by the caller)
            stream.flush()
    # Python 3.12+ warns about forking a process with other OS threads. Those here are the
    # native pools of the numerical libraries (OpenBLAS), which prepare for a fork; no
    # other Python thread runs (can_fork), and the child only writes and leaves.
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=r".*use of fork\(\) may lead to deadlocks",
                                category=DeprecationWarning)
        return os.fork()


def _read_all(fd: int) -> bytes:
    """Everything written to the pipe ``fd`` until its writer (the child) has exited."""
    chunks = []
    while chunk := os.read(fd, 65536):
        chunks.append(chunk)
    return b"".join(chunks)


def _start(work: Callable[[], object]) -> tuple[int, int] | None:
    """Fork a child doing ``work``: its pid and the pipe it reports on; ``None`` when no
    child can be made here (:func:`can_fork`, or no process or pipe to spare)."""
    if not can_fork():
        return None
    try:
        read_end, write_end = os.pipe()
    except OSError:
        return None
    try:
        pid = fork()
    except OSError:
        os.close(read_end)
        os.close(write_end)
        return None
    if pid == 0:
        _child(work, read_end, write_end)
    os.close(write_end)
    return pid, read_end


@contextmanager
def beside(work: Callable[[], object]) -> Iterator[None]:
    """Run ``work`` in a forked child while the block runs; it is done when the block ends.

    Parameters
    ----------
    work
        What to do, without arguments; its return value is dropped. It writes a file
        (the picture) and must not change anything the parent reads.

    Raises
    ------
    Exception
        What ``work`` raises when done again in this process after the child failed.
    """
    child = _start(work)
    if child is None:    # as before there were children: after the rest
        yield
        work()
        return
    pid, read_end = child
    try:
        yield
    except BaseException:
        os.close(read_end)
        os.kill(pid, signal.SIGKILL)    # the folder is given up: no picture to finish
        os.waitpid(pid, 0)
        raise
    try:
        report = _read_all(read_end)
    finally:
        os.close(read_end)
        _, status = os.waitpid(pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        work()    # raises the error here if it has one; else the result is complete
        last = report.decode("utf-8", "replace").strip().splitlines()[-1:] or \
            [f"exit status {os.waitstatus_to_exitcode(status)}"]
        print(f"spurdyn: a child process failed to write ({last[0]}); written by this "
              "process instead", file=sys.stderr)


__all__ = ["beside", "can_fork", "fork"]
