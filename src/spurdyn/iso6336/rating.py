"""ISO 6336 figures of a spur pair in one call: a convenience layer over the pure functions.

:class:`IsoGear`/:class:`IsoPair` hold plain numbers (SI); :func:`rate` returns every
nominal figure of issue 16/17 for a pinion torque, :func:`dynamic_factor_at` adds the
speed. :func:`iso_pair` reads them off a :class:`spurdyn.geometry.GearPair`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from spurdyn.iso6336 import contact, dynamics, root

if TYPE_CHECKING:  # typing only: the ISO code itself needs nothing from the model
    from spurdyn.geometry.gear import Gear
    from spurdyn.geometry.pair import GearPair


@dataclass(frozen=True)
class IsoGear:
    """One gear as ISO 6336 sees it (SI units).

    Attributes
    ----------
    teeth
        Number of teeth ``z``.
    tip_radius
        ``r_a`` (m).
    rack_dedendum
        Dedendum ``h_fP`` of the generating basic rack (m): the gear's dedendum for ``x = 0``.
    rack_tip_radius
        Root fillet radius ``rho_fP`` of the basic rack, i.e. the cutter tip radius (m).
    young, poisson, density
        ``E`` (Pa), ``nu``, ``rho`` (kg/m^3).
    inertia
        Polar moment of inertia of the whole gear (kg m^2), or ``None`` for ISO's solid
        disc of diameter ``d_m = (d_a + d_f) / 2`` and the pair's face width.
    """

    teeth: int
    tip_radius: float
    rack_dedendum: float
    rack_tip_radius: float
    young: float = 210e9
    poisson: float = 0.3
    density: float = 7800.0
    inertia: float | None = None


@dataclass(frozen=True)
class IsoPair:
    """An external spur pair on the standard centre distance, gear 1 the pinion (driving)."""

    gear1: IsoGear
    gear2: IsoGear
    module: float
    pressure_angle: float
    face_width: float

    def pitch_radius(self, gear: IsoGear) -> float:
        return 0.5 * self.module * gear.teeth

    def base_radius(self, gear: IsoGear) -> float:
        return self.pitch_radius(gear) * math.cos(self.pressure_angle)

    def inertia(self, gear: IsoGear) -> float:
        """Whole-gear inertia (kg m^2): the given one, or ISO's solid disc."""
        if gear.inertia is not None:
            return gear.inertia
        d_m = gear.tip_radius + self.pitch_radius(gear) - gear.rack_dedendum  # (d_a + d_f) / 2
        return dynamics.solid_disk_inertia_per_width(d_m, gear.density) * self.face_width


@dataclass(frozen=True)
class IsoRating:
    """Nominal ISO 6336 figures of a pair under a pinion torque (SI units; per gear: (pinion, wheel)).

    ``z_b``/``z_d`` are ISO's single pair contact factors (for :func:`safety.contact_stress`).
    ``single_pair``/``mesh`` are ``c'``/``c_gamma_alpha`` with ISO's low-load correction
    for this load (N/m^2); ``resonance_speed`` is ``Omega_E1`` (rad/s) of the pinion.
    """

    tangential_force: float
    line_load: float
    eps_alpha: float
    z_h: float
    z_e: float
    z_eps: float
    z_b: float
    z_d: float
    sigma_h0: float
    sections: tuple[root.RootSection, root.RootSection]
    y_f: tuple[float, float]
    y_s: tuple[float, float]
    sigma_f0: tuple[float, float]
    single_pair: float
    mesh: float
    reduced_mass: float
    resonance_speed: float


def rate(pair: IsoPair, torque: float, k_a: float = 1.0) -> IsoRating:
    """Every nominal ISO figure of ``pair`` for a pinion torque ``torque`` (N m).

    ``k_a`` (application factor) only enters the line load ``K_A F_t / b`` that sets
    ISO's low-load stiffness correction and ``N_S``.
    """
    g1, g2, m, alpha, b = pair.gear1, pair.gear2, pair.module, pair.pressure_angle, pair.face_width
    d1 = 2.0 * pair.pitch_radius(g1)
    f_t = torque / pair.pitch_radius(g1)
    line_load = k_a * f_t / b
    eps = contact.transverse_contact_ratio(g1.teeth, g2.teeth, m, alpha, g1.tip_radius, g2.tip_radius)
    z_h = contact.zone_factor(alpha)
    z_e = contact.elasticity_factor(g1.young, g1.poisson, g2.young, g2.poisson)
    z_eps = contact.contact_ratio_factor(eps)
    z_b, z_d = contact.single_pair_contact_factors(g1.teeth, g2.teeth, m, alpha, g1.tip_radius,
                                                    g2.tip_radius, eps)
    sigma_h0 = contact.nominal_contact_stress(f_t, d1, b, g2.teeth / g1.teeth, z_h, z_e, z_eps)
    sections = tuple(root.root_section(g.teeth, m, alpha, g.rack_dedendum, g.rack_tip_radius,
                                       g.tip_radius, eps) for g in (g1, g2))
    y_f = tuple(root.form_factor(s, m, alpha) for s in sections)
    y_s = tuple(root.stress_correction_factor(s) for s in sections)
    sigma_f0 = tuple(root.nominal_root_stress(f_t, b, m, yf, ys) for yf, ys in zip(y_f, y_s))
    # ISO's C_B takes the mean basic-rack dedendum of the two gears.
    h_fp = 0.5 * (g1.rack_dedendum + g2.rack_dedendum) / m
    c1 = dynamics.single_pair_stiffness(g1.teeth, g2.teeth, alpha, h_fp, line_load=line_load)
    c_mesh = dynamics.mesh_stiffness(c1, eps)
    m_red = dynamics.reduced_mass(pair.inertia(g1), pair.inertia(g2),
                                  pair.base_radius(g1), pair.base_radius(g2))
    omega_e1 = dynamics.resonance_speed(g1.teeth, c_mesh * b, m_red)
    return IsoRating(tangential_force=f_t, line_load=line_load, eps_alpha=eps, z_h=z_h, z_e=z_e,
                     z_eps=z_eps, z_b=z_b, z_d=z_d, sigma_h0=sigma_h0, sections=sections,
                     y_f=y_f, y_s=y_s, sigma_f0=sigma_f0, single_pair=c1, mesh=c_mesh,
                     reduced_mass=m_red, resonance_speed=omega_e1)


def dynamic_factor_at(rating: IsoRating, speed: float, pitch_deviation: float = 0.0,
                      profile_deviation: float = 0.0, tip_relief: float = 0.0) -> float:
    """ISO's ``K_v`` (method B) at pinion speed ``speed`` (rad/s); deviations as in
    :func:`spurdyn.iso6336.dynamics.dynamic_factor` (default: perfect gears, no relief)."""
    return dynamics.dynamic_factor(speed / rating.resonance_speed, rating.single_pair,
                                   rating.line_load, rating.eps_alpha, pitch_deviation,
                                   profile_deviation, tip_relief)


def iso_pair(pair: "GearPair") -> IsoPair:
    """The :class:`IsoPair` of a model pair (gear A the pinion), with its disk inertias.

    The model's gears are unshifted and cut by a rack of dedendum ``gear.dedendum`` and
    tip radius ``gear.cutter_tip_radius``; a non-standard centre distance is refused.
    """
    a, b = pair.gear_a, pair.gear_b
    if not math.isclose(pair.centre_distance, a.pitch_radius + b.pitch_radius, rel_tol=1e-12):
        raise ValueError("ISO figures here need the standard centre distance")

    def one(g: "Gear") -> IsoGear:
        mat = g.material
        return IsoGear(teeth=g.teeth, tip_radius=g.tip_radius, rack_dedendum=g.dedendum,
                       rack_tip_radius=g.cutter_tip_radius, young=mat.young, poisson=mat.poisson,
                       density=mat.density, inertia=g.disk_inertia)

    return IsoPair(gear1=one(a), gear2=one(b), module=a.module, pressure_angle=a.pressure_angle,
                   face_width=min(a.face_width, b.face_width))
