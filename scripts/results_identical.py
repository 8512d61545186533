"""Prove that a change leaves every result bit-identical.

Runs every preset, every example case file, the first 300 steps of Fig. 8 on the
NumPy backend and the sector model (modal bodies in both backends, whole bodies) through
the ``spurdyn`` command, and the sector model's RK4 reference in both backends through the
Python API, then either records the ``result.nc``
files in a folder or compares them with a folder recorded earlier: every data variable
and coordinate must be equal to the last bit (NaNs in the same places). Attributes are
not compared (they hold times and versions).

Usage::

    python scripts/results_identical.py record /tmp/before     # on the old commit
    python scripts/results_identical.py compare /tmp/before    # on the new one

Both take ``--only NAME`` (repeatable) to restrict the runs. A full pass takes a few
minutes on two cores. ``record`` fails (exit status 1, one line on stderr) when a run it
records exits with a non-zero status; ``compare`` fails on a run that has a ``result.nc``
on one side only, as on any difference.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import xarray as xr

ROOT = Path(__file__).resolve().parents[1]
PRESETS = ("paper-fig8", "paper-fig9", "paper-fig10", "paper-fig11",
           "paper-fig10-bdrive", "paper-fig11-bdrive")
#: 300 steps of dt = 3e-8 s at 4,000 rpm: 300 * 3e-8 s * 24,000 deg/s.
NUMPY_ANGLE_DEG = 300 * 3e-8 * 4000.0 * 6.0


def runs() -> dict[str, list[str]]:
    """Name -> arguments of ``spurdyn run`` (without ``--out``)."""
    table = {name: [name] for name in PRESETS}
    table.update({f"lumped-{name}": [name, "--model", "lumped"] for name in PRESETS[:2]})
    for toml in sorted((ROOT / "examples").glob("*.toml")):
        table[f"example-{toml.stem}"] = [str(toml)]
    # a pair-only file: the run settings come from the command line
    table["example-paper_pair"] += ["--speed-a", "4000", "--torque", "22.25"]
    # a case for `spurdyn stiffness`, and one for `spurdyn crack`: no speed
    table.pop("example-paper_faulty", None)
    table.pop("example-thin_rim", None)
    table["numpy-fig8-300"] = ["paper-fig8", "--backend", "numpy",
                               "--angle", repr(NUMPY_ANGLE_DEG)]
    # the sector model: modal bodies (compiled and NumPy), whole bodies, and the back flanks
    # and torque history of the example files above
    sector = ["paper-fig8", "--model", "sector", "--damping", "0.05"]
    table["sector-fig8-3"] = [*sector, "--cycles", "3"]
    table["sector-fig8-numpy"] = [*sector, "--cycles", "1", "--max-cycles", "1",
                                  "--backend", "numpy", "--mesh", "2x8"]
    table["sector-fig8-full"] = [*sector, "--cycles", "1", "--max-cycles", "1",
                                 "--bodies", "full", "--mesh", "2x8"]
    return table


#: Runs through the Python API (no command reaches them): name -> backend of the sector
#: model's RK4 reference, 400 steps of the paper's pair on 2 x 8 teeth at 20,000 rpm.
API_RUNS = {"sector-rk4-numba": "numba", "sector-rk4-numpy": "numpy"}


def run_api(name: str, out: Path) -> None:
    """Run ``API_RUNS[name]`` and write every array of its Result to ``out/result.nc``."""
    from spurdyn.geometry.presets import paper_pair
    from spurdyn.settings import RPM
    from spurdyn.solvers.check import run_settings
    from spurdyn.solvers.sector.rk4 import simulate_sector_rk4

    pair = paper_pair()
    s = run_settings(pair, 20000 * RPM, 22.25, dt=1e-6, cycles=3, damping_ratio=0.05,
                     backend=API_RUNS[name], nx=2, ny=8)
    result = simulate_sector_rk4(pair, s, dt=1e-7, steps=400)
    arrays = {key: np.asarray(value) for key, value in vars(result).items()
              if isinstance(value, np.ndarray)}
    out.mkdir(parents=True, exist_ok=True)
    xr.Dataset({key: (tuple(f"{key}_{i}" for i in range(a.ndim)), a)
                for key, a in arrays.items()}).to_netcdf(out / "result.nc")


def _frames(args: list[str]) -> list[str]:
    """``--frames-every 50`` for a run whose model keeps tooth frames (the others refuse an
    option they do not read; before the registry owned that rule they ignored it)."""
    import tomllib

    from spurdyn.settings import DEFAULT_MODEL
    from spurdyn.simulators import MODELS

    if "--model" in args:
        model = args[args.index("--model") + 1]
    elif args[0].endswith(".toml"):
        with open(args[0], "rb") as fh:
            model = tomllib.load(fh).get("model", {}).get("kind", DEFAULT_MODEL)
    else:
        model = "fe"
    return ["--frames-every", "50"] if getattr(MODELS[model], "keeps_frames", True) else []


def run_all(folder: Path, only: list[str]) -> dict[str, int]:
    """Run the table (or the runs named in ``only``) into ``folder``; returns the runs that
    exited with a non-zero status, with that status."""
    spurdyn = shutil.which("spurdyn") or str(Path(sys.executable).parent / "spurdyn")
    failed = {}
    for name, args in runs().items():
        if only and name not in only:
            continue
        out = folder / name
        cmd = [spurdyn, "run", *args, "--out", str(out), "--force", "--quiet", *_frames(args)]
        code = subprocess.run(cmd).returncode
        print(f"{name}: exit {code}", flush=True)
        if code:
            failed[name] = code
    for name in API_RUNS:
        if only and name not in only:
            continue
        code = subprocess.run([sys.executable, __file__, "api", name, str(folder / name)]).returncode
        print(f"{name}: exit {code}", flush=True)
        if code:
            failed[name] = code
    return failed


def _recorded(folder: Path, only: list[str]) -> set[str]:
    """The runs with a ``result.nc`` in ``folder`` (those named in ``only``, if any)."""
    names = {path.parent.name for path in folder.glob("*/result.nc")}
    return {name for name in names if name in only} if only else names


def compare(before: Path, after: Path, only: list[str]) -> list[str]:
    old_names, new_names = _recorded(before, only), _recorded(after, only)
    problems = [f"{name}: no result.nc after the change" for name in sorted(old_names - new_names)]
    problems += [f"{name}: no result.nc before the change" for name in sorted(new_names - old_names)]
    for name in sorted(old_names & new_names):
        old, new = before / name / "result.nc", after / name / "result.nc"
        with xr.open_dataset(old) as a, xr.open_dataset(new) as b:
            names = set(a.variables) | set(b.variables)
            for var in sorted(names):
                if var not in a.variables or var not in b.variables:
                    problems.append(f"{name}: variable {var} only on one side")
                    continue
                x, y = a[var].values, b[var].values
                if x.shape != y.shape:
                    problems.append(f"{name}: {var} shape {x.shape} -> {y.shape}")
                elif x.dtype.kind in "fc":
                    same = np.array_equal(x.view(np.uint8) if x.dtype.kind == "f" else x,
                                          y.view(np.uint8) if y.dtype.kind == "f" else y)
                    if not same:
                        diff = np.nanmax(np.abs(x - y)) if x.size else 0.0
                        problems.append(f"{name}: {var} differs (max |diff| {diff:.3g})")
                elif not np.array_equal(x, y):
                    problems.append(f"{name}: {var} differs")
        print(f"{name}: compared", flush=True)
    return problems


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    if sys.argv[1:2] == ["api"]:
        run_api(sys.argv[2], Path(sys.argv[3]))
        return 0
    parser.add_argument("action", choices=("record", "compare"))
    parser.add_argument("folder", type=Path)
    parser.add_argument("--only", action="append", default=[])
    args = parser.parse_args()
    if args.action == "record":
        failed = run_all(args.folder, args.only)
        if failed:
            runs_failed = ", ".join(f"{name} (exit {code})" for name, code in failed.items())
            print(f"results_identical: record: runs failed: {runs_failed}", file=sys.stderr)
            return 1
        return 0
    with tempfile.TemporaryDirectory() as tmp:
        run_all(Path(tmp), args.only)
        problems = compare(args.folder, Path(tmp), args.only)
    print("\n".join(problems) if problems else "every result is bit-identical")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
