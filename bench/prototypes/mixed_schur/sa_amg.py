"""Minimal smoothed-aggregation AMG (own implementation; pyamg is not installable here).
Node-blocked strength (block Frobenius norms), standard greedy aggregation, tentative P from the
near-null-space vectors (QR per aggregate), one damped-Jacobi prolongator smoothing step (omega=4/3/rho),
Galerkin coarse operators, V(1,1) cycle with symmetric Gauss-Seidel (forward pre / backward post)."""
import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as spla

def _strength(A, blk, theta):
    nb = blk.max()+1
    Pb = sp.csr_matrix((np.ones(len(blk)), (np.arange(len(blk)), blk)), shape=(len(blk), nb))
    A2 = A.multiply(A)
    G = (Pb.T @ A2 @ Pb).tocsr(); G.data = np.sqrt(G.data)
    d = G.diagonal()
    G = G.tocoo()
    keep = (G.row != G.col) & (G.data >= theta*np.sqrt(d[G.row]*d[G.col]))
    return sp.csr_matrix((np.ones(keep.sum()), (G.row[keep], G.col[keep])), shape=G.shape)

def _aggregate(C):
    n = C.shape[0]; agg = -np.ones(n, int); na = 0
    ip, ix = C.indptr, C.indices
    for i in range(n):
        if agg[i] >= 0: continue
        nb = ix[ip[i]:ip[i+1]]
        if np.all(agg[nb] < 0):
            agg[i] = na; agg[nb] = na; na += 1
    for i in range(n):
        if agg[i] >= 0: continue
        nb = ix[ip[i]:ip[i+1]]; a = agg[nb]; a = a[a >= 0]
        if len(a): agg[i] = a[0]
        else: agg[i] = na; na += 1
    return agg, na

def _tentative(B, blk, agg_of_blk):
    dof_agg = agg_of_blk[blk]
    order = np.argsort(dof_agg, kind='stable')
    bounds = np.searchsorted(dof_agg[order], np.arange(dof_agg.max()+2))
    rows, cols, vals, Bc, cblk = [], [], [], [], []
    nc = 0
    for g in range(len(bounds)-1):
        idx = order[bounds[g]:bounds[g+1]]
        Q, R = np.linalg.qr(B[idx], mode='reduced')
        # rank truncation
        dr = np.abs(np.diag(R)); r = np.sum(dr > 1e-10*max(dr.max(), 1e-300))
        if r < R.shape[0]:
            U, s, Vt = np.linalg.svd(B[idx], full_matrices=False)
            r = np.sum(s > 1e-10*s[0]); Q = U[:, :r]; R = Q.T @ B[idx]
        else:
            Q, R = Q[:, :r], R[:r]
        rows.append(np.repeat(idx, r)); cols.append(np.tile(np.arange(nc, nc+r), len(idx))); vals.append(Q.ravel())
        Bc.append(R); cblk.append(np.full(r, g)); nc += r
    T = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(B.shape[0], nc))
    return T, np.vstack(Bc), np.concatenate(cblk)

def _rho(DA, it=15):
    x = np.random.default_rng(1).standard_normal(DA.shape[0])
    for _ in range(it):
        y = DA @ x; lam = np.linalg.norm(y)/np.linalg.norm(x); x = y/np.linalg.norm(y)
    return lam*1.05

class SA:
    def __init__(self, A, B, blk, theta=0.0, max_coarse=300, max_levels=12):
        self.levels = []
        A = sp.csr_matrix(A)
        while A.shape[0] > max_coarse and len(self.levels) < max_levels:
            C = _strength(A, blk, theta)
            agg, na = _aggregate(C)
            T, Bc, cblk = _tentative(B, blk, agg)
            if T.shape[1] >= A.shape[0]*0.9: break
            Dinv = 1.0/A.diagonal()
            DA = sp.diags(Dinv) @ A
            w = 4.0/3.0/_rho(DA)
            P = (T - w*(DA @ T)).tocsr()
            L = sp.tril(A, 0, format='csc'); U = sp.triu(A, 0, format='csc')
            lvl = dict(A=A, P=P, Llu=spla.splu(L, permc_spec='NATURAL', diag_pivot_thresh=0.0),
                       Ulu=spla.splu(U, permc_spec='NATURAL', diag_pivot_thresh=0.0))
            self.levels.append(lvl)
            A = (P.T @ A @ P).tocsr(); A = 0.5*(A+A.T); B = Bc; blk = cblk
        self.Ac = A
        self.clu = spla.splu(sp.csc_matrix(A))
        self.opc = (sum(l['A'].nnz for l in self.levels) + A.nnz)/self.levels[0]['A'].nnz if self.levels else 1.0
        self.sizes = [l['A'].shape[0] for l in self.levels] + [A.shape[0]]

    def _vcycle(self, l, b):
        if l == len(self.levels): return self.clu.solve(b)
        L = self.levels[l]; A = L['A']
        x = L['Llu'].solve(b)                      # forward GS from 0
        r = b - A @ x
        x += L['P'] @ self._vcycle(l+1, L['P'].T @ r)
        x += L['Ulu'].solve(b - A @ x)             # backward GS
        return x

    def __call__(self, b):
        return self._vcycle(0, b)

def near_null(P, zigzag=()):
    """rigid body modes on the free dofs (+ optional oscillatory 'zigzag' fields (-1)^I, (-1)^J, (-1)^(I+J) per component)."""
    X = P.m['coords']; nn = P.nn
    vecs = []
    e0 = np.zeros(2*nn); e0[0::2] = 1; vecs.append(e0)
    e1 = np.zeros(2*nn); e1[1::2] = 1; vecs.append(e1)
    r = np.zeros(2*nn); r[0::2] = -X[:, 1]; r[1::2] = X[:, 0]; vecs.append(r)
    I, J = P.m['nodeI'], P.m['nodeJ']
    for z in zigzag:
        s = {'x': (-1.0)**I, 'y': (-1.0)**J, 'xy': (-1.0)**(I+J)}[z]
        for c in range(2):
            v = np.zeros(2*nn); v[c::2] = s; vecs.append(v)
    B = np.array(vecs).T[P.free]
    blk = P.free//2
    _, blk = np.unique(blk, return_inverse=True)
    return B, blk
