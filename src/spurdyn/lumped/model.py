"""The classic lumped model: two rigid disks and a time-varying mesh spring.

This is the model the paper argues against, kept beside the FE solver for comparison
(docs/lumped.md). The two disks ``J_A``, ``J_B`` are coupled by a massless spring along
the line of action whose stiffness ``k`` is the FE static single-pair stiffness at the
rigid-kinematics contact point (tabulated once by :func:`mesh_stiffness_table`). The
spring acts only in compression (the teeth may separate), optionally with a light
viscous damper, and the disks carry the same torque schedule as the FE model
(:mod:`spurdyn.model.loading`).

Coordinates: ``theta_A``, ``theta_B`` are the disk rotations since the start of contact,
each along its own sense of rotation (A clockwise, B counter-clockwise). With
``s = +1`` when A drives and ``s = -1`` when B drives, the compression of the spring is
``delta = s (r_bA theta_A - r_bB theta_B)`` and::

    F       = max(0, k delta + c delta')   if delta > 0, else 0
    J_A theta_A'' = tau_A - s r_bA F
    J_B theta_B'' = tau_B + s r_bB F

SI units: m, rad, s, kg m^2, N, N m.
"""

from __future__ import annotations

import bisect
import math
import time as _time
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline, PchipInterpolator, PPoly

from spurdyn.geometry.pair import GearPair
from spurdyn.mesh.tooth import DEFAULT_NX, DEFAULT_NY, DEFAULT_ROW_GRADING
from spurdyn.model.loading import gear_angles, gear_torques, static_force, torque_amplitudes, torque_fraction
from spurdyn.model.stiffness import pair_stiffness
from spurdyn.model.tooth import build_tooth
from spurdyn.result import Result
from spurdyn.settings import RunSettings

#: Interpolations offered for the stiffness table.
INTERPOLATIONS = ("pchip", "cubic")

#: Default number of roll angles in the stiffness table.
DEFAULT_TABLE_POINTS = 41

#: Relative tolerance of the ODE integration.
RTOL = 1e-10


@dataclass(frozen=True, eq=False)
class MeshStiffnessTable:
    """Single-pair mesh stiffness against the roll angle of gear A, with its interpolant.

    Parameters
    ----------
    roll_a
        Increasing roll angles of A (rad) spanning the path of contact.
    stiffness
        Pair stiffness (N/m) at those roll angles.
    interpolation
        ``"pchip"`` (monotone piecewise cubic, no overshoot; the default) or
        ``"cubic"`` (not-a-knot cubic spline).

    Notes
    -----
    Outside ``[roll_a[0], roll_a[-1]]`` the stiffness is zero: the teeth are out of
    mesh beyond the ends of the path of contact.
    """

    roll_a: NDArray[np.float64]
    stiffness: NDArray[np.float64]
    interpolation: str = "pchip"
    _poly: PPoly = field(init=False, repr=False, compare=False)
    _breaks: list[float] = field(init=False, repr=False, compare=False)
    _coefs: list[tuple[float, ...]] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        x = np.asarray(self.roll_a, dtype=float)
        k = np.asarray(self.stiffness, dtype=float)
        if x.ndim != 1 or x.shape != k.shape or x.size < 2:
            raise ValueError("roll_a and stiffness must be 1-D arrays of the same length >= 2")
        if np.any(np.diff(x) <= 0):
            raise ValueError("roll_a must increase strictly")
        if np.any(~np.isfinite(k)) or np.any(k <= 0):
            raise ValueError("stiffness must be positive and finite")
        if self.interpolation not in INTERPOLATIONS:
            raise ValueError(f"interpolation must be one of {INTERPOLATIONS} (got {self.interpolation!r})")
        object.__setattr__(self, "roll_a", x)
        object.__setattr__(self, "stiffness", k)
        if x.size == 2 or self.interpolation == "pchip":
            interp: Any = PchipInterpolator(x, k, extrapolate=False)
        else:
            interp = CubicSpline(x, k, extrapolate=False)
        poly = PPoly(interp.c, interp.x, extrapolate=False)
        object.__setattr__(self, "_poly", poly)
        object.__setattr__(self, "_breaks", [float(v) for v in x])
        object.__setattr__(self, "_coefs", [tuple(float(c) for c in poly.c[:, i]) for i in range(x.size - 1)])

    @classmethod
    def constant(cls, pair: GearPair, k: float) -> "MeshStiffnessTable":
        """A constant stiffness ``k`` (N/m) over the path of contact (for checks)."""
        return cls(np.array([pair.start_roll_a, pair.end_roll_a]), np.array([k, k]))

    def __call__(self, roll_a: ArrayLike) -> NDArray[np.float64]:
        """Stiffness (N/m) at roll angles of A (rad); 0 outside the path of contact."""
        return np.nan_to_num(self._poly(np.asarray(roll_a, dtype=float)), nan=0.0)

    @property
    def breaks(self) -> list[float]:
        """The polynomial pieces' breaks (roll angles of A, rad) :meth:`scalar` reads."""
        return self._breaks

    @property
    def piece_coefficients(self) -> list[tuple[float, ...]]:
        """Each piece's coefficients, highest power first, in its offset from its break."""
        return self._coefs

    def scalar(self, roll_a: float) -> float:
        """Fast scalar evaluation of :meth:`__call__` (plain Python)."""
        b = self._breaks
        if roll_a < b[0] or roll_a > b[-1]:
            return 0.0
        i = min(bisect.bisect_right(b, roll_a) - 1, len(b) - 2)
        d = roll_a - b[i]
        out = 0.0
        for c in self._coefs[i]:
            out = out * d + c
        return out

    def slope(self, roll_a: ArrayLike) -> NDArray[np.float64]:
        """``dk/droll_a`` (N/m per rad) at roll angles of A; 0 outside the path."""
        return np.nan_to_num(self._poly.derivative()(np.asarray(roll_a, dtype=float)), nan=0.0)

    def mean(self, lo: float, hi: float) -> float:
        """Mean stiffness (N/m) over the roll angles ``[lo, hi]`` of A."""
        return float(self._poly.integrate(lo, hi) / (hi - lo))

    @property
    def k_max(self) -> float:
        """Largest tabulated stiffness (N/m)."""
        return float(self.stiffness.max())

    def as_dict(self) -> dict[str, Any]:
        """Plain-Python description (for ``Result.info``)."""
        return {"roll_a": self.roll_a.tolist(), "stiffness": self.stiffness.tolist(),
                "interpolation": self.interpolation}


def mesh_stiffness_table(
    pair: GearPair,
    nx: int = DEFAULT_NX,
    ny: int = DEFAULT_NY,
    n: int = DEFAULT_TABLE_POINTS,
    interpolation: str = "pchip",
    row_grading: float = DEFAULT_ROW_GRADING,
) -> MeshStiffnessTable:
    """Tabulate the FE static single-pair stiffness over the path of contact.

    Parameters
    ----------
    pair
        The gear pair.
    nx, ny
        Q8 elements across and along each tooth (as in the FE model).
    n
        Number of roll angles of A, evenly spaced from the start to the end of the
        path of contact.
    interpolation
        See :class:`MeshStiffnessTable`.
    row_grading
        The tooth meshes' row grading (:func:`spurdyn.mesh.tooth.row_radii`; 1: even rows).

    Returns
    -------
    MeshStiffnessTable
        ``1 / (c_A + c_B)`` from :func:`spurdyn.model.stiffness.pair_stiffness`.
    """
    if n < 2:
        raise ValueError(f"n must be at least 2 (got {n})")
    tooth_a = build_tooth(pair.gear_a, nx, ny, row_grading=row_grading)
    tooth_b = (tooth_a if pair.gear_b == pair.gear_a
               else build_tooth(pair.gear_b, nx, ny, row_grading=row_grading))
    roll = np.linspace(pair.start_roll_a, pair.end_roll_a, n)
    k = pair_stiffness(pair, tooth_a, tooth_b, roll).stiffness
    return MeshStiffnessTable(roll, k, interpolation)


def equivalent_mass(pair: GearPair) -> float:
    """Mass (kg) of the two disks reduced to the line of action.

    ``m_e = 1 / (r_bA^2 / J_A + r_bB^2 / J_B)``.
    """
    a, b = pair.gear_a, pair.gear_b
    return 1.0 / (a.base_radius**2 / a.disk_inertia + b.base_radius**2 / b.disk_inertia)


def torsional_natural_frequency(pair: GearPair, k: float | ArrayLike) -> float | NDArray[np.float64]:
    """Natural frequency (Hz) of two disks coupled by a spring ``k`` on the line of action.

    ``f = sqrt(k (r_bA^2 / J_A + r_bB^2 / J_B)) / (2 pi) = sqrt(k / m_e) / (2 pi)``.

    Parameters
    ----------
    pair
        The gear pair (base radii and disk inertias).
    k
        Mesh stiffness (N/m), scalar or array.
    """
    f = np.sqrt(np.asarray(k, dtype=float) / equivalent_mass(pair)) / (2.0 * math.pi)
    return float(f) if f.ndim == 0 else f


def contact_roll_a(pair: GearPair, phi_a: ArrayLike) -> NDArray[np.float64]:
    """Roll angle on A of the rigid-kinematics contact point at A's rotation ``phi_a``.

    A driving: contact starts at B's tip, low on A, and climbs A's flank. B driving:
    contact starts at A's tip (the driven gear's tip) and descends A's flank.
    """
    phi_a = np.asarray(phi_a, dtype=float)
    if pair.driver == "a":
        return pair.start_roll_a + phi_a
    return pair.end_roll_a - phi_a


def simulate_lumped(
    pair: GearPair,
    settings: RunSettings,
    damping_ratio: float | None = None,
    *,
    table: MeshStiffnessTable | None = None,
    n_table: int = DEFAULT_TABLE_POINTS,
    interpolation: str = "pchip",
) -> Result:
    """Simulate one engagement with the two-disk, one-spring lumped model.

    Parameters
    ----------
    pair
        The gear pair; ``pair.driver`` fixes which gear ``settings.torque`` drives.
    settings
        Run settings. Used: ``speed_a``, ``speed_b`` (initial speeds, rad/s),
        ``torque`` (``tau_0``, N m), ``dt * save_every`` (output interval: the FE
        solver's saved time grid), ``angle`` (rotation of A to simulate, default
        ``theta_s``), ``nx``, ``ny`` (mesh of the stiffness table) and ``name``.
    damping_ratio
        Viscous damping ratio ``zeta`` of the pair's torsional mode: the mesh damper is
        ``c = 2 zeta sqrt(k(roll) m_e)`` (:func:`equivalent_mass`). Default:
        ``settings.damping_ratio``.
    table
        A ready stiffness table; ``None`` computes one with ``n_table`` points on the
        mesh of ``settings`` (``nx``, ``ny``).
    n_table, interpolation
        Passed to :func:`mesh_stiffness_table` when ``table`` is ``None``.

    Returns
    -------
    Result
        Sampled at ``t_k = k dt save_every`` up to the time A has turned ``angle``.
        ``gap = -delta`` (positive apart, negative compression); ``roll`` is the
        rigid-kinematics contact point; residuals, iterations and corner flags are
        zero; there are no frames. ``info`` holds ``model = "lumped"``, ``n_dof``,
        ``theta_s``, ``theta_2``, ``static_force``, ``single_zone``,
        ``mesh_stiffness_table`` and the integration statistics.
    """
    if damping_ratio is None:
        damping_ratio = settings.mesh_damping
    if not math.isfinite(damping_ratio) or damping_ratio < 0.0:
        raise ValueError(f"damping_ratio must be >= 0 (got {damping_ratio!r})")
    wall0 = _time.perf_counter()
    if table is None:
        table = mesh_stiffness_table(pair, settings.nx, settings.ny, n_table, interpolation,
                                     row_grading=settings.row_grading)
    # the mesh damper's 2 zeta sqrt(m_e), times sqrt(k) where the pair is in contact
    zeta2_sqrt_me = 2.0 * damping_ratio * math.sqrt(equivalent_mass(pair))
    target = pair.theta_s if settings.angle is None else float(settings.angle)
    rhs, reached = _equations(pair, settings, table, zeta2_sqrt_me, target)
    sol, y0, t_max, f_n = _integrate(pair, settings, table, rhs, reached)
    if sol.status == -1:
        status, reason, t_end = "incomplete", f"integration failed: {sol.message}", float(sol.t[-1])
    elif sol.t_events[0].size:
        status, reason, t_end = "complete", "", float(sol.t_events[0][0])
    else:
        status, reason, t_end = "incomplete", (f"gear A had not turned {target:.6g} rad after "
                                               f"{t_max:.6g} s"), float(sol.t[-1])
    info = _lumped_info(pair, settings, table, sol, t_end, f_n, damping_ratio)
    return _sampled_result(pair, settings, table, sol, y0, t_end, zeta2_sqrt_me, status, reason, wall0, info)


def _equations(pair: GearPair, settings: RunSettings, table: MeshStiffnessTable, zeta2_sqrt_me: float,
               target: float) -> tuple[Callable[[float, NDArray[np.float64]], list[float]],
                                       Callable[[float, NDArray[np.float64]], float]]:
    """The lumped model's right-hand side in ``y = (phi_a, omega_a, delta, delta_dot)`` and
    the terminal event of gear A having turned ``target``."""
    ga, gb = pair.gear_a, pair.gear_b
    ra, rb = ga.base_radius, gb.base_radius
    ja, jb = ga.disk_inertia, gb.disk_inertia
    s = 1.0 if pair.driver == "a" else -1.0
    (tsa, t2a), (tsb, t2b) = gear_angles(pair)
    amp_a, amp_b = torque_amplitudes(pair, settings.torque)
    roll0 = float(contact_roll_a(pair, 0.0))
    droll = 1.0 if pair.driver == "a" else -1.0
    kfun: Callable[[float], float] = table.scalar

    def force(phi_a: float, delta: float, ddelta: float) -> float:
        if delta <= 0.0:
            return 0.0
        k = kfun(roll0 + droll * phi_a)
        f = k * delta
        if zeta2_sqrt_me:
            f += zeta2_sqrt_me * math.sqrt(k) * ddelta
        return f if f > 0.0 else 0.0

    def rhs(_t: float, y: NDArray[np.float64]) -> list[float]:
        phi_a, w_a, delta, ddelta = y
        phi_b = (ra * phi_a - s * delta) / rb
        f = force(phi_a, delta, ddelta)
        acc_a = (amp_a * torque_fraction(phi_a, tsa, t2a) - s * ra * f) / ja
        acc_b = (amp_b * torque_fraction(phi_b, tsb, t2b) + s * rb * f) / jb
        return [w_a, acc_a, ddelta, s * (ra * acc_a - rb * acc_b)]

    def reached(_t: float, y: NDArray[np.float64]) -> float:
        return y[0] - target

    reached.terminal = True  # type: ignore[attr-defined]
    reached.direction = 1.0  # type: ignore[attr-defined]
    return rhs, reached


def _integrate(pair: GearPair, settings: RunSettings, table: MeshStiffnessTable,
               rhs: Callable[[float, NDArray[np.float64]], list[float]],
               reached: Callable[[float, NDArray[np.float64]], float]) -> tuple[Any, NDArray[np.float64], float, float]:
    """Integrate the model by DOP853 from the initial speeds; ``(solution, y0, t_max, f_n)``,
    the tolerances scaled by the static deflection and the torsional mode ``f_n`` (Hz)."""
    ra, rb = pair.gear_a.base_radius, pair.gear_b.base_radius
    s = 1.0 if pair.driver == "a" else -1.0
    target = pair.theta_s if settings.angle is None else float(settings.angle)
    w_a0, w_b0 = float(settings.speed_a), float(settings.speed_b)
    v0 = s * (ra * w_a0 - rb * w_b0)
    k_ref = table.k_max
    f_n = float(torsional_natural_frequency(pair, k_ref))
    static = static_force(pair, settings.torque)
    delta_ref = max(static / k_ref, abs(v0) / (2 * math.pi * f_n), 1e-9)
    atol = np.array([1e-13, 1e-10 * w_a0, RTOL * delta_ref, RTOL * delta_ref * 2 * math.pi * f_n])
    mesh_period = 2.0 * math.pi / (pair.gear_a.teeth * w_a0)
    max_step = min(mesh_period / 40.0, 0.25 / f_n)
    t_max = 4.0 * target / w_a0
    y0 = np.array([0.0, w_a0, 0.0, v0])
    sol = solve_ivp(rhs, (0.0, t_max), y0, method="DOP853", rtol=RTOL, atol=atol,
                    max_step=max_step, events=reached, dense_output=True)
    return sol, y0, t_max, f_n


def _lumped_info(pair: GearPair, settings: RunSettings, table: MeshStiffnessTable, sol: Any, t_end: float,
                 f_n: float, damping_ratio: float) -> dict[str, Any]:
    """The lumped run's record: the pair, the stiffness table, the integration statistics."""
    _, (tsb, t2b) = gear_angles(pair)
    single = (pair.theta_2, pair.theta_s - pair.theta_2)
    return {
        "model": "lumped",
        "n_dof": 2,
        "case": settings.name,
        "driver": pair.driver,
        "theta_s": pair.theta_s,
        "theta_2": pair.theta_2,
        "theta_s_b": tsb,
        "theta_2_b": t2b,
        "static_force": static_force(pair, settings.torque),
        "single_zone": single,
        "mesh_stiffness_table": table.as_dict(),
        "mesh_stiffness_single_zone": table.mean(*sorted(float(v) for v in contact_roll_a(pair, np.array(single)))),
        "natural_frequency_hz_kmax": f_n,
        "equivalent_mass": equivalent_mass(pair),
        "damping_ratio": damping_ratio,
        "integrator": "DOP853",
        "rtol": RTOL,
        "nfev": int(sol.nfev),
        "t_end": t_end,
        "angle_end": float(sol.sol(t_end)[0]) if t_end > 0 else 0.0,
        "output_interval": settings.dt * settings.save_every,
    }


def _sampled_result(pair: GearPair, settings: RunSettings, table: MeshStiffnessTable, sol: Any,
                    y0: NDArray[np.float64], t_end: float, zeta2_sqrt_me: float, status: str, reason: str,
                    wall0: float, info: dict[str, Any]) -> Result:
    """The solution sampled on the FE solver's saved time grid up to ``t_end``, as a Result."""
    ra, rb = pair.gear_a.base_radius, pair.gear_b.base_radius
    s = 1.0 if pair.driver == "a" else -1.0
    h = settings.dt * settings.save_every
    n_out = int(math.floor(t_end / h * (1.0 + 1e-12))) + 1
    # step index times dt, as the FE solver
    t = (np.arange(n_out) * settings.save_every) * settings.dt
    y = sol.sol(t)
    y[:, 0] = y0  # exact initial state
    phi_a, w_a, delta, ddelta = y
    phi_b = (ra * phi_a - s * delta) / rb
    w_b = (ra * w_a - s * ddelta) / rb
    roll_a = contact_roll_a(pair, phi_a)
    k = table(roll_a)
    f = k * delta + zeta2_sqrt_me * np.sqrt(k) * ddelta
    f = np.where(delta > 0.0, np.maximum(f, 0.0), 0.0)
    tau_a, tau_b = gear_torques(pair, settings.torque, phi_a, phi_b)
    return Result(
        time=t,
        angle=phi_a.copy(),
        contact_force=f,
        gap=-delta,
        roll=np.column_stack([roll_a, pair.roll_b_from_roll_a(roll_a)]),
        theta=np.column_stack([phi_a, phi_b]),
        omega=np.column_stack([w_a, w_b]),
        torque=np.column_stack([tau_a, tau_b]),
        frame_time=np.zeros(0),
        frame_theta=np.zeros((0, 2)),
        frame_u=np.zeros((0, 0)),
        status=status,
        reason=reason,
        steps=len(sol.sol.ts) - 1,
        wall_s=_time.perf_counter() - wall0,
        info=info,
    )
