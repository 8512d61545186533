"""Benchmark of the design report's target: ``python benchmarks/bench_report.py``.

``spurdyn report examples/pinion_23_47.toml --torque 25,50 --jobs 2`` (the 23/47 pair at
its 20 default speeds and two torques on two local workers; target 2 minutes), run as an
engineer runs it, in a fresh process, into an empty folder, the mode store and the
compile cache warm (a one-speed report into another folder fills them first, not timed);
then the same command again, every point reused (the page alone). Each row prints its
wall time, its time as a ratio to a calibration measured in the same run
(:func:`bench_mode_store.calibration`), the target, the points computed and the machine's
load average: on a shared machine only the ratios of one run compare. ``--no-lumped``
leaves out the lumped model's points (``spurdyn report --no-lumped``).
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_mode_store import calibration  # noqa: E402  (a benchmark beside this one)

ROOT = Path(__file__).resolve().parents[1]
CASE = str(ROOT / "examples" / "pinion_23_47.toml")
SPURDYN = str(Path(sys.executable).with_name("spurdyn"))
#: The target (s): 20 speeds, two torques, two local workers.
TARGET_S = 120.0


def timed(args: list[str], out: Path) -> tuple[float, int]:
    """``(wall s, exit status)`` of ``spurdyn report CASE args --out out``."""
    t = time.perf_counter()
    proc = subprocess.run([SPURDYN, "report", CASE, *args, "--quiet", "--out", str(out)],
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, check=False)
    if proc.returncode not in (0, 1):
        sys.stderr.write(proc.stderr.decode())
    return time.perf_counter() - t, proc.returncode


def points(out: Path) -> dict[str, int]:
    """The points of the report in ``out``, per model (sector, lumped)."""
    data = json.loads((out / "report.json").read_text(encoding="utf-8"))
    return {"sector": len(data["speed"]["points"]),
            "lumped": len(data["speed"]["lumped"].get("points", []))}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-lumped", action="store_true",
                        help="leave out the lumped model beside (spurdyn report --no-lumped)")
    args = parser.parse_args()
    extra = ["--torque", "25,50", "--jobs", "2"] + (["--no-lumped"] if args.no_lumped else [])
    cal = calibration()
    print(f"calibration {cal:.3f} s")
    print(f"{'report':44s} {'wall':>9s} {'x cal':>7s} {'target':>8s} {'points':>14s} "
          f"{'load':>5s} status")
    with tempfile.TemporaryDirectory() as tmp:
        timed(["--rpm", "1000", "--jobs", "1"], Path(tmp) / "warm")   # the stores filled
        out = Path(tmp) / "report"
        for name in ("20 speeds x 2 torques, 2 workers", "the same again (points reused)"):
            wall, code = timed(extra, out)
            n = points(out)
            print(f"{name:44s} {wall:8.1f}s {wall / cal:7.1f} {TARGET_S:7.0f}s "
                  f"{n['sector']:>6d}+{n['lumped']:<6d} {os.getloadavg()[0]:5.1f} {code}",
                  flush=True)


if __name__ == "__main__":
    main()
