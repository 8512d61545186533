"""ISO 6336-1:2019 mesh stiffness (method B), resonance speed and dynamic factor ``K_v`` (method B).

Pure functions of numbers, SI units: stiffness per unit face width in N/m^2 (ISO's
N/(mm um) times 1e9), masses per unit face width in kg/m, speeds in rad/s. Spur gears:
``beta = 0``, ``eps_gamma = eps_alpha``. Derivations in ``docs/iso6336.md``.

Clauses are those of ISO 6336-1:2019 (6 dynamic factor, 9 tooth stiffness). The equation
numbers quoted for ``n_E1`` and ``K_v`` are those of the 2006 edition (6.5, eqs. (6)-(30)),
as cited by the public implementation checked (``docs/iso6336.md``, section 8); the 2019
edition keeps method B in substance.
"""

from __future__ import annotations

import math

#: ISO 6336-1:2019 (clause 9, method B) coefficients C1..C9 of ``q' = 1/c'_th`` in
#: mm um / N, for the terms 1, 1/z_n1, 1/z_n2, x1, x1/z_n1, x2, x2/z_n2, x1^2, x2^2.
Q_COEFFICIENTS = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188,
                  0.00529, 0.00182)

#: ISO's stiffness unit N/(mm um) in SI (N/m^2 per unit face width).
N_PER_MM_UM = 1e9

#: Line load ``K_A F_t / b`` (N/m) above which ISO's c' and N_S need no low-load
#: correction: 100 N/mm.
REFERENCE_LINE_LOAD = 1e5


def single_pair_stiffness(z1: int, z2: int, pressure_angle: float, rack_dedendum_ratio: float,
                          shift1: float = 0.0, shift2: float = 0.0, c_m: float = 0.8,
                          c_r: float = 1.0, line_load: float | None = None,
                          modulus_ratio: float = 1.0) -> float:
    """Single-pair stiffness ``c'`` (N/m^2, per unit face width), ISO 6336-1:2019, clause 9 (method B).

    ``c' = c'_th C_M C_R C_B cos(beta)`` with ``c'_th = 1/q'``,
    ``q' = C1 + C2/z1 + C3/z2 + C4 x1 + C5 x1/z1 + C6 x2 + C7 x2/z2 + C8 x1^2 + C9 x2^2``
    (:data:`Q_COEFFICIENTS`), ``C_B = [1 + 0.5 (1.2 - h_fP/m)] [1 - 0.02 (20 deg - alpha_n)]``.
    If ``line_load = K_A F_t / b`` is given and below 100 N/mm, ISO multiplies by
    ``(line_load / 100 N/mm)^0.25``; ``None`` (the default) skips that correction, as the
    model's ``iso_6336_stiffness`` does.

    Parameters
    ----------
    z1, z2
        Numbers of teeth (``z_n = z`` for spur gears).
    pressure_angle
        ``alpha_n`` (rad).
    rack_dedendum_ratio
        ``h_fP / m_n`` of the basic rack (1.25 for ISO 53 profile A).
    shift1, shift2
        Profile shift coefficients.
    c_m
        Correction factor ``C_M`` = 0.8 (theoretical to measured stiffness of solid discs).
    c_r
        Gear blank factor ``C_R`` = 1 for solid gears.
    line_load
        ``K_A F_t / b`` (N/m) for the low-load correction, or ``None``.
    modulus_ratio
        ``E / E_st`` for pairs other than steel on steel (``E = 2 E1 E2 / (E1 + E2)``,
        ``E_st`` = 206 GPa); 1 (the default) for steel, whatever its exact modulus.
    """
    c = Q_COEFFICIENTS
    q = (c[0] + c[1] / z1 + c[2] / z2 + c[3] * shift1 + c[4] * shift1 / z1 + c[5] * shift2
         + c[6] * shift2 / z2 + c[7] * shift1**2 + c[8] * shift2**2)
    alpha_deg = math.degrees(pressure_angle)  # ISO's C_B is written in degrees
    c_b = (1.0 + 0.5 * (1.2 - rack_dedendum_ratio)) * (1.0 - 0.02 * (20.0 - alpha_deg))
    stiffness = N_PER_MM_UM / q * c_m * c_r * c_b * modulus_ratio
    if line_load is not None and line_load < REFERENCE_LINE_LOAD:
        stiffness *= (line_load / REFERENCE_LINE_LOAD) ** 0.25
    return stiffness


def mesh_stiffness(single_pair: float, eps_alpha: float) -> float:
    """Mean mesh stiffness ``c_gamma_alpha = c' (0.75 eps_alpha + 0.25)`` (ISO 6336-1:2019, clause 9)."""
    return single_pair * (0.75 * eps_alpha + 0.25)


def solid_disk_inertia_per_width(mean_diameter: float, density: float) -> float:
    """Polar moment of inertia per unit face width (kg m) of a solid disc of diameter ``d_m``.

    ``J* = pi rho d_m^4 / 32``; ISO 6336-1 (clause 6; 2006: eq. (30)) takes the gear as such a disc
    with ``d_m = (d_a + d_f) / 2``.
    """
    return math.pi * density * mean_diameter**4 / 32.0


def reduced_mass(inertia1: float, inertia2: float, base_radius1: float, base_radius2: float) -> float:
    """Mass of the pair reduced to the line of action, ``m_red = m1 m2 / (m1 + m2)``, ``m_i = J_i / r_bi^2``.

    ISO 6336-1:2019, clause 6 (2006: eq. (30)) in general form: give inertias per unit face width to
    get ``m_red`` per unit face width (kg/m), or whole inertias to get kg.
    """
    m1 = inertia1 / base_radius1**2
    m2 = inertia2 / base_radius2**2
    return m1 * m2 / (m1 + m2)


def resonance_speed(z1: int, mesh_stiffness_: float, reduced_mass_: float) -> float:
    """Pinion speed ``Omega_E1`` (rad/s) at which the mesh frequency meets the mesh resonance.

    ISO 6336-1:2019, clause 6 (2006: eq. (6)): ``n_E1 = 30000 / (pi z1) sqrt(c_gamma_alpha / m_red)``
    (min^-1, with c in N/(mm um) and m_red in kg/mm) is, in SI,
    ``Omega_E1 = sqrt(c_gamma_alpha / m_red) / z1``: ``z1 Omega_E1`` is the undamped
    natural frequency of the two discs coupled by the mesh spring. Both arguments per
    unit face width (N/m^2 and kg/m), or both whole (N/m and kg).
    """
    return math.sqrt(mesh_stiffness_ / reduced_mass_) / z1


def lower_resonance_bound(line_load: float) -> float:
    """Lower limit ``N_S`` of the main resonance range (ISO 6336-1:2019, clause 6; 2006: eqs. (11)-(12)).

    ``N_S = 0.85`` for ``K_A F_t / b >= 100 N/mm``, else ``0.5 + 0.35 sqrt(K_A F_t / b / 100 N/mm)``.
    """
    if line_load >= REFERENCE_LINE_LOAD:
        return 0.85
    return 0.5 + 0.35 * math.sqrt(line_load / REFERENCE_LINE_LOAD)


def dynamic_coefficients(eps_gamma: float) -> tuple[float, ...]:
    """``(C_v1, ..., C_v7)`` of ISO 6336-1:2019, clause 6, table of method B.

    For spur gears ``eps_gamma = eps_alpha``.
    """
    if eps_gamma <= 2.0:
        cv2, cv3, cv4, cv6 = 0.34, 0.23, 0.90, 0.47
    else:
        cv2 = 0.57 / (eps_gamma - 0.3)
        cv3 = 0.096 / (eps_gamma - 1.56)
        cv4 = (0.57 - 0.05 * eps_gamma) / (eps_gamma - 1.44)
        cv6 = 0.12 / (eps_gamma - 1.74)
    if eps_gamma <= 1.5:
        cv7 = 0.75
    elif eps_gamma <= 2.5:
        cv7 = 0.125 * math.sin(math.pi * (eps_gamma - 2.0)) + 0.875
    else:
        cv7 = 1.0
    return 0.32, cv2, cv3, cv4, 0.47, cv6, cv7


def running_in_tip_relief(sigma_hlim: float) -> float:
    """Tip relief by running-in ``C_ay`` (m) of through-hardened steel (ISO 6336-1:2019, clause 6).

    ``C_ay = 1/18 (sigma_Hlim / 97 - 18.45)^2 + 1.5`` um with ``sigma_Hlim`` in N/mm^2.
    """
    s = sigma_hlim * 1e-6
    return ((s / 97.0 - 18.45) ** 2 / 18.0 + 1.5) * 1e-6


def dynamic_factor(ratio_n: float, single_pair: float, line_load: float, eps_gamma: float,
                   pitch_deviation: float = 0.0, profile_deviation: float = 0.0,
                   tip_relief: float = 0.0) -> float:
    """Dynamic factor ``K_v`` of method B for spur gears (ISO 6336-1:2019, clause 6; 2006: eqs. (13)-(22)).

    With ``B_p = c' f_pb,eff / (K_A F_t/b)``, ``B_f = c' f_f,eff / (K_A F_t/b)`` and
    ``B_k = |1 - c' C_a / (K_A F_t/b)|``:

    * subcritical, ``N <= N_S``: ``K_v = N (C_v1 B_p + C_v2 B_f + C_v3 B_k) + 1``;
    * main resonance, ``N_S < N <= 1.15``: ``K_v = C_v1 B_p + C_v2 B_f + C_v4 B_k + 1``;
    * supercritical, ``N >= 1.5``: ``K_v = C_v5 B_p + C_v6 B_f + C_v7`` (may be below 1);
    * intermediate, ``1.15 < N < 1.5``: linear between the values at 1.15 and 1.5.

    Parameters
    ----------
    ratio_n
        Resonance ratio ``N = n1 / n_E1``.
    single_pair
        ``c'`` (N/m^2).
    line_load
        ``K_A F_t / b`` (N/m).
    eps_gamma
        Total contact ratio (``eps_alpha`` for spur gears).
    pitch_deviation, profile_deviation
        Effective (after running-in) base pitch and profile form deviations ``f_pb,eff``,
        ``f_f,eff`` (m). Default 0: perfect gears, so only the stiffness variation ``B_k``
        excites.
    tip_relief
        Tip relief ``C_a`` (m); default 0 (no relief, no running-in credit: pass
        :func:`running_in_tip_relief` to take ISO's ``C_ay``).
    """
    cv1, cv2, cv3, cv4, cv5, cv6, cv7 = dynamic_coefficients(eps_gamma)
    b_p = single_pair * pitch_deviation / line_load
    b_f = single_pair * profile_deviation / line_load
    b_k = abs(1.0 - single_pair * tip_relief / line_load)
    n_s = lower_resonance_bound(line_load)
    main = cv1 * b_p + cv2 * b_f + cv4 * b_k + 1.0
    superc = cv5 * b_p + cv6 * b_f + cv7
    if ratio_n <= n_s:
        return ratio_n * (cv1 * b_p + cv2 * b_f + cv3 * b_k) + 1.0
    if ratio_n <= 1.15:
        return main
    if ratio_n >= 1.5:
        return superc
    return superc + (main - superc) * (1.5 - ratio_n) / 0.35
