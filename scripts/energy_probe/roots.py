"""Work of the root constraint forces held in direction over each step, and the rolling term."""
import sys, numpy as np
from spurdyn.cases import resolve_cases
from spurdyn.model.system import build_system
from spurdyn.solvers.loop import make_stepper
from spurdyn.solvers.paper.dynamics_numpy import paper_flanks, root_phi_theta, blocks
contact = sys.argv[1]
over = dict(a.split('=') for a in sys.argv[2:]); over = {k: (int(v) if k in ('run.n_spline',) else float(v)) for k, v in over.items()}
case = resolve_cases("paper-fig8", over)[0]
run = case.run.with_(contact=contact)
system = build_system(case.pair, run)
st = make_stepper(system, run); S = st.S
gears = system.gears
def root_disp(u):
    out = []
    for g, (gb, ub) in enumerate(zip(gears, blocks(system, u))):
        out.append(ub.reshape(-1, 2)[gb.root_nodes].ravel())
    return np.concatenate(out)
nr = [gb.root_nodes.size for gb in gears]
work = [0.0]; ab = []
prev = (S.theta.copy(), S.u.copy(), S.x.copy())
while S.theta[0] < case.pair.theta_s:
    if st.step(): break
    th0, u0, x0 = prev
    lam = 0.5 * (x0[:-1] + S.x[:-1])
    du = root_disp(S.u) - root_disp(u0)
    k = 0; w = 0.0
    for g, gb in enumerate(gears):
        pt = root_phi_theta(gb, th0[g]).ravel()      # dPhi/dtheta at the start of the step
        n2 = 2 * nr[g]
        w += -float(lam[k:k + n2] @ (du[k:k + n2] + pt * (S.theta[g] - th0[g])))
        k += n2
    work.append(work[-1] + w)
    ab.append([S.cpar[0], S.cpar[1], S.cpar[4] if contact == 'hertz' else 0.5 * (x0[-1] + S.x[-1])])
    prev = (S.theta.copy(), S.u.copy(), S.x.copy())
work = np.array(work); ab = np.array(ab)
# rolling term: the old contact material points part by (kA dsA^2 + kB dsB^2)/2 over a step
fa, fb = paper_flanks(system)
def arc_curv(f, t):
    r = f.r0 + (f.r_tip - f.r0) * t / f.ny
    rho = np.sqrt(r * r - f.base_radius ** 2)
    return rho ** 2 / (2 * f.base_radius), 1.0 / rho
sa, ka = arc_curv(fa, ab[:, 0]); sb, kb = arc_curv(fb, ab[:, 1])
dsa = np.diff(np.concatenate([[sa[0]], sa])); dsb = np.diff(np.concatenate([[sb[0]], sb]))
roll = np.concatenate([[0], np.cumsum(-ab[:, 2] * 0.5 * (ka * dsa ** 2 + kb * dsb ** 2))])
tag = contact + ''.join('_%s%s' % (k.split('.')[-1], v) for k, v in over.items())
np.savez('roots_%s.npz' % tag, work=work, roll=roll)
print(tag, 'root work: end %+.3e  min %+.3e ; rolling term: end %+.3e' % (work[-1], work.min(), roll[-1]))
