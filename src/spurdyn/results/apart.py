"""A run folder written by a process of its own: the writers kept out of the one that steps.

The libraries a run writes with (xarray, pandas, netCDF4, Matplotlib: ~75 MB resident) and
those a run steps with (Numba and LLVM: ~140 MB) need not share a process. ``spurdyn run``
starts a writer process (:func:`start`) when a run begins; once the run's loop has begun
(:func:`begin`) it loads the writers and draws a first file and picture
(:func:`spurdyn.results.prefetch.load`) on the other core, then waits for the run.
:func:`write` sends it the result and the case (pickled, through a pipe) and it writes the folder whole
(:func:`spurdyn.results.folder.write_run_folder`) and answers with the summary. The
stepping process never imports the writers, so the largest process of the command is the
stepper or the writer, not both at once (docs/performance.md, "The paper's loop and its
memory").

The writer is a fork of the caller while the caller is still small (on Linux, one Python
thread, Numba not loaded: at the start of a command's first run, ~85 MB, NumPy, SciPy and
spurdyn loaded, which the writer then need not import again; a forked child starts with
its parent's pages counted in its own resident set), else a freshly started interpreter.

Nothing is lost to the writer: stop signals are the stepper's to act on (the writer ignores
them; the stepper holds them while the folder is written, :mod:`spurdyn.signals`), and when
the writer cannot be started, fails or dies, the folder is written by the calling process
instead, which then raises the error itself, as it would have without a writer. A writer
given nothing (the run stopped before any result) is stopped (:func:`stop`); one whose
stepper died reads the end of its input and leaves.
"""

from __future__ import annotations

import os
import pickle
import signal
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any, BinaryIO, NoReturn

from spurdyn.result import Result

#: What a fresh interpreter runs: this package first on its path (the code of the process
#: that started it, whatever the current folder or the environment say), then :func:`serve`.
_SERVE = ("import signal; signal.signal(signal.SIGINT, signal.SIG_IGN); "
          "signal.signal(signal.SIGTERM, signal.SIG_IGN); "
          "import sys; {root!r} in sys.path or sys.path.insert(0, {root!r}); "
          "from spurdyn.results.apart import serve; serve()")

#: The byte that tells a writer to load the writers (:func:`begin`).
_BEGIN = b"b"

#: Modules whose presence makes this process too large to fork a writer from: LLVM's
#: library (~75 MB resident) would count in the writer's resident set.
_LARGE = ("llvmlite", "numba")


@dataclass
class Writer:
    """A writer process: its id, the pipes to and from it, and its :class:`subprocess.Popen`
    when it is a fresh interpreter (``None`` for a fork)."""

    pid: int
    requests: BinaryIO
    answers: BinaryIO
    popen: subprocess.Popen[bytes] | None = None
    begun: bool = False
    ended: bool = False


def start() -> Writer | None:
    """Start a writer process; ``None`` when no process can be made here.

    A fork while this process is small (:data:`_LARGE`), on Linux with no other Python
    thread (:func:`spurdyn.results.beside.can_fork`); else this interpreter
    (``sys.executable``) started afresh with ``-P`` (the current folder not on its path),
    which inherits the environment and the standard error and finds this package where
    this process found it.
    """
    from spurdyn.results.beside import can_fork

    if can_fork() and not any(name in sys.modules for name in _LARGE):
        forked = _forked()
        if forked is not None:
            return forked
    root = str(Path(__file__).resolve().parents[2])
    # out of the terminal's process group: a Ctrl-C is the stepper's alone, even while the
    # writer starts (before it can ignore it)
    apart_group: dict[str, Any] = ({"creationflags": subprocess.CREATE_NEW_PROCESS_GROUP}
                                   if sys.platform == "win32" else {"process_group": 0})
    try:
        popen = subprocess.Popen([sys.executable, "-P", "-c", _SERVE.format(root=root)],
                                 stdin=subprocess.PIPE, stdout=subprocess.PIPE, **apart_group)
    except OSError:
        return None
    assert popen.stdin is not None and popen.stdout is not None
    return Writer(popen.pid, popen.stdin, popen.stdout, popen)


def _forked() -> Writer | None:
    """A forked writer, or ``None`` when no process or pipe can be made."""
    from spurdyn.results.beside import fork

    try:
        to_child, from_child = os.pipe(), os.pipe()
    except OSError:
        return None
    try:
        pid = fork()
    except OSError:
        for fd in (*to_child, *from_child):
            os.close(fd)
        return None
    if pid == 0:    # never back into the caller's code, whatever comes (a stop signal)
        try:
            os.close(to_child[1])
            os.close(from_child[0])
            _serve(os.fdopen(to_child[0], "rb"), os.fdopen(from_child[1], "wb"))
        finally:
            os._exit(0)
    os.close(to_child[0])
    os.close(from_child[1])
    return Writer(pid, os.fdopen(to_child[1], "wb"), os.fdopen(from_child[0], "rb"))


def _reap(writer: Writer) -> None:
    """Close the pipes to the writer and wait for it to end."""
    for pipe in (writer.requests, writer.answers):
        try:
            pipe.close()
        except OSError:    # the rest of a request the writer never read
            pass
    if not writer.ended:
        if writer.popen is not None:
            writer.popen.wait()
        else:
            try:
                os.waitpid(writer.pid, 0)
            except ChildProcessError:   # reaped already (SIGCHLD ignored by the caller)
                pass
        writer.ended = True


def stop(writer: Writer | None) -> None:
    """End a writer that has not answered (nothing to write, or its answer lost) and wait
    for it: it writes only what :func:`write` sent it, and a folder it left half written is
    removed by the next write there (:func:`spurdyn.results.folder.clean_stale`)."""
    if writer is not None and not writer.ended:
        try:
            if writer.popen is not None:
                writer.popen.kill()     # SIGKILL, or TerminateProcess on Windows
            else:
                os.kill(writer.pid, signal.SIGKILL)
        except ProcessLookupError:   # ended already (not yet waited for)
            pass
        _reap(writer)


def begin(writer: Writer | None) -> None:
    """Let the writer load the writers now: the run's loop has begun (on one core; the
    model's build before it is left the machine to itself). Once; :func:`write` does it for
    a run that never said so."""
    if writer is not None and not writer.begun:
        writer.begun = True
        try:
            writer.requests.write(_BEGIN)
            writer.requests.flush()
        except OSError:      # a writer gone: write() finds out, and writes here
            pass


def _ask(writer: Writer, request: tuple[Any, ...]) -> tuple[Any, ...]:
    """Send the request and read the answer: ``("done", summary, folder)`` or
    ``("failed", traceback)``; ``("failed", why)`` when the writer is gone or talks nonsense."""
    begin(writer)
    try:
        pickle.dump(request, writer.requests, protocol=pickle.HIGHEST_PROTOCOL)
        writer.requests.close()
        answer = pickle.load(writer.answers)
    except Exception as err:  # noqa: BLE001 - any failure of the writer's: written here
        stop(writer)
        return ("failed", f"{type(err).__name__}: {err}")
    except BaseException:
        stop(writer)
        raise
    _reap(writer)
    if isinstance(answer, tuple) and answer[:1] in (("done",), ("failed",)):
        return answer
    return ("failed", "an answer of another kind")


def write(writer: Writer | None, result: Result, case: Any, target: Path, *, force: bool = True,
          vtu: bool = False) -> tuple[dict[str, Any], Path]:
    """Write a run's folder in the writer process (in this one without a writer, or when the
    writer fails); the arguments and the answer are those of
    :func:`spurdyn.results.folder.write_run_folder`."""
    if writer is not None:
        answer = _ask(writer, (result, case, str(target), force, vtu))
        if answer[0] == "done":
            return answer[1], Path(answer[2])
    from spurdyn.results.folder import write_run_folder

    written = write_run_folder(result, case, target, force=force, vtu=vtu)
    if writer is not None:   # the writer failed where this process did not: say so
        last = str(answer[1]).strip().splitlines()[-1:] or ["no reason given"]
        print(f"spurdyn: the writer process failed ({last[0]}); written by this process "
              "instead", file=sys.stderr)
    return written


def serve() -> NoReturn:
    """In a freshly started writer: its standard output becomes its answers' channel alone
    (what the writers print goes to the standard error); then :func:`_serve`."""
    answers = os.fdopen(os.dup(1), "wb")
    os.dup2(2, 1)
    sys.modules.setdefault("dask", None)  # type: ignore[arg-type]  # as the command's run
    _serve(sys.stdin.buffer, answers)


def _serve(requests: BinaryIO, answers: BinaryIO) -> NoReturn:
    """In the writer: load the writers, write the folder it is sent, answer, leave without
    the interpreter's teardown (and, in a fork, without running any of the caller's code)."""
    import gc
    import traceback

    from spurdyn.results.beside import REPORT_CHARS

    try:
        for signum in (signal.SIGINT, signal.SIGTERM):  # the stepper's to act on
            signal.signal(signum, signal.SIG_IGN)
        if requests.read(1) != _BEGIN:   # the run stopped before its loop
            os._exit(0)
        from spurdyn.results import prefetch
        from spurdyn.results.folder import write_run_folder

        try:
            prefetch.load()
        except Exception:  # noqa: BLE001 - the writing's own import reports it
            pass
        gc.collect()  # the first picture's figure and its cycles
        gc.freeze()   # the libraries' objects: the writing's collections need not walk them
        result, case, target, force, vtu = pickle.load(requests)
    except BaseException:  # noqa: BLE001 - nothing (whole) to write: the stepper writes
        os._exit(0)
    try:
        summary, final = write_run_folder(result, case, Path(target), force=force, vtu=vtu)
        answer: tuple[Any, ...] = ("done", summary, str(final))
    except BaseException:  # noqa: BLE001 - reported to the stepper, which writes it again
        answer = ("failed", traceback.format_exc()[-REPORT_CHARS:])
    try:
        pickle.dump(answer, answers, protocol=pickle.HIGHEST_PROTOCOL)
        answers.flush()
        sys.stdout.flush()
        sys.stderr.flush()
    finally:
        os._exit(0)


__all__ = ["Writer", "begin", "serve", "start", "stop", "write"]
