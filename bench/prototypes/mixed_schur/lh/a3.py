"""A3: one SA-AMG V-cycle on the assembled lumped Schur complement S_a,L (RBM near-null), as preconditioner for S_a.
A1x2: two V-cycles on Kd (V + one residual correction with Kd) -- tests whether a better Kd solve helps."""
import sys, os
import numpy as np, scipy.sparse.linalg as spla
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(1, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # ../sa_amg.py
from fem2 import Problem
from iters2 import pcg_track, near_null_rbm, amg_kd
from sa_amg import SA
from lh import direct_solution
kind, ny = int(sys.argv[1]), int(sys.argv[2])
for lh in [int(v) for v in sys.argv[3].split(',')]:
    P = Problem(lh, ny, kind); xs = direct_solution(P)
    B, blk = near_null_rbm(P)
    amgL = SA(P.SLf, B, blk, theta=0.0, max_coarse=300)
    amgK = amg_kd(P)
    def twoV(r):
        x = amgK(r); return x + amgK(r - P.Kdf @ x)
    for name, prec, A, xr in [('A3 AMG(S_aL) on S_a', amgL, P.S, xs), ('CG on S_aL, AMG(S_aL)', amgL, lambda x: P.SLf @ x, spla.splu(P.SLf).solve(P.b)),
                               ('A1x2 2 V-cycles on Kd, on S_a', twoV, P.S, xs)]:
        R = pcg_track(A, P.b, prec, maxit=2000, stall=150, xref=xr, Kn=P.Kdf)
        f = lambda v: '-' if v is None else str(v)
        print(f"Q{kind} ny{ny} L/h={lh:5d} {name:32s}: its {f(R['its'][5e-3]):>4s} {f(R['its'][1e-4]):>4s} {f(R['its'][1e-8]):>4s} floor {R['floor']:.1e} | Kd-err its {f(R['eits'][5e-3]):>4s} {f(R['eits'][1e-4]):>4s} {f(R['eits'][1e-8]):>4s}", flush=True)
