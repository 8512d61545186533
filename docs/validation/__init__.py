"""The generators of the validation pages (``docs/*.md``), beside the pages they write.

One runner, from the repository root::

    .venv/bin/python docs/validation                 # the pages and what writes each
    .venv/bin/python docs/validation PAGE [OPTIONS]  # PAGE's generator (--help: its options)

The pages (each module's docstring says what it measures and how long it takes):

==============================  =====================  ===============================================
page (``docs/``)                module                 what
==============================  =====================  ===============================================
``validation.md``               ``report/``            the report: paper's cases, convergence, physics,
                                                       lumped model, relief, limits, sweep
``contact_validation.md``       ``contact``            the Hertzian strip beside the point contact
                                (+ ``contact_page``)   (its figures in ``contact_validation.json``)
``implicit_validation.md``      ``implicit``           the implicit integrator against RK4
``sector_validation.md``        ``sector``             the sector's mesh cycle against ISO 6336-1
``sector_dynamics_validation``  ``sector_dynamics``    the sector model's dynamic run
                                (+ ``sector_rattle``)  (its figures in the page's JSON)
``sector_rk4_validation.md``    ``sector_rk4``         the sector's implicit loop against RK4
``stress_validation.md``        ``stress``             the root stress against the mesh and ISO 6336-3
                                (+ ``stress_sector``)  (its sector section, figures in
                                                       ``stress_sector.json``)
``validation_sweep.md``         ``sweep``              the dynamic factor against speed (section 7)
``stiffness.md`` (printed)      ``stiffness``          the tables of the stiffness page
``engineer_defaults.md``        ``engineer``           bare case files by default: settled, rated
``faults_validation.md``        ``faults``             a root crack against the energy method
``faults_dynamics.md``          ``fault_dynamics``     a root crack at speed: sidebands, indicators
``faults_flanks.md``            ``fault_flanks``       spalls and chipped tips: the contact lost, the
                                                       signature over the revolution
``fracture.md`` (printed)       ``fracture``           stress intensity factors against the handbooks
``fracture_rims.md``            ``thin_rims``          crack paths against the backup ratio, held rims
                                                       and webbed, beside Lewicki & Ballarini
==============================  =====================  ===============================================

What they share (the pages' folder, writing a page and keeping its figures, a run timed,
the impacts of a contact force matched between two runs, a markdown table) is
:mod:`validation.common`. The package lives in ``docs/`` and is imported as
``validation`` with ``docs/`` on the path (the runner puts it there); it is not part of
the installed ``spurdyn``.
"""

from __future__ import annotations

#: Each page's name (its file in ``docs/`` without ``.md``) and the module that writes it.
PAGES = {
    "validation": "report.report",
    "contact_validation": "contact",
    "implicit_validation": "implicit",
    "sector_validation": "sector",
    "sector_dynamics_validation": "sector_dynamics",
    "sector_rk4_validation": "sector_rk4",
    "stress_validation": "stress",
    "stress_sector": "stress_sector",
    "validation_sweep": "sweep",
    "stiffness": "stiffness",
    "engineer_defaults": "engineer",
    "faults_validation": "faults",
    "faults_dynamics": "fault_dynamics",
    "faults_flanks": "fault_flanks",
    "fracture": "fracture",
    "fracture_rims": "thin_rims",
}

__all__ = ["PAGES"]
