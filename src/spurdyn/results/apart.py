"""A run folder written by a freshly started process: the writers kept out of the one that steps.

The libraries a run writes with (xarray, pandas, netCDF4, Matplotlib: ~75 MB resident) and
those a run steps with (Numba and LLVM: ~140 MB) need not share a process. ``spurdyn run``
starts a fresh interpreter (:func:`start`) when a run begins; it loads the writers and
draws a first file and picture (:func:`spurdyn.results.prefetch.load`) while the run is
built and stepped, then waits for the run. :func:`write` sends it the result and the case
(pickled, through its standard input) and it writes the folder whole
(:func:`spurdyn.results.folder.write_run_folder`) and answers with the summary. The
stepping process never imports the writers, so the largest process of the command is the
stepper or the writer, not both at once (docs/performance.md, "The paper's loop and its
memory").

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
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from spurdyn.result import Result

#: What the fresh interpreter runs: this package first on its path (the code of the process
#: that started it, whatever the current folder or the environment say), then :func:`serve`.
_SERVE = ("import sys; sys.path.insert(0, {root!r}); "
          "from spurdyn.results.apart import serve; serve()")

#: Characters of the writer's traceback kept for the note printed when it failed.
_REPORT_CHARS = 4000


@dataclass
class Writer:
    """A writer process and the pipes to it (its standard input and output)."""

    process: subprocess.Popen[bytes]


def start() -> Writer | None:
    """Start a writer process; ``None`` when no process can be made here.

    The interpreter is this one (``sys.executable``) with ``-P`` (the current folder not on
    its path); it inherits the environment and the standard error, and finds this package
    where this process found it.
    """
    root = str(Path(__file__).resolve().parents[2])
    try:
        process = subprocess.Popen([sys.executable, "-P", "-c", _SERVE.format(root=root)],
                                   stdin=subprocess.PIPE, stdout=subprocess.PIPE)
    except OSError:
        return None
    return Writer(process)


def stop(writer: Writer | None) -> None:
    """End a writer that has not answered (nothing to write, or its answer lost) and wait
    for it: it writes only what :func:`write` sent it, and a folder it left half written is
    removed by the next write there (:func:`spurdyn.results.folder.clean_stale`)."""
    if writer is not None:
        if writer.process.poll() is None:
            writer.process.kill()
        _close(writer)


def _close(writer: Writer) -> None:
    """Close the pipes to the writer and wait for it to end."""
    for pipe in (writer.process.stdin, writer.process.stdout):
        if pipe is not None:
            pipe.close()
    writer.process.wait()


def _ask(writer: Writer, request: tuple[Any, ...]) -> tuple[Any, ...]:
    """Send the request and read the answer: ``("done", summary, folder)`` or
    ``("failed", traceback)``; ``("failed", why)`` when the writer is gone or talks nonsense."""
    process = writer.process
    assert process.stdin is not None and process.stdout is not None
    try:
        pickle.dump(request, process.stdin, protocol=pickle.HIGHEST_PROTOCOL)
        process.stdin.close()
        answer = pickle.load(process.stdout)
    except (OSError, EOFError, pickle.PickleError, AttributeError, TypeError) as err:
        stop(writer)
        return ("failed", f"{type(err).__name__}: {err}")
    except BaseException:
        stop(writer)
        raise
    _close(writer)
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


def serve() -> None:
    """In the writer process: load the writers, write the folder it is sent, answer, leave.

    Its standard output is its answer's channel alone: what the writers print goes to the
    standard error. It leaves without the interpreter's teardown, as the command does.
    """
    import gc
    import signal
    import traceback

    for signum in (signal.SIGINT, signal.SIGTERM):  # the stepper's to act on
        signal.signal(signum, signal.SIG_IGN)
    channel = os.fdopen(os.dup(1), "wb")
    os.dup2(2, 1)
    sys.modules.setdefault("dask", None)  # type: ignore[arg-type]  # as the command's run
    from spurdyn.results import prefetch
    from spurdyn.results.folder import write_run_folder

    try:
        prefetch.load()
    except Exception:  # noqa: BLE001 - the writing's own import reports it
        pass
    gc.collect()  # the first picture's figure and its cycles
    gc.freeze()   # the libraries' objects: the writing's collections need not walk them
    try:
        result, case, target, force, vtu = pickle.load(sys.stdin.buffer)
    except BaseException:  # noqa: BLE001 - nothing (whole) to write: the stepper writes
        os._exit(0)
    try:
        summary, final = write_run_folder(result, case, Path(target), force=force, vtu=vtu)
        answer: tuple[Any, ...] = ("done", summary, str(final))
    except BaseException:  # noqa: BLE001 - reported to the stepper, which writes it again
        answer = ("failed", traceback.format_exc()[-_REPORT_CHARS:])
    pickle.dump(answer, channel, protocol=pickle.HIGHEST_PROTOCOL)
    channel.flush()
    sys.stderr.flush()
    os._exit(0)


__all__ = ["Writer", "serve", "start", "stop", "write"]
