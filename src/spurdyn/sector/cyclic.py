"""A whole gear's body reduced by its cyclic symmetry (docs/sector.md, section 6.9).

A whole gear of ``z`` teeth is ``z`` copies of one cell (a tooth on its rim), cell ``j``
turned by ``j`` pitches from the reference cell. A field of harmonic ``h`` (phase step
``phi_h = 2 pi h / z``) is, in cell ``j``, ``u_j = Q_j e^{i j phi_h} u``: one cell's
complex field ``u`` turned and phased. The cell's edge toward cell 1 is cell 1's other edge,
so its DOFs follow from those of the reference cell's other edge, ``u_R = e^{i phi_h} Q_1
u_L``: ``u = T_h x`` over the cell's independent DOFs ``x``, and the ring's stiffness and
mass split into one small Hermitian pair per harmonic,

    K_h = T_h^H K_c T_h,     M_h = T_h^H M_c T_h,

``K_c``, ``M_c`` the reference cell's own elements. The ring's modes are those of the
harmonics ``h = 0 .. z // 2`` (``h`` and ``z - h`` are complex conjugates: a pair of real
modes of one frequency); the static response to loads on the reference cell is
``x_h = K_h^-1 f / z`` summed over all ``z`` harmonics. The flank shapes of
:mod:`spurdyn.sector.reduced` split the same way (the loads of all teeth at a radius are a
cyclic set), so the Rayleigh-Ritz on the augmented basis is one small problem per harmonic,
and the reduction is the whole-ring one to round-off at a fraction of its cost.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from scipy.linalg import eigh
from scipy.sparse.linalg import LinearOperator, eigsh, splu
from threadpoolctl import threadpool_limits

from spurdyn.fem.assembly import assemble_lumped_mass, assemble_stiffness
from spurdyn.sector.body import SectorBody
from spurdyn.sector.reduction import Reduction
from spurdyn.sector.system import GearBlock, rotation_field


#: Rows of a ring's field formed at once from a harmonic's cell field (:meth:`CyclicGear._ring_response`).
ROW_CHUNK = 2048


def turn_matrix(angle: float) -> NDArray[np.float64]:
    """``(2, 2)`` ``Q`` turning a vector clockwise by ``angle`` (``v' = Q v``, as
    :func:`spurdyn.mesh.sector.turn` turns points)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, s], [-s, c]])


@dataclass(frozen=True)
class Cell:
    """The reference cell of a whole gear's ring (module docstring; SI units).

    Attributes
    ----------
    z, pitch
        The cells and the angle between neighbours (rad).
    nodes
        ``(n0,)`` the ring's nodes of the reference cell (its elements' nodes).
    cell_of, base_of
        ``(N,)`` for each ring node a cell holding it and its copy's place in ``nodes``.
    ind
        Places in ``nodes`` of the independent free nodes (not on the edge toward cell 1,
        not on the hub).
    right, left
        Places in ``nodes`` of the free nodes on the edge toward cell 1, and of the nodes on
        the other edge they copy.
    stiffness, mass
        ``(2 n0, 2 n0)`` stiffness and ``(2 n0,)`` lumped masses of the cell's elements.
    """

    z: int
    pitch: float
    nodes: NDArray[np.intp]
    cell_of: NDArray[np.intp]
    base_of: NDArray[np.intp]
    ind: NDArray[np.intp]
    right: NDArray[np.intp]
    left: NDArray[np.intp]
    stiffness: sp.csr_matrix
    mass: NDArray[np.float64]

    @property
    def n_ind(self) -> int:
        """The independent DOFs of a harmonic."""
        return 2 * self.ind.size

    def phase(self, h: int) -> complex:
        """``e^{i phi_h}``; exactly +-1 for the real harmonics ``0`` and ``z / 2``."""
        if h == 0:
            return 1.0
        if 2 * h == self.z:
            return -1.0
        return complex(np.exp(2j * math.pi * h / self.z))

    def expansion(self, h: int) -> sp.csr_matrix:
        """``T_h``: ``(2 n0, 2 n_ind)`` the cell's DOFs from the independent ones."""
        n0, ni = self.nodes.size, self.ind.size
        place = np.full(n0, -1, dtype=np.intp)
        place[self.ind] = np.arange(ni)
        q = self.phase(h) * turn_matrix(self.pitch)
        rows, cols, vals = [], [], []
        for a in range(2):
            rows.append(2 * self.ind + a)
            cols.append(2 * np.arange(ni) + a)
            vals.append(np.ones(ni, dtype=complex))
            src = place[self.left]
            for b in range(2):
                rows.append(2 * self.right + a)
                cols.append(2 * src + b)
                vals.append(np.full(src.size, q[a, b], dtype=complex))
        dtype = float if h == 0 or 2 * h == self.z else complex
        vals = np.concatenate(vals)
        return sp.csr_matrix((vals.real if dtype is float else vals, (np.concatenate(rows), np.concatenate(cols))),
                             shape=(2 * n0, 2 * ni), dtype=dtype)

    def harmonic(self, h: int) -> tuple[sp.csc_matrix, NDArray[np.float64], sp.csr_matrix]:
        """``(K_h, diag M_h, T_h)`` of harmonic ``h``."""
        t = self.expansion(h)
        k = (t.conj().T @ self.stiffness @ t).tocsc()
        # lumped masses, the same in x and y: T_h^H M_c T_h is diagonal
        m = np.asarray(abs(t).power(2).T @ self.mass).ravel()
        return k, m, t

    def at(self, dofs: NDArray[np.intp], y: NDArray, h: int, shift: int = 0) -> NDArray:
        """The ring's field at its DOFs ``dofs`` of harmonic ``h`` whose reference cell's
        DOFs are the columns of ``y`` ``(2 n0, c)``, shifted round the ring by ``shift``
        cells: ``Q_j e^{i (j - shift) phi_h} y`` in cell ``j``."""
        node, a = dofs // 2, dofs % 2
        j = self.cell_of[node]
        b = self.base_of[node]
        ang = j * self.pitch
        c, s = np.cos(ang), np.sin(ang)
        q0, q1 = np.where(a == 0, c, -s), np.where(a == 0, s, c)
        v = q0[:, None] * y[2 * b] + q1[:, None] * y[2 * b + 1]
        if h == 0:
            return v
        if 2 * h == self.z:
            return v * np.where((j - shift) % 2 == 0, 1.0, -1.0)[:, None]
        return v * np.exp(2j * math.pi * h * (j - shift) / self.z)[:, None]


def ring_cell(body: SectorBody) -> Cell | None:
    """The reference cell of ``body`` if it is a whole ring of identical cells (the first
    cell its first tooth's), else ``None``: cell ``j``'s elements are the first's turned by
    ``j`` pitches, of the same widths."""
    mesh, z = body.mesh, body.gear.teeth
    n_el = mesh.elements.shape[0]
    if mesh.teeth.size != z or n_el % z:
        return None
    el = mesh.elements.reshape(z, n_el // z, -1)
    width = mesh.width.reshape(z, -1)
    nodes = np.unique(el[0])
    scale = float(np.abs(mesh.nodes).max())
    for j in (1, z - 1):
        turned = mesh.nodes[el[0]] @ turn_matrix(j * mesh.pitch_angle).T
        if np.abs(mesh.nodes[el[j]] - turned).max() > 1e-9 * scale:
            return None
    if np.any(width != width[0]):
        return None
    place = np.full(mesh.n_nodes, -1, dtype=np.intp)
    place[nodes] = np.arange(nodes.size)
    cell_of = np.empty(mesh.n_nodes, dtype=np.intp)
    base_of = np.empty(mesh.n_nodes, dtype=np.intp)
    for j in range(z):
        cell_of[el[j]] = j
        base_of[el[j]] = place[el[0]]
    nxt = np.empty(nodes.size, dtype=np.intp)
    nxt[place[el[0]]] = el[1]                  # each reference node's copy in cell 1
    left = np.flatnonzero(place[nxt] >= 0)
    right = place[nxt[left]]
    held = np.isin(nodes, mesh.hub_nodes)
    keep = ~held[right]
    left, right = left[keep], right[keep]
    if np.intersect1d(left, right).size or np.any(held[left]):
        return None
    free = np.ones(nodes.size, dtype=bool)
    free[right] = False
    free[held] = False
    stiff, mass = _cell_matrices(body, el[0], width[0], nodes, place)
    return Cell(z=z, pitch=mesh.pitch_angle, nodes=nodes, cell_of=cell_of, base_of=base_of,
                ind=np.flatnonzero(free), right=right, left=left, stiffness=stiff, mass=mass)


def _cell_matrices(body: SectorBody, el: NDArray[np.intp], width: NDArray[np.float64], nodes: NDArray[np.intp],
                   place: NDArray[np.intp]) -> tuple[sp.csr_matrix, NDArray[np.float64]]:
    """The stiffness and lumped masses of the reference cell's elements ``el`` (ring node
    numbers) over its ``nodes``, assembled as the ring's are."""
    xy, local = body.mesh.nodes[nodes], place[el]
    n = 2 * nodes.size
    k = sp.csr_matrix((n, n))
    m = np.zeros(n)
    material = body.gear.material
    for w in np.unique(width):
        sel = width == w
        k = k + assemble_stiffness(xy, local[sel], material, float(w)).tocsr()
        m += assemble_lumped_mass(xy, local[sel], material, float(w))
    return k, m




class CyclicGear(Reduction):
    """A whole gear's body on its modes found harmonic by harmonic (module docstring):
    the modes' reference-cell columns ``y`` ``(2 n0, C)`` of harmonics ``harm`` ``(C,)``,
    each a real mode (harmonics ``0``, ``z / 2``) or the pair of its real and imaginary
    parts (the rest), in the order of ``omega2``; ``flex`` :meth:`flank_flex` of the two
    flanks."""

    def __init__(self, block: GearBlock, cell: Cell, y: NDArray[np.complex128], harm: NDArray[np.intp],
                 w2: NDArray[np.float64], coupling: NDArray[np.float64], flex: NDArray[np.float64]) -> None:
        self.block, self.cell, self.y, self.harm, self.flex = block, cell, y, harm, flex
        z = cell.z
        real = (harm == 0) | (2 * harm == z)
        col = np.concatenate([np.flatnonzero(real), *[np.flatnonzero(~real)] * 2])
        part = np.concatenate([np.zeros(int(real.sum()), np.intp), np.zeros(int((~real).sum()), np.intp),
                               np.ones(int((~real).sum()), np.intp)])
        order = np.lexsort((part, col, w2[col]))
        self._col, self._part = col[order], part[order]
        self._scale = np.where(real[self._col], 1.0 / math.sqrt(z), math.sqrt(2.0 / z))
        self.omega2 = w2[self._col]
        self.coupling = coupling[self._col] * (self._part == 0)
        self._lu: dict[int, tuple[_RealForm, sp.csr_matrix]] = {}
        self._resp: dict[tuple[int, int], NDArray[np.float64]] = {}

    def phi_rows(self, dofs: NDArray[np.intp]) -> NDArray[np.float64]:
        ring = self.block.body.free_dofs[np.asarray(dofs, dtype=np.intp)]
        out = np.empty((ring.size, self.m))
        for h in np.unique(self.harm):
            cols = np.flatnonzero(self.harm == h)
            v = self.cell.at(ring, self.y[:, cols], int(h))
            where = np.flatnonzero(np.isin(self._col, cols))
            pick = np.searchsorted(cols, self._col[where])
            vals = np.where(self._part[where] == 0, v.real[:, pick], np.asarray(v.imag)[:, pick])
            out[:, where] = vals * self._scale[where]
        return out

    def _ring_response(self, rows: NDArray[np.intp], loads: NDArray[np.float64], shift: int = 0,
                       keep: bool = True) -> NDArray[np.float64]:
        """``(len(rows), c)`` the ring's static response at its DOFs ``rows`` to the loads
        ``(2 n_ind, c)`` on the reference cell's independent DOFs, turned round the ring by
        ``shift`` cells: ``(1/z) sum_h x_h``, the conjugate harmonics folded in; ``keep``
        keeps the harmonics' factors for the next call (some 18 MB each on the design pair's
        53-tooth gear), else each is let go once used."""
        cell = self.cell
        out = np.zeros((rows.size, loads.shape[1]))
        for h in range(cell.z // 2 + 1):
            found = self._lu.get(h)
            if found is None:
                k, _, t = cell.harmonic(h)
                found = (_RealForm(k), t)
                if keep:
                    self._lu[h] = found
            solve, t = found
            y = t @ solve(loads, together=True)     # the columns' to round-off (the same bits here)
            weight = 1.0 if h == 0 or 2 * h == cell.z else 2.0
            # the harmonic's complex field a block of rows at a time: over a whole gear's
            # fillets at once its temporaries took some 180 MB (docs/performance.md)
            for lo in range(0, rows.size, ROW_CHUNK):
                part = slice(lo, lo + ROW_CHUNK)
                out[part] += weight * np.real(cell.at(rows[part], y, h, shift))
        return out / cell.z

    def static_response(self, k: int, side: int = 0) -> NDArray[np.float64]:
        blk = self.block
        key = (blk.tooth(k), side)
        if key not in self._resp:
            o = blk.tooth(k) - blk.first
            base = self._ring_response(blk.body.free_dofs, _unit_loads(self.cell, blk, side), o)
            # unit loads along the ring's axes at tooth k: the first tooth's turned by o cells, mixed
            q = turn_matrix(o * self.cell.pitch)
            self._resp[key] = (base.reshape(base.shape[0], -1, 2) @ q.T).reshape(base.shape[0], -1)
        return self._resp[key]

    def static_rows(self, k: int, dofs: NDArray[np.intp]) -> NDArray[np.float64]:
        """:meth:`static_response` of both flanks at the free DOFs ``dofs`` alone, summed over
        the harmonics at those rows only (the ring's whole response is never formed) and the
        harmonics' factors let go (a run's step never needs them)."""
        blk = self.block
        o = blk.tooth(k) - blk.first
        loads = np.hstack([_unit_loads(self.cell, blk, side) for side in (0, 1)])
        base = self._ring_response(blk.body.free_dofs[np.asarray(dofs, dtype=np.intp)], loads, o, keep=False)
        q = turn_matrix(o * self.cell.pitch)
        turned = (base.reshape(base.shape[0], -1, 2) @ q.T).reshape(base.shape[0], 2, -1)
        return np.ascontiguousarray(turned)

    def flank_flex(self, s: int, t: int) -> NDArray[np.float64]:
        return self.flex[s, t]


def _independent(cell: Cell, block: GearBlock, dofs: NDArray[np.intp]) -> NDArray[np.intp]:
    """The reference cell's independent DOF numbers of the block's free DOFs ``dofs`` (which
    must lie inside the first tooth's cell, off its edge toward cell 1)."""
    ring = block.body.free_dofs[dofs]
    node = ring // 2
    at = np.full(cell.nodes.size, -1, dtype=np.intp)
    at[cell.ind] = np.arange(cell.ind.size)
    idx = at[cell.base_of[node]]
    if np.any(cell.cell_of[node] != 0) or np.any(idx < 0):
        raise ValueError("the loads are not on the reference cell's independent DOFs")
    return 2 * idx + ring % 2


def cyclic_modes(block: GearBlock, cell: Cell, target: float,
                 loads: NDArray[np.float64]) -> dict[str, NDArray]:
    """The arrays of :class:`CyclicGear`: per harmonic ``h = 0 .. z // 2`` the modes below
    ``target`` (rad^2/s^2) with the static shapes of the flank ``loads`` (columns on the
    first tooth's flank DOFs, :meth:`GearBlock.flank_dofs`) and, for ``h = 0``, of the unit
    turn's inertia load, Rayleigh-Ritz on them (module docstring); and ``flex`` ``(2, 2,
    z, f, f)``, :meth:`CyclicGear.flank_flex` of the two flanks."""
    f = np.zeros((cell.n_ind, loads.shape[1]))
    f[_independent(cell, block, block.flank_dofs(block.first))] = loads
    unit = np.hstack([_unit_loads(cell, block, side) for side in (0, 1)])
    rows = np.concatenate([block.flank_dofs(block.first + d, side) for side in (0, 1) for d in range(block.count)])
    ring = block.body.free_dofs[rows]
    s = rotation_field(block.body.mesh.nodes[cell.nodes[cell.ind]], block.sense)
    ys, harm, w2s, coup = [], [], [], []
    flex = np.zeros((rows.size, unit.shape[1]))
    for h in range(cell.z // 2 + 1):
        k, m, t = cell.harmonic(h)
        w2, x, resp = _harmonic_ritz(k, m, target, np.column_stack([m * s, f]) if h == 0 else f, unit)
        ys.append(np.asarray(t @ x, dtype=complex))
        harm.append(np.full(w2.size, h, dtype=np.intp))
        w2s.append(w2)
        coup.append(math.sqrt(cell.z) * np.real(x.T @ (m * s)) if h == 0 else np.zeros(w2.size))
        flex += (1.0 if h == 0 or 2 * h == cell.z else 2.0) * np.real(cell.at(ring, t @ resp, h))
    n_f = loads.shape[0]
    flex = (flex / cell.z).reshape(2, block.count, n_f, 2, n_f).transpose(0, 3, 1, 2, 4)
    return {"y": np.hstack(ys), "harm": np.concatenate(harm), "omega2": np.concatenate(w2s),
            "coupling": np.concatenate(coup), "flex": np.ascontiguousarray(flex)}


def _unit_loads(cell: Cell, block: GearBlock, side: int) -> NDArray[np.float64]:
    """Unit loads on the first tooth's flank ``side`` DOFs, on the independent DOFs."""
    dofs = _independent(cell, block, block.flank_dofs(block.first, side))
    loads = np.zeros((cell.n_ind, dofs.size))
    loads[dofs, np.arange(dofs.size)] = 1.0
    return loads


def _harmonic_ritz(k: sp.csc_matrix, m: NDArray[np.float64], target: float, rhs: NDArray[np.float64],
                   unit: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray, NDArray]:
    """A harmonic's modes below ``target`` and the static shapes ``K_h^-1 rhs``: the
    M_h-orthonormal Ritz vectors of their span and their ``omega^2``; and ``K_h^-1 unit``."""
    d = 1.0 / np.sqrt(m)
    a = sp.diags(d) @ k @ sp.diags(d)
    solve = _RealForm(a)
    vec = d[:, None] * _lowest(a, solve, target)
    shapes = d[:, None] * solve(d[:, None] * np.column_stack([rhs, unit]))
    basis = np.column_stack([vec, _orthonormal(shapes[:, :rhs.shape[1]], vec, m)])
    kr = basis.conj().T @ (k @ basis)
    w2, v = eigh(0.5 * (kr + kr.conj().T))
    return w2, basis @ v, shapes[:, rhs.shape[1]:]


def _orthonormal(shapes: NDArray, modes: NDArray, m: NDArray[np.float64]) -> NDArray:
    """The static ``shapes`` M-orthonormalised, against the M-orthonormal ``modes`` and among
    themselves (twice, for round-off): the same span as the shapes beside the modes, but a
    basis whose Ritz problem loses no digits (the flank shapes lie close to each other and
    to the modes: their Gram matrix's condition is some 1e10)."""
    for _ in range(2):
        shapes = shapes - modes @ (modes.conj().T @ (m[:, None] * shapes))
        lam, u = np.linalg.eigh(shapes.conj().T @ (m[:, None] * shapes))
        shapes = (shapes @ u) / np.sqrt(lam)
    return shapes


class _RealForm:
    """``a^-1`` for a Hermitian ``a`` through the real form ``[[a_r, -a_i], [a_i, a_r]]``
    when it is complex (the form :func:`_lowest` iterates on), one factor for both."""

    def __init__(self, a: sp.spmatrix) -> None:
        self.n = a.shape[0]
        self.complex = np.iscomplexobj(a.data)
        form = sp.bmat([[a.real, -a.imag], [a.imag, a.real]]) if self.complex else a
        self._lu = splu(form.tocsc())

    def real(self, b: NDArray[np.float64], together: bool = False) -> NDArray[np.float64]:
        """The real form's solve, column by column, or with ``together`` all in one call on
        one BLAS thread: 2-3 times faster, on unit loads the same numbers (measured; not on
        others, so the modes' solves keep the columns); on two threads one call was 4-35
        times slower (docs/performance.md, "The Fig. 8 sector sweep's root stress")."""
        b = np.asarray(b, dtype=float)
        if b.ndim == 1:
            return self._lu.solve(b)
        if together:
            with threadpool_limits(limits=1, user_api="blas"):
                return self._lu.solve(b)
        return np.column_stack([self._lu.solve(np.ascontiguousarray(b[:, i])) for i in range(b.shape[1])])

    def __call__(self, x: NDArray, together: bool = False) -> NDArray:
        """``a^-1 x`` (:meth:`real`'s ``together``)."""
        x = np.asarray(x)
        if not self.complex:
            return self.real(x.real, together)
        y = self.real(np.concatenate([x.real, x.imag]), together)
        return y[:self.n] + 1j * y[self.n:]


def _lowest(a: sp.spmatrix, solve: _RealForm, target: float) -> NDArray:
    """Orthonormal eigenvectors spanning the eigenspaces of ``a`` (Hermitian, positive)
    below ``target``: shift-invert Lanczos about 0 (ARPACK's symmetric one: a complex
    ``a = a_r + i a_i`` as the real ``[[a_r, -a_i], [a_i, a_r]]``, whose eigenvalues are
    ``a``'s twice, with the vectors ``(x, y)`` and ``(-y, x)`` of ``x + i y`` and ``i (x + i
    y)``), asking for more until one lies above."""
    cplx = np.iscomplexobj(a.data)
    real = sp.bmat([[a.real, -a.imag], [a.imag, a.real]]).tocsr() if cplx else a.tocsr()
    n = real.shape[0]
    op = LinearOperator(real.shape, matvec=solve.real, dtype=float)
    v0 = np.random.default_rng(0).uniform(-1.0, 1.0, n)
    # a design pair's harmonic has some 6 modes below 150 kHz (twice that in the real form)
    count = 16 if cplx else 8
    while True:
        count = min(count, n - 2)
        w2, vec = eigsh(real, k=count, sigma=0.0, which="LM", OPinv=op, tol=1e-10, v0=v0)
        if w2.max() >= target or count >= n - 2:
            break
        count = max(int(1.2 * count * target / w2.max()), count + 4)
    vec = vec[:, w2 < target]
    if not cplx or not vec.shape[1]:
        return vec if not cplx else np.zeros((n // 2, 0), dtype=complex)
    half = n // 2
    v = vec[:half] + 1j * vec[half:]
    # a pair (x, y), (-y, x) gives v and i v: keep one orthonormal basis of their span
    lam, u = np.linalg.eigh(v.conj().T @ v)
    keep = lam > 1e-6 * lam.max()
    return (v @ u[:, keep]) / np.sqrt(lam[keep])




class FlankStatics:
    """A whole gear's body as the quasi-static contact analysis sees it
    (:mod:`spurdyn.sector.statics`: :meth:`load` and :meth:`compliance`), the compliance
    between loads on the drive flanks read from a :class:`CyclicGear`'s flank flexibility
    instead of solved with the whole ring's factor: ``E_i^T K^-1 E_j = B_o F_d B_o^T`` for
    teeth ``i = j + d`` and ``j = first + o``, ``F_d`` :meth:`CyclicGear.flank_flex` and
    ``B_o`` the turn by ``o`` pitches."""

    def __init__(self, gear: CyclicGear) -> None:
        blk = gear.block
        self.body, self.mesh, self.gear = blk.body, blk.body.mesh, blk.gear
        self._flex, self._pitch = gear.flank_flex(0, 0), gear.cell.pitch
        self._rows = blk.body.free_dofs[np.concatenate([blk.flank_dofs(blk.first + o) for o in range(blk.count)])]
        self._blocks: dict[tuple[int, int], NDArray[np.float64]] = {}

    def load(self, k: int, r: float, b: float) -> NDArray[np.float64]:
        return self.body.load(k, r, b)

    def _block(self, i: int, j: int) -> NDArray[np.float64]:
        """``E_i^T K^-1 E_j`` of the body's teeth ``first + i`` and ``first + j`` (kept: a mesh
        cycle asks for the same few pairs of teeth some 600 times)."""
        found = self._blocks.get((i, j))
        if found is None:
            f = self._flex.shape[1]
            turn = np.kron(np.eye(f // 2), turn_matrix(j * self._pitch))
            found = self._blocks[(i, j)] = turn @ self._flex[(i - j) % self._flex.shape[0]] @ turn.T
        return found

    def compliance(self, loads: NDArray[np.float64]) -> NDArray[np.float64]:
        """``C = F^T K^-1 F`` for load columns ``F`` on the drive flanks (any others: solved)."""
        sub = loads[self._rows]
        if np.count_nonzero(sub) != np.count_nonzero(loads):
            return self.body.compliance(loads)
        f = self._flex.shape[1]
        teeth = np.unique(np.flatnonzero(np.any(sub != 0.0, axis=1)) // f)
        part = [sub[t * f:(t + 1) * f] for t in teeth]
        return sum(part[a].T @ self._block(int(i), int(j)) @ part[b]
                   for a, i in enumerate(teeth) for b, j in enumerate(teeth))


def statics_body(gear: object) -> object:
    """What :mod:`spurdyn.sector.statics` takes for a gear of a run: :class:`FlankStatics`
    of a cyclic reduction, else the finite-element body."""
    reduced = getattr(gear, "reduced", None)
    return FlankStatics(reduced) if isinstance(reduced, CyclicGear) else gear.block.body


__all__ = ["Cell", "CyclicGear", "FlankStatics", "cyclic_modes", "ring_cell", "statics_body", "turn_matrix"]
