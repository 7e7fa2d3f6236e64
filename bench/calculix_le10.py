#!/usr/bin/env python3
"""NAFEMS LE10 (thick elliptic plate under pressure) in CalculiX, on exactly mixcon's mesh.

The mesh is built by examples/nafems_le10/make_le10_mesh.py (build(): the same node tags and
coordinates as the .msh mixcon reads) and written as a CalculiX deck: C3D20 (Hex20, Gmsh's
mid-edge order permuted to CalculiX's, checked against the corners' midpoints) or C3D8 (Hex8, full
integration, as mixcon's); E = 210000, nu = 0.3 (m, MPa); pressure 1 MPa on the upper face
z = 0.3 as *DLOAD Pk on each element face (k found by matching corner sets); u_y = 0 on y = 0,
u_x = 0 on x = 0, u_x = u_y = 0 on the outer face, u_z = 0 on its mid-plane line z = 0.
Prints sigma_yy at D = (2, 0, 0.3) from the .frd's nodal stresses (extrapolated and averaged by
ccx), the wall time and peak RSS of ccx (/usr/bin/time), and a check of the deck: the total
z-reaction of the line against the pressure times the upper face's area (the exact quarter
elliptic annulus pi/4 (3.25 * 2.75 - 2 * 1) = 5.4487 m^2, and the area of the discretised face,
which the reaction must match to solver precision).
Reference: sigma_yy(D) = -5.38 MPa (NAFEMS R0015, "The Standard NAFEMS Benchmarks", 1990, LE10).

Needs ccx (Debian package calculix-ccx, 2.20); ccx runs with OMP_NUM_THREADS=2,
CCX_NPROC_EQUATION_SOLVER=2. Pure Python 3 (no numpy: runs under any python3).
Usage: python3 bench/calculix_le10.py --element hex20 --divisions 8 4 2 [--grading 1]
           [--solver spooles|iterative] [--out out/calculix_le10] [--json] [--timeout S]
       python3 bench/calculix_le10.py --runs hex20:8x4x2,hex20:16x8x4,hex8:16x8x4
"""
import argparse
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "examples", "nafems_le10"))
from make_le10_mesh import HEX20_EDGES, build, face_area  # noqa: E402

E, NU, PRESSURE, REFERENCE = 210000.0, 0.3, 1.0, -5.38
AREA = 0.25 * math.pi * (3.25 * 2.75 - 2.0 * 1.0)
# CalculiX/Abaqus C3D20 mid-edge nodes (0-based corners), and where each sits in Gmsh's list.
CCX_EDGES = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5),
             (2, 6), (3, 7)]
GMSH_MID = [8 + [frozenset(e) for e in HEX20_EDGES].index(frozenset(e)) for e in CCX_EDGES]
CCX_FACES = {1: (0, 1, 2, 3), 2: (4, 7, 6, 5), 3: (0, 4, 5, 1), 4: (1, 5, 6, 2),
             5: (2, 6, 7, 3), 6: (3, 7, 4, 0)}


def sub(p, q):
    return [a - b for a, b in zip(p, q)]


def norm(v):
    return math.sqrt(sum(a * a for a in v))


def deck(path, element, divisions, grading, solver):
    tags, hexes, faces, line, d = build(element, divisions, grading)
    xyz = dict(tags.values())
    quadratic = element == "hex20"
    conns, offset = [], 0.0  # offset: largest |mid node - chord midpoint| / edge length
    for h in hexes:
        c = h[:8] + ([h[m] for m in GMSH_MID] if quadratic else [])
        if quadratic:  # node order check: each mid node nearest its own edge's midpoint
            mids = [[0.5 * (p + q) for p, q in zip(xyz[c[a]], xyz[c[b]])] for a, b in CCX_EDGES]
            for k, (a, b) in enumerate(CCX_EDGES):
                dist = [norm(sub(xyz[c[8 + k]], m)) for m in mids]
                if min(range(12), key=dist.__getitem__) != k:
                    sys.exit(f"mid-edge node {c[8 + k]} is not on edge {c[a]}-{c[b]}")
                offset = max(offset, dist[k] / norm(sub(xyz[c[a]], xyz[c[b]])))
        conns.append(c)
    lookup = {}  # corner set -> (element, CalculiX face)
    for e, c in enumerate(conns):
        for k, f in CCX_FACES.items():
            lookup.setdefault(frozenset(c[i] for i in f), []).append((e + 1, k))
    dload = []
    for quad in faces["upper"]:
        hit = lookup[frozenset(quad[:4])]
        if len(hit) != 1:
            sys.exit(f"upper face {quad[:4]} is not a boundary face of exactly one element")
        dload.append(f"{hit[0][0]}, P{hit[0][1]}, {PRESSURE}")
    lines = ["*HEADING", f"NAFEMS LE10, {element} {divisions}, mesh of make_le10_mesh.py",
             "*NODE"]
    lines += [f"{t}, {p[0]:.17g}, {p[1]:.17g}, {p[2]:.17g}" for t, p in sorted(tags.values())]
    lines.append(f"*ELEMENT, TYPE={'C3D20' if quadratic else 'C3D8'}, ELSET=PLATE")
    for e, c in enumerate(conns):  # at most 16 entries per line, continue with a trailing comma
        ids = [str(e + 1)] + [str(n) for n in c]
        lines += [", ".join(ids[:16]) + ("," if len(ids) > 16 else "")]
        if len(ids) > 16:
            lines.append(", ".join(ids[16:]))

    def nset(name, groups):
        ids = sorted({n for g in groups for n in g})
        lines.append(f"*NSET, NSET={name}")
        lines.extend(", ".join(map(str, ids[k:k + 12])) for k in range(0, len(ids), 12))

    for name, groups in (("Y0", faces["y0"]), ("X0", faces["x0"]), ("OUTER", faces["outer"]),
                         ("LINE", line), ("ND", [[d]])):
        nset(name, groups)
    lines += ["*MATERIAL, NAME=STEEL", "*ELASTIC", f"{E}, {NU}",
              "*SOLID SECTION, ELSET=PLATE, MATERIAL=STEEL",
              "*BOUNDARY", "Y0, 2, 2, 0.", "X0, 1, 1, 0.", "OUTER, 1, 2, 0.", "LINE, 3, 3, 0.",
              "*STEP", "*STATIC, SOLVER=" + ("SPOOLES" if solver == "spooles"
                                             else "ITERATIVE CHOLESKY"),
              "*DLOAD"] + dload + [
              "*NODE FILE", "U", "*EL FILE", "S",
              "*NODE PRINT, NSET=LINE, TOTALS=ONLY", "RF", "*END STEP"]
    with open(path, "w") as out:
        out.write("\n".join(lines) + "\n")
    return len(tags), len(hexes), d, face_area(xyz, faces["upper"]), offset


def frd_stress(path, node):
    """SXX..SZX of one node from the last STRESS block of a .frd (fixed-width columns)."""
    values, inside = None, False
    with open(path) as f:
        for row in f:
            if row.startswith(" -4"):
                inside = row[3:].split()[0] == "STRESS"
            elif inside and row.startswith(" -1") and int(row[3:13]) == node:
                values = [float(row[13 + 12 * k:25 + 12 * k]) for k in range(6)]
            elif row.startswith(" -3"):
                inside = False
    if values is None:
        sys.exit(f"no STRESS of node {node} in {path}")
    return values


def run(element, divisions, grading, solver, out, timeout):
    name = f"le10_{element}_{'x'.join(map(str, divisions))}"
    nodes, elements, d, area, offset = deck(os.path.join(out, name + ".inp"), element, divisions,
                                    grading, solver)
    env = dict(os.environ, OMP_NUM_THREADS="2", CCX_NPROC_EQUATION_SOLVER="2")
    t0 = time.perf_counter()
    p = subprocess.Popen(["/usr/bin/time", "-f", "%M", "-o", name + ".time", "ccx", name],
                         cwd=out, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         text=True, start_new_session=True)
    try:
        log = p.communicate(timeout=timeout or None)[0]
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        return dict(element=element, divisions=divisions, nodes=nodes, elements=elements,
                    skipped=f"ccx ran past {timeout} s")
    wall = time.perf_counter() - t0
    with open(os.path.join(out, name + ".log"), "w") as f:
        f.write(log)
    if p.returncode != 0 or "*ERROR" in log:
        sys.exit(f"ccx failed on {name}:\n{log[-2000:]}")
    with open(os.path.join(out, name + ".time")) as f:
        peak_kib = int(f.read().split()[-1])
    with open(os.path.join(out, name + ".dat")) as f:
        dat = f.read()
    rz = float(dat.split("total force")[-1].splitlines()[2].split()[2])
    syy = frd_stress(os.path.join(out, name + ".frd"), d)[1]
    return dict(element=element, divisions=divisions, grading=grading, solver=solver,
                nodes=nodes, elements=elements, mid_offset=round(offset, 4), sigma_yy_D=syy,
                error_pct=100 * (syy / REFERENCE - 1), wall_s=round(wall, 3),
                peak_gib=round(peak_kib / 2 ** 20, 4), reaction_z=rz, mesh_area=area,
                reaction_vs_mesh_pct=100 * (rz / (PRESSURE * area) - 1),
                reaction_vs_exact_pct=100 * (rz / (PRESSURE * AREA) - 1))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--element", choices=["hex8", "hex20"], default="hex20")
    ap.add_argument("--divisions", type=int, nargs=3, default=[8, 4, 2],
                    metavar=("NT", "NR", "NZ"))
    ap.add_argument("--runs", help="several runs, e.g. hex20:8x4x2,hex8:16x8x4")
    ap.add_argument("--grading", type=float, default=1.0)
    ap.add_argument("--solver", choices=["spooles", "iterative"], default="spooles")
    ap.add_argument("--out", default=os.path.join("out", "calculix_le10"))
    ap.add_argument("--timeout", type=float, default=0, help="skip a run past S seconds")
    ap.add_argument("--json", action="store_true", help="one JSON object per run")
    a = ap.parse_args()
    if not shutil.which("ccx"):
        sys.exit("ccx not found: apt-get install calculix-ccx")
    os.makedirs(a.out, exist_ok=True)
    runs = [(a.element, a.divisions)]
    if a.runs:
        runs = [(r.split(":")[0], [int(n) for n in r.split(":")[1].split("x")])
                for r in a.runs.split(",")]
    if not a.json:
        print(f"NAFEMS LE10 in CalculiX, sigma_yy(D) vs {REFERENCE} MPa; upper face area "
              f"{AREA:.5f} m^2 (exact)")
        print("| element | divisions | nodes | sigma_yy(D) | vs -5.38 | wall s | peak GiB | "
              "sum RF_z | vs p*A mesh | vs p*A exact |")
        print("|---|---|---|---|---|---|---|---|---|---|")
    for element, divisions in runs:
        r = run(element, divisions, a.grading, a.solver, a.out, a.timeout)
        if a.json:
            print(json.dumps(r), flush=True)
        elif "skipped" in r:
            print(f"| {element} | {'x'.join(map(str, divisions))} | {r['nodes']} | "
                  f"skipped: {r['skipped']} |", flush=True)
        else:
            print(f"| {element} | {'x'.join(map(str, divisions))} | {r['nodes']} | "
                  f"{r['sigma_yy_D']:.4f} | {r['error_pct']:+.2f} % | {r['wall_s']:.2f} | "
                  f"{r['peak_gib']:.3f} | {r['reaction_z']:.5f} | "
                  f"{r['reaction_vs_mesh_pct']:+.4f} % | {r['reaction_vs_exact_pct']:+.3f} % |",
                  flush=True)


if __name__ == "__main__":
    main()
