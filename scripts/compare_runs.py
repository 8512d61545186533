"""How far two runs' results lie apart: ``python scripts/compare_runs.py A B [C ...]``.

Each argument is a run's output folder (its ``summary.json`` and ``result.nc``); every run
after the first is compared with the first: the dynamic factor, the transmission error's
RMS over the last mesh cycle (about its mean), the peak force, and the largest difference
of the contact force over the run relative to its peak. Used for issue 34's accuracy table
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


def main(args: list[str]) -> int:
    if len(args) < 2:
        print(__doc__)
        return 2
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
