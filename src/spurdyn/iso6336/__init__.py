"""ISO 6336:2019 (parts 1-3) figures for spur gears, beside the model's.

Pure functions of numbers in SI units, one module per part of the standard:

* :mod:`~spurdyn.iso6336.contact` - part 2: ``eps_alpha``, ``Z_H``, ``Z_E``, ``Z_eps``, ``Z_B``/``Z_D``,
  ``sigma_H0``;
* :mod:`~spurdyn.iso6336.root` - part 3, method B: ``s_Fn``, ``rho_F``, ``h_Fe``, ``Y_F``, ``Y_S``,
  ``sigma_F0``;
* :mod:`~spurdyn.iso6336.dynamics` - part 1: ``c'``, ``c_gamma_alpha``, ``m_red``, ``n_E1``,
  ``K_v`` (method B);
* :mod:`~spurdyn.iso6336.safety` - ``sigma_F``, ``sigma_H``, ``S_F``, ``S_H`` (from ISO or a simulated peak);
* :mod:`~spurdyn.iso6336.rating` - all of them for one pair and load;
* :mod:`~spurdyn.iso6336.transverse` - part 1: ``K_Halpha``, ``K_Falpha``, ``y_alpha`` (method B);
* :mod:`~spurdyn.iso6336.chain` - the whole method-B chain to ``S_H``, ``S_F`` of both gears;
* :mod:`~spurdyn.iso6336.materials` - part 5 (2016): ``sigma_Hlim``, ``sigma_Flim`` of a material class.

Formulas, assumptions and hand-worked examples: ``docs/iso6336.md``. Run
``python -m spurdyn.iso6336`` to print the figures of the two worked examples.
"""

from spurdyn.iso6336.contact import (contact_ratio_factor, elasticity_factor,
                                     nominal_contact_stress, single_pair_contact_factors,
                                     transverse_contact_ratio, zone_factor)
from spurdyn.iso6336.dynamics import (dynamic_factor, mesh_stiffness, reduced_mass,
                                      resonance_speed, single_pair_stiffness)
from spurdyn.iso6336.rating import IsoGear, IsoPair, IsoRating, dynamic_factor_at, iso_pair, rate
from spurdyn.iso6336.root import (RootSection, form_factor, nominal_root_stress, root_section,
                                  stress_correction_factor)
from spurdyn.iso6336.safety import (contact_limit, contact_safety, contact_stress, root_limit,
                                    root_safety, root_stress)

__all__ = [
    "IsoGear", "IsoPair", "IsoRating", "RootSection", "contact_limit", "contact_ratio_factor",
    "contact_safety", "contact_stress", "dynamic_factor", "dynamic_factor_at",
    "elasticity_factor", "form_factor", "iso_pair", "mesh_stiffness", "nominal_contact_stress",
    "nominal_root_stress", "rate", "reduced_mass", "resonance_speed", "root_limit",
    "root_safety", "root_section", "root_stress", "single_pair_contact_factors",
    "single_pair_stiffness",
    "stress_correction_factor", "transverse_contact_ratio", "zone_factor",
]
