"""Benchmark of ``spurdyn crack``: ``python benchmarks/bench_crack.py``.

Runs ``spurdyn crack paper --increment 3e-4 --max-increments 20 --out DIR`` (a root crack of
the paper's 28-tooth driver grown by 20 increments of 0.3 mm, each a gmsh mesh of the
cracked cell, a factorised sector and the contact problem at the 8 load positions) in a
fresh process, and prints its wall time, its peak resident set (sampled from outside every
20 ms: ``VmRSS`` of the process and its children in ``/proc``), and the time as a ratio to
the calibration of ``bench_mode_store.calibration`` measured in the same run (a sparse
factorisation and solve and a dense product of fixed sizes, best of three), beside the
target of 2 minutes. The machine's load average is printed: on a shared machine only the
ratios of one run compare.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_mode_store import calibration  # noqa: E402  (a benchmark beside this one)

SPURDYN = str(Path(sys.executable).with_name("spurdyn"))
ARGS = ["crack", "paper", "--increment", "3e-4", "--max-increments", "20", "--json"]
TARGET = 120.0


def _rss_kb(pid: int) -> int:
    """``VmRSS`` (kB) of ``pid`` and its children (0 once gone)."""
    total = 0
    pids = [pid]
    try:
        pids += [int(c) for c in Path(f"/proc/{pid}/task/{pid}/children").read_text().split()]
    except OSError:
        pass
    for p in pids:
        try:
            for line in Path(f"/proc/{p}/status").read_text().splitlines():
                if line.startswith("VmRSS:"):
                    total += int(line.split()[1])
        except OSError:
            pass
    return total


def timed(args: list[str], out: Path) -> tuple[float, float, int]:
    """``(wall s, peak RSS MB, exit status)`` of ``spurdyn args --out out``."""
    t = time.perf_counter()
    proc = subprocess.Popen([SPURDYN, *args, "--out", str(out)], stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE)
    peak = 0
    while proc.poll() is None:
        peak = max(peak, _rss_kb(proc.pid))
        time.sleep(0.02)
    wall = time.perf_counter() - t
    if proc.returncode:
        sys.stderr.write(proc.stderr.read().decode())
    return wall, peak / 1024.0, proc.returncode


def main() -> None:
    cal = calibration()
    print(f"calibration {cal:.3f} s")
    with tempfile.TemporaryDirectory() as tmp:
        wall, rss, code = timed(ARGS, Path(tmp) / "crack")
        print(f"spurdyn crack paper, 20 increments: {wall:.1f} s ({wall / cal:.1f} x calibration; "
              f"target {TARGET:.0f} s), peak RSS {rss:.0f} MB, load {os.getloadavg()[0]:.2f}, "
              f"status {code}")
        summary = Path(tmp) / "crack" / "summary.json"
        if summary.exists():
            print(summary.read_text())
    print(f"calibration {calibration():.3f} s (again)")


if __name__ == "__main__":
    main()
