"""FEM building blocks for the 2D Hellinger-Reissner equal-order Q1/Q1 prototype."""
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

E_, NU_ = 1.0, 0.3
CMAT = E_ / (1 - NU_**2) * np.array([[1, NU_, 0], [NU_, 1, 0], [0, 0, (1 - NU_) / 2]])
DMAT = np.linalg.inv(CMAT)
XIA = np.array([-1, 1, 1, -1.0])
ETA = np.array([-1, -1, 1, 1.0])


def mesh(nx, ny, L=4.0, H=1.0, distort=0.0, seed=12345):
    xs = np.linspace(0, L, nx + 1)
    ys = np.linspace(0, H, ny + 1)
    X, Y = np.meshgrid(xs, ys)  # node id = j*(nx+1)+i
    coords = np.c_[X.ravel(), Y.ravel()]
    I, J = np.meshgrid(np.arange(nx + 1), np.arange(ny + 1))
    I = I.ravel(); J = J.ravel()
    if distort > 0:
        rng = np.random.default_rng(seed)
        hx, hy = L / nx, H / ny
        interior = (I > 0) & (I < nx) & (J > 0) & (J < ny)
        d = rng.uniform(-1, 1, (coords.shape[0], 2)) * distort * np.array([hx, hy])
        coords[interior] += d[interior]
    ei, ej = np.meshgrid(np.arange(nx), np.arange(ny))
    ei = ei.ravel(); ej = ej.ravel()  # element e = j*nx + i
    n0 = ej * (nx + 1) + ei
    conn = np.c_[n0, n0 + 1, n0 + nx + 2, n0 + nx + 1]  # counter-clockwise
    return dict(coords=coords, conn=conn, ei=ei, ej=ej, nx=nx, ny=ny, nodeI=I, nodeJ=J, L=L)


def _shape(xi, eta):
    N = 0.25 * (1 + xi * XIA) * (1 + eta * ETA)
    dxi = 0.25 * XIA * (1 + eta * ETA)
    deta = 0.25 * ETA * (1 + xi * XIA)
    return N, dxi, deta


def _geo(xe, xi, eta):
    N, dxi, deta = _shape(xi, eta)
    J = np.empty((xe.shape[0], 2, 2))
    J[:, 0, :] = np.einsum('a,eak->ek', dxi, xe)
    J[:, 1, :] = np.einsum('a,eak->ek', deta, xe)
    det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
    Ji = np.empty_like(J)
    Ji[:, 0, 0] = J[:, 1, 1] / det; Ji[:, 1, 1] = J[:, 0, 0] / det
    Ji[:, 0, 1] = -J[:, 0, 1] / det; Ji[:, 1, 0] = -J[:, 1, 0] / det
    dN = np.einsum('eij,ja->eia', Ji, np.vstack([dxi, deta]))  # (ne,2,4): d/dx, d/dy
    ne = xe.shape[0]
    B = np.zeros((ne, 3, 8))
    B[:, 0, 0::2] = dN[:, 0]; B[:, 1, 1::2] = dN[:, 1]
    B[:, 2, 0::2] = dN[:, 1]; B[:, 2, 1::2] = dN[:, 0]
    return N, B, det


def element_matrices(m):
    xe = m['coords'][m['conn']]
    ne = xe.shape[0]
    g = 1 / np.sqrt(3)
    Ke = np.zeros((ne, 8, 8)); K12e = np.zeros((ne, 8, 12)); Me = np.zeros((ne, 12, 12))
    for xi, eta in [(-g, -g), (g, -g), (g, g), (-g, g)]:
        N, B, det = _geo(xe, xi, eta)
        Psi = np.zeros((3, 12))
        for a in range(4):
            Psi[:, 3 * a:3 * a + 3] = N[a] * np.eye(3)
        Ke += np.einsum('e,eki,kl,elj->eij', det, B, CMAT, B)
        K12e += np.einsum('e,eki,kj->eij', det, B, Psi)
        Me += np.einsum('e,ki,kl,lj->eij', det, Psi, DMAT, Psi)
    # one-point (centroid) quadrature stiffness
    N, B0, det0 = _geo(xe, 0.0, 0.0)
    K1e = np.einsum('e,eki,kl,elj->eij', 4 * det0, B0, CMAT, B0)
    return Ke, K12e, Me, K1e, B0, 4 * det0


def _assemble(Ae, rdofs, cdofs, shape):
    ne, r, c = Ae.shape
    rows = np.repeat(rdofs[:, :, None], c, axis=2)
    cols = np.repeat(cdofs[:, None, :], r, axis=1)
    return sp.coo_matrix((Ae.ravel(), (rows.ravel(), cols.ravel())), shape=shape).tocsr()


def assemble(m):
    conn = m['conn']
    nn = m['coords'].shape[0]
    ud = np.stack([2 * conn, 2 * conn + 1], axis=2).reshape(-1, 8)
    sd = np.stack([3 * conn, 3 * conn + 1, 3 * conn + 2], axis=2).reshape(-1, 12)
    Ke, K12e, Me, K1e, B0, A0 = element_matrices(m)
    Kd = _assemble(Ke, ud, ud, (2 * nn, 2 * nn))
    K12 = _assemble(K12e, ud, sd, (2 * nn, 3 * nn))
    M = _assemble(Me, sd, sd, (3 * nn, 3 * nn))
    K1 = _assemble(K1e, ud, ud, (2 * nn, 2 * nn))
    # nodal lumped mass m_a = int psi_a ; M_L = blockdiag(m_a D)  => M_L^{-1} = blockdiag(C/m_a)
    xe = m['coords'][conn]
    g = 1 / np.sqrt(3)
    mlump = np.zeros(nn)
    for xi, eta in [(-g, -g), (g, -g), (g, g), (-g, g)]:
        N, B, det = _geo(xe, xi, eta)
        np.add.at(mlump, conn, det[:, None] * N[None, :])
    MLinv = sp.kron(sp.diags(1.0 / mlump), sp.csr_matrix(CMAT)).tocsr()
    # free displacement dofs: clamp nodes at x=0
    fixed_nodes = np.where(np.abs(m['coords'][:, 0]) < 1e-12)[0]
    fixed = np.zeros(2 * nn, bool); fixed[2 * fixed_nodes] = True; fixed[2 * fixed_nodes + 1] = True
    free = np.where(~fixed)[0]
    # load: total (0,-1) on x = L, consistent for uniform traction
    f = np.zeros(2 * nn)
    rn = np.where(np.abs(m['coords'][:, 0] - m['L']) < 1e-12)[0]
    rn = rn[np.argsort(m['coords'][rn, 1])]
    for k in range(len(rn) - 1):
        h = m['coords'][rn[k + 1], 1] - m['coords'][rn[k], 1]
        f[2 * rn[k] + 1] -= 0.5 * h; f[2 * rn[k + 1] + 1] -= 0.5 * h
    return dict(Kd=Kd, K12=K12, M=M, K1=K1, MLinv=MLinv, free=free, f=f, ud=ud, B0=B0, A0=A0,
                mlump=mlump, nn=nn)


def hourglass_H(m, sign=True, ndof=None):
    """H: (2nn x 2ne). Column 2e+c: pattern (+1,-1,+1,-1) on element e's nodes in component c,
    multiplied by (-1)^(i+j) if sign."""
    conn = m['conn']; ne = conn.shape[0]; nn = m['coords'].shape[0]
    s = (-1.0) ** (m['ei'] + m['ej']) if sign else np.ones(ne)
    pat = np.array([1, -1, 1, -1.0])
    rows, cols, vals = [], [], []
    for c in range(2):
        rows.append((2 * conn + c).ravel())
        cols.append(np.repeat(2 * np.arange(ne) + c, 4))
        vals.append((s[:, None] * pat[None, :]).ravel())
    return sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(2 * nn, 2 * ne)).tocsr()


def aggregate_P(m, k):
    """Piecewise-constant prolongation from k x k element aggregates to element coefficients
    (2 per element: x and y hourglass)."""
    nx, ny = m['nx'], m['ny']
    ne = nx * ny
    ncx = (nx + k - 1) // k; ncy = (ny + k - 1) // k
    agg = (m['ej'] // k) * ncx + (m['ei'] // k)
    na = ncx * ncy
    rows = np.concatenate([2 * np.arange(ne), 2 * np.arange(ne) + 1])
    cols = np.concatenate([2 * agg, 2 * agg + 1])
    return sp.coo_matrix((np.ones(2 * ne), (rows, cols)), shape=(2 * ne, 2 * na)).tocsr()


class Problem:
    def __init__(self, nx, ny, a=0.05, distort=0.0):
        self.m = mesh(nx, ny, distort=distort)
        A = assemble(self.m)
        self.__dict__.update(A)
        self.a = a
        fr = self.free
        self.Kdf = self.Kd[fr][:, fr].tocsc()
        self.K1f = self.K1[fr][:, fr].tocsc()
        self.K12f = self.K12[fr].tocsr()
        self.K12fT = self.K12f.T.tocsr()
        self.Mlu = spla.splu(self.M.tocsc())
        self.SLf = (a * self.Kdf + (1 - a) * (self.K12f @ self.MLinv @ self.K12fT)).tocsc()
        self.b = self.f[fr]
        self.nS = 0  # count of S applications

    def S(self, u):
        self.nS += 1
        return self.a * (self.Kdf @ u) + (1 - self.a) * (self.K12f @ self.Mlu.solve(self.K12fT @ u))

    def S_dense(self):
        MiKt = self.Mlu.solve(self.K12fT.toarray())
        return self.a * self.Kdf.toarray() + (1 - self.a) * (self.K12f @ MiKt)

    def S_cols(self, V, block=512):
        """S_a @ V for a sparse/dense V with many columns (blocked)."""
        V = sp.csr_matrix(V)
        out = np.empty((V.shape[0], V.shape[1]))
        for s in range(0, V.shape[1], block):
            Vb = V[:, s:s + block]
            Y = self.K12fT @ Vb
            Y = self.Mlu.solve(np.asarray(Y.toarray()))
            out[:, s:s + block] = self.a * (self.Kdf @ Vb).toarray() + (1 - self.a) * (self.K12f @ Y)
        return out


def pcg(Aop, b, prec, tol=1e-8, maxit=2000):
    """Flexible (Polak-Ribiere) PCG; stop on ||r||_2/||b||_2 < tol, zero initial guess."""
    x = np.zeros_like(b); r = b.copy(); nb = np.linalg.norm(b)
    z = prec(r); p = z.copy(); rz = r @ z
    for k in range(1, maxit + 1):
        Ap = Aop(p)
        alpha = rz / (p @ Ap)
        x += alpha * p
        rold = r.copy()
        r -= alpha * Ap
        if np.linalg.norm(r) / nb < tol:
            return x, k
        z = prec(r)
        beta = (z @ (r - rold)) / rz
        rz = r @ z
        p = z + beta * p
    return x, -maxit
