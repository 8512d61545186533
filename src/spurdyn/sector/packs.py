"""The typed packs the sector model fills for its compiled loops, each defined once.

The model's data as the compiled loops of :mod:`spurdyn.solvers.sector` read it: a modal
gear (:meth:`spurdyn.sector.bodies.ModalBody.compiled`), the rigid gap's table
(:meth:`spurdyn.sector.system.GapTable.compiled`), the contacts and the run's scalars
(:meth:`spurdyn.sector.model.SectorModel.packs`). Numba takes namedtuples of arrays and
scalars; they are plain descriptions of data, with no Numba here, so they sit with the
model that fills them (the loops' states, changed in place, stay in
:mod:`spurdyn.solvers.layout`). Nothing here imports spurdyn.
"""

from __future__ import annotations

from collections import namedtuple

#: One modal gear as the sector's compiled loops read it (its body's twin,
#: ``ModalBody.compiled``): ``S = M + gamma' C + beta' K`` (``M`` for the RK4 reference) is
#: an arrow, the hub's row and column ``(J, c^T)`` beside a diagonal ``d``, so ``S^-1 x`` takes
#: ``u = c / d``, ``1 / d`` and the Schur complement ``schur = J - c^T u``
#: (:func:`spurdyn.sector.bodies.arrow_solve`); ``damp`` and ``omega2`` the modes' damping and ``omega^2``,
#: ``modes`` ``(count, sides, f, m)`` the modes at each flank in its own frame, ``flex``
#: ``(count, sides, sides, f, f)`` the static flexibility between two flanks by the teeth's
#: distance round the ring (``ring`` 1) or ``(count^2, sides, sides, f, f)`` by the pair of
#: teeth ``(i, j)`` at ``i count + j`` (``ring`` 0: a faulty gear's teeth differ), ``geo`` the
#: flank's ``(r0, r_tip, ny, r_b, half base angle)``, ``first`` and ``count`` the body's teeth.
ModalGear = namedtuple("ModalGear", ["u", "dinv", "schur", "damp", "omega2", "modes", "flex", "geo", "first",
                                     "count", "ring"])

#: The rigid gap's table (``GapTable.compiled``): rolls, gaps, slopes and contact radii.
GapArrays = namedtuple("GapArrays", ["rho", "gap", "slope", "r_a", "r_b"])

#: The contacts of a sector run: contact ``i`` is the driver's tooth ``teeth[i]`` on its
#: flank ``sides[i]`` (0 drive, 1 back), ``offset`` the driver's body tooth of pair 0 (a
#: continuation runs on); ``xq``, ``wq`` the strip's quadrature; ``c_table`` the mesh
#: damper's coefficient over a pitch (:func:`~spurdyn.sector.damper.mesh_damper_table`);
#: ``pits0``, ``pits1`` ``(count, sides, 4)`` per body tooth and flank of each gear the
#: contact's rolls ``(lo, hi)`` on its path over which its gap is ``depth`` wider over the
#: share ``width`` of the face width (a spall's pit: 1 across the face, less splits the
#: contact into two rows; zeros on a healthy flank); ``gone0``, ``gone1`` ``(count,)`` 1 on a
#: missing tooth (its contacts are not made); ``lost0``, ``lost1`` ``(count, sides, 2)`` the
#: contact's rolls ``(lo, hi)`` on its path where a chip took its flank (not made there;
#: ``(inf, -inf)``: none).
SectorContacts = namedtuple("SectorContacts", ["teeth", "sides", "offset", "xq", "wq", "c_table", "pits0",
                                               "pits1", "gone0", "gone1", "lost0", "lost1"])

#: The scalars of a sector run (SI units): the path's rolls ``roll_0``, ``roll_1`` and the
#: ``reach`` beyond them, the ``pitch``, the base radii ``ra``, ``rb``, Hertz's ``estar``, the
#: face ``width``, the strip compliance ``c_h``, the generalized-alpha coefficients ``am``,
#: ``af``, ``beta``, ``gamma``, ``bp = beta'``, ``gp = gamma'`` (zeros for the RK4
#: reference), the step ``h``, the back flanks' roll sum ``sigma`` and backlash ``jn``, and
#: the driver's turns ``theta_lo .. theta_hi`` the contacts cover.
SectorConfig = namedtuple("SectorConfig", [
    "roll_0", "roll_1", "reach", "pitch", "ra", "rb", "estar", "width", "c_h",
    "am", "af", "beta", "gamma", "h", "bp", "gp", "sigma", "jn", "theta_lo", "theta_hi",
])

#: A run's crack faces as the compiled implicit loop reads them (twin of
#: :class:`~spurdyn.sector.faces.CrackFaces`): per gear ``modal`` ``(S_g, m)`` ``B^T Phi``,
#: ``columns`` ``(1 + m, S_g)`` ``S^-1 (0, B^T Phi)^T``, ``cross`` and ``reach`` ``(count,
#: sides, f, S_g)`` the residual flexibility and the step's response between each flank (in
#: its frame) and the faces (:class:`~spurdyn.sector.faces.GearFaces`); ``w_ff`` and ``r_ff``
#: ``(S, S)`` the faces' constant blocks, gear 0's faces first. A gear without a crack has
#: ``S_g = 0``; a run without, ``S = 0``.
FacePack = namedtuple("FacePack", ["modal0", "modal1", "columns0", "columns1", "cross0", "cross1", "reach0",
                                   "reach1", "w_ff", "r_ff"])

#: The hubs' bearings as the compiled implicit loop reads them (twin of
#: :class:`~spurdyn.sector.bearings.HubBearings`): ``rows`` ``(2, t)`` a drive and a back
#: contact's entries on the ``t`` translations (4, or 0 without bearings), per translation
#: ``tinv`` the inverse of ``S_tt``, the bearing's ``k`` and ``c``.
BearingPack = namedtuple("BearingPack", ["rows", "tinv", "k", "c"])

__all__ = ["BearingPack", "FacePack", "GapArrays", "ModalGear", "SectorConfig", "SectorContacts"]
