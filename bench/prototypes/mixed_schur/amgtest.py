import numpy as np, scipy.sparse.linalg as spla, time, sys
from fem import *
from sa_amg import SA, near_null
import os
meshes = [(16,4),(32,8),(64,16),(128,32),(256,64)][:int(os.environ.get("NMESH", 5))]
a = float(sys.argv[1]) if len(sys.argv) > 1 else 0.05
dist = float(sys.argv[2]) if len(sys.argv) > 2 else 0.0
print(f"a={a} distort={dist}")
for nx, ny in meshes:
    P = Problem(nx, ny, a, distort=dist); n = len(P.free)
    out = []
    def rep(name, it, amg=None, extra=''):
        s = f"   {name:40s} it {it:4d}"
        if amg is not None: s += f"  opcomplexity {amg.opc:.2f} levels {amg.sizes}"
        print(s + extra, flush=True)
    print(f"mesh {nx}x{ny} ndof {n}: nnz/row Kd {P.Kdf.nnz/n:.1f}  S_aL {P.SLf.nnz/n:.1f}", flush=True)
    B0, blk = near_null(P)
    amgK = SA(P.Kdf, B0, blk)
    _, it = pcg(lambda x: P.Kdf @ x, P.b, amgK); rep('displacement: CG on Kd, SA(Kd,RBM)', it, amgK)
    _, it = pcg(P.S, P.b, amgK); rep('S_a: P0-AMG SA(Kd,RBM)', it)
    for zz in [(), ('x', 'y'), ('x', 'y', 'xy')]:
        B, blk = near_null(P, zz)
        amgL = SA(P.SLf, B, blk)
        _, it = pcg(P.S, P.b, amgL); rep(f'S_a: P1-AMG SA(S_aL, RBM+{"/".join(zz) or "none"})', it, amgL)
        if zz == ():
            _, itL = pcg(lambda x: P.SLf @ x, P.b, amgL); rep('   (CG on S_aL itself with that AMG)', itL)
    _, it = pcg(P.S, P.b, spla.splu(P.SLf).solve); rep('S_a: P1 exact S_aL^-1', it)
