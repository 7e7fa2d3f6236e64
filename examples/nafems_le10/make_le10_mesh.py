#!/usr/bin/python3
"""Writes the Gmsh 4.1 ASCII mesh of NAFEMS LE10 (thick plate under pressure): Hex8, Hex20, Tet4
or Tet10.

The quarter plate (NAFEMS R0015, 1990, test LE10), lengths in m: between the ellipses
(x/2)^2 + y^2 = 1 (inner) and (x/3.25)^2 + (y/2.75)^2 = 1 (outer), 0.6 thick, z in [-0.3, 0.3].
A mapped grid: the node at angle parameter t in [0, pi/2] and radial parameter s in [0, 1] is
    x = (2 + 1.25 s) cos t,  y = (1 + 1.75 s) sin t
(every curve s = const is an ellipse, so the Hex20 mid-edge nodes lie on the curved faces),
divisions [nt, nr, nz] cells along t, s and z, nz even so that the mid-plane z = 0 is a node
layer. Tetrahedra: each cell split into 6 (the Kuhn split along its diagonal), the Tet10
mid-edge nodes placed by the same map.
The cells are uniform in t and z; `grading` g > 1 clusters them toward the inner ellipse
(cell boundaries at s = (j / nr)^g, mid-edge nodes halfway between their corners).

Physical groups: volume "plate"; surfaces (outward quadrangles or triangles) "upper" (z = 0.3, the loaded
face), "y0" (y = 0, the face DCD'C'), "x0" (x = 0, the face ABA'B'), "outer" (the outer
ellipse, the face BCB'C'); curve "outer_mid" (the outer face's mid-plane line, z = 0); point
"D" (2, 0, 0.3), where NAFEMS gives sigma_yy = -5.38 MPa.

    /usr/bin/python3 examples/nafems_le10/make_le10_mesh.py                 # le10.msh, shipped
    /usr/bin/python3 examples/nafems_le10/make_le10_mesh.py --element hex8 --divisions 16 8 4 \\
        --out /tmp/le10_hex8.msh
"""
import argparse
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from gmsh_writer import write_msh  # noqa: E402

# Gmsh's edge list of the 20-node hexahedron (its mid-edge nodes 8..19), corner pairs.
HEX20_EDGES = [(0, 1), (0, 3), (0, 4), (1, 2), (1, 5), (2, 3), (2, 6), (3, 7), (4, 5), (4, 7),
               (5, 6), (6, 7)]
# The corner offsets (ds, dt, dz) of the 8 corners in Gmsh's order; local axes (s, t, z) map to
# a right-handed (x, y, z) frame (s points outward, t counter-clockwise), so det J > 0.
CORNERS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
# Boundary faces as corner numbers, counter-clockwise seen from outside, each starting at its
# corner nearest corner 0 (so that fp[0]-fp[2] is the Kuhn split's diagonal of the face).
FACES = {"upper": (4, 5, 6, 7), "y0": (0, 1, 5, 4), "x0": (3, 7, 6, 2), "outer": (1, 2, 6, 5)}
# Tetrahedra: the Kuhn split of every cell into 6 tetrahedra along its diagonal 0-6 (corner
# numbers), each positively oriented (build checks the volumes); it is conforming across cells.
KUHN_TETS = [(0, 1, 2, 6), (0, 2, 3, 6), (0, 3, 7, 6), (0, 7, 4, 6), (0, 4, 5, 6), (0, 5, 1, 6)]
# Gmsh's 10-node tetrahedron numbers its mid-edge nodes by the edges 0-1, 1-2, 2-0, 3-0, 3-2, 3-1.
TET10_EDGES = [(0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)]
# Gmsh element types (volume, boundary face, line) of each element.
GMSH_TYPES = {"hex8": (5, 3, 1), "hex20": (17, 16, 8), "tet4": (4, 2, 1), "tet10": (11, 9, 8)}
THICKNESS = 0.6


def position(t, s, z):
    c, n = (0.0, 1.0) if t == 0.5 * math.pi else (math.cos(t), math.sin(t))  # x = 0 exactly
    return ((2.0 + 1.25 * s) * c, (1.0 + 1.75 * s) * n, z)


def volume_sign(x):
    """Sign of the volume of the tetrahedron of corners x[0..3] (coordinates)."""
    a, b, c = ([x[m][i] - x[0][i] for i in range(3)] for m in (1, 2, 3))
    return (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
            a[2] * (b[0] * c[1] - b[1] * c[0]))


def build(element, divisions, grading=1.0):
    """Nodes {lattice point: (tag, xyz)}, the volume elements (hexahedra or tetrahedra: the second
    value, named `hexes` below), boundary faces by group, the mid-plane line and the node D. Lattice points are (J, I, K) in half steps: corners at even indices."""
    nt, nr, nz = divisions
    if nz % 2:
        raise SystemExit("make_le10_mesh: nz must be even (the mid-plane z = 0 is a node layer)")
    quadratic = element in ("hex20", "tet10")
    tetrahedra = element.startswith("tet")
    tags = {}

    def radial(J):  # a mid-edge node (odd J) halfway between its corners, graded or not
        if J % 2:
            return 0.5 * (radial(J - 1) + radial(J + 1))
        return (J / (2.0 * nr)) ** grading

    def tag(p):
        if p not in tags:
            J, I, K = p
            s = radial(J)
            t = 0.5 * math.pi * I / (2.0 * nt)
            z = -0.5 * THICKNESS + THICKNESS * K / (2.0 * nz)
            tags[p] = (len(tags) + 1, position(t, s, z))
        return tags[p][0]

    def corner(cell, c):
        j, i, k = cell
        ds, dt, dz = CORNERS[c]
        return (2 * (j + ds), 2 * (i + dt), 2 * (k + dz))

    def mid(p, q):
        return tuple((a + b) // 2 for a, b in zip(p, q))

    hexes, faces = [], {name: [] for name in FACES}
    for k in range(nz):
        for i in range(nt):
            for j in range(nr):
                cell = (j, i, k)
                pts = [corner(cell, c) for c in range(8)]
                if tetrahedra:
                    for tet in KUHN_TETS:
                        tp = [pts[c] for c in tet]
                        conn = [tag(p) for p in tp]
                        if volume_sign([tags[p][1] for p in tp]) <= 0:  # in x, y, z
                            raise SystemExit("make_le10_mesh: a tetrahedron of non-positive volume")
                        if quadratic:
                            conn += [tag(mid(tp[a], tp[b])) for a, b in TET10_EDGES]
                        hexes.append(conn)
                else:
                    conn = [tag(p) for p in pts]
                    if quadratic:
                        conn += [tag(mid(pts[a], pts[b])) for a, b in HEX20_EDGES]
                    hexes.append(conn)
                on = {"upper": k == nz - 1, "y0": i == 0, "x0": i == nt - 1, "outer": j == nr - 1}
                for name, face in FACES.items():
                    if not on[name]:
                        continue
                    fp = [pts[c] for c in face]
                    # Tetrahedra: the face's two triangles of the Kuhn split, whose diagonal
                    # joins the face's lowest and highest corners (fp[0] and fp[2]).
                    polygons = [[fp[0], fp[1], fp[2]], [fp[0], fp[2], fp[3]]] if tetrahedra \
                        else [fp]
                    for poly in polygons:
                        n = len(poly)
                        f = [tag(p) for p in poly]
                        if quadratic:
                            f += [tag(mid(poly[m], poly[(m + 1) % n])) for m in range(n)]
                        faces[name].append(f)
    line = []  # the outer face's mid-plane, z = 0 (K = nz)
    for i in range(nt):
        a, b = (2 * nr, 2 * i, nz), (2 * nr, 2 * i + 2, nz)
        line.append([tag(a), tag(b)] + ([tag(mid(a, b))] if quadratic else []))
    d = tag((0, 0, 2 * nz))
    return tags, hexes, faces, line, d


# 4-point Gauss-Legendre rule on [-1, 1].
GAUSS4 = [(-0.8611363115940526, 0.3478548451374538), (-0.3399810435848563, 0.6521451548625461),
          (0.3399810435848563, 0.6521451548625461), (0.8611363115940526, 0.3478548451374538)]


def quad_derivatives(n, a, b):
    """d N / d(a, b) of the 4-node or 8-node quadrangle at (a, b) (corners (-1,-1), (1,-1),
    (1,1), (-1,1), then the mid-edge nodes of edges 0-1, 1-2, 2-3, 3-0), one pair per node."""
    d = []
    for p, q in [(-1, -1), (1, -1), (1, 1), (-1, 1)]:
        if n == 4:
            d.append((0.25 * p * (1 + q * b), 0.25 * q * (1 + p * a)))
        else:
            d.append((0.25 * p * (1 + q * b) * (2 * p * a + q * b),
                      0.25 * q * (1 + p * a) * (p * a + 2 * q * b)))
    if n == 8:
        for p, q in [(0, -1), (1, 0), (0, 1), (-1, 0)]:
            d.append((-a * (1 + q * b), 0.5 * q * (1 - a * a)) if p == 0 else
                     (0.5 * p * (1 - b * b), -b * (1 + p * a)))
    return d


def triangle_derivatives(n, r, s):
    """d N / d(r, s) of the 3-node or 6-node triangle at (r, s) (corners (0,0), (1,0), (0,1),
    then the mid-edge nodes of edges 0-1, 1-2, 2-0), one pair per node."""
    lam, dlam = [1 - r - s, r, s], [(-1.0, -1.0), (1.0, 0.0), (0.0, 1.0)]
    if n == 3:
        return dlam
    d = [tuple((4 * lam[i] - 1) * dlam[i][c] for c in range(2)) for i in range(3)]
    for i in range(3):
        k = (i + 1) % 3
        d.append(tuple(4 * (lam[i] * dlam[k][c] + lam[k] * dlam[i][c]) for c in range(2)))
    return d


def face_area(xyz, faces):
    """Area of boundary faces (node lists; xyz[node] its coordinates): 4- and 8-node quadrangles
    (serendipity map) and 3- and 6-node triangles, 4 x 4 Gauss points (triangles collapsed onto
    the square: r = u (1 - v), s = v)."""
    area = 0.0
    for f in faces:
        x = [xyz[node] for node in f]
        for a, wa in GAUSS4:
            for b, wb in GAUSS4:
                if len(f) in (3, 6):
                    u, v = 0.5 * (1 + a), 0.5 * (1 + b)
                    dn, scale = triangle_derivatives(len(f), u * (1 - v), v), 0.25 * (1 - v)
                else:
                    dn, scale = quad_derivatives(len(f), a, b), 1.0
                t = [[sum(dn[m][c] * x[m][k] for m in range(len(f))) for k in range(3)]
                     for c in (0, 1)]
                cross = (t[0][1] * t[1][2] - t[0][2] * t[1][1], t[0][2] * t[1][0] - t[0][0] * t[1][2],
                         t[0][0] * t[1][1] - t[0][1] * t[1][0])
                area += wa * wb * scale * math.sqrt(sum(c * c for c in cross))
    return area


def write_mesh(path, element="hex20", divisions=(8, 4, 2), grading=1.0):
    """Writes the mesh; returns (nodes, elements, faces): the counts and the boundary faces by
    group (node tags, numbered 1..N in the file's order)."""
    tags, hexes, faces, line, d = build(element, divisions, grading)
    volume, face, edge = GMSH_TYPES[element]
    names = ["upper", "y0", "x0", "outer"]
    nodes = sorted(tags.values())
    box = "0 0 -0.3 3.25 2.75 0.3"  # the quarter's bounding box
    entities = ((1, 1, 4, 1), ["1 2 0 0.3 1 1", f"1 {box} 1 1 0"] +
                [f"{n + 1} {box} 1 {n + 1} 0" for n in range(4)] + [f"1 {box} 1 1 0"])
    blocks = [(3, 1, volume, hexes)]
    blocks += [(2, n + 1, face, faces[name]) for n, name in enumerate(names)]
    blocks += [(1, 1, edge, line), (0, 1, 15, [[d]])]
    write_msh(path, [(0, 1, "D"), (1, 1, "outer_mid")] +
              [(2, n + 1, name) for n, name in enumerate(names)] + [(3, 1, "plate")],
              entities, ["%.17g %.17g %.17g" % xyz for _, xyz in nodes], blocks)
    return len(nodes), len(hexes), faces


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--element", choices=sorted(GMSH_TYPES), default="hex20")
    ap.add_argument("--divisions", type=int, nargs=3, default=[8, 4, 2],
                    metavar=("NT", "NR", "NZ"))
    ap.add_argument("--grading", type=float, default=1.0)
    ap.add_argument("--out", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                  "le10.msh"))
    a = ap.parse_args()
    nodes, elements, _ = write_mesh(a.out, a.element, a.divisions, a.grading)
    print(f"wrote {a.out}: {nodes} nodes, {elements} {a.element} elements")


if __name__ == "__main__":
    main()
