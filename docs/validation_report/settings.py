"""Paths and the settings of the studies, each defined once for the whole report."""

from __future__ import annotations

import math
from pathlib import Path

from .spurdyn_api import AVERAGING_WINDOW_S

#: ``docs/``: the report, its figures and its cache live beside this package.
DOCS = Path(__file__).resolve().parent.parent
ROOT = DOCS.parent
DATA = DOCS / "validation_data"
FIGURES = DOCS / "figures"
REPORT = DOCS / "validation.md"
#: Section 7 as ``docs/make_sweep_figures.py`` writes it, and that script.
SWEEP_FRAGMENT = DOCS / "validation_sweep.md"
SWEEP_SCRIPT = DOCS / "make_sweep_figures.py"

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
