import numpy as np, scipy.linalg as sla, scipy.sparse as sp
from fem import *
np.set_printoptions(precision=4, suppress=True, linewidth=150)

def hg_energy_fraction(P, X):
    """fraction of Kd-energy in element hourglass (non-constant-strain) modes: 1 - sum_e A_e (B0 u_e)^T C (B0 u_e) / u^T Kd u"""
    out = []
    for k in range(X.shape[1]):
        u = np.zeros(2*P.nn); u[P.free] = X[:, k]
        ue = u[P.ud]                       # ne x 8
        eps0 = np.einsum('eij,ej->ei', P.B0, ue)
        e1 = np.sum(P.A0*np.einsum('ei,ij,ej->e', eps0, CMAT, eps0))
        out.append(1 - e1/(u@(P.Kd@u)))
    return np.array(out)

def proj_frac(Kd, V, X):
    """||P_V x||_Kd/||x||_Kd with P_V Kd-orthogonal projector onto span(V) (pinv for safety)."""
    G = V.T@Kd@V
    c = np.linalg.lstsq(G, V.T@(Kd@X), rcond=1e-12)[0]
    PX = V@c
    return np.sqrt(np.einsum('ik,ik->k', PX, Kd@PX)/np.einsum('ik,ik->k', X, Kd@X))

for (nx, ny) in [(16,4),(32,8),(64,16)]:
    P = Problem(nx, ny, a=0.05)
    Kd = P.Kdf.toarray(); fr = P.free
    S0 = P.S_dense(); Q = (S0 - 0.05*Kd)/0.95    # K12 M^-1 K12^T
    K1 = P.K1f.toarray()
    H = hourglass_H(P.m, True)[fr].toarray()
    sv = np.linalg.svd(H, compute_uv=False)
    print(f"\n=== mesh {nx}x{ny}: ndof {Kd.shape[0]}, H {H.shape}, rank(H)={np.sum(sv>1e-10*sv[0])}, sv min/max {sv.min():.3e}/{sv.max():.3e}")
    for a in [0.05, 0.0]:
        S = a*Kd + (1-a)*Q
        lam, X = sla.eigh(S, Kd)
        n = len(lam)
        print(f"-- a={a}: lambda(Kd^-1 S_a) min {lam.min():.4e} max {lam.max():.6f}; "
              f"#<a+0.01:{np.sum(lam<a+0.01)} #<0.1:{np.sum(lam<0.1)} #<0.2:{np.sum(lam<0.2)} #<0.5:{np.sum(lam<0.5)} #>0.9:{np.sum(lam>0.9)} of {n}")
        hist, edges = np.histogram(lam, bins=[0,0.01,0.05,0.06,0.1,0.2,0.3,0.5,0.7,0.9,0.99,1.0000001])
        print("   histogram bins", edges.round(3).tolist()); print("   counts       ", hist.tolist())
        if nx <= 32:
            sm = X[:, :10]; lg = X[:, -10:]
            print("   10 smallest lam:", lam[:10])
            print("   P_H frac (smallest):", proj_frac(Kd, H, sm))
            print("   P_H frac (largest): ", proj_frac(Kd, H, lg))
            rnd = np.random.default_rng(0).standard_normal((Kd.shape[0], 5))
            print("   P_H frac (random):  ", proj_frac(Kd, H, rnd))
            for k in [2, 4]:
                HP = (hourglass_H(P.m, True)@aggregate_P(P.m, k))[fr].toarray()
                HPn = (hourglass_H(P.m, False)@aggregate_P(P.m, k))[fr].toarray()
                print(f"   P_(H P_{k}) frac, {HP.shape[1]} cols (smallest):", proj_frac(Kd, HP, sm), " largest mean", proj_frac(Kd, HP, lg).mean().round(3))
                print(f"   same without checkerboard sign (smallest):     ", proj_frac(Kd, HPn, sm))
            print("   hourglass energy fraction (smallest):", hg_energy_fraction(P, sm))
            print("   hourglass energy fraction (largest): ", hg_energy_fraction(P, lg))
            # fraction of spectrum with hourglass energy > 0.5
            hf = hg_energy_fraction(P, X)
            for thr in [0.1, 0.2, 0.5]:
                sel = lam < thr
                print(f"   eigvecs with lam<{thr}: mean hourglass-energy frac {hf[sel].mean():.3f}; lam>=0.5: {hf[lam>=0.5].mean():.3f}")
    # other preconditioned spectra, a=0.05
    S = P.S_dense(); SL = P.SLf.toarray()
    Kst = 0.05*Kd + 0.95*K1
    for name, Pm in [("S_aL", SL), ("Kstab=aKd+(1-a)K1pt", Kst)]:
        lam = sla.eigh(S, Pm, eigvals_only=True)
        print(f"-- lambda(({name})^-1 S_a): min {lam.min():.4f} max {lam.max():.4f} kappa {lam.max()/lam.min():.2f}")
    lam = sla.eigh(Kd, Kst, eigvals_only=True)  # how far is Kstab from Kd
    print(f"-- lambda(Kstab^-1 Kd): min {lam.min():.4f} max {lam.max():.4f}")
