import sys, time, numpy as np
from spurdyn.cases import resolve_cases
from spurdyn.model.system import build_system
from spurdyn.results.balances import track
from spurdyn.solvers.loop import make_stepper
contact = sys.argv[1]; over = dict(a.split('=') for a in sys.argv[2:])
over = {k: (float(v) if k not in ('mesh.nx','mesh.ny','run.n_spline') else int(v)) for k, v in over.items()}
case = resolve_cases("paper-fig8", over)[0]
run = case.run.with_(contact=contact)
system = build_system(case.pair, run)
t0=time.time()
st = make_stepper(system, run)
rows=[]
import spurdyn.results.balances as B
orig = st.step
def step():
    s = orig(); S = st.S
    rows.append([S.x[-1], S.cpar[0], S.cpar[1], S.cpar[2], S.cpar[4], S.cpar[5]]); return s
st.step = step
rec = track(st, angle=case.pair.theta_s)
err = rec.energy_error
print(contact, over, 'dt', run.dt, 'steps', len(err)-1, 'err end %.3e max %.3e strain %.3e  rel max %.2f%% end %.2f%%' % (err[-1], abs(err).max(), rec.strain.max(), 100*abs(err).max()/rec.strain.max(), 100*err[-1]/rec.strain.max()), 'wall', time.time()-t0)
tag = sys.argv[1] + ''.join('_%s%s' % (k.split('.')[-1], v) for k, v in over.items())
np.savez('base_%s.npz' % tag, t=rec.t, angle=rec.angle, F=rec.contact_force, E=rec.energy, strain=rec.strain, Wt=rec.torque_work, Wc=rec.contact_work, err=err, extra=np.array(rows))
