"""The backlash-and-rattle part of docs/sector_dynamics_validation.md (its script,
``sector_dynamics.py``, imports it; ``--only rattle`` re-measures it): the
idle-rattle example measured, its figure, and the momentum and energy balances of the same
case undamped."""

from __future__ import annotations

import time

import numpy as np

from spurdyn.settings import RPM
from spurdyn.solvers.sector.run import simulate_sector
from validation.common import FIGURES, ROOT, timed

#: The bodies without the sector model's default structural damping (the undamped checks of
#: both scripts, the ring of the mesh damper alone, the tip-relief runs of undamped Fig. 8).
UNDAMPED = dict(rayleigh_mass=0.0, rayleigh_stiffness=0.0)


def rattle(mesh: dict) -> dict:
    """Idle rattle (examples/idle_rattle.toml on ``mesh``): the run as the example gives it,
    its figure, and the same case undamped with ``rho_inf = 1`` in the NumPy loop for the
    momentum and energy balances over its nine cycles."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from spurdyn.case import load_case

    case = load_case(ROOT / "examples" / "idle_rattle.toml",
                     {"mesh.nx": mesh["nx"], "mesh.ny": mesh["ny"]}, {})
    pair, s = case.pair, case.run
    run, wall = timed(simulate_sector, pair, s)
    back, drive = run.back_force.sum(axis=1), np.nansum(run.pair_force, axis=1)
    jn = run.info["backlash_normal_m"]
    hit = int(np.flatnonzero(back > 0)[0])
    apart = int(np.flatnonzero(drive == 0)[0])
    fig, ax = plt.subplots(3, 1, figsize=(8, 7), sharex=True)
    ms = run.time * 1e3
    ax[0].plot(ms, run.torque[:, 0], "k", lw=1)
    ax[0].axhline(0.0, color="0.6", lw=0.5)
    ax[0].set_ylabel("driver's torque (N m)")
    ax[1].plot(ms, drive, "k", lw=1, label="drive flanks")
    ax[1].plot(ms, -back, "tab:red", lw=1, label="back flanks (drawn negative)")
    ax[1].axhline(run.info["static_force"], color="0.5", ls="--", lw=0.8, label="static T/r_b")
    ax[1].set_ylabel("mesh force (N)")
    ax[1].legend(loc="lower left", fontsize=8)
    ax[2].plot(ms, run.transmission_error * 1e6, "tab:blue", lw=1)
    ax[2].axhline(-jn * 1e6, color="tab:red", ls=":", lw=0.8, label="-j_n")
    ax[2].set_ylabel("transmission error (µm)")
    ax[2].set_xlabel("time (ms)")
    ax[2].legend(loc="lower left", fontsize=8)
    ax[0].set_title(f"idle rattle: {s.speed_a / RPM:,.0f} rpm, j_n = {jn * 1e6:.1f} µm, "
                    f"{mesh['nx']} x {mesh['ny']} teeth")
    fig.tight_layout()
    fig.savefig(FIGURES / "validation_idle_rattle.png", dpi=110)
    plt.close(fig)
    ref = simulate_sector(pair, s.with_(backend="numpy", rho_inf=1.0, damping_ratio=0.0, **UNDAMPED),
                          energy=True)
    p = np.array(ref.info["momentum"]["hub_momentum"])
    q = np.array(ref.info["momentum"]["contact_torque"]) + ref.torque
    impulse = np.concatenate([np.zeros((1, 2)), np.cumsum(0.5 * np.diff(ref.time)[:, None] * (q[1:] + q[:-1]), axis=0)])
    e = ref.info["energy"]
    total = np.array(e["kinetic_J"]) + np.array(e["strain_J"]) + np.array(e["strip_J"]) - np.array(e["work_J"])
    back_ref = ref.back_force.sum(axis=1)
    return {"status": run.status, "wall_s": wall, "steps": int(run.time.size - 1), "backlash_um": jn * 1e6,
            "static_N": run.info["static_force"], "first_apart_ms": float(run.time[apart] * 1e3),
            "first_back_ms": float(run.time[hit] * 1e3), "te_at_back_um": float(run.transmission_error[hit] * 1e6),
            "back_max_N": float(back.max()), "drive_max_N": float(drive.max()),
            "back_steps": int((back > 0).sum()), "apart_steps": int(((back == 0) & (drive == 0)).sum()),
            "ref_status": ref.status, "ref_back_max_N": float(back_ref.max()),
            "momentum_error_rel": float(np.abs(p - p[0] - impulse).max() / np.abs(p[0]).max()),
            "energy_error_max_rel": float(np.abs(total - total[0]).max() / max(e["strain_J"])),
            "energy_error_end_rel": float((total[-1] - total[0]) / max(e["strain_J"])),
            "kinetic_swing_rel": float((max(e["kinetic_J"]) - min(e["kinetic_J"])) / max(e["strain_J"]))}


def rattle_lines(ra: dict, mesh: str) -> list[str]:
    """The page's section of the figures ``ra`` measured on ``mesh`` (``"4 x 14"``)."""
    return [
        "",
        f"## Backlash and rattle (examples/idle_rattle.toml, {mesh} tooth meshes)",
        "",
        f"The paper's pair 0.1 mm beyond its tight centre distance (j_n = {ra['backlash_um']:.1f} µm) at "
        "1,000 rpm under 1 N m of drag, its driver's torque fluctuating by 4 N m at 200 Hz (a torque "
        "history from a CSV file, repeated), 5 % mesh damper, 9 cycles (docs/sector.md, 6.8). "
        f"{ra['status'].capitalize()}, {ra['steps']:,} steps in {ra['wall_s']:.0f} s:",
        "",
        "| | |",
        "| --- | --- |",
        f"| drive flanks first apart | {ra['first_apart_ms']:.2f} ms |",
        f"| back flanks first strike | {ra['first_back_ms']:.2f} ms, the transmission error "
        f"{ra['te_at_back_um']:.1f} µm |",
        f"| largest back-flank force | {ra['back_max_N']:,.0f} N ({ra['back_max_N'] / ra['static_N']:.1f} "
        f"x the static {ra['static_N']:.1f} N) |",
        f"| largest drive-flank force | {ra['drive_max_N']:,.0f} N ({ra['drive_max_N'] / ra['static_N']:.1f} x) |",
        f"| steps with a back contact / with no contact | {ra['back_steps']:,} / {ra['apart_steps']:,} |",
        "",
        "![idle rattle: the driver's torque, both flanks' forces (the back flanks' drawn negative) and the "
        "transmission error crossing the backlash](figures/validation_idle_rattle.png)",
        "",
        "The same run undamped (bodies and mesh) with rho_inf = 1, in the NumPy loop "
        f"({ra['ref_status']}, back flanks up to {ra['ref_back_max_N']:,.0f} N): each hub's momentum is its "
        "torques' (the history's) and the contacts' trapezoidal impulse to "
        f"{ra['momentum_error_rel']:.1e} of its momentum over the nine cycles; the energy balance moves by "
        f"up to {ra['energy_error_max_rel']:.1%} of the largest strain energy ({ra['energy_error_end_rel']:+.1%} "
        "at the end; the hubs' kinetic energy swings by "
        f"{ra['kinetic_swing_rel']:.0f} times it): each impact is closed at the end of a step with the rows "
        "held, a plastic impact at the step's scale (docs/sector.md, 6.5 and 6.7).",
    ]
