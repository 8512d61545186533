"""The finite-element model of one tooth: mesh, stiffness and HRZ-lumped mass."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import brentq

from spurdyn.fem.element import edge_weights
from spurdyn.fem.assembly import assemble_lumped_mass, assemble_stiffness
from spurdyn.fem.stable_step import StableStep, stable_time_step
from spurdyn.geometry.gear import Gear
from spurdyn.mesh.tooth import (DEFAULT_GRADING, DEFAULT_NX, DEFAULT_NY, DEFAULT_ROW_GRADING,
                                ToothMesh, tooth_mesh)


@dataclass(frozen=True)
class ToothModel:
    """One gear's tooth ready for analysis.

    Attributes
    ----------
    gear
        The gear the tooth belongs to.
    mesh
        Its Q8 mesh in the gear frame.
    stiffness
        ``(2N, 2N)`` sparse small-strain stiffness, DOFs ``[u0x, u0y, u1x, ...]``.
    mass
        ``(2N,)`` HRZ-lumped nodal masses (the diagonal of M).
    """

    gear: Gear
    mesh: ToothMesh
    stiffness: sp.csr_matrix
    mass: NDArray[np.float64]

    @property
    def tooth_mass(self) -> float:
        """Mass of the tooth (kg): the lumped masses of one direction add up to it."""
        return float(self.mass[0::2].sum())

    @property
    def root_dofs(self) -> NDArray[np.intp]:
        r = self.mesh.root_nodes
        return np.sort(np.concatenate([2 * r, 2 * r + 1]))

    def stable_step(self) -> StableStep:
        """Largest stable explicit step of the unconstrained tooth (RK4 and central)."""
        return stable_time_step(self.stiffness, self.mass)

    def side_point(self, side: str, r: float) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
        """Nodes and weights that interpolate the outline point at radius ``r``.

        The point lies on the quadratic element edge of the outline ``side`` whose
        interpolated radius equals ``r``. Returns the three edge nodes (root, middle,
        tip) and their shape-function weights.
        """
        nodes = self.mesh.side(side)
        xy = self.mesh.nodes
        radii = np.hypot(xy[nodes, 0], xy[nodes, 1])
        tol = 1e-12 * radii[-1]
        if not radii[0] - tol <= r <= radii[-1] + tol:
            raise ValueError(f"radius {r:g} m is outside the tooth outline")
        r = min(max(r, radii[0]), radii[-1])
        row = min(int(np.searchsorted(radii[::2], r, side="right")) - 1, self.mesh.ny - 1)
        row = max(row, 0)
        edge = nodes[2 * row:2 * row + 3]
        p = xy[edge]

        def gap(eta: float) -> float:
            return float(np.hypot(*(edge_weights(eta) @ p))) - r

        eta = brentq(gap, -1.0, 1.0, xtol=1e-15) if gap(-1.0) * gap(1.0) < 0 else \
            (-1.0 if abs(gap(-1.0)) < abs(gap(1.0)) else 1.0)
        return edge, edge_weights(eta)


def build_tooth(gear: Gear, nx: int = DEFAULT_NX, ny: int = DEFAULT_NY,
                grading: float = DEFAULT_GRADING,
                row_grading: float = DEFAULT_ROW_GRADING) -> ToothModel:
    """Mesh one tooth of ``gear`` (graded across by ``grading``) and assemble its stiffness
    and lumped mass."""
    mesh = tooth_mesh(gear, nx, ny, grading=grading, row_grading=row_grading)
    k = assemble_stiffness(mesh.nodes, mesh.elements, gear.material, gear.face_width)
    m = assemble_lumped_mass(mesh.nodes, mesh.elements, gear.material, gear.face_width)
    return ToothModel(gear=gear, mesh=mesh, stiffness=k.tocsr(), mass=m)
