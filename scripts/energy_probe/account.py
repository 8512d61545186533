import sys, numpy as np
for tag in sys.argv[1:]:
    d = np.load('decomp_%s.npz' % tag); r = np.load('roots_%s.npz' % tag)
    o = d['o']; err = d['err']; sm = d['strain'].max()
    pbar, s1, s1c, s1n = o[:, 1], o[:, 3], o[:, 6], o[:, 7]
    A = np.concatenate([[0], np.cumsum(-pbar * (s1c - s1))])
    Bb = np.concatenate([[0, 0], np.cumsum(-pbar[1:] * (s1n[:-1] - s1c[:-1]))])
    root = r['work']; roll = r['roll']
    res = err - A - Bb - root
    f = lambda v: '%5.2f%% (end %+5.2f%%)' % (100 * abs(v).max() / sm, 100 * v[-1] / sm)
    print(f'{tag:18s} A-rolling {f(A - roll)} |')
    print(f'{tag:18s} err {f(err)} | pair move A {f(A)} of which rolling(est.) {f(roll)} | strip re-spread B {f(Bb)} | root held dirs {f(root)} | rest {f(res)}')
