"""Finite-difference check of the constrained gap against the contact row, on states of Fig. 8."""
import sys, numpy as np
from dataclasses import replace
from spurdyn.cases import resolve_cases
from spurdyn.model.system import build_system
from spurdyn.solvers.loop import make_stepper
from spurdyn.solvers.paper.dynamics_numpy import paper_flanks, blocks, contact_at, strip_law, jacobian
from spurdyn.contact.search_numpy import flank_spline, outward_normal
from spurdyn.contact.strip_numpy import strip_rows
from spurdyn.geometry.involute import rot

contact = sys.argv[1]; steps = [int(s) for s in sys.argv[2].split(',')]
case = resolve_cases("paper-fig8")[0]
run = case.run.with_(contact=contact)
system = build_system(case.pair, run)
law = strip_law(system) if contact == 'hertz' else None
fa, fb = paper_flanks(system)
st = make_stepper(system, run); S = st.S
X = [g.X for g in system.gears]; sense = [g.sense for g in system.gears]
rng = np.random.default_rng(1)

def gap(theta, u, guess, load):
    c = contact_at(system, theta, u, guess, load, law)
    return c

def gap_fixed(theta, u, c):
    ua, ub = blocks(system, u)
    xa = X[0] + ua.reshape(-1, 2); xb = X[1] + ub.reshape(-1, 2)
    ra, rb = rot(sense[0]*theta[0]), rot(sense[1]*theta[1])
    return float(c.normal @ ((c.weights_a @ xa[c.nodes_a] + ra @ c.delta_a) - (c.weights_b @ xb[c.nodes_b] + rb @ c.delta_b)))

def spline_gap(theta, u, a, b, n):
    ua, ub = blocks(system, u)
    xa = X[0] + ua.reshape(-1, 2); xb = X[1] + ub.reshape(-1, 2)
    ra, rb = rot(sense[0]*theta[0]), rot(sense[1]*theta[1])
    pa, pb = flank_spline(fa, xa, ra), flank_spline(fb, xb, rb)
    return float(n @ (pa(a) - pb(b)))

k = 0
for target in steps:
    while k < target:
        st.step(); k += 1
    theta, u, v, om = S.theta.copy(), S.u.copy(), S.v.copy(), S.omega.copy()
    load = abs(S.x[-1]) if law else 0.0
    guess = (S.cpar[0], S.cpar[1])
    c = gap(theta, u, guess, load)
    G = jacobian(system, theta, c)[-1]
    print(f'step {k}: angle {np.degrees(theta[0]):.3f} deg, F {-S.x[-1]:.1f} N, alpha {c.alpha:.4f} beta {c.beta:.4f} b {c.half_width:.3e} m')
    dirs = [('actual motion', np.concatenate([om, v]))]
    # random displacement of the flank nodes (smooth, 1 um scale) and the disk rotations
    for j in range(2):
        d = np.zeros(2 + system.n_u)
        for g, f in enumerate((fa, fb)):
            off = 2 + system.offsets[g]
            for node in f.side_nodes:
                d[off + 2*node: off + 2*node + 2] = rng.normal(size=2)
        dirs.append((f'random nodal {j}', d))
    for name, d in dirs:
        scale = 1e-9 / np.abs(d[2:]).max()
        d = d * scale
        def total(e):
            th = theta + e * d[:2]; uu = u + e * d[2:]
            return gap(th, uu, (c.alpha, c.beta), load)
        cp, cm = total(1.0), total(-1.0)
        dtot = (cp.s - cm.s) / 2
        dfix = (gap_fixed(theta + d[:2], u + d[2:], c) - gap_fixed(theta - d[:2], u - d[2:], c)) / 2
        row = float(G @ d)
        # the spline's own gap at its own pair, and along its own normal: stationary?
        dsp = (spline_gap(theta + d[:2], u + d[2:], cp.alpha, cp.beta, cp.normal) - spline_gap(theta - d[:2], u - d[2:], cm.alpha, cm.beta, cm.normal)) / 2
        dsp_fixed = (spline_gap(theta + d[:2], u + d[2:], c.alpha, c.beta, c.normal) - spline_gap(theta - d[:2], u - d[2:], c.alpha, c.beta, c.normal)) / 2
        print(f'  {name:15s}: total d(gap) {dtot:+.4e}  row G.dq {row:+.4e}  pair fixed {dfix:+.4e}  '
              f'(total-row)/|row| {(dtot-row)/abs(row):+.2e}  | spline gap: total {dsp:+.4e} pair fixed {dsp_fixed:+.4e} rel {(dsp-dsp_fixed)/abs(dsp_fixed):+.1e}  dalpha {(cp.alpha-cm.alpha)/2:+.2e}')
