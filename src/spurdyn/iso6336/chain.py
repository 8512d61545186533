"""ISO 6336-2/-3 method B safety factors of a spur pair: the whole chain of load factors.

:func:`safety_chain` takes the nominal figures of :func:`spurdyn.iso6336.rating.rate`
and adds ISO's load factors (``K_A``, ``K_v``, ``K_Hbeta``/``K_Fbeta``,
``K_Halpha``/``K_Falpha``), the stresses ``sigma_H``, ``sigma_F`` of each gear, their
limits ``sigma_HG``, ``sigma_FG`` (ISO 6336-5's allowable stress numbers, all life and
condition factors 1) and ``S_H``, ``S_F``. Which factors are 1, and why, is
:data:`UNITY_NOTE`; the derivation and a hand check are in ``docs/iso6336.md``, section 11.
"""

from __future__ import annotations

from dataclasses import dataclass

from spurdyn.iso6336 import safety, transverse
from spurdyn.iso6336.rating import IsoRating, dynamic_factor_at

#: The factors of the chain taken as 1, and why (reported beside the figures).
UNITY_NOTE = ("K_A = 1 (the run's torque is the nominal load); K_Hbeta = K_Fbeta = 1 "
              "(the plane model carries the load evenly over the face width, no "
              "misalignment); K_v, K_Halpha, K_Falpha for perfect gears (f_pb = f_f = 0, no "
              "tip relief) unless deviations are given; Z_beta = Y_beta = Y_B = Y_DT = 1 "
              "(spur, solid rim, eps_alpha <= 2.05); life and condition factors Z_NT Z_L "
              "Z_v Z_R Z_W Z_X = Y_NT Y_deltarelT Y_RrelT Y_X = 1 (long life, reference "
              "test conditions); sigma_FG = sigma_Flim Y_ST with Y_ST = 2")


@dataclass(frozen=True)
class SafetyChain:
    """ISO's load factors and, per gear (pinion, wheel), stresses, limits and safety factors.

    Stresses and limits in Pa; a gear without an allowable stress number has ``None``
    for that limit and safety factor. ``y_alpha`` is the running-in allowance (m) that
    entered ``K_alpha``.
    """

    k_a: float
    k_v: float
    k_hbeta: float
    k_fbeta: float
    k_halpha: float
    k_falpha: float
    y_alpha: float
    sigma_h: tuple[float, float]
    sigma_f: tuple[float, float]
    sigma_hg: tuple[float | None, float | None]
    sigma_fg: tuple[float | None, float | None]
    s_h: tuple[float | None, float | None]
    s_f: tuple[float | None, float | None]


def pair_running_in(groups: tuple[str | None, str | None], pitch_deviation: float,
                    sigma_hlim: tuple[float | None, float | None], pitch_speed: float) -> float:
    """The pair's ``y_alpha`` (m): the mean of the gears' (ISO 6336-1, clause 8), 0 when a
    gear's running-in group or contact stress number is unknown (no running-in credit)."""
    values = []
    for group, s in zip(groups, sigma_hlim):
        if group is None or (group == "steel" and s is None):
            return 0.0
        values.append(transverse.running_in_allowance(group, pitch_deviation, s or 0.0,
                                                      pitch_speed))
    return 0.5 * (values[0] + values[1])


def safety_chain(rating: IsoRating, speed: float, sigma_hlim: tuple[float | None, float | None],
                 sigma_flim: tuple[float | None, float | None], pitch_speed: float,
                 groups: tuple[str | None, str | None] = (None, None),
                 pitch_deviation: float = 0.0, k_a: float = 1.0) -> SafetyChain:
    """ISO 6336-2/-3 (method B) stresses and safety factors of both gears.

    Parameters
    ----------
    rating
        The pair's nominal figures (:func:`~spurdyn.iso6336.rating.rate`, same ``k_a``).
    speed
        Pinion speed (rad/s), for ``K_v``.
    sigma_hlim, sigma_flim
        ISO 6336-5 allowable stress numbers (Pa) of (pinion, wheel), ``None`` if unknown.
    pitch_speed
        Pitch line velocity (m/s), for the running-in allowance's limits.
    groups
        Running-in groups of the gears (:data:`transverse.RUNNING_IN_GROUPS`), or ``None``.
    pitch_deviation
        Base pitch deviation ``f_pb`` (m), the larger of the pair's; 0 for perfect gears.
    k_a
        Application factor ``K_A``.
    """
    y_alpha = pair_running_in(groups, pitch_deviation, sigma_hlim, pitch_speed)
    effective = max(pitch_deviation - y_alpha, 0.0)     # f_pb,eff of K_v, after running-in
    k_v = dynamic_factor_at(rating, speed, pitch_deviation=effective)
    k_hbeta = k_fbeta = 1.0
    k_halpha, k_falpha = transverse.transverse_factors(
        rating.mesh, pitch_deviation, y_alpha, rating.line_load * k_v * k_hbeta,
        rating.eps_alpha, rating.z_eps)
    z_bd = (rating.z_b, rating.z_d)
    sigma_h = tuple(safety.contact_stress(rating.sigma_h0, k_a, k_v, k_hbeta, k_halpha, z)
                    for z in z_bd)
    sigma_f = tuple(safety.root_stress(s0, k_a, k_v, k_fbeta, k_falpha) for s0 in rating.sigma_f0)
    hg = tuple(None if s is None else safety.contact_limit(s) for s in sigma_hlim)
    fg = tuple(None if s is None else safety.root_limit(s) for s in sigma_flim)
    return SafetyChain(
        k_a=k_a, k_v=k_v, k_hbeta=k_hbeta, k_fbeta=k_fbeta, k_halpha=k_halpha,
        k_falpha=k_falpha, y_alpha=y_alpha, sigma_h=sigma_h, sigma_f=sigma_f,  # type: ignore[arg-type]
        sigma_hg=hg, sigma_fg=fg,  # type: ignore[arg-type]
        s_h=tuple(None if g is None else safety.contact_safety(s, g)
                  for s, g in zip(sigma_h, hg)),  # type: ignore[arg-type]
        s_f=tuple(None if g is None else safety.root_safety(s, g)
                  for s, g in zip(sigma_f, fg)))  # type: ignore[arg-type]


__all__ = ["SafetyChain", "UNITY_NOTE", "pair_running_in", "safety_chain"]
