"""Where do the error and the residual of PCG(S_a, Kd^-1) live? Modal split in the (S_a, Kd) eigenbasis.
Usage: decomp.py kind ny lh"""
import sys, os
import numpy as np, scipy.linalg as sla, scipy.sparse.linalg as spla
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fem2 import Problem
from lh import direct_solution
kind, ny, lh = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
P = Problem(lh, ny, kind); xs = direct_solution(P)
K = P.Kdf.toarray(); S = P.S_dense()
lam, X = sla.eigh(S, K)          # X^T K X = I
Klu = spla.splu(P.Kdf)
b = P.b; nb = np.linalg.norm(b)
groups = [('lam<0.2', lam < 0.2), ('0.2<=lam<0.99', (lam >= 0.2) & (lam < 0.99)), ('lam>=0.99', lam >= 0.99)]
print(f"Q{kind} ny{ny} L/h={lh}: ndof {len(b)}; group sizes " + ', '.join(f"{g}: {m.sum()}" for g, m in groups))
c_b = X.T @ b   # b = K X c_x... solution coefficients: x* = X diag(1/lam) X^T b
print("  load b: share of ||x*||_S^2 per group: " + ', '.join(f"{g}: {np.sum(c_b[m]**2/lam[m])/np.sum(c_b**2/lam):.2e}" for g, m in groups))
x = np.zeros_like(b); r = b.copy(); z = Klu.solve(r); p = z.copy(); rz = r @ z
for k in range(1, 41):
    Ap = P.S(p); al = rz / (p @ Ap); x += al * p; r -= al * Ap
    if k in (1, 2, 5, 10, 15, 20, 25, 30, 40):
        e = xs - x; c = X.T @ (K @ e)        # e = X c
        eS = np.sqrt(np.sum(lam * c**2)); xS = np.sqrt(xs @ S @ xs)
        parts = []
        for g, m in groups:
            rg = K @ (X[:, m] @ (lam[m] * c[m]))   # S e restricted to the group
            parts.append(f"{g}: ||r||/||b|| {np.linalg.norm(rg)/nb:.1e}, ||e||_S/||x||_S {np.sqrt(np.sum(lam[m]*c[m]**2))/xS:.1e}")
        print(f"  it {k:3d}: true ||r||/||b|| {np.linalg.norm(b - P.S(x))/nb:.1e}, ||e||_S/||x||_S {eS/xS:.1e} | " + ' | '.join(parts), flush=True)
    z = Klu.solve(r); rzn = r @ z; p = z + rzn / rz * p; rz = rzn
