"""The compiled stepper: packs a :class:`~spurdyn.solver.system.PairSystem` into arrays and
drives :func:`spurdyn.integrate.fast_step.advance` chunk by chunk."""

from __future__ import annotations

from collections import namedtuple

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import block_diag

from spurdyn.model.loading import gear_angles, torque_amplitudes
from spurdyn.solver.case import RunCase
from spurdyn.solver.reference import ReferenceStepper, initial_state, jacobian
from spurdyn.solver.system import PairSystem

#: Constant model arrays (see the field comments in :func:`pack`).
Packed = namedtuple("Packed", [
    "Y", "mass", "node_gear", "sense", "J", "centre", "indptr", "indices", "data", "keep",
    "tpar", "rnode", "rgear", "fpar", "fl_nodes", "fl_w", "fl_delta", "side", "sideY",
    "rel_nodes", "rel_pos",
])

#: Mutable state arrays of the fast stepper.
FastState = namedtuple("FastState", [
    "t", "theta", "omega", "u", "v", "x", "alpha_n", "a_n", "cn", "cw", "normal", "cpar", "C",
    "res", "its",
])

FAILURES = {1: "displacement", 2: "velocity", 3: "acceleration"}


def pack(system: PairSystem, case: RunCase) -> Packed:
    """The model as plain arrays, nodes of both teeth stacked (A first)."""
    ga, gb = system.gears
    na = ga.mesh.n_nodes
    k = block_diag([ga.stiffness, gb.stiffness], format="csr").tobsr(blocksize=(2, 2))
    k.sort_indices()
    node_gear = np.concatenate([np.zeros(na, np.int64), np.ones(gb.mesh.n_nodes, np.int64)])
    offs = (0, na)
    rnode = np.concatenate([ga.root_nodes + offs[0], gb.root_nodes + offs[1]]).astype(np.int64)
    rgear = np.concatenate([np.zeros(ga.root_nodes.size, np.int64), np.ones(gb.root_nodes.size, np.int64)])
    fpar = np.zeros((2, 13))
    fl_nodes, fl_w, fl_delta, side, side_y, rel = [], [], [], [], [], [set(rnode.tolist())]
    for g, body in enumerate(system.gears):
        f = body.flank
        fpar[g] = [f.t0, f.t1, f.r0, f.r_tip, f.base_radius, f.psi_base, f.ref_angle, f.ny, f.h,
                   *f.relief]
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
    amp = torque_amplitudes(system.pair, case.torque)
    angles = gear_angles(system.pair)
    tpar = np.array([[amp[0], angles[0][0], angles[0][1]], [amp[1], angles[1][0], angles[1][1]]])
    return Packed(
        Y=np.concatenate([ga.Y, gb.Y]), mass=system.mass, node_gear=node_gear,
        sense=np.array([ga.sense, gb.sense]), J=np.array([ga.inertia, gb.inertia]),
        centre=np.array([ga.centre, gb.centre]), indptr=k.indptr.astype(np.int64),
        indices=k.indices.astype(np.int64), data=np.ascontiguousarray(k.data, dtype=np.float64),
        keep=1 if case.keep_theta_term else 0, tpar=tpar, rnode=rnode, rgear=rgear, fpar=fpar,
        fl_nodes=np.array(fl_nodes, dtype=np.int64), fl_w=np.array(fl_w), fl_delta=np.array(fl_delta),
        side=np.array(side, dtype=np.int64), sideY=np.array(side_y),
        rel_nodes=rel_nodes, rel_pos=rel_pos,
    )


def root_eigenvalue(system: PairSystem, reference: ReferenceStepper, state) -> float:
    """Smallest eigenvalue of the root blocks of ``G M^-1 G^T``.

    The disk rotations turn each root block by an orthogonal similarity (the nodal
    masses are equal in x and y), so its spectrum is constant over a run.
    """
    g = jacobian(system, state.theta, state.contact)[:-1]
    c = (g * reference.minv) @ g.T
    return float(np.linalg.eigvalsh(c)[0])


class FastStepper:
    """The paper's method compiled with Numba, superposing the response to the forces."""

    def __init__(self, system: PairSystem, case: RunCase) -> None:
        from spurdyn.integrate import fast_step

        self._kernel = fast_step
        self.system = system
        self.case = case
        self.P = pack(system, case)
        ref = ReferenceStepper(system, case)
        st = initial_state(ref)
        c = st.contact
        na = system.gears[0].mesh.n_nodes
        cn = np.concatenate([c.nodes_a, c.nodes_b + na]).astype(np.int64)
        cw = np.concatenate([c.weights_a, c.weights_b])
        # Accelerations at t = 0 with the initial forces: RK4's first slope of step 1.
        from spurdyn.solver.reference import constraint_force

        alpha0, a0 = ref.accelerations(st.theta, st.u, *constraint_force(system, st.theta, c, st.x))
        gmat = jacobian(system, st.theta, c)
        self.S = FastState(
            t=np.zeros(1), theta=st.theta.copy(), omega=st.omega.copy(), u=st.u.copy(),
            v=st.v.copy(), x=st.x.copy(), alpha_n=alpha0, a_n=a0, cn=cn, cw=cw,
            normal=c.normal.copy(), cpar=np.array([c.alpha, c.beta, float(c.mode), c.s]),
            C=(gmat * ref.minv) @ gmat.T, res=np.zeros(3), its=np.zeros(3, dtype=np.int64),
        )
        self.cfg = np.array([case.dt, case.tol_disp, case.tol_vel, case.tol_acc, case.max_iter,
                             case.accel_levels, root_eigenvalue(system, ref, st), case.pin_after])
        self.index = 0
        self._row = np.empty((1, 18))

    @property
    def theta_a(self) -> float:
        return float(self.S.theta[0])

    @property
    def theta(self) -> NDArray[np.float64]:
        return self.S.theta

    @property
    def u(self) -> NDArray[np.float64]:
        return self.S.u

    @property
    def t(self) -> float:
        return float(self.S.t[0])

    def row(self) -> NDArray[np.float64]:
        self._kernel.write_row(self.P, self.S, self._row[0])
        return self._row[0].copy()

    def step(self) -> int:
        """One step (for tests); returns the kernel's status."""
        status = self._kernel.step(self.P, self.S, self.cfg)
        self.index += 1
        return int(status)

    def advance(self, n, angle_end, save_every, rows, frames_every, frames):
        nf_max = n // frames_every + 1 if frames_every else 0
        fr = np.empty((nf_max, 3 + self.S.u.size))
        done, nr, nf, status = self._kernel.advance(self.P, self.S, self.cfg, n, angle_end,
                                                    save_every, rows, frames_every, fr, self.index)
        self.index += int(done)
        for i in range(int(nf)):
            frames.append((float(fr[i, 0]), fr[i, 1:3].copy(), fr[i, 3:].copy()))
        reason = ""
        if status:
            step = self.index + 1
            if status == 4:
                reason = f"the solution became NaN at step {step}"
            else:
                stage = FAILURES[int(status)]
                k = int(status) - 1
                tol = self.cfg[1 + k]
                reason = (f"step {step}: the {stage} stage did not converge in {self.case.max_iter} "
                          f"iterations (residual {self.S.res[k]:.3e}, tolerance {tol:.3e})")
        return int(done), int(nr), reason
