"""2D Hellinger-Reissner equal-order (u, sigma) model on a clamped strip L x 1, Quad4 (2x2 Gauss) or
Quad8 serendipity (3x3 Gauss). Plane stress, nu = 0.3, thickness 1.
Kd = sum int B^T C B ; K12 = sum int B^T Psi ; M = sum int Psi^T D Psi (consistent), D = C^-1.
S_a = a Kd + (1-a) K12 M^-1 K12^T ; S_a,L with lumped M_L = blockdiag(m_a D)
(Quad4: row sums; Quad8: HRZ lumping)."""
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

NU_ = 0.3


def cmat(E):
    return E / (1 - NU_**2) * np.array([[1, NU_, 0], [NU_, 1, 0], [0, 0, (1 - NU_) / 2]])


# ---------------------------------------------------------------- shape functions
Q4_XI = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1.0]])
Q8_XI = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1], [0, -1], [1, 0], [0, 1], [-1, 0.0]])


def shape(kind, xi, eta):
    if kind == 4:
        a, b = Q4_XI[:, 0], Q4_XI[:, 1]
        N = 0.25 * (1 + xi * a) * (1 + eta * b)
        dxi = 0.25 * a * (1 + eta * b)
        deta = 0.25 * b * (1 + xi * a)
        return N, dxi, deta
    a, b = Q8_XI[:, 0], Q8_XI[:, 1]
    N = np.zeros(8); dxi = np.zeros(8); deta = np.zeros(8)
    for k in range(8):
        if k < 4:
            N[k] = 0.25 * (1 + xi * a[k]) * (1 + eta * b[k]) * (xi * a[k] + eta * b[k] - 1)
            dxi[k] = 0.25 * a[k] * (1 + eta * b[k]) * (2 * xi * a[k] + eta * b[k])
            deta[k] = 0.25 * b[k] * (1 + xi * a[k]) * (xi * a[k] + 2 * eta * b[k])
        elif a[k] == 0:
            N[k] = 0.5 * (1 - xi**2) * (1 + eta * b[k])
            dxi[k] = -xi * (1 + eta * b[k])
            deta[k] = 0.5 * (1 - xi**2) * b[k]
        else:
            N[k] = 0.5 * (1 + xi * a[k]) * (1 - eta**2)
            dxi[k] = 0.5 * a[k] * (1 - eta**2)
            deta[k] = -eta * (1 + xi * a[k])
    return N, dxi, deta


def gauss(kind):
    if kind == 4:
        g = np.array([-1, 1]) / np.sqrt(3); w = np.array([1.0, 1.0])
    else:
        g = np.array([-np.sqrt(0.6), 0, np.sqrt(0.6)]); w = np.array([5, 8, 5]) / 9.0
    return [(g[i], g[j], w[i] * w[j]) for i in range(len(g)) for j in range(len(g))]


# ---------------------------------------------------------------- mesh
def strip_mesh(lh, ny, kind):
    """Strip [0, lh] x [0, 1], square elements: nx = lh*ny along, ny through the depth."""
    nx = int(round(lh * ny))
    if kind == 4:
        gx, gy = nx + 1, ny + 1
        X, Y = np.meshgrid(np.linspace(0, lh, gx), np.linspace(0, 1, gy))  # [J, I]
        I, J = np.meshgrid(np.arange(gx), np.arange(gy))
        nid = np.arange(gx * gy).reshape(gy, gx)
        coords = np.c_[X.ravel(), Y.ravel()]
        ei, ej = np.meshgrid(np.arange(nx), np.arange(ny)); ei = ei.ravel(); ej = ej.ravel()
        conn = np.c_[nid[ej, ei], nid[ej, ei + 1], nid[ej + 1, ei + 1], nid[ej + 1, ei]]
        return dict(coords=coords, conn=conn, nx=nx, ny=ny, kind=4, L=lh,
                    gI=I.ravel(), gJ=J.ravel())
    gx, gy = 2 * nx + 1, 2 * ny + 1
    I, J = np.meshgrid(np.arange(gx), np.arange(gy))
    keep = ~((I % 2 == 1) & (J % 2 == 1))
    nid = -np.ones((gy, gx), int)
    nid[keep] = np.arange(keep.sum())
    coords = np.c_[(I[keep] / (2 * nx)) * lh, J[keep] / (2 * ny)]
    ei, ej = np.meshgrid(np.arange(nx), np.arange(ny)); ei = ei.ravel(); ej = ej.ravel()
    i0, j0 = 2 * ei, 2 * ej
    conn = np.c_[nid[j0, i0], nid[j0, i0 + 2], nid[j0 + 2, i0 + 2], nid[j0 + 2, i0],
                 nid[j0, i0 + 1], nid[j0 + 1, i0 + 2], nid[j0 + 2, i0 + 1], nid[j0 + 1, i0]]
    return dict(coords=coords, conn=conn, nx=nx, ny=ny, kind=8, L=lh, gI=I[keep], gJ=J[keep])


def _assemble(Ae, rdofs, cdofs, shape_):
    ne, r, c = Ae.shape
    rows = np.repeat(rdofs[:, :, None], c, axis=2)
    cols = np.repeat(cdofs[:, None, :], r, axis=1)
    return sp.coo_matrix((Ae.ravel(), (rows.ravel(), cols.ravel())), shape=shape_).tocsr()


def assemble(m, E=1e4, traction=(0.0, -1e-3)):
    C = cmat(E); D = np.linalg.inv(C)
    kind = m['kind']; conn = m['conn']; nen = conn.shape[1]
    xe = m['coords'][conn]; ne = xe.shape[0]; nn = m['coords'].shape[0]
    Ke = np.zeros((ne, 2 * nen, 2 * nen)); K12e = np.zeros((ne, 2 * nen, 3 * nen))
    Me = np.zeros((ne, 3 * nen, 3 * nen)); me = np.zeros((ne, nen, nen))
    for xi, eta, w in gauss(kind):
        N, dxi, deta = shape(kind, xi, eta)
        Jm = np.empty((ne, 2, 2))
        Jm[:, 0, :] = np.einsum('a,eak->ek', dxi, xe)
        Jm[:, 1, :] = np.einsum('a,eak->ek', deta, xe)
        det = Jm[:, 0, 0] * Jm[:, 1, 1] - Jm[:, 0, 1] * Jm[:, 1, 0]
        Ji = np.empty_like(Jm)
        Ji[:, 0, 0] = Jm[:, 1, 1] / det; Ji[:, 1, 1] = Jm[:, 0, 0] / det
        Ji[:, 0, 1] = -Jm[:, 0, 1] / det; Ji[:, 1, 0] = -Jm[:, 1, 0] / det
        dN = np.einsum('eij,ja->eia', Ji, np.vstack([dxi, deta]))
        B = np.zeros((ne, 3, 2 * nen))
        B[:, 0, 0::2] = dN[:, 0]; B[:, 1, 1::2] = dN[:, 1]
        B[:, 2, 0::2] = dN[:, 1]; B[:, 2, 1::2] = dN[:, 0]
        Psi = np.kron(N[None, :], np.eye(3))  # 3 x 3nen
        dw = det * w
        Ke += np.einsum('e,eki,kl,elj->eij', dw, B, C, B)
        K12e += np.einsum('e,eki,kj->eij', dw, B, Psi)
        Me += np.einsum('e,ki,kl,lj->eij', dw, Psi, D, Psi)
        me += dw[:, None, None] * np.outer(N, N)[None]
    ud = np.stack([2 * conn, 2 * conn + 1], axis=2).reshape(ne, -1)
    sd = np.stack([3 * conn, 3 * conn + 1, 3 * conn + 2], axis=2).reshape(ne, -1)
    Kd = _assemble(Ke, ud, ud, (2 * nn, 2 * nn))
    K12 = _assemble(K12e, ud, sd, (2 * nn, 3 * nn))
    M = _assemble(Me, sd, sd, (3 * nn, 3 * nn))
    # lumping
    if kind == 4:
        mle = me.sum(axis=2)
    else:  # HRZ
        dg = np.einsum('eaa->ea', me)
        mle = dg * (me.sum(axis=(1, 2)) / dg.sum(axis=1))[:, None]
    mlump = np.zeros(nn); np.add.at(mlump, conn, mle)
    MLinv = sp.kron(sp.diags(1.0 / mlump), sp.csr_matrix(C)).tocsr()
    # BCs: clamp x = 0
    X = m['coords']
    fixed_nodes = np.where(np.abs(X[:, 0]) < 1e-12)[0]
    fixed = np.zeros(2 * nn, bool); fixed[2 * fixed_nodes] = True; fixed[2 * fixed_nodes + 1] = True
    free = np.where(~fixed)[0]
    # traction on the top edge y = 1 (consistent)
    f = np.zeros(2 * nn)
    top = conn[np.arange(ne) >= ne - m['nx']]  # top row of elements (ej = ny-1)
    if kind == 4:
        en, wts = top[:, [3, 2]], np.array([0.5, 0.5])
    else:
        en, wts = top[:, [3, 6, 2]], np.array([1, 4, 1]) / 6.0
    hx = m['L'] / m['nx']
    for k in range(en.shape[1]):
        np.add.at(f, 2 * en[:, k], traction[0] * hx * wts[k])
        np.add.at(f, 2 * en[:, k] + 1, traction[1] * hx * wts[k])
    return dict(Kd=Kd, K12=K12, M=M, MLinv=MLinv, free=free, f=f, nn=nn, C=C, D=D, mlump=mlump)


class Problem:
    def __init__(self, lh, ny, kind, a=0.05, E=1e4):
        self.m = strip_mesh(lh, ny, kind)
        A = assemble(self.m, E=E)
        self.__dict__.update(A)
        self.a = a
        fr = self.free
        self.Kdf = self.Kd[fr][:, fr].tocsc()
        self.K12f = self.K12[fr].tocsr()
        self.K12fT = self.K12f.T.tocsr()
        self.Mlu = spla.splu(self.M.tocsc())
        self.SLf = (a * self.Kdf + (1 - a) * (self.K12f @ self.MLinv @ self.K12fT)).tocsc()
        self.b = self.f[fr]
        self.nS = 0

    def S(self, u):
        self.nS += 1
        return self.a * (self.Kdf @ u) + (1 - self.a) * (self.K12f @ self.Mlu.solve(self.K12fT @ u))

    def S_dense(self):
        MiKt = self.Mlu.solve(self.K12fT.toarray())
        S = self.a * self.Kdf.toarray() + (1 - self.a) * (self.K12f @ MiKt)
        return 0.5 * (S + S.T)
