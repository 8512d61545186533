import sys, numpy as np
d = np.load(sys.argv[1])
err, ang, F = d['err'], np.degrees(d['angle']), d['F']
ex = d['extra']
de = np.diff(err)
a, b, s = int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
for i in range(a, b, s):
    print('%6d alpha %7.4f beta %7.4f hw %.3e F %8.3f de %+.3e err %+.4e' % (i+1, ex[i,1], ex[i,2], ex[i,5], F[i+1], de[i], err[i+1]))
