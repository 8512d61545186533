"""Shared by the tests of what a run leaves on disk (test_results_io, test_results_pictures,
test_cli_run and its kin, test_unattended, test_properties, test_results_beside): a
synthetic solver, ``fake_simulate``, whose results are shaped like the solver's, and a run
folder written from it (the module fixtures ``short_case`` and ``run_dir``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from spurdyn.case import preset_case
from spurdyn.geometry.pair import GearPair
from spurdyn.geometry.placement import mesh_angles, to_world_a, to_world_b
from spurdyn.mesh.tooth import tooth_mesh
from spurdyn.result import Result
from spurdyn.settings import RunSettings

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


# -- a synthetic solver ----------------------------------------------------------------

def _rot(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def fake_simulate(pair: GearPair, case: RunSettings, progress=None, *, status: str = "complete",
                  reason: str = "", separations: tuple[tuple[float, float], ...] = (),
                  elastic: float = 2e-7, chunk: int = 20) -> Result:
    """A stand-in for ``spurdyn.solvers.loop.simulate`` with the same contract.

    Gear A turns at its initial speed; the force follows the torque schedule with a
    ripple and drops to zero in the windows ``separations`` (deg). Frames hold the rigid
    rotation of each tooth plus an elastic shear of amplitude ``elastic`` (m) at the tip.
    Ctrl-C in ``progress`` ends the run early with ``status = "incomplete"``.
    """
    total = pair.theta_s if case.angle is None else case.angle
    n = max(1, math.ceil(total / (case.speed_a * case.dt)))
    done = n
    try:
        for step in range(chunk, n + chunk, chunk):
            if progress is not None:
                progress(min(step, n), min(step, n) * case.speed_a * case.dt, total)
    except KeyboardInterrupt:
        done = min(step, n)
        status, reason = "incomplete", f"interrupted by the user at step {done}"
    steps = np.unique(np.append(np.arange(0, done + 1, case.save_every), done))
    t = steps * case.dt
    angle = case.speed_a * t
    deg = np.degrees(angle)
    static = case.torque / pair.gear_a.base_radius
    ramp = np.clip(np.minimum(angle, pair.theta_s - angle) / pair.theta_2, 0.0, 1.0)
    force = static * ramp * (1.0 + 0.1 * np.sin(40.0 * angle))
    for lo, hi in separations:
        force[(deg > lo) & (deg < hi)] = 0.0
    ratio = pair.gear_a.teeth / pair.gear_b.teeth
    theta = np.column_stack([angle, angle * ratio])
    it = np.tile([6, 4, 3], (len(t), 1)).astype(np.int64)
    it[0] = 0
    res = np.tile([1e-13, 1e-6, 1.0], (len(t), 1)) * (1.0 + np.arange(len(t)))[:, None]
    half = 1e-5 * np.sqrt(force / static)

    mesh_a = tooth_mesh(pair.gear_a, case.nx, case.ny)
    mesh_b = tooth_mesh(pair.gear_b, case.nx, case.ny)
    ta0, tb0 = mesh_angles(pair, pair.start_roll_a)
    c = (np.zeros(2), np.array([0.0, pair.centre_distance]))
    x0 = (to_world_a(mesh_a.nodes, ta0), to_world_b(mesh_b.nodes, tb0, pair.centre_distance))
    frame_steps = np.arange(0, done + 1, case.frames_every) if case.frames_every else np.zeros(0, int)
    frame_u = np.zeros((len(frame_steps), 2 * (mesh_a.n_nodes + mesh_b.n_nodes)))
    for k, s in enumerate(frame_steps):
        blocks = []
        for g, sign in ((0, -1.0), (1, 1.0)):
            a = s * case.dt * case.speed_a * (1.0 if g == 0 else ratio)
            rel = x0[g] - c[g]
            height = np.hypot(*rel.T) - np.hypot(*rel.T).min()
            shear = elastic * k / max(len(frame_steps) - 1, 1) * height / height.max()
            d = np.column_stack([shear, np.zeros_like(shear)])
            blocks.append((c[g] + (rel + d) @ _rot(sign * a).T - x0[g]).ravel())
        frame_u[k] = np.concatenate(blocks)
    return Result(
        time=t, angle=angle, contact_force=force, gap=np.where(force > 0, -force / 2e8, 1e-7),
        roll=np.column_stack([pair.start_roll_a + angle,
                              pair.roll_b_from_roll_a(pair.start_roll_a + angle)]),
        theta=theta, omega=np.column_stack([np.full_like(t, case.speed_a),
                                            np.full_like(t, case.speed_b)]),
        torque=np.column_stack([case.torque * ramp, case.torque * ramp / ratio]),
        residual=res, iterations=it, corner=np.zeros(len(t), np.int8),
        frame_time=frame_steps * case.dt, frame_theta=np.column_stack(
            [frame_steps * case.dt * case.speed_a, frame_steps * case.dt * case.speed_a * ratio])
        if len(frame_steps) else np.zeros((0, 2)),
        frame_u=frame_u, status=status, reason=reason, steps=int(done), wall_s=0.25,
        info={"n_dof": 2 * (mesh_a.n_nodes + mesh_b.n_nodes) + 2, "theta_s": pair.theta_s,
              "theta_2": pair.theta_2, "static_force": static,
              "single_zone": (pair.theta_2, pair.theta_s - pair.theta_2), "note": np.float64(1)},
        # Hertz's strip as the FE model gives it: b ~ sqrt(F), p = 2 F / (pi b L)
        contact_half_width=half, contact_pressure_max=np.where(
            half > 0, 2.0 * force / (np.pi * np.where(half > 0, half, 1.0) * pair.gear_a.face_width), 0.0),
    )


@pytest.fixture(scope="module")
def short_case():
    """paper-fig9 over 0.3 deg, every step kept, a frame every 10 steps."""
    return preset_case("paper-fig9", {"run.angle_deg": 0.3, "run.frames_every": 10},
                       check_step=False)


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory, short_case):
    from spurdyn.results.io import write_run   # not at the top: a command's process that
                                              # uses fake_simulate steps without xarray
    d = tmp_path_factory.mktemp("run")
    result = fake_simulate(short_case.pair, short_case.run, separations=((0.1, 0.12),))
    summary = write_run(result, short_case, d, vtu=True)
    return d, result, summary

