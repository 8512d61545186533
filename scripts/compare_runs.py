"""How far two runs' results lie apart: ``python scripts/compare_runs.py A B [C ...]``.

Each argument is a run's output folder (its ``summary.json`` and ``result.nc``) or a
sweep's (its ``sweep.nc``); every one after the first is compared with the first: for runs
the dynamic factor, the transmission error's RMS over the last mesh cycle (about its mean),
the peak force, and the largest difference of the contact force over the run relative to
its peak; for sweeps the largest relative difference over the speeds of the dynamic factor
and of the transmission error's RMS. Used for issue 34's accuracy table
(docs/performance.md): a speed-up keeps the dynamic factor within 0.1 % and the
transmission error's RMS within 0.5 %.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import xarray as xr


def figures(folder: Path) -> dict[str, object]:
    """The figures compared, and the contact force, of the run in ``folder``."""
    summary = json.loads((folder / "summary.json").read_text())
    with xr.open_dataset(folder / "result.nc") as d:
        t = d["time"].values
        te = d["transmission_error"].values
        force = d["contact_force"].values
    teeth = int(json.loads(d.attrs["case"])["gear_a"]["teeth"])
    omega = 2.0 * np.pi * float(summary["speed_a_rpm"]) / 60.0
    last = t >= t[-1] - 2.0 * np.pi / teeth / omega
    return {"dynamic_factor": float(summary["dynamic_factor"]),
            "te_rms": float(np.sqrt(np.mean((te[last] - te[last].mean()) ** 2))),
            "peak": float(summary["peak_force_N"]), "force": force, "status": summary["status"]}


def sweeps(base: Path, others: list[Path]) -> int:
    """The sweeps' dynamic factors and transmission errors' RMS, speed by speed."""
    with xr.open_dataset(base / "sweep.nc") as ref:
        df, te = ref["dynamic_factor"].values, ref["transmission_error_rms"].values
    print(f"{base}: {df.size} points, DF {np.nanmin(df):.4f} .. {np.nanmax(df):.4f}")
    for other in others:
        with xr.open_dataset(other / "sweep.nc") as d:
            rel_df = np.nanmax(np.abs(d["dynamic_factor"].values / df - 1))
            rel_te = np.nanmax(np.abs(d["transmission_error_rms"].values / te - 1))
        print(f"{other}: DF within {rel_df:.2e}, TE RMS within {rel_te:.2e} (relative, every speed)")
    return 0


def main(args: list[str]) -> int:
    if len(args) < 2:
        print(__doc__)
        return 2
    if (Path(args[0]) / "sweep.nc").exists():
        return sweeps(Path(args[0]), [Path(a) for a in args[1:]])
    base = figures(Path(args[0]))
    print(f"{args[0]}: DF {base['dynamic_factor']:.6f}, TE RMS {base['te_rms'] * 1e6:.5f} um, "
          f"peak {base['peak']:.2f} N ({base['status']})")
    for other in args[1:]:
        f = figures(Path(other))
        n = min(f["force"].size, base["force"].size)
        dforce = np.abs(f["force"][:n] - base["force"][:n]).max() / abs(base["peak"])
        print(f"{other}: DF {f['dynamic_factor']:.6f} ({f['dynamic_factor'] / base['dynamic_factor'] - 1:+.2e}), "
              f"TE RMS {f['te_rms'] * 1e6:.5f} um ({f['te_rms'] / base['te_rms'] - 1:+.2e}), "
              f"peak {f['peak']:.2f} N, force {dforce:.2e} of the peak at most ({f['status']})")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
