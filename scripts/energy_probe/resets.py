import sys, numpy as np
from spurdyn.cases import resolve_cases
from spurdyn.model.system import build_system
from spurdyn.solvers.paper.dynamics_numpy import paper_flanks
from spurdyn.contact.hertz import strip_coordinates, strip_quadrature
d = np.load(sys.argv[1]); ex = d['extra']; err = d['err']; de = np.diff(err)
case = resolve_cases("paper-fig8")[0]
system = build_system(case.pair, case.run.with_(contact='hertz'))
fa, fb = paper_flanks(system)
print('A t0 t1 r0 rtip ny rb n_data', fa.t0, fa.t1, fa.r0, fa.r_tip, fa.ny, fa.base_radius, fa.n_data)
x, w = strip_quadrature()
a, b = int(sys.argv[2]), int(sys.argv[3])
def cells(f, tc, hw):
    ts = strip_coordinates(tc, hw, f.r0, f.r_tip, f.ny, f.base_radius, x)
    return np.floor(ts).astype(int), ts
prevA = prevB = None
for i in range(a, b):
    ca, tsa = cells(fa, ex[i,1], ex[i,5]); cb, tsb = cells(fb, ex[i,2], ex[i,5])
    if prevA is not None and (not np.array_equal(ca, prevA) or not np.array_equal(cb, prevB)):
        print('cross at step', i+1, 'A', np.nonzero(ca!=prevA)[0], 'B', np.nonzero(cb!=prevB)[0], 'de before/after %+.2e %+.2e' % (de[i-1], de[i]))
    prevA, prevB = ca, cb
print('strip extent A (t units)', tsa.min()-ex[b-1,1], tsa.max()-ex[b-1,1])
# big reset steps
r = [i+1 for i in range(a, b) if de[i] - de[i-1] > 2e-8]
print('resets', r)
