#!/usr/bin/python3
"""NAFEMS LE10 (thick plate under pressure): sigma_yy at D against the NAFEMS reference, both
3D models, Hex8, Hex20, Tet4 and Tet10, on refined meshes.

The problem is examples/nafems_le10/le10.yaml (its comment and make_le10_mesh.py give the
geometry, the supports and the load). Reference: sigma_yy(D) = -5.38 MPa at D = (2, 0, 0.3),
NAFEMS R0015 "The Standard NAFEMS Benchmarks" (1990), test LE10 (a converged value of the
benchmark's authors; there is no closed form). Each run writes its mesh (make_le10_mesh.write_mesh),
runs `mixcon run` on the problem file with that mesh (and, for the mixed model,
`model: {formulation: mixed}`), and reads from results.h5:
 - sigma_yy at the node D: the displacement model's nodal stress (hexahedra: extrapolated from
   the Gauss points of the one element at D; tetrahedra: evaluated at the node in each element
   sharing D and averaged) or the mixed model's nodal stress unknown;
 - the relative deflection u_z(D) - u_z(A), A = (0, 1, 0.3) the inner ellipse's other end (no
   reference value: it shows the models converge to one solution; u_z(D) alone grows without
   bound under refinement, like log(1/h), because a line support is singular in 3D);
 - the z resultant of the reactions on the supported line "outer_mid" against the load, the
   pressure times the area of the mesh's upper face (equilibrium of the solved system);
 - the unknowns, the solver's iterations and the wall time.

--check (CI: ctest example.nafems_le10_study, about 10 s on an idle machine) runs the Hex20 meshes 8 x 4 x 2 and
16 x 8 x 4 with both models, the Tet10 mesh 16 x 8 x 4 with the displacement model and the Tet4
mesh 16 x 8 x 4 with both, and asserts:
 - sigma_yy(D) on 16 x 8 x 4 within 1 % of -5.38 MPa (Hex20, displacement model), 1.5 %
   (Hex20, mixed model), 3 % (Tet10, displacement model; Tet4, mixed model);
 - on Tet4 the mixed model's sigma_yy(D) is more than 5x closer to it than the displacement
   model's (whose constant-strain elements give -25 %);
 - the refinement 8 x 4 x 2 -> 16 x 8 x 4 moves each Hex20 model's sigma_yy(D) towards the
   reference or keeps it within 1 %, and the two models agree within 1.5 % on 16 x 8 x 4;
 - every run's reaction resultant equals the load to 1e-6.
Writes <out>/le10.md (the table), <out>/le10.json and <out>/le10.png (sigma_yy(D) against the
unknowns).

Usage: python3 examples/nafems_le10_study.py [--mixcon build/apps/mixcon] [--out out/nafems_le10]
       [--runs hex20:8x4x2:displacement,hex20:8x4x2:mixed,...] [--check]
"""
import argparse
import json
import os
import sys
import time

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "nafems_le10"))
sys.path.insert(0, HERE)
from make_le10_mesh import face_area, write_mesh  # noqa: E402
from study_util import finish_figure, run_variant  # noqa: E402

REFERENCE = -5.38  # MPa, NAFEMS R0015 (1990), LE10
D = np.array([2.0, 0.0, 0.3])
A = np.array([0.0, 1.0, 0.3])  # the inner ellipse's end on the y axis, upper face
PRESSURE = 1.0
SOURCE = os.path.join(HERE, "nafems_le10", "le10.yaml")
DEFAULT_RUNS = ",".join(
    [f"hex20:{d}:displacement" for d in ("4x2x2", "8x4x2", "16x8x4", "24x12x6", "32x16x8")] +
    [f"hex20:{d}:mixed" for d in ("4x2x2", "8x4x2", "16x8x4", "24x12x6")] +
    [f"hex8:{d}:{m}" for m in ("displacement", "mixed") for d in ("8x4x2", "16x8x4", "32x16x8")] +
    [f"tet10:{d}:{m}" for m in ("displacement", "mixed") for d in ("8x4x2", "16x8x4", "24x12x6")] +
    [f"tet4:{d}:{m}" for m in ("displacement", "mixed") for d in ("16x8x4", "32x16x8")])
CHECK_RUNS = ",".join([f"hex20:{d}:{m}" for m in ("displacement", "mixed")
                       for d in ("8x4x2", "16x8x4")] +
                      ["tet10:16x8x4:displacement", "tet4:16x8x4:displacement",
                       "tet4:16x8x4:mixed"])
# --check's bounds on |sigma_yy(D) / -5.38 - 1| (measured: docs/validation-3d.md).
CHECK_BOUNDS = {("hex20", "16x8x4", "displacement"): 0.01, ("hex20", "16x8x4", "mixed"): 0.015,
                ("tet10", "16x8x4", "displacement"): 0.03, ("tet4", "16x8x4", "mixed"): 0.03}


def run(mixcon, out, spec):
    element, divisions, model = spec.split(":")
    div = [int(v) for v in divisions.split("x")]
    name = f"{element}_{divisions}_{model}"
    os.makedirs(out, exist_ok=True)
    msh = os.path.join(out, name + ".msh")
    _, _, faces = write_mesh(msh, element, div)
    subs = [("mesh: {file: le10.msh}", "mesh: {file: %s}" % msh)]
    if model == "mixed":
        subs.append(("materials:", "model: {formulation: mixed}\nmaterials:"))
    start = time.time()
    result = run_variant(mixcon, SOURCE, name, out, subs)
    wall = time.time() - start
    with h5py.File(os.path.join(result, "results.h5"), "r") as f:
        nodes = f["mesh/nodes"][:]
        step = f["steps"][max(f["steps"].keys(), key=int)]
        stress = step["stress"][:]
        displacement = step["displacement"][:]
        reaction = step["reaction"][:]
    d, a = (int(np.argmin(np.linalg.norm(nodes - p, axis=1))) for p in (D, A))
    assert np.linalg.norm(nodes[d] - D) < 1e-12 and np.linalg.norm(nodes[a] - A) < 1e-12
    summary = json.load(open(os.path.join(result, "summary.json")))
    mid = np.where((np.abs(nodes[:, 2]) < 1e-12) &
                   (np.abs((nodes[:, 0] / 3.25) ** 2 + (nodes[:, 1] / 2.75) ** 2 - 1) < 1e-9))[0]
    # results.h5 keeps the file's node order: tag t is row t - 1.
    load = PRESSURE * face_area(nodes, [[t - 1 for t in f] for f in faces["upper"]])
    steps = summary.get("steps", [{}])
    return {
        "element": element, "divisions": divisions, "model": model,
        "unknowns": int(nodes.shape[0] * (9 if model == "mixed" else 3)),
        "sigma_yy_D": float(stress[d, 1]),
        "error": float(stress[d, 1] / REFERENCE - 1),
        "uz_DA": float(displacement[d, 2] - displacement[a, 2]),
        "reaction_z": float(reaction[mid, 2].sum()), "load": float(load),
        "linear_iterations": steps[-1].get("linear_iterations"),
        "wall_s": wall,
    }


def table(rows):
    out = ["| element | divisions | model | unknowns | sigma_yy(D) MPa | vs -5.38 | uz(D) - uz(A) um | "
           "reaction z / load - 1 | linear its | wall s |", "|---" * 10 + "|"]
    for r in rows:
        out.append(f"| {r['element']} | {r['divisions']} | {r['model']} | {r['unknowns']:,} | "
                   f"{r['sigma_yy_D']:.4f} | {100 * r['error']:+.2f} % | {1e6 * r['uz_DA']:.3f} | "
                   f"{r['reaction_z'] / r['load'] - 1:.1e} | {r['linear_iterations']} | "
                   f"{r['wall_s']:.1f} |")
    return "\n".join(out)


def checks(rows):
    by = {(r["element"], r["divisions"], r["model"]): r for r in rows}
    failed = []

    def check(ok, what):
        print(("ok      " if ok else "FAILED  ") + what)
        if not ok:
            failed.append(what)

    for r in rows:
        check(abs(r["reaction_z"] / r["load"] - 1) < 1e-6,
              f"{r['element']} {r['divisions']} {r['model']}: reaction resultant "
              f"{r['reaction_z']:.8f} = load {r['load']:.8f}")
    for key, bound in CHECK_BOUNDS.items():
        if key in by:
            r = by[key]
            check(abs(r["error"]) < bound,
                  f"{' '.join(key)}: sigma_yy(D) {r['sigma_yy_D']:.4f} within {100 * bound:g} % "
                  f"of {REFERENCE} ({100 * r['error']:+.2f} %)")
    for model in ("displacement", "mixed"):
        fine, coarse = by.get(("hex20", "16x8x4", model)), by.get(("hex20", "8x4x2", model))
        if fine and coarse:
            check(abs(fine["error"]) <= max(abs(coarse["error"]), 0.01),
                  f"hex20 {model}: refinement 8x4x2 -> 16x8x4 moves sigma_yy(D) towards the "
                  f"reference or keeps it within 1 % ({100 * coarse['error']:+.2f} % -> "
                  f"{100 * fine['error']:+.2f} %)")
    d, m = by.get(("tet4", "16x8x4", "displacement")), by.get(("tet4", "16x8x4", "mixed"))
    if d and m:
        check(abs(m["error"]) < 0.2 * abs(d["error"]),
              f"tet4 16x8x4: the mixed model's nodal stress at D is more than 5x closer to the "
              f"reference than the displacement model's ({100 * m['error']:+.2f} % against "
              f"{100 * d['error']:+.2f} %)")
    d, m = by.get(("hex20", "16x8x4", "displacement")), by.get(("hex20", "16x8x4", "mixed"))
    if d and m:
        check(abs(m["sigma_yy_D"] / d["sigma_yy_D"] - 1) < 0.015,
              f"hex20 16x8x4: the two models' sigma_yy(D) within 1.5 % of each other "
              f"({m['sigma_yy_D']:.4f} against {d['sigma_yy_D']:.4f})")
    return failed


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for (element, model), style in {("hex20", "displacement"): "o-", ("hex20", "mixed"): "s-",
                                    ("hex8", "displacement"): "o--", ("hex8", "mixed"): "s--",
                                    ("tet10", "displacement"): "^-", ("tet10", "mixed"): "v-",
                                    ("tet4", "displacement"): "^:", ("tet4", "mixed"): "v:"}.items():
        rs = [r for r in rows if r["element"] == element and r["model"] == model]
        if rs:
            ax.semilogx([r["unknowns"] for r in rs], [r["sigma_yy_D"] for r in rs], style,
                        label=f"{element}, {model} model")
    ax.axhline(REFERENCE, color="k", lw=0.8, label="NAFEMS reference -5.38 MPa")
    finish_figure(fig, ax, path, "unknowns", "sigma_yy at D (MPa)",
                  "NAFEMS LE10 thick plate: sigma_yy at D")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mixcon", default="build/apps/mixcon")
    ap.add_argument("--out", default="out/nafems_le10")
    ap.add_argument("--runs", default=None, help="element:NTxNRxNZ:model,... (default: all; "
                                                 "--check: CHECK_RUNS)")
    ap.add_argument("--check", action="store_true", help="exit 1 when a check fails")
    a = ap.parse_args()
    runs = a.runs or (CHECK_RUNS if a.check else DEFAULT_RUNS)
    rows = []
    for spec in runs.split(","):
        rows.append(run(os.path.abspath(a.mixcon), os.path.abspath(a.out), spec))
        r = rows[-1]
        print(f"{spec}: {r['unknowns']} unknowns, sigma_yy(D) = {r['sigma_yy_D']:.4f} MPa "
              f"({100 * r['error']:+.2f} % from {REFERENCE}), {r['wall_s']:.1f} s", flush=True)
    md = table(rows)
    print(md)
    with open(os.path.join(a.out, "le10.md"), "w") as f:
        f.write(md + "\n")
    with open(os.path.join(a.out, "le10.json"), "w") as f:
        json.dump(rows, f, indent=1)
    plot(rows, os.path.join(a.out, "le10.png"))
    if a.check and checks(rows):
        sys.exit(1)


if __name__ == "__main__":
    main()
