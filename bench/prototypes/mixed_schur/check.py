import numpy as np, scipy.sparse.linalg as spla
from fem import *
for dist in [0.0, 0.2]:
    m = mesh(8,2, distort=dist); A = assemble(m)
    x, y = m['coords'][:,0], m['coords'][:,1]
    u = np.zeros(2*A['nn']); u[0::2] = 0.01*x+0.02*y; u[1::2]=0.03*x
    eps = np.array([0.01, 0.0, 0.02+0.03]); sig = CMAT@eps
    lu = spla.splu(A['M'].tocsc())
    s = lu.solve(A['K12'].T@u)
    print('dist',dist,'max |M^-1 K12^T u - C eps| =', np.abs(s.reshape(-1,3)-sig).max())
    a=0.05
    Su = a*(A['Kd']@u)+(1-a)*(A['K12']@s)
    print('  max|S_a u - Kd u| =', np.abs(Su-A['Kd']@u).max(), ' |Kd u|max', np.abs(A['Kd']@u).max())
    SLu = a*(A['Kd']@u)+(1-a)*(A['K12']@(A['MLinv']@(A['K12'].T@u)))
    print('  lumped: max|S_aL u - Kd u| =', np.abs(SLu-A['Kd']@u).max())
    print('  sum f =', A['f'].reshape(-1,2).sum(0))
