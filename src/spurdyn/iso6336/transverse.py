"""ISO 6336-1:2019 transverse load factors ``K_Halpha``, ``K_Falpha`` (clause 8, method B).

Pure functions of numbers, SI units: stiffness per unit face width in N/m^2, deviations
in m, line loads in N/m, speeds in m/s. Spur gears: ``eps_gamma = eps_alpha``.
Derivation, limits and a hand check in ``docs/iso6336.md``, section 11.
"""

from __future__ import annotations

import math

#: Running-in groups of ISO 6336-1 (clause 8): through-hardened and normalized steels
#: (and pearlitic cast irons), grey and ferritic cast irons, surface-hardened steels.
RUNNING_IN_GROUPS = ("steel", "cast_iron", "surface_hardened")
#: 1 um in m: ISO writes the running-in limits in um and N/mm^2.
UM = 1e-6


def running_in_allowance(group: str, pitch_deviation: float, sigma_hlim: float,
                         pitch_speed: float) -> float:
    """Running-in allowance ``y_alpha`` (m) of one gear (ISO 6336-1:2019, clause 8).

    * ``steel``: ``y_alpha = 160 / sigma_Hlim f_pb`` (``sigma_Hlim`` in N/mm^2), at most
      ``12800 / sigma_Hlim`` um for ``5 < v <= 10`` m/s and ``6400 / sigma_Hlim`` um
      above 10 m/s (the values at ``f_pb`` = 80 and 40 um);
    * ``cast_iron``: ``y_alpha = 0.275 f_pb``, at most 22 um (5 to 10 m/s), 11 um (above);
    * ``surface_hardened``: ``y_alpha = 0.075 f_pb``, at most 3 um at any speed.

    For a pair of different materials ISO takes the mean of the two gears' values.

    Parameters
    ----------
    group
        One of :data:`RUNNING_IN_GROUPS`.
    pitch_deviation
        Base pitch deviation ``f_pb`` (m), the larger of the pair's.
    sigma_hlim
        Allowable contact stress number (Pa); used by ``steel`` only.
    pitch_speed
        Pitch line velocity ``v`` (m/s).
    """
    if group not in RUNNING_IN_GROUPS:
        raise ValueError(f"running-in group must be one of {RUNNING_IN_GROUPS} (got {group!r})")
    if group == "steel":
        s = sigma_hlim * 1e-6
        y, caps = 160.0 / s * pitch_deviation, (12800.0 / s, 6400.0 / s)
    elif group == "cast_iron":
        y, caps = 0.275 * pitch_deviation, (22.0, 11.0)
    else:
        return min(0.075 * pitch_deviation, 3.0 * UM)
    if pitch_speed > 10.0:
        return min(y, caps[1] * UM)
    if pitch_speed > 5.0:
        return min(y, caps[0] * UM)
    return y


def transverse_factors(mesh_stiffness: float, pitch_deviation: float, running_in: float,
                       line_load: float, eps_alpha: float, z_eps: float) -> tuple[float, float]:
    """``(K_Halpha, K_Falpha)`` of a spur pair, method B (ISO 6336-1:2019, clause 8).

    With ``q = c_gamma_alpha (f_pb - y_alpha) / (F_tH / b)`` and
    ``F_tH = F_t K_A K_v K_Hbeta``, ISO's ``K = eps_gamma / 2 (0.9 + 0.4 q)`` for
    ``eps_gamma <= 2`` and ``K = 0.9 + 0.4 sqrt(2 (eps_gamma - 1) / eps_gamma) q`` above
    (the two meet at ``eps_gamma = 2``). ``K_Halpha`` is held between 1 and
    ``eps_gamma / (eps_alpha Z_eps^2)``, ``K_Falpha`` between 1 and
    ``eps_gamma / (0.25 eps_alpha + 0.75)``: the load of a pair can neither fall below
    its share nor exceed the whole. Perfect gears (``f_pb = 0``) give 1 for both.

    Parameters
    ----------
    mesh_stiffness
        ``c_gamma_alpha`` (N/m^2, per unit face width).
    pitch_deviation
        Base pitch deviation ``f_pb`` (m), the larger of the pair's (or the profile form
        deviation where that is larger).
    running_in
        Running-in allowance ``y_alpha`` (m) (:func:`running_in_allowance`).
    line_load
        ``F_tH / b`` (N/m).
    eps_alpha
        Transverse contact ratio (``eps_gamma`` for spur gears).
    z_eps
        Contact ratio factor ``Z_eps``.
    """
    q = mesh_stiffness * (pitch_deviation - running_in) / line_load
    if eps_alpha <= 2.0:
        k = 0.5 * eps_alpha * (0.9 + 0.4 * q)
    else:
        k = 0.9 + 0.4 * math.sqrt(2.0 * (eps_alpha - 1.0) / eps_alpha) * q
    k_h = min(max(k, 1.0), eps_alpha / (eps_alpha * z_eps * z_eps))
    k_f = min(max(k, 1.0), eps_alpha / (0.25 * eps_alpha + 0.75))
    return k_h, k_f


__all__ = ["RUNNING_IN_GROUPS", "running_in_allowance", "transverse_factors"]
