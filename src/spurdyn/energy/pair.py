"""A tooth pair's stiffness and the mesh stiffness over the mesh cycle, by the energy method.

A pair's compliance is the sum, in series, of both teeth's (bending, shear, axial and,
when the bores are given, the fillet foundation's) and the Hertzian contact's of the
line contact, constant along the path as the literature takes it (Yang & Sun 1985;
Tian 2004): ``1/k_h = 2 / (pi L) [(1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2]``, which is
``k_h = pi E L / (4 (1 - nu^2))`` for one material. The pairs in contact act in parallel:
the pair whose contact on gear A lies at roll angle ``xi`` meshes beside those at
``xi +- p``, ``p = 2 pi / z_A``, that lie on the path of contact. ``docs/faults_energy.md``,
section 4.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from spurdyn.geometry.pair import GearPair
from spurdyn.energy.crack import Crack
from spurdyn.energy.tooth import DEFAULT_POINTS, ToothCompliance, gauss_segments, tooth_compliance


def pair_face_width(pair: GearPair) -> float:
    """The face width both teeth carry load over (m): the narrower gear's."""
    return min(pair.gear_a.face_width, pair.gear_b.face_width)


def hertz_compliance(pair: GearPair) -> float:
    """The Hertzian contact's compliance (m/N) of the published constant line-contact form."""
    ma, mb = pair.gear_a.material, pair.gear_b.material
    soft = (1.0 - ma.poisson**2) / ma.young + (1.0 - mb.poisson**2) / mb.young
    return 2.0 * soft / (math.pi * pair_face_width(pair))


@dataclass(frozen=True)
class PairCompliance:
    """One tooth pair's compliances (m/N) by contact position (roll angle on A)."""

    roll_a: NDArray[np.float64]
    tooth_a: ToothCompliance
    tooth_b: ToothCompliance
    hertz: float

    @property
    def total(self) -> NDArray[np.float64]:
        return self.tooth_a.total + self.tooth_b.total + self.hertz

    @property
    def stiffness(self) -> NDArray[np.float64]:
        """The pair's stiffness (N/m) along the line of action."""
        return 1.0 / self.total


def pair_compliance(pair: GearPair, roll_a: ArrayLike, crack_a: Crack | None = None,
                    crack_b: Crack | None = None,
                    bore_radii: tuple[float, float] | None = None,
                    points: int = DEFAULT_POINTS, root_segment: bool = False) -> PairCompliance:
    """The compliances of the tooth pair whose contact lies at roll angles ``roll_a`` on A.

    ``crack_a``/``crack_b`` crack the tooth of A/B on its loaded flank; ``bore_radii``
    (m, of A and B) add the fillet foundations, ``None`` leaves them out;
    ``root_segment`` adds the teeth below their base circles (not in the published form).
    """
    roll_a = np.atleast_1d(np.asarray(roll_a, dtype=float))
    roll_b = pair.roll_b_from_roll_a(roll_a)
    width = pair_face_width(pair)
    bores = (None, None) if bore_radii is None else bore_radii
    teeth = [tooth_compliance(g, r, c, bore, width, points, root_segment)
             for g, r, c, bore in ((pair.gear_a, roll_a, crack_a, bores[0]),
                                   (pair.gear_b, roll_b, crack_b, bores[1]))]
    return PairCompliance(roll_a=roll_a, tooth_a=teeth[0], tooth_b=teeth[1],
                          hertz=hertz_compliance(pair))


@dataclass(frozen=True)
class MeshCycle:
    """The mesh stiffness along the engagement of one (possibly faulty) tooth pair.

    ``roll_a`` are that pair's contact positions (rad, on A), ``pair`` its stiffness
    there, ``mesh`` the sum over every pair then in contact (N/m), ``pairs`` their number.
    """

    roll_a: NDArray[np.float64]
    pair: NDArray[np.float64]
    mesh: NDArray[np.float64]
    pairs: NDArray[np.int64]


def mesh_cycle(pair: GearPair, roll_a: ArrayLike, crack_a: Crack | None = None,
               crack_b: Crack | None = None, bore_radii: tuple[float, float] | None = None,
               points: int = DEFAULT_POINTS, root_segment: bool = False) -> MeshCycle:
    """The mesh stiffness while the pair carrying the cracks (if any) is at ``roll_a``,
    which must lie on the path of contact; its neighbours are healthy."""
    roll_a = np.atleast_1d(np.asarray(roll_a, dtype=float))
    start, end, pitch = pair.start_roll_a, pair.end_roll_a, 2.0 * math.pi / pair.gear_a.teeth
    tol = 1e-12 * end
    if np.any(roll_a < start - tol) or np.any(roll_a > end + tol):
        raise ValueError("roll_a must lie on the path of contact")
    own = pair_compliance(pair, roll_a, crack_a, crack_b, bore_radii, points,
                          root_segment).stiffness
    mesh, count = own.copy(), np.ones(roll_a.size, dtype=np.int64)
    reach = math.ceil(pair.contact_ratio)
    for j in (*range(-reach, 0), *range(1, reach + 1)):
        other = roll_a + j * pitch
        on = (other >= start - tol) & (other <= end + tol)
        if np.any(on):
            k = pair_compliance(pair, other[on], None, None, bore_radii, points,
                                root_segment).stiffness
            mesh[on] += k
            count[on] += 1
    return MeshCycle(roll_a=roll_a, pair=own, mesh=mesh, pairs=count)


def mean_mesh_stiffness(pair: GearPair, crack_a: Crack | None = None,
                        crack_b: Crack | None = None,
                        bore_radii: tuple[float, float] | None = None,
                        points: int = DEFAULT_POINTS, root_segment: bool = False) -> float:
    """The mesh stiffness's mean over one mesh cycle (N/m) when every pair is alike:
    ``(1/p) int k_pair(xi) dxi`` over the path of contact, each tooth pair's engagement
    counted once a cycle (docs/faults_energy.md, section 4)."""
    start, end = np.array([pair.start_roll_a]), np.array([pair.end_roll_a])
    xi, w = gauss_segments(start, end, points)
    k = pair_compliance(pair, xi[0], crack_a, crack_b, bore_radii, points,
                        root_segment).stiffness
    return float(np.sum(w[0] * k)) * pair.gear_a.teeth / (2.0 * math.pi)


__all__ = ["MeshCycle", "PairCompliance", "hertz_compliance", "mean_mesh_stiffness",
           "mesh_cycle", "pair_compliance", "pair_face_width"]
