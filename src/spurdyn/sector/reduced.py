"""A gear body of the sector model reduced to its low modes and its flanks' static
flexibility (docs/sector.md, section 6.6).

The body's elastic displacements in the hub's frame are a sum of ``m`` modes of the body
with the hub held and a quasi-static remainder under the contact loads,

    u = Phi eta + R f,      R = K^-1 - Phi Omega^-2 Phi^T,

``Phi`` M-orthonormal with ``Phi^T K Phi = Omega^2``: the lowest modes, Ritz-augmented by
the static response to the hub's angular acceleration ``K^-1 M s`` (so that the inertia of a
turning rim is in the basis) and to unit normal loads at a few radii of every flank (so that
the teeth's deflection under a contact is mostly in the basis). ``R`` is the residual
flexibility: the part of the static response the modes miss, which acts without inertia
(the modes above the basis' highest lie far above the frequencies a run resolves). The
contact load of a pair on a tooth is ``f = b F``, so a pair's gap reads ``b^T Phi eta``
through the modes and the pairs couple through ``b_i^T R b_j``, a compliance beside the
strip's ``c_H``. The gear's coordinates become ``(theta, eta)``: a few hundred numbers
instead of tens of thousands.

The flexibility blocks ``E_i^T K^-1 E_j`` between the flank DOFs of teeth ``i`` and ``j`` come
from the static factor's response to unit loads on a flank, computed once per tooth; on a
whole gear, whose ring is the same under a turn by a pitch, once: in the teeth's own frames
the block depends on ``j - i`` only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.sparse.linalg import eigsh
from threadpoolctl import threadpool_limits

from spurdyn import store
from spurdyn.fem.factor import factor_spd
from spurdyn.sector.cyclic import CyclicGear, cyclic_modes, ring_cell
from spurdyn.sector.reduction import Reduction
from spurdyn.sector.system import GearBlock

#: Static shapes added to the basis per tooth: the response to a unit normal load at this
#: many radii along its flank, so that the teeth's deflection under a contact is mostly in
#: the coordinates; what they miss is left to the residual flexibility.
FLANK_SHAPES = 5


@dataclass
class ReducedGear(Reduction):
    """One gear's body on its modes (module docstring; SI units).

    Attributes
    ----------
    block
        The full gear (:class:`~spurdyn.sector.system.GearBlock`).
    phi
        ``(n, m)`` M-orthonormal modes of the held body (free DOFs).
    omega2
        ``(m,)`` their ``omega^2`` (rad^2/s^2).
    coupling
        ``(m,)`` ``Phi^T M s``: the modes' share of the rim's turning inertia.
    """

    block: GearBlock
    phi: NDArray[np.float64]
    omega2: NDArray[np.float64]
    coupling: NDArray[np.float64]
    _resp: dict[tuple[int, int], NDArray[np.float64]] = field(default_factory=dict, repr=False)

    def phi_rows(self, dofs: NDArray[np.intp]) -> NDArray[np.float64]:
        return self.phi[dofs]

    def static_response(self, k: int, side: int = 0) -> NDArray[np.float64]:
        """``K^-1 E_k``: the held body's response to unit loads on tooth ``k``'s flank DOFs
        (from the mode store when a run before solved for it)."""
        key = (self.block.tooth(k), side)
        if key not in self._resp:
            blk = self.block
            dofs = blk.flank_dofs(k, side)
            name = store.digest("static", _revision(blk), blk.stiffness, dofs)
            found = store.load(name)
            if found is None:
                rhs = np.zeros((blk.mass.size, dofs.size))
                rhs[dofs, np.arange(dofs.size)] = 1.0
                found = {"response": blk.body.solve_free(rhs)}
                store.save(name, **found)
            self._resp[key] = found["response"]
        return self._resp[key]


def reduce_gear(block: GearBlock, max_frequency: float, method: str = "auto") -> Reduction:
    """The modes of ``block``'s held body below ``max_frequency`` (Hz), Ritz-augmented by
    the static response to a unit hub acceleration's inertial load and to unit loads on the
    flanks (module docstring); read from the mode store (:mod:`spurdyn.store`) when a run
    before computed them for the same body, code and libraries. ``method`` ``"auto"``
    solves a whole ring of identical cells harmonic by harmonic
    (:mod:`spurdyn.sector.cyclic`) and any other body whole; ``"ring"`` solves every body
    whole (the reference the harmonics are compared with)."""
    if method not in ("auto", "ring"):
        raise ValueError(f"method must be 'auto' or 'ring' (got {method!r})")
    # one BLAS thread: the dense work is small, where OpenBLAS's threads cost more than they
    # give (the 53-tooth gear's harmonics: 3.9 s against 10.3 s on two busy cores); the
    # store's key is taken inside, so it names the thread count the entry was computed with
    with threadpool_limits(limits=1):
        return _reduce_gear(block, max_frequency, method)


def _reduce_gear(block: GearBlock, max_frequency: float, method: str) -> Reduction:
    """:func:`reduce_gear` on the threads it set."""
    target = (2.0 * math.pi * max_frequency) ** 2
    cell = ring_cell(block.body) if method == "auto" and block.whole else None
    if cell is not None:
        loads = _first_flank_loads(block)
        key = store.digest("cyclic", _revision(block), cell.stiffness, cell.mass, block.rot, loads, target)
        found = store.load(key)
        if found is None:
            found = cyclic_modes(block, cell, target, loads)
            store.save(key, **found)
        return CyclicGear(block, cell, found["y"], found["harm"], found["omega2"], found["coupling"],
                          found["flex"])
    loads = _flank_loads(block)
    key = store.digest("reduced", _revision(block), block.stiffness, block.mass, block.rot, loads, target)
    found = store.load(key)
    if found is None:
        found = _reduce(block, target, loads)
        store.save(key, **found)
    return ReducedGear(block=block, phi=found["phi"], omega2=found["omega2"], coupling=found["coupling"])


def _revision(block: GearBlock) -> str:
    """What decides the modes' last bits besides the body: this module's code, the body's
    factor's and the libraries' versions."""
    return store.code_revision(__name__, type(block.body).__module__, factor_spd.__module__, CyclicGear.__module__)


def _radii(block: GearBlock, top: float | None = None) -> NDArray[np.float64]:
    """The :data:`FLANK_SHAPES` radii of the static shapes' loads, evenly inside the flank
    (below ``top``, a chipped flank's cut radius, if given: above it every load falls on the
    one stand-in node, and the shapes would be one)."""
    flank = block.body.flank
    return np.linspace(flank.r0, flank.r_tip if top is None else top, FLANK_SHAPES + 2)[1:-1]


def _cut_radius(block: GearBlock, tooth: int) -> float | None:
    """The radius of the node where tooth ``tooth``'s drive flank ends at a chip's cut (the
    stand-in of the flank nodes above it: the first flank node met twice), ``None`` on a flank
    with no cut."""
    body = block.body
    nodes = body.mesh.tooth_dofs(block.tooth(tooth)).reshape(-1, 2)[body.flank.side_nodes, 0]
    twice = np.flatnonzero((nodes[1:] == nodes[:-1]) & (nodes[1:] >= 0))
    if twice.size == 0:
        return None
    return float(np.hypot(*body.mesh.nodes[nodes[twice[0]] // 2]))


def _first_flank_loads(block: GearBlock) -> NDArray[np.float64]:
    """``(f, FLANK_SHAPES)`` the unit normal loads at :func:`_radii` of the first tooth's
    drive flank on its flank DOFs, a column each (every tooth's are these turned)."""
    return np.column_stack([block.flank_load(block.first, float(r), 0.0) for r in _radii(block)])


def _flank_loads(block: GearBlock) -> NDArray[np.float64]:
    """The unit normal loads at :func:`_radii` of every tooth's drive flank, a column each
    (none for a missing tooth's)."""
    teeth = [block.first + t for t in range(block.count) if block.first + t not in block.missing]
    loads = np.zeros((block.mass.size, len(teeth) * FLANK_SHAPES))
    for t, tooth in enumerate(teeth):
        for i, r in enumerate(_radii(block, _cut_radius(block, tooth))):
            # added, not set: a chipped flank's cut node stands in for several flank nodes
            np.add.at(loads, (block.flank_dofs(tooth), t * FLANK_SHAPES + i), block.flank_load(tooth, float(r), 0.0))
    return loads


def _reduce(block: GearBlock, target: float, loads: NDArray[np.float64]) -> dict[str, NDArray[np.float64]]:
    """:func:`reduce_gear`'s arrays computed: the held body's modes below ``target``
    (rad^2/s^2) in a basis with the static shapes, Rayleigh-Ritz on it."""
    w2, vec = _held_modes(block, target)
    shapes = block.body.solve_free(np.column_stack([block.mass * block.rot, loads]))
    basis = np.column_stack([vec, shapes])
    # Rayleigh-Ritz on the augmented basis: M-orthonormal modes diagonalising K
    k = block.stiffness.tocsc()
    kr = basis.T @ (k @ basis)
    mr = basis.T @ (block.mass[:, None] * basis)
    # a chipped flank's shapes load one stand-in node and may be dependent, which would give
    # Ritz values below the held body's lowest: truncated to their independent span first.
    # Other bodies as they always were (a whole ring's basis may stand near the threshold
    # without being dependent: a missing tooth's at 8e-12)
    chipped = any(_cut_radius(block, block.first + t) is not None for t in range(block.count)
                  if block.first + t not in block.missing)
    w2r, vr = _truncated_eigh(kr, mr) if chipped and not _independent(mr) else _generalized_eigh(kr, mr)
    phi = basis @ vr
    return {"phi": phi, "omega2": w2r, "coupling": phi.T @ (block.mass * block.rot)}


#: The held body's modes this process computed last, by a digest of the body: the two gears
#: of a pair of equal gears share theirs.
_HELD: dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]] = {}


def _held_modes(block: GearBlock, target: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The held body's ``omega^2`` below ``target`` and their modes (shift-invert Lanczos)."""
    key = store.digest("held", _revision(block), block.stiffness, block.mass, target)
    if key not in _HELD:
        _HELD.clear()                   # one body's at a time: a few hundred MB on a design pair
        _HELD[key] = _lanczos(block, target)
    return _HELD[key]


def _lanczos(block: GearBlock, target: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """:func:`_held_modes` computed: ARPACK about 0 through the body's own static factor,
    asking for more modes until one lies above ``target``."""
    mass = sp.diags(block.mass).tocsc()
    k = block.stiffness.tocsc()
    # shift-invert about 0 through the body's own static factor: the lowest modes first
    solve = block.body.solve_free
    op = sp.linalg.LinearOperator(k.shape, matvec=lambda x: solve(np.asarray(x, dtype=float)), dtype=float)
    # a first guess of three modes a tooth and the rim's (the paper's whole gear on 4 x 14
    # teeth has 82 below 150 kHz: 2.9 a tooth), more until one lies above the top: a plane
    # body's count of modes grows as omega^2 (Weyl), so as the eigenvalue
    count = 3 * block.count + 24
    # a fixed start vector: ARPACK's own is drawn from a generator that lives as long as the
    # process, so the modes (to round-off) would hang on what ran before in it
    v0 = np.random.default_rng(0).uniform(-1.0, 1.0, k.shape[0])
    while True:
        count = min(count, k.shape[0] - 2)
        w2, vec = eigsh(k, k=count, M=mass, sigma=0.0, which="LM", OPinv=op, tol=1e-10, v0=v0)
        if w2.max() >= target or count >= k.shape[0] - 2:
            break
        count = max(int(1.2 * count * target / w2.max()), count + 8)
    keep = w2 < target
    return w2[keep], vec[:, keep]


#: Smallest eigenvalue, relative to the largest, of a Ritz basis' mass matrix with its
#: columns scaled to unit diagonal for the basis to count as independent; below it the
#: directions it spans least are dropped (:func:`_truncated_eigh`).
INDEPENDENT = 1e-10


def _scaled_mass(mr: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """``(d, lam, u)``: ``d = diag(mr)^-1/2`` and the eigenpairs of ``d mr d``."""
    d = 1.0 / np.sqrt(np.diag(mr))
    lam, u = np.linalg.eigh(0.5 * (mr + mr.T) * d[:, None] * d[None, :])
    return d, lam, u


def _independent(mr: NDArray[np.float64]) -> bool:
    """Whether the Ritz basis whose mass matrix is ``mr`` is independent (:data:`INDEPENDENT`)."""
    _, lam, _ = _scaled_mass(mr)
    return bool(lam[0] > INDEPENDENT * lam[-1])


def _truncated_eigh(k: NDArray[np.float64], m: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rayleigh-Ritz on a dependent basis: the basis M-orthonormalised with the directions of
    scaled mass below :data:`INDEPENDENT` of the largest dropped, then ``K`` diagonalised on
    what is left; the vectors returned are the basis' coefficients (fewer columns)."""
    d, lam, u = _scaled_mass(m)
    keep = lam > INDEPENDENT * lam[-1]
    t = d[:, None] * u[:, keep] / np.sqrt(lam[keep])        # t^T m t = I
    kt = t.T @ k @ t
    w2, v = np.linalg.eigh(0.5 * (kt + kt.T))
    return w2, t @ v


def _generalized_eigh(k: NDArray[np.float64], m: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    from scipy.linalg import eigh

    w2, v = eigh(0.5 * (k + k.T), 0.5 * (m + m.T))
    return w2, v


__all__ = ["ReducedGear", "reduce_gear"]
