"""Decompose the energy error of Fig. 8 step by step.
A_n: change of the constrained gap at fixed q_{n+1} from the pair's move (alpha, beta, normal) over step n
B_n: change of the gap at fixed q_n from re-spreading the strip b_{n-1} -> b_n
D_n: the part of the held-row gap change from R delta_bar turning (not in G)
W_n: p_bar * [sbar(q_{n+1}; rows_n) - sbar(q_n; rows_n)] - D_n : the work of the held contact force
"""
import sys, time, numpy as np
from spurdyn.cases import resolve_cases
from spurdyn.model.system import build_system
from spurdyn.solvers.loop import make_stepper
from spurdyn.solvers.paper.dynamics_numpy import paper_flanks, blocks
from spurdyn.contact.strip_numpy import strip_rows
from spurdyn.geometry.involute import rot
import spurdyn.results.balances as B

contact = sys.argv[1]
over = dict(a.split('=') for a in sys.argv[2:])
over = {k: (int(v) if k in ('mesh.nx','mesh.ny','run.n_spline') else float(v)) for k, v in over.items()}
case = resolve_cases("paper-fig8", over)[0]
run = case.run.with_(contact=contact)
system = build_system(case.pair, run)
fa, fb = paper_flanks(system)
st = make_stepper(system, run)
S = st.S
X = [g.X for g in system.gears]
sense = [g.sense for g in system.gears]

def sbar(theta, u, a, b, normal, hw, rigid=True):
    ua, ub = blocks(system, u)
    xa = X[0] + ua.reshape(-1, 2); xb = X[1] + ub.reshape(-1, 2)
    na, wa, da = strip_rows(fa, a, hw); nb, wb, db = strip_rows(fb, b, hw)
    ra, rb = rot(sense[0]*theta[0]), rot(sense[1]*theta[1])
    pa = wa @ xa[na]; pb = wb @ xb[nb]
    if rigid:
        pa = pa + ra @ da; pb = pb + rb @ db
    return float(normal @ (pa - pb))

def snap():
    return dict(theta=S.theta.copy(), u=S.u.copy(), a=S.cpar[0], b=S.cpar[1], mode=S.cpar[2], n=S.normal.copy(),
                hw=S.cpar[5], p=S.x[-1], pheld=S.cpar[4])

angle = case.pair.theta_s
rows = [B.snapshot(st)]
prev = snap()
out = []
t0 = time.time()
while S.theta[0] < angle:
    status = st.step()
    if status: print('status', status); break
    rows.append(B.snapshot(st))
    cur = snap()
    pbar = cur["pheld"] if contact == "hertz" else 0.5 * (prev["p"] + cur["p"])
    hw_force = prev['hw']            # rows of the force this step (no relocation assumed)
    # gap with the force's rows at start and end
    s0 = sbar(prev['theta'], prev['u'], prev['a'], prev['b'], prev['n'], hw_force)
    s1 = sbar(cur['theta'], cur['u'], prev['a'], prev['b'], prev['n'], hw_force)
    s0e = sbar(prev['theta'], prev['u'], prev['a'], prev['b'], prev['n'], hw_force, rigid=False)
    s1e = sbar(cur['theta'], cur['u'], prev['a'], prev['b'], prev['n'], hw_force, rigid=False)
    # the gap the displacement stage held: new pair, strip of the force this step
    s1c = sbar(cur['theta'], cur['u'], cur['a'], cur['b'], cur['n'], hw_force)
    # next step's rows at the same q: re-spread at |x_{n+1}|
    s1n = sbar(cur['theta'], cur['u'], cur['a'], cur['b'], cur['n'], cur['hw'])
    out.append([cur['p'], pbar, s0, s1, s0e, s1e, s1c, s1n, cur['a'], cur['b'], cur['hw'], cur['mode']])
    prev = cur
print('steps', len(out), 'wall', time.time() - t0)
t = np.array([r.t for r in rows]); h = np.diff(t)
E = np.array([r.energy for r in rows])
tp = np.array([r.torque_power for r in rows]); cp = np.array([r.contact_power for r in rows])
Wt = np.concatenate([[0], np.cumsum(0.5*(tp[1:]+tp[:-1])*h)])
Wc = np.concatenate([[0], np.cumsum(0.5*(cp[1:]+cp[:-1])*h)])
err = E - E[0] - Wt - Wc
strain = np.array([r.strain.sum() for r in rows])
o = np.array(out)
tag = contact + ''.join('_%s%s' % (k.split('.')[-1], v) for k, v in over.items())
np.savez('decomp_%s.npz' % tag, o=o, err=err, E=E, Wt=Wt, Wc=Wc, strain=strain, t=t,
         angle=np.array([r.theta[0] for r in rows]), theta_b=np.array([r.theta[1] for r in rows]))
print('err max %.3e end %.3e strain max %.3e' % (abs(err).max(), err[-1], strain.max()))
