#!/usr/bin/env python3
"""Hertz contact side by side with CalculiX (issue 8): the cylinder on a rigid plane of
examples/hertz/hertz_refined.yaml on a graded Quad4 mesh (quarter_disk [48, 32], 5,505 nodes),
solved by mixcon (direct and AMG) and by CalculiX's ccx on the same mesh, with its input deck
generated from mixcon's mesh (results.h5): plane strain CPE4, the rigid plane a fixed row of CPE4
elements above y = 1, contact surface to surface with a linear penalty (1e7; the default node to
surface HARD variant is run too), the diameter y = 0 moved up by 0.016.
For both: wall time of the whole run (2 threads: OMP_NUM_THREADS=2, CCX_NPROC_EQUATION_SOLVER=2),
the load P (twice the quarter's reaction), and p(0) against the Hertz closed form at that load,
p0 = 2 P / (pi b), b = sqrt(4 P R (1 - nu^2) / (pi E)). mixcon's p(0) is the contact traction of
the node at x = 0 (force over its boundary share); CalculiX's is its contact stress at the
integration points of the first slave face (surface to surface) or of the node (node to surface).
Both use Debian's default BLAS (reference libblas3): ccx through SPOOLES/ARPACK, mixcon through
hypre (Eigen has its own kernels).

With --divisions 48x32,32x22,24x16 both codes run on each of those meshes (node to surface on the
first only), and the table ends with the comparison at equal accuracy: each code's fastest run
whose |p(0) - p0| is within the best accuracy CalculiX reached (surface to surface).

Needs ccx (Debian package calculix-ccx; not installed by cmake/install-deps.sh) and h5py.
Usage: python3 bench/calculix_hertz.py [--mixcon build/apps/mixcon] [--out out/calculix]
                                       [--divisions 48x32[,NxM...]]
Writes <out>/calculix_hertz.md with the table.
"""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "examples"))
from study_util import run_variant  # noqa: E402

R, E, NU, DELTA = 1.0, 21000.0, 0.3, 0.016


def hertz(P):
    b = np.sqrt(4 * P * R * (1 - NU ** 2) / (np.pi * E))
    return b, 2 * P / (np.pi * b)


def deck(mesh_h5, path, surface_to_surface):
    """Writes a CalculiX deck of the Hertz problem on the mesh of a mixcon result."""
    f = h5py.File(mesh_h5, "r")
    xy, el = f["mesh/nodes"][:], f["mesh/elements"][:]
    n = len(xy)
    lines = ["*HEADING", "Hertz cylinder on a rigid plane (mesh from mixcon)", "*NODE"]
    lines += [f"{i + 1}, {x:.15g}, {y:.15g}" for i, (x, y) in enumerate(xy[:, :2])]
    nb, x0, x1, y0, y1 = 130, -0.05, 0.6, 1.0, 1.05  # the rigid plane: a fixed row of elements
    bid, nid = {}, n
    for j, y in enumerate((y0, y1)):
        for i, x in enumerate(np.linspace(x0, x1, nb + 1)):
            nid += 1
            bid[(i, j)] = nid
            lines.append(f"{nid}, {x:.15g}, {y:.15g}")
    lines.append("*ELEMENT, TYPE=CPE4, ELSET=CYL")
    lines += [f"{e + 1}, " + ", ".join(str(k + 1) for k in c[:4]) for e, c in enumerate(el)]
    lines.append("*ELEMENT, TYPE=CPE4, ELSET=RIGID")
    ne = len(el)
    lines += [f"{ne + k + 1}, {bid[(k, 0)]}, {bid[(k + 1, 0)]}, {bid[(k + 1, 1)]}, {bid[(k, 1)]}"
              for k in range(nb)]

    def listing(header, ids):
        lines.append(header)
        ids = list(ids)
        lines.extend(", ".join(str(i) for i in ids[k:k + 12]) for k in range(0, len(ids), 12))

    r = np.hypot(xy[:, 0], xy[:, 1])
    arc = (np.abs(r - 1) < 1e-9) & (xy[:, 0] < 0.5)
    listing("*NSET, NSET=LEFT", [i + 1 for i in range(n) if abs(xy[i, 0]) < 1e-12])
    listing("*NSET, NSET=BOTTOM", [i + 1 for i in range(n) if abs(xy[i, 1]) < 1e-12])
    listing("*NSET, NSET=ARC", [i + 1 for i in range(n) if arc[i]])
    listing("*NSET, NSET=RIGIDN", sorted(bid.values()))
    listing("*ELSET, ELSET=RBOT", range(ne + 1, ne + nb + 1))
    if surface_to_surface:
        faces = {}
        for e, c in enumerate(el):
            for s in range(4):
                if arc[c[s]] and arc[c[(s + 1) % 4]]:
                    faces.setdefault(s + 1, []).append(e + 1)
        for s, es in faces.items():
            listing(f"*ELSET, ELSET=ARCF{s}", es)
        lines += ["*SURFACE, NAME=SSLAVE"] + [f"ARCF{s}, S{s}" for s in faces]
        pair, behaviour = "SURFACE TO SURFACE", ["PRESSURE-OVERCLOSURE=LINEAR", "1e7"]
    else:
        lines += ["*SURFACE, NAME=SSLAVE, TYPE=NODE", "ARC"]
        pair, behaviour = "NODE TO SURFACE", ["PRESSURE-OVERCLOSURE=HARD"]
    lines += ["*SURFACE, NAME=SMASTER", "RBOT, S1",
              f"*CONTACT PAIR, INTERACTION=SI, TYPE={pair}", "SSLAVE, SMASTER",
              "*SURFACE INTERACTION, NAME=SI", f"*SURFACE BEHAVIOR, {behaviour[0]}",
              *behaviour[1:],
              "*MATERIAL, NAME=STEEL", "*ELASTIC", f"{E}, {NU}",
              "*SOLID SECTION, ELSET=CYL, MATERIAL=STEEL", "1.",
              "*SOLID SECTION, ELSET=RIGID, MATERIAL=STEEL", "1.",
              "*BOUNDARY", "LEFT, 1, 1, 0.", "RIGIDN, 1, 2, 0.",
              "*STEP, INC=1000", "*STATIC", "0.01, 1.0, 1e-5, 0.1",
              "*BOUNDARY", f"BOTTOM, 2, 2, {DELTA}",
              "*NODE PRINT, NSET=BOTTOM, TOTALS=ONLY", "RF",
              "*CONTACT PRINT", "CSTR", "*END STEP"]
    with open(path, "w") as out:
        out.write("\n".join(lines) + "\n")
    return xy, el


def calculix(mesh_h5, out, surface_to_surface, tag=""):
    name = ("hertz_s2s" if surface_to_surface else "hertz_n2s") + tag
    xy, el = deck(mesh_h5, os.path.join(out, name + ".inp"), surface_to_surface)
    env = dict(os.environ, OMP_NUM_THREADS="2", CCX_NPROC_EQUATION_SOLVER="2")
    t0 = time.perf_counter()
    log = subprocess.run(["ccx", name], cwd=out, capture_output=True, text=True, env=env)
    seconds = time.perf_counter() - t0
    if log.returncode != 0 or "ERROR" in log.stdout:
        sys.exit(f"ccx failed on {name}:\n{log.stdout[-2000:]}")
    dat = open(os.path.join(out, name + ".dat")).read()
    P = 2 * abs(float(dat.split("total force")[-1].splitlines()[2].split()[1]))
    b, p0 = hertz(P)
    rows = [r.split() for r in dat.split("contact stress")[-1].splitlines()[2:] if r.strip()]
    if surface_to_surface:  # element, face, pressure at each integration point of slave faces
        faces = {}
        for r in rows:
            faces.setdefault(int(r[0]), []).append(float(r[2]))
        first = min(faces, key=lambda e: xy[el[e - 1][:4], 0].mean())
        p_first = max(faces[first])
    else:  # slave node, pressure
        p_first = float(min(rows, key=lambda r: xy[int(r[0]) - 1, 0])[1])
    return seconds, P, p_first / p0 - 1


def mixcon(binary, out, solver, divisions=(48, 32)):
    source = os.path.join(ROOT, "examples", "hertz", "hertz_refined.yaml")
    subs = [("divisions: [24, 16], grading: [1.6, 1.5], element: quad8",
             f"divisions: [{divisions[0]}, {divisions[1]}], grading: [1.6, 1.5], element: quad4"),
            ("solver: {type: direct}", f"solver: {{type: {solver}}}")]
    t0 = time.perf_counter()
    result = run_variant(binary, source, f"mixcon_{solver}_{divisions[0]}x{divisions[1]}", out,
                         subs)
    seconds = time.perf_counter() - t0
    rows = [r for r in csv.DictReader(open(os.path.join(result, "contact.csv")))]
    last = max(int(r["step"]) for r in rows)
    rows = [r for r in rows if int(r["step"]) == last]
    P = 2 * sum(float(r["normal_force"]) for r in rows)
    b, p0 = hertz(P)
    first = min(rows, key=lambda r: float(r["x"]))
    corrections = sum(s["iterations"] for s in
                      json.load(open(os.path.join(result, "summary.json")))["steps"])
    return seconds, P, float(first["normal_stress"]) / p0 - 1, result, corrections


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mixcon", default=os.path.join(ROOT, "build", "apps", "mixcon"))
    ap.add_argument("--out", default=os.path.join("out", "calculix"))
    ap.add_argument("--divisions", default="48x32",
                    help="quarter_disk meshes NxM (Quad4, grading [1.6, 1.5]), comma separated")
    args = ap.parse_args()
    if not shutil.which("ccx"):
        sys.exit("ccx not found: apt-get install calculix-ccx")
    os.makedirs(args.out, exist_ok=True)
    os.environ["OMP_NUM_THREADS"] = "2"
    meshes = [tuple(int(v) for v in d.split("x")) for d in args.divisions.split(",")]
    table = ["| mesh | solver | wall time (s) | P | p(0) vs Hertz |", "|---|---|---|---|---|"]
    runs = []  # (code, label, mesh, seconds, relative error of p(0))
    s2s_label = "CalculiX 2.20, surface to surface, penalty 1e7"
    for k, divisions in enumerate(meshes):
        name = f"{divisions[0]}x{divisions[1]}"
        mesh = None
        for solver in ("amg", "direct"):
            s, P, e, result, corr = mixcon(args.mixcon, args.out, solver, divisions)
            mesh = os.path.join(result, "results.h5")
            runs.append(("mixcon", f"mixcon {solver}", name, s, e))
            table.append(f"| {name} | mixcon, {solver} ({corr} corrections in 12 steps) | {s:.2f} "
                         f"| {P:.2f} | {100 * e:+.2f} % |")
        for s2s in (True, False) if k == 0 else (True,):
            s, P, e = calculix(mesh, args.out, s2s, "" if k == 0 else "_" + name)
            label = s2s_label if s2s else "CalculiX 2.20, node to surface, HARD"
            if s2s:
                runs.append(("ccx", label, name, s, e))
            table.append(f"| {name} | {label} | {s:.2f} | {P:.2f} | {100 * e:+.2f} % |")
    text = "\n".join(table) + "\n"
    first = meshes[0][0], meshes[0][1]
    on_first = [r for r in runs if r[2] == f"{first[0]}x{first[1]}"]
    best = min(r[3] for r in on_first if r[0] == "mixcon")
    ccx = min(r[3] for r in on_first if r[0] == "ccx")
    text += (f"\nSame mesh ({first[0]}x{first[1]}): mixcon (fastest) is {ccx / best:.1f}x faster "
             f"than CalculiX surface to surface.\n")
    if len(meshes) > 1:
        target = min(abs(r[4]) for r in runs if r[0] == "ccx")
        fastest = {code: min((r for r in runs if r[0] == code and abs(r[4]) <= target + 1e-12),
                             key=lambda r: r[3]) for code in ("mixcon", "ccx")}
        m, c = fastest["mixcon"], fastest["ccx"]
        text += (f"Equal accuracy (|p(0) - p0| <= {100 * target:.2f} %, CalculiX's best): CalculiX "
                 f"{c[3]:.2f} s on {c[2]}, mixcon {m[3]:.2f} s ({m[1]}) on {m[2]}: "
                 f"{c[3] / m[3]:.1f}x.\n")
    open(os.path.join(args.out, "calculix_hertz.md"), "w").write(text)
    print(text)


if __name__ == "__main__":
    main()
