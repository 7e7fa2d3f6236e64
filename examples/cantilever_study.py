#!/usr/bin/env python3
"""The report's nonlinear cantilever (issue 4): runs mixcon on examples/cantilever/*.yaml (5 Quad8
elements as in the report, a refined 40 x 4 mesh, the linear analysis, and the slender h = 0.1
variant), then writes CSV tables and PNG figures and prints the comparisons:

  fig2_tip_displacement.png / tip_vs_load.csv   tip displacement vs load (report Fig. 2)
  fig3_upper_gauss_stress.png / upper_gauss_stress.csv
                                                axial stress at the upper Gauss points at the final
                                                load (report Fig. 3)
  gauss_point_table.csv                         the report's table: displacement gradients and
                                                tau_xx at the lower-left Gauss point of the
                                                rightmost element, nodal vs Almansi stress
  slender_vs_elastica.csv / slender_elastica.png
                                                slender variant against the elastica

Usage: python3 examples/cantilever_study.py [--mixcon build/apps/mixcon] [--out out/cantilever/study]
Needs python3-h5py, python3-numpy, python3-matplotlib (cmake/install-deps.sh installs them).
"""
import argparse
import csv
import json
import os
import subprocess
import sys

import h5py
import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
L, H, E, NU = 10.0, 1.0, 1.2e4, 0.2
K_MAX = 10.0  # qL^3/EI at load factor 1
CALCULIX = {"w": 7.502, "u": 4.129}  # CalculiX 2.20, St. Venant-Kirchhoff, refined (issue 4)
ELASTICA = [(1.0, 0.12347, 0.00875), (2.0, 0.23851, 0.03311), (5.0, 0.49591, 0.15334),
            (10.0, 0.70020, 0.34365)]


def run(mixcon, source, out_dir, name, substitutions=()):
    """Runs mixcon on a copy of `source` with textual substitutions; returns the result dir."""
    text = open(os.path.join(HERE, "cantilever", source)).read()
    for a, b in substitutions:
        if a not in text:
            sys.exit(f"{source}: cannot substitute '{a}'")
        text = text.replace(a, b)
    path = os.path.join(out_dir, name + ".yaml")
    with open(path, "w") as f:
        f.write(text)
    result = os.path.join(out_dir, name)
    log = subprocess.run([mixcon, "run", path, "--output", result], capture_output=True, text=True)
    if log.returncode != 0:
        sys.exit(f"mixcon failed on {name}:\n{log.stdout}\n{log.stderr}")
    return result


def load(result):
    f = h5py.File(os.path.join(result, "results.h5"), "r")
    steps = sorted(f["steps"].keys(), key=int)
    return f, steps


def node_at(f, x, y):
    xy = f["mesh/nodes"][:]
    return int(np.argmin((xy[:, 0] - x) ** 2 + (xy[:, 1] - y) ** 2))


def tip_history(result, y_tip):
    f, steps = load(result)
    tip = node_at(f, L, y_tip)
    rows = []
    for s in steps:
        g = f["steps"][s]
        u = g["displacement"][tip]
        rows.append((g.attrs["load_factor"] * K_MAX, -u[1], -u[0]))
    return np.array(rows)


def green_strain_max(grad):
    """Largest principal Green-Lagrange strain magnitude from du/dx (4 per point)."""
    worst = 0.0
    for h in grad.reshape(-1, 2, 2):
        fgrad = np.linalg.inv(np.eye(2) - h)
        e = 0.5 * (fgrad.T @ fgrad - np.eye(2))
        worst = max(worst, np.max(np.abs(np.linalg.eigvalsh(e))))
    return worst


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mixcon", default=os.path.join(HERE, "..", "build", "apps", "mixcon"))
    ap.add_argument("--out", default=os.path.join("out", "cantilever", "study"))
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    refine = [("divisions: [5, 1]", "divisions: [40, 4]")]
    incremental = [("geometric_nonlinearity: true", "geometric_nonlinearity: true, "
                    "mixed_form: incremental")]

    runs = {
        "linear": run(args.mixcon, "report_linear.yaml", args.out, "linear_5"),
        "displacement": run(args.mixcon, "report_displacement.yaml", args.out, "displacement_5"),
        "mixed": run(args.mixcon, "report_mixed.yaml", args.out, "mixed_5"),
        "mixed_incremental": run(args.mixcon, "report_mixed.yaml", args.out,
                                 "mixed_incremental_5", incremental),
        "displacement_refined": run(args.mixcon, "report_displacement.yaml", args.out,
                                    "displacement_40x4", refine),
        "mixed_refined": run(args.mixcon, "report_mixed.yaml", args.out, "mixed_40x4", refine),
        "slender_displacement": run(args.mixcon, "slender_displacement.yaml", args.out,
                                    "slender_displacement"),
        "slender_mixed": run(args.mixcon, "slender_mixed.yaml", args.out, "slender_mixed"),
    }

    # --- Fig. 2: tip displacement (mid-height node of the end section) vs load.
    tips = {k: tip_history(v, H / 2) for k, v in runs.items() if not k.startswith("slender")}
    with open(os.path.join(args.out, "tip_vs_load.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["qL3_over_EI"] + [f"{k}_{c}" for k in tips for c in ("w_over_L", "u_over_L")])
        for i in range(len(tips["linear"])):
            w.writerow([f"{tips['linear'][i, 0]:.4f}"] +
                       [f"{tips[k][i, j] / L:.6f}" for k in tips for j in (1, 2)])
    plt.figure(figsize=(6, 4.5))
    styles = {"linear": "k--", "displacement": "bo-", "mixed": "rs-", "mixed_incremental": "m^-",
              "displacement_refined": "b:", "mixed_refined": "r:"}
    for k, t in tips.items():
        plt.plot(t[:, 0], t[:, 1] / L, styles[k], ms=4, label=k.replace("_", " "))
    plt.plot([K_MAX], [CALCULIX["w"] / L], "g^", label="CalculiX 2.20 (SVK)")
    plt.xlabel(r"$qL^3/EI$")
    plt.ylabel(r"tip deflection $w/L$")
    plt.ylim(0, 1.0)
    plt.title("Cantilever under uniform load (report Fig. 2)")
    plt.legend(fontsize=8)
    plt.grid(alpha=0.3)
    plt.tight_layout()
    plt.savefig(os.path.join(args.out, "fig2_tip_displacement.png"), dpi=120)
    plt.close()

    # --- Fig. 3: tau_xx at the upper row of Gauss points at the final load.
    curves = {}
    for k in ("displacement", "mixed", "displacement_refined", "mixed_refined"):
        f, steps = load(runs[k])
        gp = f["steps"][steps[-1]]["gauss_points"]
        npe = int(gp.attrs["points_per_element"])
        n1 = int(round(np.sqrt(npe)))
        xy = gp["coordinates"][:].reshape(-1, npe, 2)
        almansi = gp["stress"][:].reshape(-1, npe, 3)
        ymax = xy[:, :, 1].max()
        rows = []
        for e in range(xy.shape[0]):
            for q in range(npe - n1, npe):  # upper row of the element's rule (xi fastest)
                if abs(xy[e, q, 1] - ymax) < 1e-9:
                    r = [xy[e, q, 0], almansi[e, q, 0]]
                    if "interpolated_stress" in gp:
                        r.append(gp["interpolated_stress"][e * npe + q, 0])
                    rows.append(r)
        curves[k] = np.array(sorted(rows))
    with open(os.path.join(args.out, "upper_gauss_stress.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["model", "x", "tau_xx_almansi_from_displacements", "tau_xx_nodal_interpolated"])
        for k, c in curves.items():
            for r in c:
                w.writerow([k, f"{r[0]:.5f}", f"{r[1]:.5f}", f"{r[2]:.5f}" if len(r) > 2 else ""])
    plt.figure(figsize=(6, 4.5))
    plt.plot(curves["displacement"][:, 0], curves["displacement"][:, 1], "bo-", ms=4,
             label="displacement model (Almansi), 5 el.")
    plt.plot(curves["mixed"][:, 0], curves["mixed"][:, 2], "rs-", ms=4,
             label="mixed model (nodal stresses), 5 el.")
    plt.plot(curves["mixed"][:, 0], curves["mixed"][:, 1], "m^:", ms=4,
             label="mixed displacements through Almansi, 5 el.")
    plt.plot(curves["displacement_refined"][:, 0], curves["displacement_refined"][:, 1], "b-",
             lw=0.8, label="displacement model, 40x4")
    plt.plot(curves["mixed_refined"][:, 0], curves["mixed_refined"][:, 2], "r--", lw=0.8,
             label="mixed model (nodal), 40x4")
    plt.xlabel("x (reference), in")
    plt.ylabel(r"$\tau_{xx}$ at the upper Gauss points, psi")
    plt.title(r"Axial stress at $qL^3/EI = 10$ (report Fig. 3)")
    plt.legend(fontsize=7)
    plt.grid(alpha=0.3)
    plt.tight_layout()
    plt.savefig(os.path.join(args.out, "fig3_upper_gauss_stress.png"), dpi=120)
    plt.close()

    # --- The report's table: lower-left Gauss point of the rightmost element.
    table = []
    for step_index in (0, -1):
        row = {}
        for k in ("displacement", "mixed"):
            f, steps = load(runs[k])
            g = f["steps"][steps[step_index]]
            gp = g["gauss_points"]
            npe = int(gp.attrs["points_per_element"])
            xy = gp["coordinates"][:].reshape(-1, npe, 2)
            e = int(np.argmax(xy[:, 0, 0] - 1e-6 * xy[:, 0, 1]))  # rightmost, lowest
            grad = gp["displacement_gradient"][e * npe]
            row[k] = {"u_x": grad[0], "u_y": grad[1], "v_x": grad[2], "v_y": grad[3],
                      "tau_almansi": gp["stress"][e * npe, 0]}
            if "interpolated_stress" in gp:
                row[k]["tau_nodal"] = gp["interpolated_stress"][e * npe, 0]
            row["K"] = g.attrs["load_factor"] * K_MAX
        table.append(row)
    with open(os.path.join(args.out, "gauss_point_table.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["qL3_over_EI", "quantity", "displacement_model", "mixed_model"])
        for row in table:
            for q in ("u_x", "u_y", "v_x", "v_y", "tau_almansi"):
                w.writerow([f"{row['K']:.4f}", q, f"{row['displacement'][q]:.5f}",
                            f"{row['mixed'][q]:.5f}"])
            w.writerow([f"{row['K']:.4f}", "tau_nodal", "", f"{row['mixed']['tau_nodal']:.5f}"])

    # --- Slender variant against the elastica.
    slender = {k: tip_history(runs["slender_" + k], 0.0) for k in ("displacement", "mixed")}
    with open(os.path.join(args.out, "slender_vs_elastica.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["qL3_over_EI", "w_over_L_elastica", "u_over_L_elastica", "model",
                    "w_over_L", "u_over_L", "w_error_percent", "u_error_percent"])
        for kk, wr, ur in ELASTICA:
            for m, t in slender.items():
                i = int(np.argmin(np.abs(t[:, 0] - kk)))
                wl, ul = t[i, 1] / L, t[i, 2] / L
                w.writerow([kk, wr, ur, m, f"{wl:.5f}", f"{ul:.5f}",
                            f"{100 * (wl / wr - 1):+.2f}", f"{100 * (ul / ur - 1):+.2f}"])
    plt.figure(figsize=(6, 4.5))
    for m, st in (("displacement", "bo-"), ("mixed", "rs--")):
        t = slender[m]
        plt.plot(t[:, 0], t[:, 1] / L, st, ms=3, label=f"w/L {m}")
        plt.plot(t[:, 0], t[:, 2] / L, st, ms=3, alpha=0.5, label=f"u/L {m}")
    er = np.array(ELASTICA)
    plt.plot(er[:, 0], er[:, 1], "k*", ms=10, label="elastica w/L")
    plt.plot(er[:, 0], er[:, 2], "kx", ms=10, label="elastica u/L")
    plt.xlabel(r"$qL^3/EI$")
    plt.ylabel("tip displacement / L")
    plt.title("Slender cantilever (h = 0.1) vs the elastica")
    plt.legend(fontsize=7)
    plt.grid(alpha=0.3)
    plt.tight_layout()
    plt.savefig(os.path.join(args.out, "slender_elastica.png"), dpi=120)
    plt.close()

    # --- Printed comparison.
    strain = {}
    for k in ("displacement", "displacement_refined", "mixed_refined"):
        f, steps = load(runs[k])
        strain[k] = green_strain_max(f["steps"][steps[-1]]["gauss_points/displacement_gradient"][:])
    summary = {}
    for k in ("displacement", "mixed", "mixed_incremental"):
        s = json.load(open(os.path.join(runs[k], "summary.json")))
        summary[k] = [st["iterations"] for st in s["steps"]]
    print("Report cantilever at qL^3/EI = 10 (tip = mid-height of the end section):")
    print(f"  {'analysis':<22} {'w (in)':>8} {'u (in)':>8}  {'w vs CCX':>9} {'u vs CCX':>9}")
    for k, t in tips.items():
        w_, u_ = t[-1, 1], t[-1, 2]
        print(f"  {k:<22} {w_:8.3f} {u_:8.3f}  {100 * (w_ / CALCULIX['w'] - 1):+8.2f}% "
              f"{100 * (u_ / CALCULIX['u'] - 1):+8.2f}%")
    print(f"  CalculiX 2.20 (SVK)    {CALCULIX['w']:8.3f} {CALCULIX['u']:8.3f}")
    d = tips["displacement"][:, 1]
    m = tips["mixed"][:, 1]
    print(f"  mixed vs displacement tip deflection, 5 el.: max {100 * np.max(m / d - 1):+.2f}% "
          f"(report: up to +2.8%)")
    peak_d = np.max(np.abs(curves["displacement"][:, 1]))
    peak_m = np.max(np.abs(curves["mixed"][:, 2]))
    print(f"  peak |tau_xx| upper Gauss points, 5 el.: displacement {peak_d:.1f}, mixed (nodal) "
          f"{peak_m:.1f} psi ({100 * (peak_m / peak_d - 1):+.1f}%; report: mixed +4.8%)")
    print(f"  largest principal Green-Lagrange strain at the final load: "
          + ", ".join(f"{k} {100 * v:.1f}%" for k, v in strain.items()))
    for k, its in summary.items():
        print(f"  Newton iterations per step, {k}: {its}")
    mi = tips["mixed_incremental"][:, 1]
    print(f"  mixed incremental (report's literal form) vs displacement, 5 el.: max "
          f"{100 * np.max(mi / d - 1):+.2f}%")
    for row in table:
        print(f"  lower-left Gauss point of the rightmost element at qL^3/EI = {row['K']:.3f}:")
        for q in ("u_x", "u_y", "v_x", "v_y", "tau_almansi"):
            print(f"    {q:<12} displacement {row['displacement'][q]:9.4f}   mixed "
                  f"{row['mixed'][q]:9.4f}")
        print(f"    {'tau_nodal':<12} {'':22} mixed {row['mixed']['tau_nodal']:9.4f}")
    print("Slender variant vs the elastica (w, u errors):")
    with open(os.path.join(args.out, "slender_vs_elastica.csv")) as f:
        for r in list(csv.reader(f))[1:]:
            print(f"  qL^3/EI = {r[0]:>4} {r[3]:<13} w {r[6]}%  u {r[7]}%")
    print(f"wrote CSV and PNG files to {args.out}")


if __name__ == "__main__":
    main()
