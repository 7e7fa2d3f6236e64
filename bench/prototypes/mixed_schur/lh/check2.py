import numpy as np, scipy.sparse.linalg as spla
from fem2 import *
for kind in [4, 8]:
    m = strip_mesh(3, 2, kind); A = assemble(m)
    # distort interior nodes slightly? keep regular + also a sheared test
    x, y = m['coords'][:,0], m['coords'][:,1]
    u = np.zeros(2*A['nn']); u[0::2] = 0.01*x+0.02*y+0.5; u[1::2]=0.03*x-0.015*y-0.2
    eps = np.array([0.01, -0.015, 0.02+0.03]); sig = A['C']@eps
    lu = spla.splu(A['M'].tocsc())
    s = lu.solve(A['K12'].T@u)
    print(f'Quad{kind}: max|M^-1 K12^T u - C eps|/|C eps| =', np.abs(s.reshape(-1,3)-sig).max()/np.abs(sig).max())
    a=0.05
    Su = a*(A['Kd']@u)+(1-a)*(A['K12']@s)
    print('   max|S_a u - Kd u|/max|Kd u| =', np.abs(Su-A['Kd']@u).max()/np.abs(A['Kd']@u).max())
    SLu = a*(A['Kd']@u)+(1-a)*(A['K12']@(A['MLinv']@(A['K12'].T@u)))
    print('   lumped: max|S_aL u - Kd u|/max|Kd u| =', np.abs(SLu-A['Kd']@u).max()/np.abs(A['Kd']@u).max())
    print('   sum f =', A['f'].reshape(-1,2).sum(0), ' (expect (0, -3e-3)); min mlump', A['mlump'].min(), 'sum', A['mlump'].sum())
    # rigid body: Kd r = 0
    r = np.zeros(2*A['nn']); r[0::2]=-y; r[1::2]=x
    print('   |Kd r_rot| =', np.abs(A['Kd']@r).max())
