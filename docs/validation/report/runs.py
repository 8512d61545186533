"""The runs of the report and their cache in ``docs/validation_data/<name>.npz``.

A cached run is reused when the digest stored with it equals its :class:`Spec`'s
digest, a hash of the spec's fields alone: neither the code of this package nor the
solver's enters it, so moving this code around keeps the cache valid, and a change of
the solver needs ``--rerun``.
"""

from __future__ import annotations

import hashlib
import json
import math
import subprocess
import time
from dataclasses import asdict, dataclass
from typing import Any, Callable

import numpy as np
from numpy.typing import NDArray

from .settings import (DATA, MESH_SPLINE, MESHES, MESHES_20K, ROOT, RPM, SOLVER_DIRS,
                       STABLE_FRACTION)
from .spurdyn_api import (PAPER_DT, CompiledStepper, GearPair, RunSettings, build_system,
                          nasa_like_relief, paper_gear, simulate, simulate_lumped, stable_step,
                          track)


@dataclass(frozen=True)
class Spec:
    """One run of the report.

    ``kind``: ``fe`` (``simulate``), ``lumped`` (``simulate_lumped``) or ``balance``
    (a CompiledStepper stepped by ``spurdyn.results.balances.track``). ``dt`` None is the
    paper's 3e-8 s; a negative ``dt`` means that fraction of the mesh's stable RK4 step.
    ``relief`` is the tip relief (m) on both gears, 0 for none.
    """

    name: str
    kind: str
    speed_a_rpm: float
    speed_b_rpm: float
    torque: float = 22.25
    driver: str = "a"
    nx: int = 4
    ny: int = 14
    dt: float | None = None
    n_spline: int = 61
    tol_disp: float = 1e-12
    save_every: int = 1
    relief: float = 0.0

    def digest(self) -> str:
        """The cache key: a hash of every field (the run's settings), not of any code."""
        return hashlib.sha1(json.dumps(asdict(self), sort_keys=True).encode()).hexdigest()[:12]


def make_pair(spec: Spec) -> GearPair:
    """The paper's pair with the spec's relief and driver."""
    g = paper_gear()
    if spec.relief:
        g = nasa_like_relief(g, amount=spec.relief)
    return GearPair(gear_a=g, gear_b=g, driver=spec.driver)


def make_case(spec: Spec, pair: GearPair) -> RunSettings:
    """The spec's run settings, with its time step resolved to seconds."""
    case = RunSettings(contact="point", speed_a=spec.speed_a_rpm * RPM, speed_b=spec.speed_b_rpm * RPM,
                   torque=spec.torque, nx=spec.nx, ny=spec.ny, n_spline=spec.n_spline,
                   tol_disp=spec.tol_disp, save_every=spec.save_every, frames_every=0,
                   name=spec.name)
    if spec.dt is None:
        return case.with_(dt=PAPER_DT)
    if spec.dt < 0:
        inner = pair
        if pair.driver == "b":
            inner = GearPair(gear_a=pair.gear_b, gear_b=pair.gear_a, driver="a")
        return case.with_(dt=-spec.dt * stable_step(build_system(inner, case)))
    return case.with_(dt=spec.dt)


def plain(value: Any) -> Any:
    """JSON-safe copy of ``Result.info`` values."""
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return plain(value.tolist())
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        v = float(value)
        return v if math.isfinite(v) else None
    if isinstance(value, (int, str, bool)) or value is None:
        return value
    return str(value)


def git_state() -> str:
    """HEAD commit (short) and whether the solver's sources differ from it."""
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                              text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no",
                                *(f"src/spurdyn/{d}" for d in SOLVER_DIRS)], cwd=ROOT,
                               capture_output=True, text=True, check=True).stdout.strip()
        return head + (" (with uncommitted changes to the model or solver)" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def execute(spec: Spec) -> tuple[dict[str, NDArray[Any]], dict[str, Any]]:
    """Run ``spec``; return its arrays and its metadata."""
    pair = make_pair(spec)
    case = make_case(spec, pair)
    t0 = time.perf_counter()
    if spec.kind == "balance":
        rec = track(CompiledStepper(build_system(pair, case), case), angle=pair.theta_s)
        arrays = {k: np.asarray(getattr(rec, k)) for k in (
            "t", "angle", "contact_force", "momentum", "angular_impulse", "energy", "strain",
            "torque_work", "contact_work")}
        meta = {"status": "complete" if rec.status == 0 else f"stopped ({rec.status})",
                "steps": int(len(rec.t) - 1)}
    else:
        if spec.kind == "lumped":
            r = simulate_lumped(pair, case)
        else:
            r = simulate(pair, case)
        arrays = {"time": r.time, "angle": r.angle, "contact_force": r.contact_force,
                  "gap": r.gap, "roll": r.roll, "theta": r.theta, "omega": r.omega,
                  "torque": r.torque, "residual": r.residual, "iterations": r.iterations,
                  "corner": r.corner}
        keep = ("model", "n_dof", "theta_s", "theta_2", "static_force", "single_zone",
                "mesh_stiffness_single_zone", "equivalent_mass", "nodes")
        meta = {"status": r.status, "reason": r.reason, "steps": int(r.steps),
                "info": plain({k: v for k, v in r.info.items() if k in keep})}
    meta.update(wall_s=time.perf_counter() - t0, dt=case.dt, digest=spec.digest(),
                spec=asdict(spec), git=git_state(),
                date=time.strftime("%Y-%m-%d %H:%M:%S"))
    return arrays, meta


class Run(dict):
    """A cached run: its arrays as items, its metadata as ``.meta``."""

    meta: dict[str, Any]


def load_or_run(spec: Spec, rerun: bool = False, log: Callable[[str], None] = print) -> Run:
    """The run of ``spec`` from ``docs/validation_data`` or, if missing/stale, computed."""
    path = DATA / f"{spec.name}.npz"
    if path.is_file() and not rerun:
        with np.load(path, allow_pickle=False) as z:
            meta = json.loads(str(z["meta"]))
            if meta.get("digest") == spec.digest():
                run = Run({k: z[k] for k in z.files if k != "meta"})
                run.meta = meta
                return run
    log(f"  running {spec.name} ({spec.kind}, {spec.speed_a_rpm:g}/{spec.speed_b_rpm:g} rpm, "
        f"{spec.nx}x{spec.ny}, driver {spec.driver}) ...")
    arrays, meta = execute(spec)
    DATA.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".tmp.npz")
    np.savez_compressed(tmp, meta=np.array(json.dumps(meta)), **arrays)
    tmp.replace(path)
    log(f"    {meta['status']}, {meta['steps']:,} steps, {meta['wall_s']:.1f} s")
    run = Run(arrays)
    run.meta = meta
    return run


def specs() -> list[Spec]:
    """Every run of the report, cheapest and most important first."""
    s: list[Spec] = []
    paper = [("fig8", 4000, 4000), ("fig9", 20000, 20000), ("fig10", 4000, 4040),
             ("fig11", 20000, 20200)]
    for name, a, b in paper:
        s.append(Spec(name, "fe", a, b))
    for name, a, b in paper[2:]:
        s.append(Spec(f"{name}_b", "fe", a, b, driver="b"))
    for name, a, b in paper:
        s.append(Spec(f"lumped_{name}", "lumped", a, b))
    for name, a, b in paper[2:]:
        s.append(Spec(f"lumped_{name}_b", "lumped", a, b, driver="b"))
    s.append(Spec("lumped_qs1000", "lumped", 1000, 1000))
    for nx, ny in MESHES + ((12, 40),):
        s.append(Spec(f"mesh_{nx}x{ny}", "fe", 4000, 4000, nx=nx, ny=ny, dt=-STABLE_FRACTION,
                      n_spline=MESH_SPLINE))
    for nx, ny in MESHES_20K:
        s.append(Spec(f"mesh20k_{nx}x{ny}", "fe", 20000, 20000, nx=nx, ny=ny,
                      dt=-STABLE_FRACTION, n_spline=MESH_SPLINE))
    # the same finer meshes with the paper's 61 spline points (they stop: section 2)
    for name, a, b, nx, ny in (("mesh_6x20", 4000, 4000, 6, 20), ("mesh_8x28", 4000, 4000, 8, 28),
                               ("mesh_12x40", 4000, 4000, 12, 40),
                               ("mesh20k_6x20", 20000, 20000, 6, 20),
                               ("mesh20k_8x28", 20000, 20000, 8, 28),
                               ("fig10_6x20", 4000, 4040, 6, 20)):
        s.append(Spec(f"{name}_s61", "fe", a, b, nx=nx, ny=ny, dt=-STABLE_FRACTION))
    s.append(Spec("mesh20k_8x28_s61_dt05", "fe", 20000, 20000, nx=8, ny=28, dt=-0.5))
    s.append(Spec("fig10_6x20_s61_dt05", "fe", 4000, 4040, nx=6, ny=20, dt=-0.5))
    s.append(Spec("mesh_12x40_s481", "fe", 4000, 4000, nx=12, ny=40, dt=-STABLE_FRACTION,
                  n_spline=481))
    s.append(Spec("dt_half", "fe", 4000, 4000, dt=1.5e-8))
    s.append(Spec("spline_121", "fe", 4000, 4000, n_spline=121))
    s.append(Spec("spline_241", "fe", 4000, 4000, n_spline=241))
    s.append(Spec("tol_1e-13", "fe", 4000, 4000, tol_disp=1e-13))
    s.append(Spec("qs1000", "fe", 1000, 1000, save_every=5))
    s.append(Spec("fig11_b_dt15", "fe", 20000, 20200, driver="b", dt=1.5e-8))
    s.append(Spec("fig11_b_dt10", "fe", 20000, 20200, driver="b", dt=1.0e-8))
    s.append(Spec("fig10_dt15", "fe", 4000, 4040, dt=1.5e-8))
    s.append(Spec("fig10_s121", "fe", 4000, 4040, n_spline=121))
    s.append(Spec("fig10_s241", "fe", 4000, 4040, n_spline=241))
    s.append(Spec("fig10_6x20", "fe", 4000, 4040, nx=6, ny=20, dt=-STABLE_FRACTION,
                  n_spline=MESH_SPLINE))
    s.append(Spec("fig10_4x14_s241", "fe", 4000, 4040, dt=-STABLE_FRACTION, n_spline=MESH_SPLINE))
    s.append(Spec("relief_20um", "fe", 4000, 4000, relief=20e-6))
    s.append(Spec("relief_5um", "fe", 4000, 4000, relief=5e-6))
    s.append(Spec("bal_fig9", "balance", 20000, 20000))
    s.append(Spec("bal_fig9_free", "balance", 20000, 20000, torque=0.0))
    s.append(Spec("bal_fig8", "balance", 4000, 4000))
    s.append(Spec("bal_fig8_free", "balance", 4000, 4000, torque=0.0))
    s.append(Spec("bal_fig10", "balance", 4000, 4040))
    s.append(Spec("bal_fig10_s241", "balance", 4000, 4040, n_spline=241))
    s.append(Spec("bal_fig10_dt15", "balance", 4000, 4040, dt=1.5e-8))
    return s


def all_runs(rerun: bool = False, log: Callable[[str], None] = print) -> dict[str, Run]:
    """Every run of :func:`specs` by name, from the cache or computed."""
    return {sp.name: load_or_run(sp, rerun, log) for sp in specs()}
