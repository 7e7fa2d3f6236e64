"""Dense generalized eigenvalues of (S_a, Kd), (S_a, S_aL) and of the AMG-preconditioned operators, for
small L/h. Usage: /usr/bin/python3 eig.py kind ny lh [lh ...]"""
import sys, os, time
import numpy as np, scipy.linalg as sla
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fem2 import Problem
from iters2 import amg_kd


def top_edge(P):
    X = P.m['coords']; nn = P.nn
    top = np.where(np.abs(X[:, 1] - 1) < 1e-12)[0]
    top = top[np.argsort(X[top, 0])]
    top = top[X[top, 0] > 0]
    full_idx = -np.ones(2 * nn, int); full_idx[P.free] = np.arange(len(P.free))
    return full_idx[2 * top], full_idx[2 * top + 1]


def sign_changes(v, rel=1e-3):
    v = v[np.abs(v) > rel * np.abs(v).max()]
    return int(np.sum(np.sign(v[1:]) != np.sign(v[:-1])))


def describe(P, K, X, lam, idx, Phi, tu, tv):
    """For eigenvectors X[:, idx]: sign changes of u, v along the top edge and the Kd-energy share in
    span(Phi) (Phi: Kd-orthonormal lowest vibration modes)."""
    out = []
    for i in idx:
        x = X[:, i]
        KxN = x @ (K @ x)
        c = Phi.T @ (K @ x)
        share = float(c @ c / KxN)
        out.append(f"lam={lam[i]:.4f} sc(u_top)={sign_changes(x[tu])} sc(v_top)={sign_changes(x[tv])} "
                   f"share(low {Phi.shape[1]} beam modes)={share:.3f}")
    return out


def main(kind, ny, lhs, nmodes=10):
    for lh in lhs:
        t = time.time()
        P = Problem(lh, ny, kind)
        n = len(P.free)
        K = P.Kdf.toarray(); S = P.S_dense(); SL = P.SLf.toarray(); SL = 0.5 * (SL + SL.T)
        tu, tv = top_edge(P)
        # lowest vibration modes of the clamped beam: Kd phi = w^2 m phi, m = lumped scalar mass per dof
        mass = np.repeat(P.mlump, 2)[P.free]
        w2, Phi = sla.eigh(K, np.diag(mass), subset_by_index=[0, nmodes - 1])
        Phi = Phi / np.sqrt(np.einsum('ij,ij->j', Phi, K @ Phi))
        print(f"== Quad{kind} ny={ny} L/h={lh}: ndof {n}; lowest beam modes: sign changes of v_top "
              f"{[sign_changes(Phi[tv, j]) for j in range(nmodes)]}, of u_top {[sign_changes(Phi[tu, j]) for j in range(nmodes)]}", flush=True)
        for name, Bm in [('S_a vs Kd', K), ('S_a vs S_aL', SL)]:
            lam, X = sla.eigh(S, Bm)
            print(f"  [{name}] lam_min {lam[0]:.4f}  lam_max {lam[-1]:.4f}  kappa {lam[-1]/lam[0]:.2f}  "
                  f"#<0.1 {np.sum(lam<0.1)}  #<0.2 {np.sum(lam<0.2)}  #<0.5 {np.sum(lam<0.5)}  #>0.99 {np.sum(lam>0.99)}", flush=True)
            for s in describe(P, K, X, lam, [0, 1, 2, 3, 4], Phi, tu, tv):
                print('     low : ' + s)
            for s in describe(P, K, X, lam, [n - 1, n - 2, n - 3], Phi, tu, tv):
                print('     high: ' + s)
            # which eigenpairs carry the beam modes? Kd-weighted mean of lam over the lowest beam modes
            C = X.T @ (Bm @ Phi)  # coefficients of Phi in the B-orthonormal eigenbasis
            w = C**2 / np.sum(C**2, axis=0)
            print('     Rayleigh quotients lam(phi_j) of the 10 lowest beam modes: ' +
                  ' '.join(f"{(Phi[:, j] @ S @ Phi[:, j]) / (Phi[:, j] @ Bm @ Phi[:, j]):.4f}" for j in range(nmodes)), flush=True)
        # AMG-preconditioned spectra
        amg = amg_kd(P)
        Bv = amg(np.eye(n)); Bv = 0.5 * (Bv + Bv.T)
        Lk = np.linalg.cholesky(K); Ls = np.linalg.cholesky(S)
        for name, Lc in [('AMG*Kd', Lk), ('AMG*S_a', Ls)]:
            lam, X = np.linalg.eigh(Lc.T @ Bv @ Lc)
            # eigvecs of B A: y = B^{-1}... here A-orthonormal ones are x = L^-T z
            Xs = sla.solve_triangular(Lc.T, X, lower=False)
            print(f"  [{name}] lam_min {lam[0]:.4g} lam_max {lam[-1]:.4g} kappa {lam[-1]/lam[0]:.1f}  "
                  f"#<0.1*max {np.sum(lam < 0.1*lam[-1])}  #<0.01*max {np.sum(lam < 0.01*lam[-1])}", flush=True)
            for s in describe(P, K, Xs, lam, [0, 1, 2, 3], Phi, tu, tv):
                print('     low : ' + s)
        print(f"  ({time.time()-t:.1f}s)", flush=True)


if __name__ == '__main__':
    kind, ny = int(sys.argv[1]), int(sys.argv[2])
    main(kind, ny, [int(v) for v in sys.argv[3:]] or [10, 30, 100])
