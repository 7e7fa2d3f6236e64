"""Which oscillation pattern do the small eigenvectors of Kd^-1 S_a carry?"""
import numpy as np, scipy.linalg as sla, scipy.sparse as sp
from fem import *
from spectrum import proj_frac, hg_energy_fraction
np.set_printoptions(precision=3, suppress=True, linewidth=160)

def modulated_space(P, mod, k):
    m = P.m; I, J = m['nodeI'], m['nodeJ']
    s = {'none': np.ones_like(I), 'x': (-1.0)**I, 'y': (-1.0)**J, 'xy': (-1.0)**(I+J)}[mod]
    ncx = m['nx']//k + 1
    agg = (J//k)*ncx + I//k
    na = agg.max()+1
    cols = []
    nn = P.nn
    rows = np.concatenate([2*np.arange(nn), 2*np.arange(nn)+1])
    cc = np.concatenate([2*agg, 2*agg+1]); vv = np.concatenate([s, s]).astype(float)
    V = sp.coo_matrix((vv, (rows, cc)), shape=(2*nn, 2*na)).tocsr()[P.free]
    V = V[:, np.asarray(abs(V).sum(0)).ravel() > 0]
    return V.toarray()

for nx, ny in [(32, 8), (64, 16)]:
    P = Problem(nx, ny, 0.05)
    Kd = P.Kdf.toarray(); S = P.S_dense()
    lam, X = sla.eigh(S, Kd, subset_by_index=[0, 9])
    print(f"mesh {nx}x{ny}, 10 smallest lam of Kd^-1 S_a:", lam)
    k = 4
    for mod in ['none', 'x', 'y', 'xy']:
        V = modulated_space(P, mod, k)
        print(f"  Kd-proj frac onto (-1)^{mod:4s} x (piecewise const on {k}x{k} node aggregates), dim {V.shape[1]:4d}:", proj_frac(Kd, V, X))
    V = np.hstack([modulated_space(P, mo, k) for mo in ['none', 'x', 'y', 'xy']])
    print("  ... onto all four together:", proj_frac(Kd, V, X))
    # element constant-strain alternation: correlation of centroid strains of x-neighbours and y-neighbours
    for kk in range(3):
        u = np.zeros(2*P.nn); u[P.free] = X[:, kk]
        eps = np.einsum('eij,ej->ei', P.B0, u[P.ud]).reshape(ny, nx, 3)
        cx = np.sum(eps[:, 1:]*eps[:, :-1])/np.sum(eps**2); cy = np.sum(eps[1:]*eps[:-1])/np.sum(eps**2)
        print(f"  eigvec {kk}: neighbour strain correlation x {cx:+.3f}, y {cy:+.3f}; centroid strain comps rms {np.sqrt((eps**2).mean((0,1)))}")
