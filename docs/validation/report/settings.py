"""Paths and the settings of the studies, each defined once for the whole report."""

from __future__ import annotations

import math

# ``docs/`` and its figures, as every page generator has them (re-exported for the report)
from validation.common import DOCS, FIGURES, ROOT, RUNNER  # noqa: F401

from .spurdyn_api import AVERAGING_WINDOW_S

DATA = DOCS / "validation_data"
REPORT = DOCS / "validation.md"
#: Section 7 as :mod:`validation.sweep` writes it (``python docs/validation validation_sweep``).
SWEEP_FRAGMENT = DOCS / "validation_sweep.md"

#: Width of the moving window that the runs are compared on (s): the one of spurdyn's
#: dynamic factor.
WINDOW = AVERAGING_WINDOW_S
#: Acceptance of a mesh: peak of the 10-us-averaged force within this of the next finer mesh.
MESH_CRITERION = 0.03
#: Stable RK4 steps are used at this fraction in the mesh study.
STABLE_FRACTION = 0.9
#: Meshes of the study at 4,000 rpm (the last is the reference) and at 20,000 rpm.
MESHES = ((3, 10), (4, 14), (6, 20), (8, 28))
MESHES_20K = ((3, 10), (4, 14), (6, 20), (8, 28))
#: Spline data points of the mesh study (the paper's 61 are too few for the finer meshes).
MESH_SPLINE = 241

#: rad/s per rpm.
RPM = 2.0 * math.pi / 60.0
#: Packages whose state the runs depend on (for the provenance line of the report).
SOLVER_DIRS = ("geometry", "mesh", "fem", "model", "contact", "solvers", "lumped", "results")
