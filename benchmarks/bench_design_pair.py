"""Benchmark of issue 34's targets: ``python benchmarks/bench_design_pair.py [--skip-sweeps]``.

Runs, each in a fresh process as an engineer would, and prints its wall time, its peak
resident set (the command's own process) and its time as a ratio to a calibration measured
in the same run (:func:`bench_mode_store.calibration`: a sparse factorisation and solve and
a dense product of fixed sizes, best of three), beside the issue's target in seconds:

- ``design, empty store``: issue 34's design pair (``examples/design_19_53.toml``: 19/53,
  module 4, 428.5 N m at 2,000 rpm, whole gears) to its settled steady state,
  ``spurdyn run ... --model sector --cycles 5 --damping 0.05``, on an empty mode store
  (target 20 s);
- ``design, full store``: the same again (target 5 s);
- ``design sweep``: the pair's 40-speed settled sweep from 1,000 to 10,000 rpm on two local
  workers, store full (target 60 s);
- ``paper-fig8 sector sweep``: ``spurdyn sweep paper-fig8 --model sector --cycles 20
  --damping 0.05 --rpm 1000:20000/40`` on an empty store (target 45 s).

The compile cache is the user's (warm after the first run of a version); the first run's
compile is ``benchmarks/bench_fig8_compile.py``'s. The machine's load average is printed
with each row: on a shared machine only the ratios of one run compare.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_mode_store import calibration  # noqa: E402  (a benchmark beside this one)

ROOT = Path(__file__).resolve().parents[1]
PAIR = str(ROOT / "examples" / "design_19_53.toml")
SPURDYN = str(Path(sys.executable).with_name("spurdyn"))


def timed(args: list[str], store: Path, out: Path) -> tuple[float, float, int]:
    """``(wall s, peak RSS MB, exit status)`` of ``spurdyn args`` with the mode store
    ``store``, writing to ``out``."""
    env = dict(os.environ, SPURDYN_MODE_CACHE=str(store))
    t = time.perf_counter()
    proc = subprocess.Popen([SPURDYN, *args, "--out", str(out), "--force"], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode not in (0, 1):
        sys.stderr.write(proc.stderr.read().decode())
    return wall, usage.ru_maxrss / 1024.0, proc.returncode


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--skip-sweeps", action="store_true", help="only the two runs of the design pair")
    args = parser.parse_args()
    run = ["run", PAIR, "--model", "sector", "--cycles", "5", "--damping", "0.05"]
    rows = [("design, empty store", run, "empty", 20.0), ("design, full store", run, "full", 5.0)]
    if not args.skip_sweeps:
        rows += [("design sweep (40 speeds, 2 workers)",
                  ["sweep", PAIR, "--model", "sector", "--cycles", "5", "--damping", "0.05",
                   "--rpm", "1000:10000/40", "--jobs", "2", "--quiet"], "full", 60.0),
                 ("paper-fig8 sector sweep (40 speeds)",
                  ["sweep", "paper-fig8", "--model", "sector", "--cycles", "20", "--damping", "0.05",
                   "--rpm", "1000:20000/40", "--quiet"], "empty", 45.0)]
    cal = calibration()
    print(f"calibration {cal:.3f} s")
    print(f"{'run':40s} {'wall':>9s} {'x cal':>7s} {'target':>8s} {'RSS MB':>8s} {'load':>5s} status")
    with tempfile.TemporaryDirectory() as tmp:
        full = Path(tmp) / "store"
        for i, (name, cmd, store, target) in enumerate(rows):
            folder = full if store == "full" else Path(tmp) / f"empty{i}"
            wall, rss, code = timed(cmd, folder, Path(tmp) / f"out{i}")
            print(f"{name:40s} {wall:8.1f}s {wall / cal:7.1f} {target:7.0f}s {rss:8.0f} "
                  f"{os.getloadavg()[0]:5.1f} {code}", flush=True)
            if store == "empty" and i == 0:
                os.replace(folder, full)
    print(f"calibration {calibration():.3f} s (again)")


if __name__ == "__main__":
    main()
