"""The two-gear system: everything about a run that is constant, as plain arrays.

Generalised coordinates (paper eq. 1): per gear ``g`` (0 = A, 1 = B) the disk rotation
``theta[g]`` since the start of contact, positive along the gear's own sense of
rotation (A clockwise, B counter-clockwise), and the *absolute* displacements ``u`` of
the tooth nodes in the world frame, measured from their initial positions ``X``.
Both teeth's displacements live in one vector, A's block first.

Frames. The world frame is the one of :mod:`spurdyn.geometry.placement`: A's centre
at the origin, B's at ``(0, a)``. A gear turning by ``theta`` along its sense turns its
material by the world angle ``sense * theta`` (``sense`` = -1 for A, +1 for B), so a
point fixed to the disk moves from ``c + Y`` to ``c + R(sense theta) Y``.

The stiffness ``K`` of each tooth is assembled once on the initial world positions
(the disk frame at ``theta = 0``); the elastic displacement is
``w = R^T (Y + u) - Y`` (docs/solver.md derives it and the forces).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from spurdyn.errors import InputError
from spurdyn.fem.assembly import assemble_lumped_mass, assemble_stiffness
from spurdyn.geometry.gear import Gear
from spurdyn.geometry.pair import GearPair
from spurdyn.geometry.placement import mesh_angles, to_world_a, to_world_b
from spurdyn.mesh.tooth import DEFAULT_GRADING, DEFAULT_ROW_GRADING, ToothMesh, tooth_mesh
from spurdyn.model.flank import Flank, make_flank
from spurdyn.settings import RunSettings

#: Sense of rotation of each gear: the world angle is ``SENSE[g] * theta[g]``.
SENSE = np.array([-1.0, 1.0])


@dataclass(frozen=True)
class ToothBody:
    """One elastic tooth of a gear, meshed and placed in the world frame.

    Attributes
    ----------
    mesh
        The tooth mesh (gear frame).
    X
        ``(N, 2)`` initial world positions of the nodes.
    Y
        ``(2N,)`` initial positions relative to the gear's centre, interleaved.
    stiffness
        ``(2N, 2N)`` stiffness on the initial world positions (CSR).
    mass
        ``(2N,)`` HRZ-lumped nodal masses.
    root_nodes
        Nodes tied to the disk.
    flank
        The drive flank.
    """

    mesh: ToothMesh
    X: NDArray[np.float64]
    Y: NDArray[np.float64]
    stiffness: sp.csr_matrix
    mass: NDArray[np.float64]
    root_nodes: NDArray[np.intp]
    flank: Flank

    @property
    def n_u(self) -> int:
        return int(self.mass.size)


def _of_the_tooth(name: str) -> property:
    """An attribute of a one-tooth gear's tooth, read through the gear."""
    return property(lambda self: getattr(self.tooth, name),
                    doc=f"The ``{name}`` of the gear's one tooth (:attr:`GearBody.tooth`).")


@dataclass(frozen=True)
class GearBody:
    """One gear of the system: a rigid disk carrying ``K`` elastic teeth, in the world frame.

    The paper's model carries one tooth (``K = 1``) and reads it through :attr:`tooth` and
    the attributes below (``mesh``, ``X``, ``Y``, ``stiffness``, ``mass``, ``root_nodes``,
    ``flank``); a body of several teeth stacks their displacements in the order of
    :attr:`teeth`.

    Attributes
    ----------
    sense
        -1 (clockwise, gear A) or +1 (counter-clockwise, gear B).
    centre
        Disk centre (m).
    inertia
        Disk moment of inertia ``J`` (kg m^2).
    base_radius
        Base radius of the gear (m), for roll angles.
    teeth
        The elastic teeth on the disk.
    """

    sense: float
    centre: NDArray[np.float64]
    inertia: float
    base_radius: float
    teeth: tuple[ToothBody, ...]

    @property
    def tooth(self) -> ToothBody:
        """The one tooth of the paper's model."""
        if len(self.teeth) != 1:
            raise ValueError(f"this gear body carries {len(self.teeth)} teeth; the paper's "
                             "one-tooth model reads exactly one")
        return self.teeth[0]

    mesh = _of_the_tooth("mesh")
    X = _of_the_tooth("X")
    Y = _of_the_tooth("Y")
    stiffness = _of_the_tooth("stiffness")
    root_nodes = _of_the_tooth("root_nodes")
    flank = _of_the_tooth("flank")

    @property
    def mass(self) -> NDArray[np.float64]:
        """``(n_u,)`` nodal masses of all teeth, stacked in the order of :attr:`teeth`."""
        return self.teeth[0].mass if len(self.teeth) == 1 else np.concatenate([t.mass for t in self.teeth])

    @property
    def n_u(self) -> int:
        return sum(t.n_u for t in self.teeth)

    @property
    def root_dofs(self) -> NDArray[np.intp]:
        r = self.root_nodes
        return np.column_stack([2 * r, 2 * r + 1]).ravel()


@dataclass(frozen=True)
class FlankPair:
    """Two facing flanks that may touch: the contact pairs a run constrains.

    ``tooth_a``, ``tooth_b`` index the teeth of gears A and B; ``flanks`` says which
    flanks face each other (``"drive"``: the loaded flanks; ``"back"`` is for bodies that
    model backlash, not built yet).
    """

    tooth_a: int = 0
    tooth_b: int = 0
    flanks: str = "drive"


@dataclass(frozen=True)
class PairSystem:
    """Both gears, placed so that their teeth just touch at the start of contact.

    Attributes
    ----------
    pair
        The gear pair (gear A drives).
    gears
        ``(A, B)``.
    offsets
        Start of each gear's block in the stacked displacement vector, and its end.
    theta0
        Placement rotations of the tooth meshes (A clockwise, B counter-clockwise).
    contacts
        The flank pairs the run constrains (one in the paper's model).
    """

    pair: GearPair
    gears: tuple[GearBody, GearBody]
    offsets: tuple[int, int, int]
    theta0: tuple[float, float]
    contacts: tuple[FlankPair, ...] = (FlankPair(),)

    @property
    def n_u(self) -> int:
        return self.offsets[2]

    @property
    def n_lambda(self) -> tuple[int, int]:
        return tuple(2 * sum(t.root_nodes.size for t in g.teeth) for g in self.gears)  # type: ignore[return-value]

    @property
    def n_x(self) -> int:
        """Length of ``x = [lambda_A, lambda_B, p_1 ... p_c]``: one multiplier per contact."""
        return sum(self.n_lambda) + len(self.contacts)

    @property
    def n_dof(self) -> int:
        """Degrees of freedom: two disk rotations and every tooth displacement."""
        return 2 + self.n_u

    @property
    def mass(self) -> NDArray[np.float64]:
        return np.concatenate([g.mass for g in self.gears])

    def flanks(self, contact: FlankPair) -> tuple[Flank, Flank]:
        """The flanks of A and B that ``contact`` pairs."""
        if contact.flanks != "drive":
            raise ValueError(f"only drive flanks are modelled (got {contact.flanks!r})")
        return self.gears[0].teeth[contact.tooth_a].flank, self.gears[1].teeth[contact.tooth_b].flank


def assemble_system(pair: GearPair, gears: tuple[GearBody, GearBody], theta0: tuple[float, float],
                    contacts: tuple[FlankPair, ...] = (FlankPair(),)) -> PairSystem:
    """A :class:`PairSystem` from its bodies and contact pairs (offsets counted over the teeth)."""
    na, nb = gears[0].n_u, gears[1].n_u
    return PairSystem(pair=pair, gears=gears, offsets=(0, na, na + nb), theta0=theta0,
                      contacts=tuple(contacts))


def tooth_body(gear: Gear, mesh: ToothMesh, X: NDArray[np.float64], centre: NDArray[np.float64],
               ref_angle: float, n_spline: int) -> ToothBody:
    """Assemble one placed tooth: stiffness and mass on its world positions, its drive flank."""
    k = assemble_stiffness(X, mesh.elements, gear.material, gear.face_width).tocsr()
    k.sort_indices()
    m = assemble_lumped_mass(X, mesh.elements, gear.material, gear.face_width)
    flank = make_flank(mesh, gear, X, centre, ref_angle, n_spline)
    return ToothBody(mesh=mesh, X=X, Y=(X - centre).ravel(), stiffness=k, mass=m,
                     root_nodes=mesh.root_nodes.copy(), flank=flank)


def gear_body(gear: Gear, teeth: tuple[ToothBody, ...], centre: NDArray[np.float64],
              sense: float) -> GearBody:
    """A disk of ``gear`` (its inertia and base radius) carrying ``teeth``."""
    return GearBody(sense=sense, centre=centre, inertia=gear.disk_inertia,
                    base_radius=gear.base_radius, teeth=teeth)


def solver_pair(pair: GearPair) -> GearPair:
    """The pair the solver runs: ``pair`` itself when A drives, its mirror image when B drives.

    With A turning clockwise and B counter-clockwise, a driving B pushes on the other
    flanks. Mirrored about the line between the centres, the pair is a pair whose first
    gear (B) drives clockwise on its right flank, which is what the solver models
    (:func:`spurdyn.solvers.loop.simulate` maps the results back).
    """
    if pair.driver == "a":
        return pair
    return GearPair(gear_a=pair.gear_b, gear_b=pair.gear_a, centre_distance=pair.centre_distance,
                    driver="a")


def build_system(pair: GearPair, settings: RunSettings) -> PairSystem:
    """The system of ``pair`` (gear A driving) on the tooth meshes of ``settings``; see
    :func:`system_for`."""
    if pair.driver != "a":
        raise InputError("pair.driver", "only gear A driving is supported by the solver yet; "
                         "swap gear_a and gear_b")
    return system_for(pair, settings.nx, settings.ny, settings.n_spline, settings.grading,
                      settings.row_grading)


def system_for(pair: GearPair, nx: int, ny: int, n_spline: int,
               grading: float = DEFAULT_GRADING, row_grading: float = DEFAULT_ROW_GRADING) -> PairSystem:
    """Mesh both teeth (columns graded by ``grading``, rows by ``row_grading``:
    :func:`spurdyn.mesh.tooth.tooth_mesh`), place them just touching at the start of
    contact, assemble K and M.

    The system of the pair the solver runs (:func:`solver_pair`). The last two systems built
    are kept, so the run check of a case file and the run itself share one assembly and one
    stable-step eigen-solve; nothing mutates a system. (A pair that cannot be hashed is
    built afresh each time.)
    """
    try:
        hash(pair)
    except TypeError:   # an unhashable pair cannot be a key
        return _build_system(pair, nx, ny, n_spline, grading, row_grading)
    return _kept_system(pair, nx, ny, n_spline, grading, row_grading)


@lru_cache(maxsize=2)
def _kept_system(pair: GearPair, nx: int, ny: int, n_spline: int, grading: float,
                 row_grading: float = DEFAULT_ROW_GRADING) -> PairSystem:
    return _build_system(pair, nx, ny, n_spline, grading, row_grading)


def _build_system(pair: GearPair, nx: int, ny: int, n_spline: int,
                  grading: float = DEFAULT_GRADING, row_grading: float = DEFAULT_ROW_GRADING) -> PairSystem:
    """:func:`system_for` without keeping it.

    The surfaces of :class:`Flank` are the exact involutes, which touch at the start of
    the path of contact at the rotations of :func:`~spurdyn.geometry.placement.mesh_angles`
    (to round-off; with a tip relief they stand apart by the relief there).
    """
    pair = solver_pair(pair)
    theta_a, theta_b = mesh_angles(pair, pair.start_roll_a)
    mesh_a = tooth_mesh(pair.gear_a, nx, ny, grading=grading, row_grading=row_grading)
    mesh_b = tooth_mesh(pair.gear_b, nx, ny, grading=grading, row_grading=row_grading)
    ca, cb = np.array([0.0, 0.0]), np.array([0.0, pair.centre_distance])
    xa = to_world_a(mesh_a.nodes, theta_a)
    xb = to_world_b(mesh_b.nodes, theta_b, pair.centre_distance)
    tooth_a = tooth_body(pair.gear_a, mesh_a, xa, ca, -theta_a, n_spline)
    tooth_b = tooth_body(pair.gear_b, mesh_b, xb, cb, math.pi + theta_b, n_spline)
    gears = (gear_body(pair.gear_a, (tooth_a,), ca, float(SENSE[0])),
             gear_body(pair.gear_b, (tooth_b,), cb, float(SENSE[1])))
    return assemble_system(pair, gears, (theta_a, theta_b))
