import sys, numpy as np
d = np.load(sys.argv[1]); o = d['o']; err = d['err']; strain = d['strain']; Wc = d['Wc']; ang = np.degrees(d['angle'])
p, pbar, s0, s1, s0e, s1e, s1c, s1n = o[:, :8].T
A = np.concatenate([[0], np.cumsum(-pbar * (s1c - s1))])
W = np.concatenate([[0], np.cumsum(pbar * (s1e - s0e))])
F = np.concatenate([[0], -p])
for i in np.linspace(0, len(err)-1, 43).astype(int):
    print('%6d ang %6.2f F %7.1f err %+.3e A %+.3e err-A %+.3e  W-Wc %+.3e' % (i, ang[i], F[i], err[i], A[i], err[i]-A[i], W[i]-Wc[i]))
