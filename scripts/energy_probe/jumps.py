import sys, numpy as np
d = np.load(sys.argv[1])
err, ang, F = d['err'], np.degrees(d['angle']), d['F']
ex = d['extra']
de = np.diff(err)
print('sum |de| %.3e, max |de| %.3e, std de %.3e' % (abs(de).sum(), abs(de).max(), de.std()))
idx = np.argsort(-abs(de))[:25]
for i in sorted(idx):
    print('%6d ang %6.3f F %8.2f de %+.3e  alpha %.4f beta %.4f hw %.3e' % (i+1, ang[i+1], F[i+1], de[i], ex[i,1], ex[i,2], ex[i,5]))
# smoothed: fraction of error from top 1% steps
k = max(1,len(de)//100)
top = np.argsort(-abs(de))[:k]
print('sum of top 1%% increments %.3e ; total signed sum %.3e' % (de[top].sum(), de.sum()))
# running with a 200-step moving average removed
