"""Along Fig. 8's (current) trajectory: the pair-move work term of candidate gap definitions.
cur : FE strip rows at the spline pair (today)
F3  : spline-strip rows at the spline pair
F2  : spline-strip rows at the pair polished to be stationary for the strip-averaged curves
"""
import sys, numpy as np
from scipy.interpolate import CubicSpline
from spurdyn.cases import resolve_cases
from spurdyn.model.system import build_system
from spurdyn.solvers.loop import make_stepper
from spurdyn.solvers.paper.dynamics_numpy import paper_flanks, blocks
from spurdyn.contact.strip_numpy import strip_rows, spline_strip_rows
from spurdyn.contact.search_numpy import data_values, _newton_pair, outward_normal
from spurdyn.contact.hertz import strip_quadrature
from spurdyn.geometry.involute import rot

case = resolve_cases("paper-fig8")[0]
run = case.run.with_(contact='hertz')
system = build_system(case.pair, run)
fa, fb = paper_flanks(system)
st = make_stepper(system, run); S = st.S
X = [g.X for g in system.gears]; sense = [g.sense for g in system.gears]; cen = [g.centre for g in system.gears]
Yb = [g.Y.reshape(-1, 2) for g in system.gears]
xq, wq = strip_quadrature()

class Virtual:
    """x_bar(a) = P(a) - E(a) + sum_k w_k E(t_k(a)) and its derivatives."""
    def __init__(self, f, xw, R, c, hw):
        t = np.linspace(f.t0, f.t1, f.n_data)
        xd = data_values(f, xw, R)
        rig = data_values(f, c + (Yfull := None) if False else None, R) if False else None
        self.P = CubicSpline(t, xd, bc_type="not-a-knot")
        self.f, self.hw = f, hw
    def set_elastic(self, E):
        self.E = E
    def tk(self, a):
        f = self.f; slope = (f.r_tip - f.r0) / f.ny
        rc = f.r0 + slope * a
        r = np.sqrt(rc * rc + 2 * f.base_radius * self.hw * xq)
        t = (r - f.r0) / slope
        d1 = rc / r; d2 = slope * (r * r - rc * rc) / r ** 3
        out = (t < 0) | (t > f.ny)
        t = np.clip(t, 0, f.ny); d1 = np.where(out, 0, d1); d2 = np.where(out, 0, d2)
        return t, d1, d2
    def __call__(self, a, nu=0):
        t, d1, d2 = self.tk(a)
        if nu == 0:
            return self.P(a) - self.E(a) + wq @ self.E(t)
        if nu == 1:
            return self.P(a, 1) - self.E(a, 1) + (wq * d1) @ self.E(t, 1)
        return self.P(a, 2) - self.E(a, 2) + (wq * d1 * d1) @ self.E(t, 2) + (wq * d2) @ self.E(t, 1)

def curves(theta, u, hw):
    out = []
    for g, f in enumerate((fa, fb)):
        ub = blocks(system, u)[g].reshape(-1, 2)
        R = rot(sense[g] * theta[g])
        v = Virtual(f, X[g] + ub, R, cen[g], hw)
        t = np.linspace(f.t0, f.t1, f.n_data)
        rig = data_values(f, cen[g] + Yb[g] @ R.T, R)
        v.set_elastic(CubicSpline(t, data_values(f, X[g] + ub, R) - rig, bc_type="not-a-knot"))
        out.append(v)
    return out

def polish(theta, u, hw, a, b):
    va, vb = curves(theta, u, hw)
    a2, b2, ok = _newton_pair(va, vb, a, b)
    assert ok and abs(a2 - a) < 0.05, (a, a2, b, b2)
    return a2, b2, outward_normal(va(a2, 1))

def gap(theta, u, a, b, n, hw, rows):
    ua, ub = blocks(system, u)
    xa = X[0] + ua.reshape(-1, 2); xb = X[1] + ub.reshape(-1, 2)
    na, wa, da = rows(fa, a, hw); nb, wb, db = rows(fb, b, hw)
    ra, rb = rot(sense[0]*theta[0]), rot(sense[1]*theta[1])
    return float(n @ ((wa @ xa[na] + ra @ da) - (wb @ xb[nb] + rb @ db)))

every = int(sys.argv[1]) if len(sys.argv) > 1 else 1
A = {'cur': [0.0], 'F3': [0.0], 'F2': [0.0]}
prev = None; k = 0
while S.theta[0] < case.pair.theta_s:
    if st.step(): break
    k += 1
    cur = dict(theta=S.theta.copy(), u=S.u.copy(), a=S.cpar[0], b=S.cpar[1], n=S.normal.copy(), hw_force=None, p=S.cpar[4])
    if prev is not None and prev['hw'] > 0 and (k % every == 0):
        hw = prev['hw']; p = cur['p']
        for name, rows in (('cur', strip_rows), ('F3', spline_strip_rows)):
            s_new = gap(cur['theta'], cur['u'], cur['a'], cur['b'], cur['n'], hw, rows)
            s_old = gap(cur['theta'], cur['u'], prev['a'], prev['b'], prev['n'], hw, rows)
            A[name].append(A[name][-1] - p * (s_new - s_old))
        # F2: polished pairs at q_n and q_{n+1} for the same hw
        a0, b0, n0 = polish(prev['theta'], prev['u'], hw, prev['a'], prev['b'])
        a1, b1, n1 = polish(cur['theta'], cur['u'], hw, cur['a'], cur['b'])
        s_new = gap(cur['theta'], cur['u'], a1, b1, n1, hw, spline_strip_rows)
        s_old = gap(cur['theta'], cur['u'], a0, b0, n0, hw, spline_strip_rows)
        A['F2'].append(A['F2'][-1] - p * (s_new - s_old))
    else:
        for v in A.values(): v.append(v[-1])
    cur['hw'] = S.cpar[5]
    prev = cur
for kname, v in A.items():
    v = np.array(v); print(f'{kname}: pair-move term max {abs(v).max():.3e} end {v[-1]:+.3e}  ({100*abs(v).max()/9.982e-4:.2f}% / {100*v[-1]/9.982e-4:+.2f}%)')
np.savez('cand_%d.npz' % every, **{k: np.array(v) for k, v in A.items()})
