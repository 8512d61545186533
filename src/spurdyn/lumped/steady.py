"""Steady state of the lumped model over many mesh cycles (issue 16; docs/lumped.md).

The one-engagement model of :mod:`spurdyn.lumped.model` loads one pair through the
paper's torque ramps. Here the torques are constant and every tooth pair that the path
of contact holds at a moment is a spring in parallel: pair ``j`` enters when gear A has
turned ``j`` angular pitches ``p = 2 pi / z_A``, at the roll angle of the start of contact,
and leaves ``theta_s`` later, so at A's rotation ``phi``

    k(phi) = sum_j k_s(rho(phi - j p)),     F_j = max(0, k_j delta + c_j delta_dot)  (delta > 0),

with ``k_s`` the single-pair stiffness (:class:`~spurdyn.lumped.model.MeshStiffnessTable`,
zero off the path) and ``rho`` the contact point's roll angle on A. The damper of the
mesh, ``c = 2 zeta sqrt(k(phi) m_e)`` (the damping ratio of the pair's torsional mode at
the mesh stiffness of the moment), is shared in proportion to the pairs' stiffnesses,
``c_j = c k_j / k``. The run starts from the static compression ``delta_0 = F_0 / k(0)``
at nominal speeds, so a quasi-static run starts at rest in the mesh, and lasts ``N`` mesh
cycles (``N p`` of A's rotation), and if it has not settled then, one more at a time until it
has or has run ``max_cycles`` (:attr:`~spurdyn.settings.RunSettings.cycles_limit`).
"""

from __future__ import annotations

import math
import time as _time
from typing import Any, Callable, NamedTuple

import numpy as np
from numpy.typing import NDArray
from scipy.integrate import solve_ivp

from spurdyn.geometry.pair import GearPair
from spurdyn.lumped.cycle import SectorCycle, TableCycle, pair_rolls
from spurdyn.lumped.model import RTOL, MeshStiffnessTable, contact_roll_a, equivalent_mass, torsional_natural_frequency
from spurdyn.model.loading import check_history, hub_torques, static_force, torque_amplitudes
from spurdyn.result import Result
from spurdyn.settings import RunSettings
from spurdyn.solvers.steady import cycle_figures, settled_after, steady_record

#: Saved samples per mesh period, and the longest interval between samples (s): the
#: headline's 10-us average needs several samples a window.
SAMPLES_PER_CYCLE = 200
MAX_SAMPLE_INTERVAL = 1e-6


Cycle = TableCycle | SectorCycle


def samples_per_cycle(period: float) -> int:
    """Samples a mesh cycle of ``period`` (s) keeps: :data:`SAMPLES_PER_CYCLE`, or more to keep
    them :data:`MAX_SAMPLE_INTERVAL` apart at most (a whole number, so that every cycle is
    sampled at the same phases)."""
    return max(SAMPLES_PER_CYCLE, int(math.ceil(period / MAX_SAMPLE_INTERVAL)))


def as_cycle(pair: GearPair, stiffness: MeshStiffnessTable | Cycle) -> Cycle:
    """A single-pair table as its :class:`~spurdyn.lumped.cycle.TableCycle`; a cycle as is."""
    return TableCycle(pair, stiffness) if isinstance(stiffness, MeshStiffnessTable) else stiffness


def cycle_stiffness(pair: GearPair, stiffness: MeshStiffnessTable | Cycle,
                    samples: int = 2000) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The stiffness of each tooth pair in contact over one mesh cycle under constant
    torques: rows are the pairs that entered 0, 1, ... pitches before, columns A's
    rotations ``phi`` in ``[0, p)``; returns ``(phi, k_j(phi))``. Their sum is the mesh
    stiffness ``k(phi)`` of the module docstring, whose mean sets the torsional frequency
    of the steady-state pair."""
    cycle = as_cycle(pair, stiffness)
    phis = np.arange(samples) * (cycle.pitch / samples)
    return phis, cycle.grid(phis)


def simulate_steady(pair: GearPair, settings: RunSettings, stiffness: MeshStiffnessTable | Cycle,
                    damping_ratio: float, cycles: int) -> Result:
    """The lumped pair under constant torques over ``cycles`` mesh cycles (module docstring),
    its pairs' stiffnesses from the single-pair table or a cycle (:mod:`spurdyn.lumped.cycle`).

    Returns a :class:`~spurdyn.result.Result` whose ``contact_force`` is the force of the
    most loaded tooth pair at each sample and ``gap`` minus the compression ``delta`` along
    the line of action (the transmission error, positive where the teeth yield); ``info``
    holds ``steady``: the cycles, the mesh period, the settled test and its figures.
    """
    wall0 = _time.perf_counter()
    check_history(pair, settings)
    cycle = as_cycle(pair, stiffness)
    zeta2_sqrt_me = 2.0 * damping_ratio * math.sqrt(equivalent_mass(pair))
    rhs, pair_forces, stiffnesses = _steady_equations(pair, settings, cycle, zeta2_sqrt_me)
    grid = _steady_grid(pair, settings, cycle, stiffnesses, cycles)
    sol = solve_ivp(rhs, (0.0, grid.t[-1]), grid.y0, method="DOP853", rtol=RTOL, atol=grid.atol,
                    max_step=grid.step, t_eval=grid.t)
    status, reason = "complete", ""
    if sol.status != 0:
        status, reason = "incomplete", f"integration failed: {sol.message}"
    # not settled, and it may go on (max_cycles): one more cycle from where it ended
    limit = max(settings.cycles_limit or cycles, cycles)
    t, y, nfev, status, reason = _go_on(rhs, pair_forces, grid, sol, status, reason, cycles, limit)
    forces, j_all = pair_forces(y[0], y[2], y[3])
    info = _steady_info(pair, settings, cycle, t, y, forces, nfev, grid, cycles, limit, damping_ratio)
    return _steady_result(pair, settings, t, y, forces, j_all.size, status, reason, nfev, wall0, info)


class _Grid(NamedTuple):
    """The steady run's sampling and tolerances: the mesh ``period`` (s), ``per_cycle``
    samples a cycle ``h`` apart, the first run's sample times ``t``, the start ``y0``,
    the integrator's ``atol`` and largest ``step``, the torsional mode ``f_n`` (Hz) and the
    static force."""

    period: float
    per_cycle: int
    h: float
    t: NDArray[np.float64]
    y0: NDArray[np.float64]
    atol: NDArray[np.float64]
    step: float
    f_n: float
    static: float


def _steady_equations(pair: GearPair, settings: RunSettings, cycle: Cycle, zeta2_sqrt_me: float) -> tuple[
        Callable[[float, NDArray[np.float64]], Any],
        Callable[..., tuple[NDArray[np.float64], NDArray[np.int64]]], Callable[[float], list[float]]]:
    """The steady pair's right-hand side in ``y = (phi_a, omega_a, delta, delta_dot)``, every
    pair's force at samples (with the pairs' numbers) and the pairs' stiffnesses at ``phi``."""
    ga, gb = pair.gear_a, pair.gear_b
    ra, rb = ga.base_radius, gb.base_radius
    ja, jb = ga.disk_inertia, gb.disk_inertia
    s = 1.0 if pair.driver == "a" else -1.0
    amp_a, amp_b = torque_amplitudes(pair, settings.torque)
    # torques that vary (a history, a ramp from rest) are read at each time, others once
    varying = settings.torque_history is not None or settings.start == "rest"
    pitch = 2.0 * math.pi / ga.teeth
    n_back = cycle.rows - 1                           # pairs entered before phi = 0

    def stiffnesses(phi: float) -> list[float]:
        return cycle.at(phi - pitch * math.floor(phi / pitch))

    def mesh_force(phi: float, delta: float, ddelta: float) -> float:
        if delta <= 0.0:
            return 0.0
        ks = stiffnesses(phi)
        k = sum(ks)
        if k <= 0.0:
            return 0.0
        c = zeta2_sqrt_me * math.sqrt(k)
        return sum(max(0.0, kj * delta + c * kj / k * ddelta) for kj in ks)

    def rhs_python(t: float, y: NDArray[np.float64]) -> list[float]:
        phi_a, w_a, delta, ddelta = y
        f = mesh_force(phi_a, delta, ddelta)
        t_a, t_b = hub_torques(pair, settings, t) if varying else (amp_a, amp_b)
        acc_a = (t_a - s * ra * f) / ja
        acc_b = (t_b + s * rb * f) / jb
        return [w_a, acc_a, ddelta, s * (ra * acc_a - rb * acc_b)]

    rhs: Callable[[float, NDArray[np.float64]], Any] = rhs_python
    if not varying and settings.backend == "numba":
        # the same arithmetic compiled (lumped/steady_compiled.py): the torques constant
        dense, bounds, h, roll0, droll = cycle.tables()
        par = np.array([h, pitch, zeta2_sqrt_me, ra, rb, ja, jb, s, amp_a, amp_b, roll0, droll])
        rhs = _compiled_rhs(dense, bounds, par, cycle.rows)

    def pair_forces(phi_a: NDArray[np.float64], delta: NDArray[np.float64],
                    ddelta: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
        """Every pair's force at every sample, and the pairs' numbers."""
        n = phi_a.size
        first = np.floor(phi_a / pitch).astype(np.int64)
        j_all = np.arange(int(first.min()) - n_back, int(first.max()) + 1)
        rows = cycle.grid(phi_a - pitch * first)          # (rows, n): row r entered at first - r
        ks = np.zeros((j_all.size, n))
        for r in range(cycle.rows):
            ks[first - r - j_all[0], np.arange(n)] = rows[r]
        k_tot = ks.sum(axis=0)
        c = zeta2_sqrt_me * np.sqrt(np.maximum(k_tot, 0.0))
        with np.errstate(invalid="ignore", divide="ignore"):
            share = np.where(k_tot > 0, ks / k_tot, 0.0)
        return np.where(delta > 0, np.maximum(ks * delta + c * share * ddelta, 0.0), 0.0), j_all

    return rhs, pair_forces, stiffnesses


def _compiled_rhs(dense: NDArray[np.float64], bounds: NDArray[np.float64], par: NDArray[np.float64],
                  rows: int) -> Callable[[float, NDArray[np.float64]], NDArray[np.float64]]:
    """:func:`spurdyn.lumped.steady_compiled.rhs` on these tables, as SciPy calls it."""
    from spurdyn.lumped.steady_compiled import rhs as kernel

    rows = np.int64(rows)
    return lambda t, y: kernel(t, y, dense, bounds, par, rows)


def _steady_grid(pair: GearPair, settings: RunSettings, cycle: Cycle, stiffnesses: Callable[[float], list[float]],
                 cycles: int) -> _Grid:
    """The first run's samples, start and tolerances (the static compression at nominal
    speeds, another run's end, or rest)."""
    ra, rb = pair.gear_a.base_radius, pair.gear_b.base_radius
    s = 1.0 if pair.driver == "a" else -1.0
    pitch = 2.0 * math.pi / pair.gear_a.teeth
    w_a0 = float(settings.speed_a)
    period = pitch / w_a0
    static = static_force(pair, settings.torque)
    k0 = sum(stiffnesses(0.0))
    delta0 = static / k0 if k0 > 0 else 0.0
    w_b0 = float(settings.speed_b)
    v0 = s * (ra * w_a0 - rb * w_b0)
    f_n = float(torsional_natural_frequency(pair, cycle.k_max))
    t_end = cycles * period
    # a whole number of samples a cycle, so that every cycle is sampled at the same phases
    per_cycle = samples_per_cycle(period)
    h = period / per_cycle
    n_out = cycles * per_cycle + 1
    t = np.linspace(0.0, t_end, n_out)     # ends exactly at t_end, the integration's end
    delta_ref = max(delta0, abs(v0) / (2 * math.pi * f_n), 1e-9)
    atol = np.array([1e-13, 1e-10 * w_a0, RTOL * delta_ref, RTOL * delta_ref * 2 * math.pi * f_n])
    if settings.start_state is not None:    # another run's end: the same phase of a cycle
        delta0, v0 = settings.start_state[0], settings.start_state[1] * w_a0
    elif settings.start == "rest":          # undeformed, the torques ramped up from zero
        delta0 = 0.0
    y0 = np.array([0.0, w_a0, delta0, v0])
    step = min(period / 40.0, 0.25 / f_n)
    return _Grid(period, per_cycle, h, t, y0, atol, step, f_n, static)


def _go_on(rhs: Callable[[float, NDArray[np.float64]], Any],
           pair_forces: Callable[..., tuple[NDArray[np.float64], NDArray[np.int64]]], grid: _Grid, sol: Any,
           status: str, reason: str, cycles: int,
           limit: int) -> tuple[NDArray[np.float64], NDArray[np.float64], int, str, str]:
    """Run one more cycle at a time from the first run's end ``sol`` until the last two
    settle or the run has ``limit`` cycles; ``(t, y, nfev, status, reason)``."""
    t, y, nfev = sol.t, sol.y, int(sol.nfev)
    period, per_cycle = grid.period, grid.per_cycle
    target = cycles
    while status == "complete" and target < limit:
        last2 = y[:, -2 * per_cycle - 1:]
        if settled_after(pair_forces(last2[0], last2[2], last2[3])[0].sum(axis=0), last2[2], per_cycle, 2):
            break
        t_more = np.linspace(target * period, (target + 1) * period, per_cycle + 1)
        more = solve_ivp(rhs, (t_more[0], t_more[-1]), y[:, -1], method="DOP853", rtol=RTOL, atol=grid.atol,
                         max_step=grid.step, t_eval=t_more)
        nfev += int(more.nfev)
        if more.status != 0:
            status, reason = "incomplete", f"integration failed: {more.message}"
        t, y = np.concatenate([t, more.t[1:]]), np.concatenate([y, more.y[:, 1:]], axis=1)
        target += 1
    return t, y, nfev, status, reason


def _steady_info(pair: GearPair, settings: RunSettings, cycle: Cycle, t: NDArray[np.float64],
                 y: NDArray[np.float64], forces: NDArray[np.float64], nfev: int, grid: _Grid, cycles: int, limit: int, damping_ratio: float) -> dict[str, Any]:
    """The steady run's record: the pair, the cycle's stiffness, the integration statistics
    and the settled test (``steady``); ``forces`` every pair's at the samples ``t``."""
    phi_a, w_a, delta, ddelta = y
    n = t.size
    static, theta_s = grid.static, pair.theta_s
    mesh = forces.sum(axis=0)
    # the quasi-static largest pair force of a cycle: F_0 k_j / k, sampled finely
    _, kq = cycle_stiffness(pair, cycle)
    kq_tot = kq.sum(axis=0)
    static_pair_max = float(np.max(np.where(kq_tot > 0, static * kq / np.where(kq_tot > 0, kq_tot, 1.0), 0.0)))
    fig = cycle_figures(t, mesh, delta, grid.per_cycle, cycles, limit)
    return {
        "model": "lumped",
        "n_dof": 2,
        "case": settings.name,
        "driver": pair.driver,
        "theta_s": theta_s,
        "theta_2": pair.theta_2,
        "static_force": static,
        "single_zone": (pair.theta_2, theta_s - pair.theta_2),
        "mesh_stiffness_cycle": cycle.describe(),
        "natural_frequency_hz_kmax": grid.f_n,
        "equivalent_mass": equivalent_mass(pair),
        "damping_ratio": damping_ratio,
        "start": settings.start,
        "torque_history": None if settings.torque_history is None else (settings.torque_history.source or "table"),
        "integrator": "DOP853",
        "rtol": RTOL,
        "nfev": nfev,
        "t_end": float(t[-1]) if n else 0.0,
        "angle_end": float(phi_a[-1]) if n else 0.0,
        "output_interval": grid.h,
        "steady": steady_record(
            fig, grid.period, static_pair_max, float(kq_tot.mean()),
            # where the next speed of a continuation starts (a whole number of cycles: phase 0)
            end_state=[float(delta[-1]), float(ddelta[-1] / w_a[-1])] if n else None,
            start_state=None if settings.start_state is None else list(settings.start_state)),
    }


def _steady_result(pair: GearPair, settings: RunSettings, t: NDArray[np.float64], y: NDArray[np.float64],
                   forces: NDArray[np.float64], n_pairs: int, status: str, reason: str, nfev: int, wall0: float, info: dict[str, Any]) -> Result:
    """The steady run as a :class:`~spurdyn.result.Result` (:func:`simulate_steady`): the most
    loaded of the ``n_pairs`` pairs' ``forces`` at each sample."""
    ra, rb = pair.gear_a.base_radius, pair.gear_b.base_radius
    s = 1.0 if pair.driver == "a" else -1.0
    pitch = 2.0 * math.pi / pair.gear_a.teeth
    amp_a, amp_b = torque_amplitudes(pair, settings.torque)
    varying = settings.torque_history is not None or settings.start == "rest"
    phi_a, w_a, delta, ddelta = y
    n = t.size
    phi_b = (ra * phi_a - s * delta) / rb
    w_b = (ra * w_a - s * ddelta) / rb
    most = forces.max(axis=0) if n_pairs else np.zeros(n)
    roll_a = contact_roll_a(pair, phi_a - pitch * np.floor(phi_a / pitch))
    return Result(
        time=t, angle=phi_a.copy(), contact_force=most, gap=-delta,
        roll=np.column_stack([roll_a, pair.roll_b_from_roll_a(roll_a)]),
        theta=np.column_stack([phi_a, phi_b]), omega=np.column_stack([w_a, w_b]),
        torque=hub_torques(pair, settings, t) if varying else np.column_stack([np.full(n, amp_a), np.full(n, amp_b)]),
        frame_time=np.zeros(0), frame_theta=np.zeros((0, 2)),
        frame_u=np.zeros((0, 0)), status=status, reason=reason, steps=nfev,
        wall_s=_time.perf_counter() - wall0, info=info)
