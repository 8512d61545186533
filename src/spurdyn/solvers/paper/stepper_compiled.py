"""The paper's method compiled as a :class:`~spurdyn.solvers.base.Stepper` (``backend="numba"``).

:func:`pack` turns a :class:`~spurdyn.model.system.PairSystem` into the typed packs of
:mod:`spurdyn.solvers.layout`; :class:`CompiledStepper` drives
:func:`spurdyn.solvers.paper.step_compiled.advance` chunk by chunk. The compiled modules
are imported when the first stepper is made, so importing this module stays cheap.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import block_diag

from spurdyn.contact.constants import flank_row
from spurdyn.contact.search_numpy import ContactPair
from spurdyn.contact.hertz import half_width, involute_curvature_radius, strip_compliance
from spurdyn.model.loading import gear_angles, torque_amplitudes
from spurdyn.model.system import PairSystem
from spurdyn.settings import RunSettings
from spurdyn.solvers.base import Frames, Stepper
from spurdyn.solvers.layout import NCOL, CompiledState, Config, Packed
from spurdyn.solvers.paper.dynamics_numpy import (
    accelerations, constraint_force, inverse_mass, jacobian, paper_flanks, strip_law,
)
from spurdyn.solvers.paper.step_numpy import State, initial_state


def pack(system: PairSystem, settings: RunSettings) -> Packed:
    """The model as plain arrays, nodes of both teeth stacked (A first)."""
    ga, gb = system.gears
    na = ga.mesh.n_nodes
    k = block_diag([ga.stiffness, gb.stiffness], format="csr").tobsr(blocksize=(2, 2))
    k.sort_indices()
    node_gear = np.concatenate([np.zeros(na, np.int64), np.ones(gb.mesh.n_nodes, np.int64)])
    offs = (0, na)
    rnode = np.concatenate([ga.root_nodes + offs[0], gb.root_nodes + offs[1]]).astype(np.int64)
    rgear = np.concatenate([np.zeros(ga.root_nodes.size, np.int64), np.ones(gb.root_nodes.size, np.int64)])
    fl_nodes, fl_w, fl_delta, side, side_y, rel = [], [], [], [], [], [set(rnode.tolist())]
    flanks = paper_flanks(system)
    for g, f in enumerate(flanks):
        fl_nodes.append(f.data_nodes + offs[g])
        fl_w.append(f.data_weights)
        fl_delta.append(f.data_delta)
        side.append(f.side_nodes + offs[g])
        side_y.append(f.side_Y)
        # Flank nodes the contact can reach: every outline node from the row of t0 up.
        first = 2 * int(np.floor(f.t0))
        rel.append(set((f.side_nodes[first:] + offs[g]).tolist()))
    rel_nodes = np.array(sorted(set().union(*rel)), dtype=np.int64)
    rel_pos = -np.ones(node_gear.size, dtype=np.int64)
    rel_pos[rel_nodes] = np.arange(rel_nodes.size)
    amp = torque_amplitudes(system.pair, settings.torque)
    angles = gear_angles(system.pair)
    tpar = np.array([[amp[0], angles[0][0], angles[0][1]], [amp[1], angles[1][0], angles[1][1]]])
    return Packed(
        Y=np.concatenate([ga.Y, gb.Y]), mass=system.mass, node_gear=node_gear,
        sense=np.array([ga.sense, gb.sense]), J=np.array([ga.inertia, gb.inertia]),
        centre=np.array([ga.centre, gb.centre]), indptr=k.indptr.astype(np.int64),
        indices=k.indices.astype(np.int64), data=np.ascontiguousarray(k.data, dtype=np.float64),
        keep=1 if settings.keep_theta_term else 0, tpar=tpar, rnode=rnode, rgear=rgear,
        fpar=np.array([flank_row(f) for f in flanks]),
        fl_nodes=np.array(fl_nodes, dtype=np.int64), fl_w=np.array(fl_w), fl_delta=np.array(fl_delta),
        side=np.array(side, dtype=np.int64), sideY=np.array(side_y),
        rel_nodes=rel_nodes, rel_pos=rel_pos,
    )


def root_eigenvalue(system: PairSystem, state: State) -> float:
    """Smallest eigenvalue of the root blocks of ``G M^-1 G^T``.

    The disk rotations turn each root block by an orthogonal similarity (the nodal
    masses are equal in x and y), so its spectrum is constant over a run.
    """
    g = jacobian(system, state.theta, state.contact)[:-1]
    c = (g * inverse_mass(system)) @ g.T
    return float(np.linalg.eigvalsh(c)[0])


#: The largest contact force a run's strip slots are sized for, in static loads
#: ``tau_0 / r_b`` (and at least :data:`STRIP_FORCE_FLOOR` newtons).
STRIP_FORCE_FACTOR = 50.0
STRIP_FORCE_FLOOR = 1e4


def strip_slots(system: PairSystem, settings: RunSettings) -> int:
    """Contact-row slots per gear: 3 for the point contact; for the distributed one, the
    outline nodes a strip of :data:`STRIP_FORCE_FACTOR` static loads can cover on the
    finest element edge (``2 rows + 1``, at most the whole outline)."""
    if settings.contact != "hertz":
        return 3
    estar, face = strip_law(system)
    fa, fb = paper_flanks(system)
    force = max(STRIP_FORCE_FACTOR * settings.torque / system.gears[0].base_radius, STRIP_FORCE_FLOOR)
    # the largest radius of curvature of each flank: its tip
    rho = [involute_curvature_radius(f.r_tip, f.base_radius) for f in (fa, fb)]
    b = half_width(force, rho[0], rho[1], estar, face)
    # the shortest arc of an element edge is the one nearest the base circle: >= dr
    rows = max(int(np.ceil(2.0 * b / min((f.r_tip - f.r0) / f.ny for f in (fa, fb)))) + 1, 1)
    return int(min(2 * rows + 1, 2 * min(fa.ny, fb.ny) + 1))


def contact_slots(system: PairSystem, c: ContactPair, ns: int
                  ) -> tuple[NDArray[np.int64], NDArray[np.float64]]:
    """The contact rows of ``c`` in ``ns`` slots per gear: nodes ``cn`` (both teeth's
    stacked, A first) and weights ``cw``, a narrower row padded by its first node with
    weight 0."""
    na = system.gears[0].mesh.n_nodes

    def slots(nodes: NDArray[np.intp], w: NDArray[np.float64]) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
        pad = ns - nodes.size
        return np.concatenate([nodes, np.full(pad, nodes[0])]), np.concatenate([w, np.zeros(pad)])

    (nsa, wsa), (nsb, wsb) = slots(c.nodes_a, c.weights_a), slots(c.nodes_b, c.weights_b)
    return np.concatenate([nsa, nsb + na]).astype(np.int64), np.concatenate([wsa, wsb])


def compiled_start(system: PairSystem, settings: RunSettings, st: State) -> CompiledState:
    """The compiled state of the NumPy start state ``st`` (with its accelerations and ``C``)."""
    c = st.contact
    cn, cw = contact_slots(system, c, strip_slots(system, settings))
    # Accelerations at t = 0 with the initial forces: RK4's first slope of step 1.
    alpha0, a0 = accelerations(system, settings, st.theta, st.u,
                               *constraint_force(system, st.theta, c, st.x))
    gmat = jacobian(system, st.theta, c)
    return CompiledState(
        t=np.zeros(1), theta=st.theta.copy(), omega=st.omega.copy(), u=st.u.copy(),
        v=st.v.copy(), x=st.x.copy(), alpha_n=alpha0, a_n=a0, cn=cn, cw=cw,
        normal=c.normal.copy(), gth=np.array(c.theta_row, dtype=float),
        cpar=np.array([c.alpha, c.beta, float(c.mode), c.s, st.p_held, c.half_width, st.jump]),
        C=(gmat * inverse_mass(system)) @ gmat.T, res=np.zeros(3), its=np.zeros(3, dtype=np.int64),
    )


def config(settings: RunSettings, eps_root: float, system: PairSystem | None = None) -> Config:
    """The run settings a compiled step reads (the distributed contact's law from ``system``)."""
    s = settings
    estar, face, c_h = 0.0, 0.0, 0.0
    if s.contact == "hertz":
        if system is None:
            raise ValueError("the distributed contact's configuration needs the system")
        estar, face = strip_law(system)
        c_h = strip_compliance(estar, face)
    return Config(dt=float(s.dt), tol_disp=float(s.tol_disp), tol_vel=float(s.tol_vel),
                  tol_acc=float(s.tol_acc), max_iter=int(s.max_iter), levels=int(s.accel_levels),
                  eps_root=float(eps_root), estar=float(estar),
                  face=float(face), c_h=float(c_h))


class CompiledStepper(Stepper):
    """The paper's method compiled with Numba, superposing the response to the forces."""

    def __init__(self, system: PairSystem, settings: RunSettings) -> None:
        from spurdyn.solvers.paper import step_compiled

        super().__init__(system, settings)
        self._kernel = step_compiled
        self.P = pack(system, settings)
        start = initial_state(system, settings)
        self.S = compiled_start(system, settings, start)
        self.cfg = config(settings, root_eigenvalue(system, start), system)
        # None leaves the strip's code out of the point contact's kernel (step_compiled.step)
        self.strip = True if settings.contact == "hertz" else None
        self.residual = self.S.res
        self.iterations = self.S.its
        self._row = np.empty((1, NCOL))

    @property
    def state(self) -> CompiledState:
        return self.S

    def row(self) -> NDArray[np.float64]:
        self._kernel.write_row(self.P, self.S, self._row[0])
        return self._row[0].copy()

    def step(self) -> int:
        """One step (for tests); returns the kernel's status."""
        status = self._kernel.step(self.P, self.S, self.cfg, self.strip)
        self.index += 1
        return int(status)

    def _advance(self, n: int, angle_end: float, save_every: int, rows: NDArray[np.float64],
                 frames_every: int, frames: Frames) -> tuple[int, int, int]:
        nf_max = n // frames_every + 1 if frames_every else 0
        fr = np.empty((nf_max, 3 + self.S.u.size))
        done, nr, nf, status = self._kernel.advance(self.P, self.S, self.cfg, self.strip, n,
                                                    angle_end, save_every, rows, frames_every, fr,
                                                    self.index)
        for i in range(int(nf)):
            frames.append((float(fr[i, 0]), fr[i, 1:3].copy(), fr[i, 3:].copy()))
        return int(done), int(nr), int(status)
