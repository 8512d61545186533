"""One run folder, written whole or not at all: for ``spurdyn run`` and the sweep.

The files go to a hidden partial folder ``.NAME.partial-HOST-PID`` beside the target,
which is renamed into place once every file is written. The partial folder is removed
on every exit path that runs code (an error, Ctrl-C, SIGTERM); one left by a killed
process (SIGKILL, a lost node) is removed by the next write to the same place when its
process is gone, and reported when it belongs to another host.
"""

from __future__ import annotations

import os
import shutil
import socket
import sys
from pathlib import Path
from typing import Any

from spurdyn.result import Result

#: Markers of the hidden folders a writer makes beside its target.
_PARTIAL, _OLD = "partial", "old"


def _host() -> str:
    return socket.gethostname().replace("-", "_") or "host"


def _hidden(target: Path, kind: str) -> Path:
    return target.with_name(f".{target.name}.{kind}-{_host()}-{os.getpid()}")


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # someone else's process
        return True
    return True


def clean_stale(target: Path, stream: Any = None) -> list[Path]:
    """Remove the hidden folders of ``target`` whose process on this host is gone.

    Those of other hosts (a shared file system) cannot be judged from here: they are
    reported on ``stream`` (default stderr), not touched. Returns the folders removed.
    """
    stream = sys.stderr if stream is None else stream
    removed: list[Path] = []
    if not target.parent.is_dir():
        return removed
    for kind in (_PARTIAL, _OLD):
        for path in target.parent.glob(f".{target.name}.{kind}-*"):
            host, _, pid = path.name.rsplit(f".{kind}-", 1)[1].rpartition("-")
            if not pid.isdigit() or int(pid) == os.getpid():
                continue
            if host != _host():
                print(f"spurdyn: {path} was left by process {pid} on {host or 'another host'}; "
                      "remove it once that run is over", file=stream)
                continue
            if not _alive(int(pid)):
                shutil.rmtree(path, ignore_errors=True)
                removed.append(path)
    if removed:
        print(f"spurdyn: removed {len(removed)} folder(s) left by a killed run: "
              + ", ".join(p.name for p in removed), file=stream)
    return removed


def _free_name(target: Path) -> Path:
    """``<target>-2``, ``<target>-3``, ... whichever is free."""
    k = 2
    while True:
        alt = target.with_name(f"{target.name}-{k}")
        if not alt.exists():
            return alt
        k += 1


def move_into_place(tmp: Path, target: Path, force: bool = True) -> Path:
    """Move the written folder ``tmp`` to ``target``; return where it went.

    ``target`` was checked before the run, but another run may have filled it since:
    without ``force`` that folder is kept and the results go beside it under a free
    name, so neither is lost. With ``force`` it is replaced.
    """
    if target.exists():
        if target.is_dir() and not any(target.iterdir()):
            target.rmdir()
        elif not force:
            target = _free_name(target)
        else:
            old = _hidden(target, _OLD)
            target.rename(old)
            tmp.rename(target)
            shutil.rmtree(old, ignore_errors=True)
            return target
    tmp.rename(target)
    return target


def write_run_folder(result: Result, case: Any, target: Path, *, force: bool = True,
                     vtu: bool = False, png: bool = True) -> tuple[dict[str, Any], Path]:
    """Write a run's folder (:func:`spurdyn.results.io.write_run`) at ``target``.

    Parameters
    ----------
    result, case
        The run and its :class:`~spurdyn.case.file.Case`.
    target
        The folder; its parent must exist.
    force
        Replace a folder that appeared at ``target`` meanwhile (else write beside it).
    vtu, png
        Also write the ParaView series; the picture.

    Returns
    -------
    tuple
        The summary and the folder written.
    """
    from spurdyn.results.io import write_run

    clean_stale(target)
    tmp = _hidden(target, _PARTIAL)
    shutil.rmtree(tmp, ignore_errors=True)
    try:
        tmp.mkdir()
        summary = write_run(result, case, tmp, vtu=vtu, png=png)
        final = move_into_place(tmp, target, force)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return summary, final


__all__ = ["clean_stale", "move_into_place", "write_run_folder"]
