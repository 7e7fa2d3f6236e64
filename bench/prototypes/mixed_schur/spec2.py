import numpy as np, scipy.linalg as sla
from fem import *
for a, d in [(0.05,0),(0.01,0),(0.2,0),(0.05,0.2),(0.0,0)]:
    for nx, ny in [(32,8),(64,16)]:
        P = Problem(nx, ny, a, distort=d); Kd = P.Kdf.toarray(); S = P.S_dense(); SL = P.SLf.toarray()
        l1 = sla.eigh(S, Kd, eigvals_only=True); l2 = sla.eigh(S, SL, eigvals_only=True)
        print(f"a={a} distort={d} {nx}x{ny}: lam(Kd^-1 S) [{l1.min():.4f},{l1.max():.4f}] kappa {l1.max()/l1.min():.1f} | lam(S_aL^-1 S) [{l2.min():.4f},{l2.max():.4f}] kappa {l2.max()/l2.min():.2f}", flush=True)
