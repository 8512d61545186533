"""Safety factors ``S_F`` and ``S_H`` (ISO 6336-3:2019 and 6336-2:2019, clause 5), from ISO or a simulation.

Pure functions of numbers, SI units (Pa). ISO's load factors default to 1 except where
given; the life, size, roughness, lubricant and speed factors are 1 unless given (state
them when you pass others). Derivations in ``docs/iso6336.md``.
"""

from __future__ import annotations

import math

#: Stress correction factor of ISO's reference test gear, ``Y_ST = 2`` (ISO 6336-3:2019, clause 5):
#: it turns the material's nominal stress number ``sigma_Flim`` into ``sigma_FE``.
Y_ST = 2.0


def root_stress(sigma_f0: float, k_a: float = 1.0, k_v: float = 1.0, k_fbeta: float = 1.0,
                k_falpha: float = 1.0) -> float:
    """Tooth-root stress ``sigma_F = sigma_F0 K_A K_v K_Fbeta K_Falpha`` (ISO 6336-3:2019, clause 5)."""
    return sigma_f0 * k_a * k_v * k_fbeta * k_falpha


def contact_stress(sigma_h0: float, k_a: float = 1.0, k_v: float = 1.0, k_hbeta: float = 1.0,
                   k_halpha: float = 1.0, z_b: float = 1.0) -> float:
    """Contact stress ``sigma_H = Z_B sigma_H0 sqrt(K_A K_v K_Hbeta K_Halpha)`` (ISO 6336-2:2019, clause 5).

    ``Z_B`` (pinion) or ``Z_D`` (wheel), the single pair tooth contact factor, defaults to 1
    (its value for ``eps_alpha`` near 2 and for the wheel of most pairs; pass it to move the
    stress from the pitch point to the inner point of single contact).
    """
    return z_b * sigma_h0 * math.sqrt(k_a * k_v * k_hbeta * k_halpha)


def root_limit(sigma_flim: float, y_nt: float = 1.0, y_delta_rel_t: float = 1.0,
               y_r_rel_t: float = 1.0, y_x: float = 1.0) -> float:
    """Tooth-root stress limit ``sigma_FG`` (ISO 6336-3:2019, clause 5).

    ``sigma_FG = sigma_Flim Y_ST Y_NT Y_deltarelT Y_RrelT Y_X``.

    ``sigma_Flim`` is the nominal stress number (bending) of ISO 6336-5; ``Y_ST = 2``.
    Life ``Y_NT``, notch sensitivity ``Y_deltarelT``, surface ``Y_RrelT`` and size ``Y_X``
    factors are 1 unless given (long life, reference conditions).
    """
    return sigma_flim * Y_ST * y_nt * y_delta_rel_t * y_r_rel_t * y_x


def contact_limit(sigma_hlim: float, z_nt: float = 1.0, z_l: float = 1.0, z_v: float = 1.0,
                  z_r: float = 1.0, z_w: float = 1.0, z_x: float = 1.0) -> float:
    """Pitting stress limit ``sigma_HG = sigma_Hlim Z_NT Z_L Z_v Z_R Z_W Z_X`` (ISO 6336-2:2019, clause 5).

    Life, lubricant, speed, roughness, work hardening and size factors are 1 unless given.
    """
    return sigma_hlim * z_nt * z_l * z_v * z_r * z_w * z_x


def root_safety(sigma_f: float, sigma_fg: float) -> float:
    """Bending safety factor ``S_F = sigma_FG / sigma_F`` (ISO 6336-3:2019, clause 5)."""
    return sigma_fg / sigma_f


def contact_safety(sigma_h: float, sigma_hg: float) -> float:
    """Pitting safety factor ``S_H = sigma_HG / sigma_H`` (ISO 6336-2:2019, clause 5)."""
    return sigma_hg / sigma_h


def root_stress_from_peak(peak_root_stress: float, k_a: float = 1.0, k_fbeta: float = 1.0,
                          k_falpha: float = 1.0) -> float:
    """``sigma_F`` with a simulation's peak root stress in place of ``sigma_F0 K_v``.

    The model's dynamic peak already holds the dynamic overload (``K_v``) and the notch
    (``Y_S``, since it is the fillet's own stress); what it lacks is the application and
    load-distribution factors, which multiply it as in :func:`root_stress`.
    """
    return peak_root_stress * k_a * k_fbeta * k_falpha


def contact_stress_from_peak(peak_contact_stress: float, k_a: float = 1.0, k_hbeta: float = 1.0,
                             k_halpha: float = 1.0) -> float:
    """``sigma_H`` with a simulation's peak contact stress in place of ``Z_B sigma_H0 sqrt(K_v)``.

    Contact stress grows as the square root of the load, so the remaining load factors
    enter under a square root as in :func:`contact_stress`.
    """
    return peak_contact_stress * math.sqrt(k_a * k_hbeta * k_halpha)
