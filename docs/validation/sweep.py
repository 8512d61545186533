"""Dynamic factor against speed of the paper's pair, FE and lumped: the validation figure
``docs/figures/dynamic_factor_sweep.png`` and the fragment ``docs/validation_sweep.md``.

    python docs/validation validation_sweep [--out DIR] [--jobs N]

Runs (or resumes: the sweep folder keeps every finished point) two sweeps of
``paper-fig8`` (the paper's pair, 22.25 N m, dt 3e-8 s, 4 x 14 mesh, whole engagement,
equal pitch-line speeds) into one folder, default ``out/sweep-validation``:

- FE: 40 speeds 1,000-20,000 rpm (``1000:20000/40``) and 21,000-30,000 rpm by 1,000;
- lumped: 500-30,000 rpm by 100 rpm.

Every number of the fragment is computed here from the two sweeps.
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path
from typing import Sequence

import numpy as np
import xarray as xr

from spurdyn.case import preset_case
from spurdyn.sweep.backends import default_jobs, local_backend
from spurdyn.sweep.resonance import ResonanceEstimate, resonance_estimate
from spurdyn.sweep.runner import run_sweep
from spurdyn.sweep.spec import SweepPlan, parse_speeds
from spurdyn.sweep.store import STATUS_CODES
from validation.common import DOCS, FIGURES

FIGURE = FIGURES / "dynamic_factor_sweep.png"
FRAGMENT = DOCS / "validation_sweep.md"
FE_SPEEDS = ("1000:20000/40", "21000:30000:1000")
LUMPED_SPEEDS = ("500:30000:100",)
#: Relative difference of the dynamic factors at which the models are said to part.
PART = (0.02, 0.05)


def speeds(grids: tuple[str, ...]) -> tuple[float, ...]:
    return tuple(sorted({v for g in grids for v in parse_speeds(g)}))


def run(out: Path, jobs: int) -> tuple[xr.Dataset, xr.Dataset, ResonanceEstimate, dict]:
    case = preset_case("paper-fig8")
    resonance = resonance_estimate(case)
    walls = {}
    results = {}
    for model, grid in (("lumped", LUMPED_SPEEDS), ("fe", FE_SPEEDS)):
        plan = SweepPlan(case=case, model=model, rpms=speeds(grid), torques=None, out=out)
        t0 = time.perf_counter()
        with local_backend(jobs) as backend:
            report = run_sweep(plan, backend, resonance=resonance)
        walls[model] = (time.perf_counter() - t0, report.computed, report.reused)
        if not report.all_complete:
            raise SystemExit(f"{model} sweep not complete: {report.counts}; run again")
        results[model] = report.dataset
    return results["fe"], results["lumped"], resonance, walls


def local_peaks(rpm: np.ndarray, y: np.ndarray, prominence: float) -> list[tuple[float, float]]:
    """Interior local maxima standing ``prominence`` above the lowest point on each side
    before a higher one (a plain prominence), plus the last point if it is the largest."""
    peaks = []
    for i in range(1, len(y) - 1):
        if not (y[i] >= y[i - 1] and y[i] > y[i + 1]):
            continue
        left = y[:i][::-1]
        stop = np.argmax(left > y[i]) if (left > y[i]).any() else len(left)
        right = y[i + 1:]
        stop_r = np.argmax(right > y[i]) if (right > y[i]).any() else len(right)
        base = max(left[:stop].min(), right[:stop_r].min())
        if y[i] - base >= prominence:
            peaks.append((float(rpm[i]), float(y[i])))
    return peaks


def parabolic_peak(rpm: np.ndarray, y: np.ndarray, i: int) -> float:
    """Speed of the vertex of the parabola through the points ``i - 1, i, i + 1``."""
    if i <= 0 or i >= len(y) - 1:
        return float(rpm[i])
    x0, x1, x2 = rpm[i - 1:i + 2]
    y0, y1, y2 = y[i - 1:i + 2]
    den = (x0 - x1) * (x0 - x2) * (x1 - x2)
    a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / den
    b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / den
    return float(-b / (2 * a)) if a < 0 else float(rpm[i])


def figure(fe: xr.Dataset, lumped: xr.Dataset, res: ResonanceEstimate, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from spurdyn.sweep.plot import draw_dynamic_factor

    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(9.5, 8.2), sharex=True,
                                  gridspec_kw={"height_ratios": [2.2, 1]}, layout="constrained")
    draw_dynamic_factor(ax, {"fe": fe, "lumped": lumped}, res)
    ax.plot(fe["rpm"], fe["dynamic_factor_raw"], color="C2", lw=1.0, ls="-",
            marker=".", ms=4, label="FE, raw step-to-step peak (dynamic_factor_raw)")
    ax.legend(fontsize=8, loc="lower right")
    ax.set_xlabel("")
    ax.set_title("Paper's pair, 22.25 N m, equal speeds, one engagement per speed "
                 "(dt 3e-8 s, 4 x 14 mesh)", fontsize=10)
    rpm = fe["rpm"].values
    lump_at = np.interp(rpm, lumped["rpm"].values, lumped["dynamic_factor"].values)
    ax2.axhline(0.0, color="0.5", lw=0.8)
    ax2.plot(rpm, 100 * (fe["dynamic_factor"].values / lump_at - 1), "o-", ms=3, color="C0",
             label="FE / lumped - 1 (peaks of the 10-us averages: the dynamic factors)")
    ax2.plot(rpm, 100 * (fe["dynamic_factor_raw"].values / lump_at - 1), ".-", ms=4,
             color="C2", label="FE raw peak / lumped - 1")
    for p in sorted(PART, reverse=True):
        ax2.axhspan(-100 * p, 100 * p, color="0.92" if p == max(PART) else "0.84", lw=0,
                    zorder=0)
    ax2.axvline(res.resonance_rpm, color="C3", lw=1.2, ls="-.")
    ax2.axvline(res.resonance_rpm / 2, color="C3", lw=1.0, ls=":", alpha=0.5)
    ax2.set_ylabel("FE vs lumped (%)")
    ax2.set_xlabel("speed of gear A (rpm)")
    ax2.grid(True, lw=0.4, alpha=0.5)
    ax2.legend(fontsize=8)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=130)
    plt.close(fig)


def reading(rf: np.ndarray, df_fe: np.ndarray, df_fs: np.ndarray, rl: np.ndarray,
            df_l: np.ndarray, rel: np.ndarray, rel_s: np.ndarray, n_res: float,
            fe_sep: np.ndarray, lump_sep: np.ndarray) -> str:
    """What the curves say, in sentences whose every number and claim is computed."""
    out = ["**Reading.**"]
    near = []
    for name, rpm, y in (("FE", rf, df_fe), ("lumped", rl, df_l)):
        peaks = [n for n, _ in local_peaks(rpm, y, 0.03) if abs(n / n_res - 1) <= 0.10]
        near.append((name, peaks))
    theta_s = preset_case("paper-fig8").pair.theta_s
    t_eng = theta_s / (n_res * 2 * math.pi / 60)
    f_n = n_res * 28 / 60
    if not any(p for _, p in near):
        lo_i, hi_i = np.searchsorted(rl, 0.9 * n_res), np.searchsorted(rl, 1.1 * n_res)
        out.append(
            f"Neither curve has a peak within 10 % of the estimated {n_res:,.0f} rpm: both rise "
            f"through it (lumped {df_l[lo_i]:.3f} at {rl[lo_i]:,.0f} rpm to {df_l[hi_i]:.3f} at "
            f"{rl[hi_i]:,.0f} rpm). Each point is one engagement from first contact, so the "
            "dynamic factor is the largest transient response to the loading of one tooth pair "
            "(a shock-response measure), not the steady-state response to a periodic mesh "
            "excitation that the resonance estimate refers to. At that speed the engagement "
            f"lasts {t_eng * 1e6:.0f} us against a natural period of {1e6 / f_n:.0f} us, so "
            "one engagement holds less than two periods of the mode.")
    else:
        out.append("Peaks within 10 % of the estimated " f"{n_res:,.0f} rpm: " + "; ".join(
            f"{name} at {', '.join(f'{n:,.0f}' for n in p) or 'none'} rpm" for name, p in near)
            + ".")
    half, largest = [], True
    for name, rpm, y in (("FE", rf, df_fe), ("FE 10 us", rf, df_fs), ("lumped", rl, df_l)):
        below = [(n, v) for n, v in local_peaks(rpm, y, 0.03) if n < 0.9 * n_res]
        p = [(n, v) for n, v in below if abs(n / (n_res / 2) - 1) <= 0.15]
        if p:
            n, v = max(p, key=lambda t: t[1])
            half.append(f"{name} {v:.3f} at {n:,.0f} rpm")
            largest &= v >= max(b[1] for b in below)
        else:
            largest = False
    if half:
        which = "its largest bump" if largest else "a bump"
        who = "each curve has" if len(half) == 3 else "some curves have"
        out.append(f"Below it, {who} {which} near {n_res / 2:,.0f} rpm, where twice the mesh "
                   f"frequency equals f_n: {', '.join(half)}.")
    mid = (rf >= 2500) & (rf <= 22000)
    late = np.flatnonzero((rf > 22000) & (rel_s < -0.01))
    ends = (f"at {rf[0]:,.0f} rpm ({rel_s[0]:+.1%})" + (
        f" and from about {rf[late[0]]:,.0f} rpm, where the FE falls below "
        f"({rel_s[-1]:+.1%} at {rf[-1]:,.0f} rpm)" if late.size else ""))
    out.append(
        f"Averaged over 10 us the FE peak follows the lumped curve closely from 2,500 to "
        f"22,000 rpm (mean |difference| {np.mean(np.abs(rel_s[mid])):.1%}, at most "
        f"{np.max(np.abs(rel_s[mid])):.1%}); the raw FE peak lies above the lumped one at "
        f"{int((rel > 0).sum())} of {rf.size} speeds (mean {np.mean(rel):+.1%}): the ripple of "
        "local tooth modes, which the lumped model has not got, adds to the peak. The "
        f"averaged curves part at the ends: {ends}. The FE teeth separate (contact lost and "
        f"the gap opening beyond 10 nm) at least once after first contact at "
        f"{int((fe_sep > 0).sum())} of {rf.size} speeds, the lumped model's at "
        f"{int((lump_sep > 0).sum())} of {rl.size}: in the FE model the tooth-level ripple "
        "takes the force to zero where the ramped torque is low, which the lumped model's "
        "smooth force does not.")
    return " ".join(out) + "\n"


def fragment(fe: xr.Dataset, lumped: xr.Dataset, res: ResonanceEstimate, walls: dict) -> str:
    rf, rl = fe["rpm"].values, lumped["rpm"].values
    # FE raw and averaged (the dynamic factor); the lumped model's dynamic factor (averaged)
    df_fe, df_fs = fe["dynamic_factor_raw"].values, fe["dynamic_factor"].values
    df_l = lumped["dynamic_factor"].values
    lump_at = np.interp(rf, rl, df_l)
    rel = df_fe / lump_at - 1.0
    rel_s = df_fs / lump_at - 1.0
    n_res = res.resonance_rpm

    def peak_text(rpm: np.ndarray, y: np.ndarray, prominence: float) -> str:
        peaks = local_peaks(rpm, y, prominence)
        if not peaks:
            return "none"
        return ", ".join(f"{n:,.0f} rpm ({v:.3f})" for n, v in peaks)

    def top(rpm: np.ndarray, y: np.ndarray, lo: float, hi: float) -> tuple[float, float, float]:
        sel = np.flatnonzero((rpm >= lo) & (rpm <= hi))
        i = sel[np.argmax(y[sel])]
        return float(rpm[i]), float(y[i]), parabolic_peak(rpm, y, i)

    lines = []
    w = walls
    lines.append("<!-- written by docs/validation/sweep.py: every number below is computed "
                 "there; do not edit by hand -->")
    lines.append("## Dynamic factor against speed: FE and lumped (`spurdyn sweep`)\n")
    lines.append(
        f"Paper's pair (`paper-fig8`: 22.25 N m, equal pitch-line speeds, dt 3e-8 s, 4 x 14 "
        f"mesh, whole engagement from first contact), one engagement per speed: FE at "
        f"{rf.size} speeds {rf.min():,.0f}-{rf.max():,.0f} rpm, lumped (two disks, FE "
        f"mesh-stiffness table, no damping) at {rl.size} speeds {rl.min():,.0f}-"
        f"{rl.max():,.0f} rpm. Figure: `docs/figures/dynamic_factor_sweep.png`. The points' "
        f"own run times add up to {float(np.nansum(fe['wall_s'].values)):.0f} s (FE, "
        f"{int(np.nansum(fe['steps'].values)):,} steps) and "
        f"{float(np.nansum(lumped['wall_s'].values)):.0f} s (lumped); this run of the script "
        f"took {w['fe'][0]:.0f} s and {w['lumped'][0]:.0f} s ({w['fe'][1]} and {w['lumped'][1]} "
        f"points computed, {w['fe'][2]} and {w['lumped'][2]} found in the sweep folder).\n")
    lines.append(
        f"**Estimate.** Mean FE single-pair mesh stiffness over the path of contact "
        f"k = {res.mesh_stiffness_mean:.4g} N/m, disks reduced to the line of action "
        f"m_e = {res.equivalent_mass:.4g} kg: f_n = sqrt(k/m_e)/2pi = "
        f"{res.natural_frequency_hz:,.0f} Hz; the mesh frequency 28 n/60 equals f_n at "
        f"**{n_res:,.0f} rpm**, and twice the mesh frequency does at {n_res / 2:,.0f} rpm.\n")

    lines.append("| | FE (raw peak) | FE (10 us average: the dynamic factor) | lumped (10 us "
                 "average) |")
    lines.append("| --- | --- | --- | --- |")
    for label, (lo, hi) in (("largest dynamic factor, whole range", (0, np.inf)),
                            (f"largest below 20,000 rpm", (0, 20000)),
                            (f"largest within +-25 % of {n_res / 2:,.0f} rpm (2 x mesh = f_n)",
                             (0.75 * n_res / 2, 1.25 * n_res / 2)),
                            (f"largest within +-25 % of {n_res:,.0f} rpm (mesh = f_n)",
                             (0.75 * n_res, 1.25 * n_res))):
        cells = []
        for rpm, y in ((rf, df_fe), (rf, df_fs), (rl, df_l)):
            n, v, nv = top(rpm, y, lo, hi)
            edge = " (edge of the window)" if n in (rpm[(rpm >= lo) & (rpm <= hi)].min(),
                                                    rpm[(rpm >= lo) & (rpm <= hi)].max()) else ""
            cells.append(f"{v:.3f} at {n:,.0f} rpm{edge}")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    lines.append(f"| local peaks (prominence >= 0.03) | {peak_text(rf, df_fe, 0.03)} | "
                 f"{peak_text(rf, df_fs, 0.03)} | {peak_text(rl, df_l, 0.03)} |")
    lines.append(f"| dynamic factor at {rf.min():,.0f} rpm (near quasi-static) | "
                 f"{df_fe[0]:.3f} | {df_fs[0]:.3f} | "
                 f"{float(np.interp(rf.min(), rl, df_l)):.3f} |")
    sep_fe = fe["separations"].values
    nearest = np.abs(rl[None, :] - rf[:, None]).argmin(axis=1)
    sep_l = lumped["separations"].values[nearest]
    lines.append(f"| speeds with a separation | {int((sep_fe > 0).sum())} of {rf.size} | | "
                 f"{int((lumped['separations'].values > 0).sum())} of {rl.size} |\n")

    lines.append("**Where the two models part** (FE against the lumped curve interpolated at "
                 "the FE speeds):\n")
    for name, r in (("raw FE peak", rel), ("10-us-averaged FE peak", rel_s)):
        parts = []
        for p in PART:
            over = np.flatnonzero(np.abs(r) > p)
            if over.size <= 8:
                listed = ", ".join(f"{rf[k]:,.0f} ({r[k]:+.1%})" for k in over) or "none"
            else:
                listed = (f"{over.size} of the {rf.size} speeds, {rf[over[0]]:,.0f} to "
                          f"{rf[over[-1]]:,.0f} rpm")
            parts.append(f"speeds with |difference| > {p:.0%}: {listed}")
        i = int(np.argmax(np.abs(r)))
        parts.append(f"mean |difference| {np.mean(np.abs(r)):.1%}, largest {r[i]:+.1%} at "
                     f"{rf[i]:,.0f} rpm, FE above lumped at {int((r > 0).sum())} of {rf.size} "
                     "speeds")
        lines.append(f"- {name}: " + "; ".join(parts) + ".")
    lines.append("")
    lines.append(reading(rf, df_fe, df_fs, rl, df_l, rel, rel_s, n_res,
                         fe["separations"].values, lumped["separations"].values))
    lines.append("")
    lines.append("| rpm | mesh frequency (Hz) | FE raw | FE 10 us | lumped 10 us | FE raw/lumped - 1 | "
                 "separations FE / lumped (nearest lumped speed) |")
    lines.append("| --- | --- | --- | --- | --- | --- | --- |")
    for k in range(rf.size):
        lines.append(f"| {rf[k]:,.0f} | {28 * rf[k] / 60:,.0f} | {df_fe[k]:.3f} | "
                     f"{df_fs[k]:.3f} | {lump_at[k]:.3f} | {rel[k]:+.1%} | "
                     f"{int(sep_fe[k])} / {int(sep_l[k])} |")
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: run (or resume) the two sweeps, then write the figure and the fragment."""
    parser = argparse.ArgumentParser(prog="docs/validation validation_sweep",
                                     description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="out/sweep-validation", help="sweep folder")
    parser.add_argument("--jobs", type=int, default=default_jobs(), help="local workers")
    args = parser.parse_args(argv)
    fe, lumped, res, walls = run(Path(args.out), args.jobs)
    for ds in (fe, lumped):
        assert (ds["status"].values == STATUS_CODES["complete"]).all()
    figure(fe, lumped, res, FIGURE)
    FRAGMENT.write_text(fragment(fe, lumped, res, walls), encoding="utf-8")
    print(f"wrote {FIGURE} and {FRAGMENT}")
    return 0
