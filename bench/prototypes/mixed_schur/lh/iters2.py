"""PCG with true-residual tracking; preconditioners E1 (Kd^-1), E2 (S_aL^-1), A1 (SA-AMG V-cycle on Kd),
A2 (A1 + exact coarse correction on piecewise rigid-body modes of 2x2-element aggregates), D (CG on Kd)."""
import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as spla, time
import os as _os, sys as _sys
_sys.path.insert(0, _os.path.dirname(_os.path.dirname(_os.path.abspath(__file__))))  # ../sa_amg.py
from sa_amg import SA

TOLS = (5e-3, 1e-4, 1e-8)


def pcg_track(Aop, b, prec, tols=TOLS, maxit=4000, stall=60, xref=None, Kn=None):
    """Standard PCG (Fletcher-Reeves beta; the preconditioners here are fixed SPD operators), zero
    initial guess. Each iteration the TRUE residual ||b - A x||/||b|| is computed (one extra A-apply).
    Returns dict: its[tol] = first iteration with true relres < tol (None if never), floor = min true
    relres, n = iterations run, rec = final recursive relres, hist (true relres per iteration)."""
    nb = np.linalg.norm(b)
    x = np.zeros_like(b); r = b.copy()
    z = prec(r); p = z.copy(); rz = r @ z
    its = {t: None for t in tols}; hist = []
    eits = {t: None for t in tols}; ehist = []
    zits = {t: None for t in tols}; rz0 = rz
    if xref is not None:
        nref = np.sqrt(xref @ (Kn @ xref))
    best = 1.0; best_it = 0
    for k in range(1, maxit + 1):
        Ap = Aop(p)
        pAp = p @ Ap
        if pAp <= 0:
            break
        alpha = rz / pAp
        x += alpha * p
        r -= alpha * Ap
        tr = np.linalg.norm(b - Aop(x)) / nb
        hist.append(tr)
        if xref is not None:
            e = x - xref; er = np.sqrt(abs(e @ (Kn @ e))) / nref; ehist.append(er)
            for t in tols:
                if eits[t] is None and er < t:
                    eits[t] = k
        for t in tols:
            if its[t] is None and tr < t:
                its[t] = k
        if tr < best * 0.9:
            best, best_it = tr, k
        best = min(best, tr)
        if (tr < min(tols) and (xref is None or ehist[-1] < min(tols))) or k - best_it > stall:
            break
        z = prec(r)
        rzn = r @ z
        for t in tols:   # preconditioned-residual criterion sqrt(r^T B r / b^T B b) (recursive r)
            if zits[t] is None and np.sqrt(abs(rzn / rz0)) < t:
                zits[t] = k
        p = z + (rzn / rz) * p
        rz = rzn
    return dict(its=its, floor=min(hist), n=k, rec=np.linalg.norm(r) / nb, hist=np.array(hist), x=x,
                eits=eits, ehist=np.array(ehist), efloor=min(ehist) if ehist else None, zits=zits)


def near_null_rbm(P):
    X = P.m['coords']; nn = P.nn
    B = np.zeros((2 * nn, 3))
    B[0::2, 0] = 1; B[1::2, 1] = 1
    xc = X - X.mean(0)
    B[0::2, 2] = -xc[:, 1]; B[1::2, 2] = xc[:, 0]
    Bf = B[P.free]
    _, blk = np.unique(P.free // 2, return_inverse=True)
    return Bf, blk


def amg_kd(P, max_coarse=300):
    B, blk = near_null_rbm(P)
    return SA(P.Kdf, B, blk, theta=0.0, max_coarse=max_coarse)


def rbm_coarse_P(P, k=2):
    """Piecewise rigid-body modes on aggregates of k x k elements (nodes assigned to the aggregate of
    the element with the smallest index containing them). Columns per aggregate: u, v, rotation."""
    m = P.m; conn = m['conn']; nx, ny = m['nx'], m['ny']
    ne = conn.shape[0]; ei = np.arange(ne) % nx; ej = np.arange(ne) // nx
    ncx = (nx + k - 1) // k
    agg_e = (ej // k) * ncx + ei // k
    node_agg = np.full(P.nn, 10**9)
    for c in range(conn.shape[1]):
        np.minimum.at(node_agg, conn[:, c], agg_e)
    _, node_agg = np.unique(node_agg, return_inverse=True)
    na = node_agg.max() + 1
    X = m['coords']
    cen = np.zeros((na, 2)); cnt = np.bincount(node_agg, minlength=na)
    for d in range(2):
        cen[:, d] = np.bincount(node_agg, X[:, d], minlength=na) / cnt
    xc = X - cen[node_agg]
    nn = P.nn
    rows = np.r_[2 * np.arange(nn), 2 * np.arange(nn) + 1, 2 * np.arange(nn), 2 * np.arange(nn) + 1]
    cols = np.r_[3 * node_agg, 3 * node_agg + 1, 3 * node_agg + 2, 3 * node_agg + 2]
    vals = np.r_[np.ones(nn), np.ones(nn), -xc[:, 1], xc[:, 0]]
    Pc = sp.csr_matrix((vals, (rows, cols)), shape=(2 * nn, 3 * na))[P.free]
    Pc = Pc[:, np.asarray(abs(Pc).sum(0)).ravel() > 0]
    return Pc.tocsc()


def two_level_mult(A, V, Pc):
    """Symmetric multiplicative: coarse (exact on Pc^T A Pc), V-cycle, coarse."""
    Ac = (Pc.T @ A @ Pc).tocsc()
    clu = spla.splu(Ac)
    def cc(r):
        return Pc @ clu.solve(Pc.T @ r)
    def prec(r):
        x = cc(r)
        x = x + V(r - A @ x)
        return x + cc(r - A @ x)
    return prec


def gmres_track(Aop, b, prec, restart=30, tols=TOLS, maxit=3000, xref=None, Kn=None, stall=150):
    """Right-preconditioned restarted GMRES(restart) from zero (the Krylov method and preconditioning side of
    mixcon's block-triangular method, with the Schur block only). Residual = ||b - A x||/||b|| from the
    Arnoldi least-squares problem per iteration; true residual recomputed at every restart and at the end.
    Returns iterations to each tolerance (by the Arnoldi residual), the final true residual and Kd-error its."""
    nb = np.linalg.norm(b); n = len(b)
    x = np.zeros(n); its = {t: None for t in tols}; eits = {t: None for t in tols}
    k = 0; hist = []; ehist = []; best = 1.0; best_it = 0
    if xref is not None:
        nref = np.sqrt(xref @ (Kn @ xref))
    while k < maxit:
        r = b - Aop(x); beta = np.linalg.norm(r)
        hist_true = beta / nb
        V = np.zeros((restart + 1, n)); Z = np.zeros((restart, n)); Hm = np.zeros((restart + 1, restart))
        V[0] = r / beta
        for j in range(restart):
            Z[j] = prec(V[j]); w = Aop(Z[j])
            for i in range(j + 1):
                Hm[i, j] = w @ V[i]; w -= Hm[i, j] * V[i]
            for i in range(j + 1):  # reorthogonalize
                h = w @ V[i]; Hm[i, j] += h; w -= h * V[i]
            Hm[j + 1, j] = np.linalg.norm(w)
            if Hm[j + 1, j] > 0:
                V[j + 1] = w / Hm[j + 1, j]
            e1 = np.zeros(j + 2); e1[0] = beta
            y, *_ = np.linalg.lstsq(Hm[:j + 2, :j + 1], e1, rcond=None)
            res = np.linalg.norm(e1 - Hm[:j + 2, :j + 1] @ y) / nb
            k += 1; hist.append(res)
            xk = x + Z[:j + 1].T @ y
            if xref is not None:
                e = xk - xref; er = np.sqrt(abs(e @ (Kn @ e))) / nref; ehist.append(er)
                for t in tols:
                    if eits[t] is None and er < t:
                        eits[t] = k
            for t in tols:
                if its[t] is None and res < t:
                    its[t] = k
            if res < best * 0.9:
                best, best_it = res, k
            if res < min(tols) or k >= maxit or k - best_it > stall or Hm[j + 1, j] == 0:
                break
        x = xk
        if res < min(tols) or k - best_it > stall or k >= maxit:
            break
    true = np.linalg.norm(b - Aop(x)) / nb
    return dict(its=its, eits=eits, n=k, floor=min(hist), true_final=true, hist=np.array(hist), x=x)
