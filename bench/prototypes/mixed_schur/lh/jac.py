"""Additive correction of the Kd preconditioner with a nodal block-Jacobi of S_a,L:
B = B_Kd + omega * blockdiag_2x2(S_aL)^-1   (B_Kd = exact Kd^-1 or one AMG V-cycle)."""
import sys, os, time
import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as spla
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fem2 import Problem
from iters2 import pcg_track, amg_kd, TOLS
from lh import direct_solution

def blockjac(A):
    n = A.shape[0]; A = A.tocsr()
    blocks = np.zeros((n // 2, 2, 2))
    for i in range(2):
        for j in range(2):
            blocks[:, i, j] = A[i::2, :][:, j::2].diagonal()
    inv = np.linalg.inv(blocks)
    return sp.block_diag(list(inv), format='csr')

kind, ny = int(sys.argv[1]), int(sys.argv[2])
lhs = [int(v) for v in sys.argv[3].split(',')]
oms = [float(v) for v in sys.argv[4].split(',')]
for lh in lhs:
    P = Problem(lh, ny, kind); xs = direct_solution(P)
    Klu = spla.splu(P.Kdf); amg = amg_kd(P)
    J = blockjac(P.SLf)   # free dofs are (u,v) pairs per node in order
    for om in oms:
        for name, B in [('Kd^-1', Klu.solve), ('AMG', amg)]:
            prec = (lambda r, B=B, om=om: B(r) + om * (J @ r))
            R = pcg_track(P.S, P.b, prec, maxit=2000, stall=150, xref=xs, Kn=P.Kdf)
            f = lambda v: '-' if v is None else str(v)
            print(f"Q{kind} ny{ny} L/h={lh:5d} {name:6s}+{om:4.2f}*J(S_aL): its {f(R['its'][5e-3]):>4s} {f(R['its'][1e-4]):>4s} {f(R['its'][1e-8]):>4s} floor {R['floor']:.1e} | Kd-err its {f(R['eits'][5e-3]):>4s} {f(R['eits'][1e-4]):>4s} {f(R['eits'][1e-8]):>4s}", flush=True)
