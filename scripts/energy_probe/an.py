import sys, numpy as np
d = np.load(sys.argv[1]); o = d['o']; err = d['err']; strain = d['strain']; Wc = d['Wc']
p, pbar, s0, s1, s0e, s1e, s1c, s1n = o[:, :8].T
W = np.concatenate([[0], np.cumsum(pbar * (s1e - s0e))])     # actual work of the held force on the FE
Wfull = np.concatenate([[0], np.cumsum(pbar * (s1 - s0))])
A = np.concatenate([[0], np.cumsum(-pbar * (s1c - s1))])      # - p (gap change from the pair's move at q_{n+1})
Bb = np.concatenate([[0], np.cumsum(-pbar[1:] * (s1n[:-1] - s1c[:-1]))]); Bb = np.concatenate([[0], Bb])  # re-spread, charged to next step's p
Dd = Wfull - W
sm = strain.max()
def show(name, v):
    print('%-40s max|.| %.3e (%.2f%%) end %+.3e' % (name, abs(v).max(), 100*abs(v).max()/sm, v[-1]))
show('energy error (tracker)', err)
show('booked contact work Wc', Wc)
show('held-force work on FE  W', W)
show('W - Wc', W - Wc)
show('err - (W - Wc)', err - (W - Wc))
show('pair-move term A', A)
show('re-spread term B', Bb)
show('rigid delta_bar rotation term D', Dd)
show('A + B + D', A + Bb + Dd)
show('err - (A+B)', err - (A + Bb))
# W identity check: W = sum p (s1c - s0c_prev) ... 
c = np.corrcoef(np.diff(err), np.diff(A))[0,1]; print('corr of per-step increments err vs A: %.3f' % c)
