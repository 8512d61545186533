"""Benchmark of the mode store (:mod:`spurdyn.store`): ``python benchmarks/bench_mode_store.py``.

Builds the sector model of the paper's pair (whole gears, modal bodies, 4,000 rpm, the
default mesh unless ``--mesh NXxNY``) in a fresh process each time, three ways:

- ``off``: the store off (``SPURDYN_MODE_CACHE=off``): every build computes the modes, as
  before the store (but the second gear of the equal pair shares the first's Lanczos solve);
- ``cold``: an empty store: the build computes the modes and writes them;
- ``warm``: the same store again: the build reads them.

Each time is printed in seconds and as a ratio to a calibration measured in the same run
(a sparse LU factorisation and solve and a dense product of fixed sizes, best of three), so
that runs on a loaded or another machine compare.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

CHILD = """
import json, sys, time
t0 = time.perf_counter()
from spurdyn.geometry.presets import paper_pair
from spurdyn.sector.model import SectorModel
from spurdyn.settings import RPM
from spurdyn.solvers.check import run_settings
mesh = json.loads(sys.argv[1])
s = run_settings(paper_pair(), 4000 * RPM, 22.25, model="sector", cycles=3, max_cycles=3, **mesh)
t1 = time.perf_counter()
m = SectorModel.build(paper_pair(), s)
t2 = time.perf_counter()
print(json.dumps({"build": t2 - t1, "dofs": int(sum(b.mass.size for b in m.blocks)),
                  "modes": [int(g.n - 1) for g in m.gears]}))
"""


def calibration() -> float:
    """Seconds of a fixed sparse factorisation and solve and a dense product (best of 3)."""
    import numpy as np
    import scipy.sparse as sp
    from scipy.sparse.linalg import splu

    n = 150
    lap1 = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(n, n))
    lap = (sp.kron(lap1, sp.eye(n)) + sp.kron(sp.eye(n), lap1)).tocsc()
    rhs = np.ones((n * n, 20))
    dense = np.random.default_rng(0).normal(size=(600, 600))
    best = float("inf")
    for _ in range(3):
        t = time.perf_counter()
        splu(lap).solve(rhs)
        dense @ dense
        best = min(best, time.perf_counter() - t)
    return best


def build(mesh: dict[str, int], store: str) -> dict:
    """The child's figures, the store at ``store``."""
    env = {**os.environ, "SPURDYN_MODE_CACHE": store}
    out = subprocess.run([sys.executable, "-c", CHILD, json.dumps(mesh)], env=env, check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mesh", metavar="NXxNY", help="the teeth's mesh (default: the model's)")
    args = ap.parse_args()
    mesh = {}
    if args.mesh:
        nx, ny = args.mesh.lower().split("x")
        mesh = {"nx": int(nx), "ny": int(ny)}
    cal = calibration()
    print(f"calibration {cal:.3f} s; load average {os.getloadavg()[0]:.1f}")
    with tempfile.TemporaryDirectory() as folder:
        for name, store in (("off", "off"), ("cold", folder), ("warm", folder)):
            got = build(mesh, store)
            print(f"{name:5s} build {got['build']:7.2f} s = {got['build'] / cal:7.1f} x calibration "
                  f"({got['dofs']:,} FE DOFs, modes {got['modes']})")
    print(f"load average {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
