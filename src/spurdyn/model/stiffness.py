"""Static stiffness of one tooth pair along the path of contact.

Both teeth are clamped at their root curves (rigid disks held still) and loaded by equal
and opposite unit forces along the line of action at the contact point. Each tooth's
compliance is the displacement of the loaded point along the load; the pair's stiffness
is ``1 / (c_A + c_B)``. This is the one-pair mesh stiffness without rim, body or shaft
compliance (see ``docs/stiffness.md``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.linalg import splu

from spurdyn.geometry.pair import GearPair
from spurdyn.model.tooth import ToothModel


class ToothCompliance:
    """Point compliance of a root-clamped tooth along its flank normal."""

    def __init__(self, tooth: ToothModel, side: str = "right") -> None:
        self.tooth = tooth
        self.side = side
        n = tooth.mesh.n_dof
        free = np.setdiff1d(np.arange(n), tooth.root_dofs)
        self._free = free
        self._lu = splu(sp.csc_matrix(tooth.stiffness[free][:, free]))

    def load_vector(self, r: float) -> NDArray[np.float64]:
        """Nodal forces of a unit compressive load on the flank at radius ``r``."""
        gear = self.tooth.gear
        nodes, w = self.tooth.side_point(self.side, r)
        normal = gear.flank_normal(np.asarray(r))
        if self.side == "left":
            normal = normal * np.array([-1.0, 1.0])
        f = np.zeros(self.tooth.mesh.n_dof)
        # The mating flank pushes into the tooth: against the outward normal.
        f[2 * nodes] -= w * normal[0]
        f[2 * nodes + 1] -= w * normal[1]
        return f

    def __call__(self, r: float) -> float:
        """Compliance (m/N) at the flank point of radius ``r``."""
        f = self.load_vector(r)
        u = np.zeros_like(f)
        u[self._free] = self._lu.solve(f[self._free])
        return float(f @ u)


@dataclass(frozen=True)
class PairStiffness:
    """Static single-pair stiffness along the path of contact.

    Attributes
    ----------
    roll_a
        Roll angles of gear A (rad) at which it was computed.
    compliance_a, compliance_b
        Each tooth's compliance (m/N).
    stiffness
        ``1 / (c_A + c_B)`` (N/m).
    """

    roll_a: NDArray[np.float64]
    compliance_a: NDArray[np.float64]
    compliance_b: NDArray[np.float64]

    @property
    def stiffness(self) -> NDArray[np.float64]:
        return 1.0 / (self.compliance_a + self.compliance_b)


def pair_stiffness(
    pair: GearPair, tooth_a: ToothModel, tooth_b: ToothModel, roll_a: NDArray[np.float64] | float
) -> PairStiffness:
    """Static single-pair stiffness at the given roll angles of gear A (rad)."""
    roll_a = np.atleast_1d(np.asarray(roll_a, dtype=float))
    roll_b = pair.roll_b_from_roll_a(roll_a)
    ca, cb = ToothCompliance(tooth_a), ToothCompliance(tooth_b)
    r_a = pair.gear_a.radius_at_roll_angle(roll_a)
    r_b = pair.gear_b.radius_at_roll_angle(roll_b)
    return PairStiffness(
        roll_a=roll_a,
        compliance_a=np.array([ca(float(r)) for r in r_a]),
        compliance_b=np.array([cb(float(r)) for r in r_b]),
    )


def pitch_point_stiffness(pair: GearPair, tooth_a: ToothModel, tooth_b: ToothModel) -> float:
    """Static single-pair stiffness (N/m) with the contact at the pitch point."""
    return float(pair_stiffness(pair, tooth_a, tooth_b, pair.pitch_roll_a).stiffness[0])


@dataclass(frozen=True)
class IsoStiffness:
    """ISO 6336-1 (method B) mesh stiffness of a spur pair, per unit face width.

    Attributes
    ----------
    single_pair
        ``c'`` in N/(mm um): the maximum single-pair stiffness.
    mesh
        ``c_gamma_alpha = c' (0.75 eps_alpha + 0.25)`` in N/(mm um): the mean mesh stiffness.
    """

    single_pair: float
    mesh: float

    def per_face_width(self, face_width: float) -> tuple[float, float]:
        """Both stiffnesses in N/m for a face width in m."""
        scale = face_width * 1e3 * 1e6  # N/(mm um) * mm -> N/um -> N/m
        return self.single_pair * scale, self.mesh * scale


def iso_6336_stiffness(pair: GearPair, correction: float = 0.8) -> IsoStiffness:
    """ISO 6336-1 method B stiffness of a solid spur pair, in N/(mm um).

    The formula's one home is :func:`spurdyn.iso6336.dynamics.single_pair_stiffness`
    (``C_M`` = ``correction``, no low-load reduction); the basic rack's dedendum ratio
    is the gear's dedendum over the module plus its profile shift (``h_fP = h_f + x m``).
    """
    from spurdyn.iso6336.dynamics import N_PER_MM_UM, mesh_stiffness, single_pair_stiffness

    ga, gb = pair.gear_a, pair.gear_b
    c1 = single_pair_stiffness(ga.teeth, gb.teeth, ga.pressure_angle,
                               ga.dedendum / ga.module + ga.profile_shift, ga.profile_shift,
                               gb.profile_shift, c_m=correction) / N_PER_MM_UM
    return IsoStiffness(single_pair=float(c1), mesh=float(mesh_stiffness(c1, pair.contact_ratio)))
