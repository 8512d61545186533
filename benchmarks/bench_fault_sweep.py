"""Benchmark of a fault dataset's target: ``python benchmarks/bench_fault_sweep.py``.

``spurdyn sweep examples/paper_cracked.toml --rpm 1000 --fault-size 0:2e-3/6 --cycles 84
--max-cycles 84 --jobs 2``: six crack lengths (0, 0.4, 0.8, 1.2, 1.6 and 2 mm; 0 the
healthy pair), three revolutions each of the paper's 28-tooth pinion at 1,000 rpm, on two
local workers; target 10 minutes. Run as a researcher runs it, in a fresh process, into an
empty folder, the compile cache and the mode store warm (a short sector run fills them
first, not timed). Prints the wall time, its ratio to a calibration measured in the same
run (:func:`bench_mode_store.calibration`), the target, each point's time on its worker
and its model's build, the peak memory (VmRSS of the command and its children, sampled
from outside every 20 ms: the largest process and the sum) and the machine's load
average: on a shared machine only the ratios of one run compare.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np
import xarray as xr

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_mode_store import calibration  # noqa: E402  (a benchmark beside this one)

ROOT = Path(__file__).resolve().parents[1]
CASE = str(ROOT / "examples" / "paper_cracked.toml")
SPURDYN = str(Path(sys.executable).with_name("spurdyn"))
#: The sweep: six crack lengths, three revolutions of the pinion (84 mesh cycles), 1,000 rpm.
ARGS = ["--rpm", "1000", "--fault-size", "0:2e-3/6", "--cycles", "84", "--max-cycles", "84"]
#: The target (s).
TARGET_S = 600.0


def _tree(pid: int) -> list[int]:
    """``pid`` and its descendants (from /proc)."""
    out, todo = [], [pid]
    while todo:
        p = todo.pop()
        out.append(p)
        for task in Path(f"/proc/{p}/task").glob("*"):
            try:
                todo += [int(c) for c in (task / "children").read_text().split()]
            except OSError:
                pass
    return out


def _rss(pid: int) -> int:
    """VmRSS of ``pid`` (bytes), 0 if gone."""
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    return 0


def timed(argv: list[str]) -> tuple[float, int, int, int]:
    """``(wall s, exit status, largest process's peak RSS, the tree's peak sum)`` of a
    command, its memory sampled every 20 ms from this process."""
    t = time.perf_counter()
    proc = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    peak = [0, 0]

    def sample() -> None:
        while proc.poll() is None:
            sizes = [_rss(p) for p in _tree(proc.pid)]
            peak[0], peak[1] = max(peak[0], max(sizes, default=0)), max(peak[1], sum(sizes))
            time.sleep(0.02)

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    _, err = proc.communicate()
    sampler.join()
    if proc.returncode not in (0, 1):
        sys.stderr.write(err.decode())
    return time.perf_counter() - t, proc.returncode, peak[0], peak[1]


def timeline(out: Path, t0: float) -> float:
    """Each point's worker, start and end (s from the command's start), its whole time on
    the worker, the run's (``wall_s``: the build and the steps), the run's result after
    its steps (a crack's faces' openings), and the figures' (the summary, the signals); the
    points' whole times summed."""
    rows = []
    for path in (out / "points").glob("*.json"):
        r = json.loads(path.read_text())
        sig = r["signals"]
        point, figures = sig["point_s"], sig["figures_s"]
        rows.append((r["finished"] - point - t0, r["finished"] - t0, r["worker"], r["fault_size"], point,
                     r["wall_s"], point - r["wall_s"] - figures, figures))
    print(f"{'worker':>14s} {'size (mm)':>9s} {'start (s)':>9s} {'end (s)':>8s} {'point (s)':>9s} "
          f"{'run (s)':>8s} {'result (s)':>10s} {'figures (s)':>11s}")
    for start, end, worker, size, point, run, result, figures in sorted(rows):
        print(f"{worker:>14s} {size * 1e3:9.2f} {start:9.1f} {end:8.1f} {point:9.1f} {run:8.1f} {result:10.1f} "
              f"{figures:11.1f}")
    return sum(row[4] for row in rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--keep", metavar="DIR", help="keep the sweep folder in DIR (default: a temporary one)")
    args = parser.parse_args()
    cal = calibration()
    print(f"calibration {cal:.3f} s; load average before {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    with tempfile.TemporaryDirectory() as tmp:
        if args.keep:
            tmp = args.keep
            Path(tmp).mkdir(parents=True, exist_ok=True)
        subprocess.run([SPURDYN, "run", "paper-fig8", "--model", "sector", "--cycles", "1", "--max-cycles", "1",
                        "--quiet", "--out", str(Path(tmp) / "warm")], check=True,
                       stdout=subprocess.DEVNULL)      # the compile cache and the mode store filled
        out = Path(tmp) / "faults"
        t0 = time.time()
        wall, code, largest, total = timed([SPURDYN, "sweep", CASE, *ARGS, "--jobs", "2", "--quiet", "--out", str(out)])
        print(f"six crack lengths x three revolutions at 1,000 rpm, 2 workers: {wall:.1f} s = {wall / cal:.1f} x "
              f"calibration (target {TARGET_S:.0f} s); exit {code}; peak memory {largest / 2**20:.0f} MiB the "
              f"largest process, {total / 2**20:.0f} MiB all; load average after "
              f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}")
        with xr.open_dataset(out / "fault_sweep.nc") as ds:
            sizes = ds["fault_size"].values
            print(f"{'size (mm)':>10s} {'point (s)':>10s} {'build (s)':>10s} {'cycles':>7s} {'settled':>8s} status")
            for i, size in enumerate(sizes):
                p = ds.isel(rpm=0, fault_size=i)
                print(f"{size * 1e3:10.2f} {float(p['wall_s']):10.1f} {float(p['build_s']):10.1f} "
                      f"{int(p['cycles_done']):7d} {float(p['settled']):8.0f} {int(p['status'])}")
            point_s, build_s = np.nansum(ds["wall_s"].values), np.nansum(ds["build_s"].values)
            print(f"the runs' time {point_s:.1f} s, of which the builds {build_s:.1f} s ({build_s / point_s:.0%})")
        busy = timeline(out, t0)
        print(f"the points' whole time {busy:.1f} s: two workers busy {busy / (2 * wall):.0%} of the wall time")


if __name__ == "__main__":
    main()
