import sys, numpy as np
def load(f):
    d = np.load(f); o = d['o']; pbar = o[:,1]; s1 = o[:,3]; s1c = o[:,6]
    A = np.concatenate([[0], np.cumsum(-pbar * (s1c - s1))])
    return d['t'], d['err'], A, d['strain'], np.degrees(d['angle'])
t1, e1, A1, st1, ang = load(sys.argv[1]); t2, e2, A2, st2, _ = load(sys.argv[2])
n = min(len(t1), (len(t2)+1)//2)
e2c, A2c = e2[0:2*n:2], A2[0:2*n:2]
print('time check', abs(t2[0:2*n:2] - t1[:n]).max())
e0 = 2*e2c - e1[:n]; A0 = 2*A2c - A1[:n]
sm = st1.max()
for name, v in [('err dt', e1[:n]), ('err dt/2', e2c), ('err extrap dt->0', e0), ('A dt', A1[:n]), ('A dt/2', A2c), ('A extrap', A0), ('err-A extrap', e0 - A0)]:
    print('%-20s max %.2f%%  end %+.2f%%' % (name, 100*abs(v).max()/sm, 100*v[-1]/sm))
for i in np.linspace(0, n-1, 22).astype(int):
    print('%6.2f  err0 %+.3e  A0 %+.3e  err0-A0 %+.3e' % (ang[i], e0[i], A0[i], e0[i]-A0[i]))
