"""GMRES on S_a at given L/h with Kd^-1, AMG(Kd), AMG(Kd)+RBM 2x2 coarse (A2)."""
import sys, os
import numpy as np, scipy.sparse.linalg as spla
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fem2 import Problem
from iters2 import gmres_track, amg_kd, rbm_coarse_P, two_level_mult
from lh import direct_solution
kind, ny = int(sys.argv[1]), int(sys.argv[2])
for lh in [int(v) for v in sys.argv[3].split(',')]:
    P = Problem(lh, ny, kind); xs = direct_solution(P)
    Klu = spla.splu(P.Kdf); amg = amg_kd(P); A2 = two_level_mult(P.Kdf, amg, rbm_coarse_P(P, 2))
    for name, prec in [('Kd^-1', Klu.solve), ('AMG(Kd)', amg), ('A2', A2)]:
        for rs in [30, 300]:
            if name == 'Kd^-1' and rs == 300: continue
            R = gmres_track(P.S, P.b, prec, restart=rs, maxit=450, xref=xs, Kn=P.Kdf)
            f = lambda v: '-' if v is None else str(v)
            print(f"Q{kind} ny{ny} L/h={lh:5d} GMRES({rs:3d}) {name:8s}: its {f(R['its'][5e-3]):>4s} {f(R['its'][1e-4]):>4s} {f(R['its'][1e-8]):>4s} floor(arnoldi) {R['floor']:.1e} true {R['true_final']:.1e} | Kd-err its {f(R['eits'][5e-3]):>4s} {f(R['eits'][1e-4]):>4s} {f(R['eits'][1e-8]):>4s}", flush=True)
