"""GMRES(30)/GMRES(inf), right-preconditioned, on S_a with Kd^-1 / AMG(Kd); vs PCG (see lh.py)."""
import sys, os
import numpy as np, scipy.sparse.linalg as spla
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fem2 import Problem
from iters2 import gmres_track, amg_kd
from lh import direct_solution
kind, ny = int(sys.argv[1]), int(sys.argv[2])
for lh in [int(v) for v in sys.argv[3].split(',')]:
    P = Problem(lh, ny, kind); xs = direct_solution(P)
    Klu = spla.splu(P.Kdf); amg = amg_kd(P)
    for name, prec in [('Kd^-1', Klu.solve), ('AMG(Kd)', amg)]:
        for rs in [30, 300]:
            R = gmres_track(P.S, P.b, prec, restart=rs, maxit=600, xref=xs, Kn=P.Kdf)
            f = lambda v: '-' if v is None else str(v)
            print(f"Q{kind} ny{ny} L/h={lh:5d} GMRES({rs:3d}) {name:8s}: its {f(R['its'][5e-3]):>4s} {f(R['its'][1e-4]):>4s} {f(R['its'][1e-8]):>4s} floor(arnoldi) {R['floor']:.1e} true {R['true_final']:.1e} | Kd-err its {f(R['eits'][5e-3]):>4s} {f(R['eits'][1e-4]):>4s} {f(R['eits'][1e-8]):>4s}", flush=True)
