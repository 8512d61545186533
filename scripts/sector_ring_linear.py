"""The pair's ring as a linear model (docs/sector.md 6.5): the two bodies' M and K in single
contact at the middle of the stretch after an exit, the pair a spring 1/c_s on its row G q
(c_s = c_H, plus the residual compliance on modal bodies), a damper c row^T row on the
teeth's deflection H, on the rows' rigid part D (the hubs) or on G; the complex eigenvalues
near the ring by shift-invert on the quadratic pencil.

    PYTHONPATH=src .venv/bin/python scripts/sector_ring_linear.py NX NY full|modal
"""
import sys, math, time, json
import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu, eigs, LinearOperator
sys.path.insert(0, str(__import__("pathlib").Path(__file__).resolve().parents[1] / "docs"))
from make_sector_dynamics_validation import PAIR, TORQUE
from spurdyn.settings import RPM
from spurdyn.solvers.check import run_settings
from spurdyn.sector.statics import contact_law, driving_pair, mesh_cycle, pairs_in_path, solve_position
from spurdyn.solvers.sector.system import contact_radii, gear_block, half_widths, teeth_for
from spurdyn.solvers.sector import reduced as red
from spurdyn.iso6336.dynamics import reduced_mass
from spurdyn.solvers.implicit.damping import mesh_damper_coefficient

dp = driving_pair(PAIR)
ra, rb = dp.gear_a.base_radius, dp.gear_b.base_radius
pitch = 2 * math.pi / dp.gear_a.teeth
_BLOCKS = {}

def blocks_for(nx, ny, grading):
    key = (nx, ny, grading)
    if key not in _BLOCKS:
        (fa, ca), (fb, cb) = teeth_for(dp, 1)
        _BLOCKS[key] = (gear_block(dp.gear_a, 1.0, fa, ca, nx, ny, grading),
                        gear_block(dp.gear_b, -1.0, fb, cb, nx, ny, grading))
    return _BLOCKS[key]

class System:
    def __init__(self, nx, ny, bodies="full", phase=None, flank_shapes=5, top=150e3, kmean=None):
        s = run_settings(PAIR, 300 * RPM, TORQUE, dt=1e-6, cycles=1, nx=nx, ny=ny)
        self.blocks = blk = blocks_for(nx, ny, s.grading)
        law = contact_law(PAIR, TORQUE, (blk[0].body, blk[1].body))
        self.c_h = law.c_h
        if phase is None:
            phase = 0.5 * (PAIR.contact_ratio % 1.0 + 0.1 + 0.93)
        roll0 = dp.start_roll_a + phase * pitch
        js, f0, e0, cmat, _ = solve_position(law, roll0)
        assert list(js) == [0] or len(js) == 1, js
        self.W, self.e0 = float(f0.sum()), e0
        self.k_single = 1.0 / float(cmat[0, 0])
        hw = half_widths(dp, [roll0], f0, law.estar, law.width)
        radii = contact_radii(dp, [roll0])
        self.jA, self.jB = blk[0].inertia, blk[1].inertia
        self.m_e = reduced_mass(self.jA, self.jB, ra, rb)
        if kmean is None:
            kmean = mesh_cycle(PAIR, TORQUE, nx, ny, positions=21, bodies=(blk[0].body, blk[1].body)).stiffness_mean
        self.kmean = kmean
        self.c_mesh = mesh_damper_coefficient(0.05, kmean, self.m_e)
        Ms, Ks, Grows, Hrows, loads = [], [], [], [], []
        c_res = 0.0
        for g, (sign, coef) in enumerate(((1, -ra), (-1, rb))):
            b = blk[g]
            k = sign * 0
            load = b.flank_load(k, float(radii[g][0]), float(hw[0]))
            loads.append(load)
            if bodies == "full":
                M = b.matrix(1.0, 0.0, 0.0, (0.0, 0.0)); K = b.matrix(0.0, 0.0, 1.0, (0.0, 0.0))
                h = np.zeros(b.n); h[b.flank_dofs(k) + 1] = load
            else:
                old = red.FLANK_SHAPES; red.FLANK_SHAPES = flank_shapes
                try:
                    rg = red.reduce_gear(b, top)
                finally:
                    red.FLANK_SHAPES = old
                m = rg.m
                Md = np.zeros((m + 1, m + 1)); Md[0, 0] = b.inertia
                Md[0, 1:] = Md[1:, 0] = rg.coupling; Md[1:, 1:] = np.eye(m)
                M = sp.csc_matrix(Md); K = sp.diags(np.concatenate([[0.0], rg.omega2])).tocsc()
                h = np.concatenate([[0.0], rg.modes_at(k).T @ load])
                c_res += float(load @ rg.residual(k, k) @ load)
            gr = h.copy(); gr[0] = coef
            Ms.append(M); Ks.append(K); Grows.append(gr); Hrows.append(h)
        self.c_res = c_res
        self.M = sp.block_diag(Ms).tocsc(); self.K0 = sp.block_diag(Ks).tocsc()
        self.n = self.M.shape[0]; self.na = Ms[0].shape[0]
        self.G = np.concatenate(Grows); self.H = np.concatenate(Hrows)
        self.R = np.zeros(self.n); self.R[0] = -ra; self.R[self.na] = rb     # rigid part of G
        self.c_contact = self.c_h + c_res
        # the body's compliance at the pair without the strip: 1/k_single - c_contact
        self.c_body = 1.0 / self.k_single - self.c_h

    def matrices(self, dampers=()):
        """dampers: [(coefficient, row)] each adding c row^T row."""
        K = self.K0 + sp.csc_matrix(np.outer(self.G, self.G) / self.c_contact) if self.n < 2000 else \
            self.K0 + self._outer(self.G) / self.c_contact
        C = sp.csc_matrix((self.n, self.n))
        for c, row in dampers:
            C = C + c * (self._outer(row) if self.n >= 2000 else sp.csc_matrix(np.outer(row, row)))
        return self.M, C.tocsc(), K.tocsc()

    def _outer(self, row):
        nz = np.flatnonzero(row)
        I, J = np.meshgrid(nz, nz, indexing="ij")
        return sp.csc_matrix((np.outer(row[nz], row[nz]).ravel(), (I.ravel(), J.ravel())), shape=(self.n, self.n))

    def eig(self, dampers=(), f_hz=6000.0, k=8):
        M, C, K = self.matrices(dampers)
        sigma = 2j * math.pi * f_hz
        P = (K + sigma * C + sigma**2 * M).astype(complex).tocsc()
        if self.n < 2000:
            import scipy.linalg as sl
            lu = sl.lu_factor(P.toarray()); solve = lambda b: sl.lu_solve(lu, b)
        else:
            lu = splu(P, permc_spec="MMD_AT_PLUS_A"); solve = lu.solve
        n = self.n
        def op(z):
            a, b = z[:n], M @ z[n:]
            x = solve(-b - (C @ a + sigma * (M @ a)))
            return np.concatenate([x, a + sigma * x])
        L = LinearOperator((2 * n, 2 * n), matvec=op, dtype=complex)
        mu, vec = eigs(L, k=k, which="LM", tol=1e-10)
        lam = sigma + 1.0 / mu
        out = []
        for i in np.argsort(np.abs(lam.imag)):
            if lam[i].imag <= 0: continue
            q = vec[:n, i]
            te = ra * q[0] - rb * q[self.na]
            force = -(self.G @ q) / self.c_contact
            out.append(dict(f_hz=lam[i].imag / (2 * math.pi), zeta=-lam[i].real / abs(lam[i]),
                            te=abs(te), force=abs(force), hq=abs(self.H @ q), q=q))
        return out

if __name__ == "__main__":
    nx, ny, bodies = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    t0 = time.perf_counter()
    S = System(nx, ny, bodies, flank_shapes=int(sys.argv[4]) if len(sys.argv) > 4 else 5)
    print(f"n={S.n} c_h={S.c_h:.3e} c_res={S.c_res:.3e} k_single={S.k_single/1e6:.2f} kmean={S.kmean/1e6:.2f} "
          f"m_e={S.m_e:.5f} c={S.c_mesh:.1f} jA={S.jA:.3e} setup {time.perf_counter()-t0:.1f}s", flush=True)
    for label, damp in (("none", ()), ("H", ((S.c_mesh, S.H),)), ("D", ((S.c_mesh, S.R),)), ("G", ((S.c_mesh, S.G),))):
        t0 = time.perf_counter()
        res = S.eig(damp)
        wmax = max(r["force"] for r in res)
        print(label, f"{time.perf_counter()-t0:.1f}s", "; ".join(f"{r['f_hz']:.0f}Hz z={r['zeta']:.4f} F={r['force']/wmax:.2f}" for r in res if r["f_hz"] > 100.0), flush=True)
