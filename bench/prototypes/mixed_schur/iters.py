import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as spla, scipy.linalg as sla, time, sys
from fem import *

def two_level_add(P, Kinv, Hf, Cfac):
    def prec(r):
        return Kinv(r) + Hf @ sla.cho_solve(Cfac, Hf.T @ r) if isinstance(Cfac, tuple) else Kinv(r) + Hf @ Cfac(Hf.T @ r)
    return prec

def coarse_solver(C):
    if sp.issparse(C):
        lu = spla.splu(sp.csc_matrix(C)); return lu.solve
    f = sla.cho_factor(C); return lambda x: sla.cho_solve(f, x)

def run(nx, ny, a, distort=0.0, which=None, exact_max_ne=4096):
    P = Problem(nx, ny, a=a, distort=distort)
    fr = P.free; ne = nx*ny
    Klu = spla.splu(P.Kdf); Kinv = Klu.solve
    SLlu = spla.splu(P.SLf); SLinv = SLlu.solve
    res = {}
    def go(name, prec):
        if which and name not in which: return
        P.nS = 0; t = time.time()
        x, it = pcg(P.S, P.b, prec)
        res[name] = (it, P.nS, time.time()-t)
    # reference: displacement model CG on Kd with exact Kd^-1 is trivially 1 iteration; report P0
    go('P0 Kd^-1', Kinv)
    go('P1 S_aL^-1', SLinv)
    for sign in [True, False]:
        tag = '' if sign else ' nosign'
        H = hourglass_H(P.m, sign)[fr].tocsc()
        # H^T S_aL H (sparse)
        CL = (H.T @ P.SLf @ H).tocsc()
        cL = coarse_solver(CL)
        go('P2 add H(HtSLH)' + tag, lambda r: Kinv(r) + H @ cL(H.T @ r))
        def mult(cs, H=H):
            def prec(r):
                x = Kinv(r)
                x = x + H @ cs(H.T @ (r - P.S(x)))
                return x + Kinv(r - P.S(x))
            return prec
        go('P2 mult H(HtSLH)' + tag, mult(cL))
        if ne <= exact_max_ne:
            SH = P.S_cols(H)
            CE = H.T @ SH; CE = 0.5*(CE+CE.T)
            cE = coarse_solver(CE)
            go('P2 add H(HtSH) exact' + tag, lambda r: Kinv(r) + H @ cE(H.T @ r))
            go('P2 mult H(HtSH) exact' + tag, mult(cE))
        for k in [2, 4]:
            HP = (hourglass_H(P.m, sign) @ aggregate_P(P.m, k))[fr].tocsc()
            SH = P.S_cols(HP); CE = HP.T @ SH; CE = 0.5*(CE+CE.T)
            cE = coarse_solver(CE)
            go(f'P2c add HP{k}(exact S)' + tag, lambda r: Kinv(r) + HP @ cE(HP.T @ r))
            go(f'P2c mult HP{k}(exact S)' + tag, mult(cE, HP))
    return P, res

if __name__ == '__main__':
    import os
    meshes = [(16,4),(32,8),(64,16),(128,32),(256,64)][:int(os.environ.get("NMESH", 4))]
    a = float(sys.argv[1]) if len(sys.argv) > 1 else 0.05
    allres = {}
    for nx, ny in meshes:
        t = time.time()
        P, res = run(nx, ny, a)
        allres[(nx,ny)] = res
        print(f"mesh {nx}x{ny} ndof {len(P.free)} ({time.time()-t:.1f}s)", flush=True)
        for k, v in res.items(): print(f"   {k:32s} it {v[0]:5d}  S-applies {v[1]:5d}  {v[2]:.1f}s", flush=True)
