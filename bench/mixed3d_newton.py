#!/usr/bin/env python3
"""One Newton increment of the geometrically nonlinear 3D mixed model (issue 17), at up to and
beyond a million unknowns: time, GMRES iterations and peak memory.

The problem: the unit cube of N^3 Hex8 or Hex20 elements (`generator: box`), isotropic E = 1000,
nu = 0.3, mixed model (9 unknowns per node) in the current form with a = 0.05, the face x = 0
clamped, a shear traction (0, 0, -20) on the face x = 1 (2 % strain: four Newton iterations),
one increment, `solver: {type: amg, <--solver-keys>}` (flexible GMRES(100) on the Jacobian with
the block-triangular preconditioner, solver/SolidMixedSolve.hpp; the keys default to one
aggressive AMG level and PMaxElmts 4, measured 2.6x faster on the cube; "" for the model's
defaults; add `jacobian: matrix_free` to apply the Jacobian without assembling it). Each run is `mixcon run FILE -v` alone under `/usr/bin/time -v` (peak memory: "Maximum
resident set size"); the table has the element, N, unknowns, Newton iterations, GMRES iterations
per Newton iteration, summary.json's setup (assembly, K^L, the AMG setups, the blocks C and M)
and solve seconds, the wall time per Newton iteration, the whole run's wall time and its peak
resident memory per unknown.

Usage: python3 bench/mixed3d_newton.py [--mixcon build/apps/mixcon] [--runs hex8:24,hex8:48,
       hex20:30] [--solver-keys "aggressive_levels: 0"] [--out out/mixed3d_newton] [--json FILE]
Writes <out>/mixed3d_newton.md (the table) and, with --json, the rows as JSON.
"""
import argparse
import json
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cube_hex8 import ROOT, timed  # noqa: E402  (the shared /usr/bin/time -v runner)

PROBLEM = """title: One Newton increment of the 3D mixed model, cube {n}^3 {element}
mesh:
  generator: {{type: box, size: [1, 1, 1], divisions: [{n}, {n}, {n}], element: {element}}}
model: {{formulation: mixed, geometric_nonlinearity: true, stabilization: 0.05}}
materials:
  - {{region: body, type: isotropic, E: 1000, nu: 0.3}}
boundary_conditions:
  - {{boundary: xmin, ux: 0, uy: 0, uz: 0}}
loads:
  - {{boundary: xmax, traction: [0, 0, -20]}}
steps: {{increments: 1}}
solver: {{type: amg{keys}}}
output: {{directory: {out}, hdf5: false}}
"""


def run(binary, element, n, out, keys, timeout):
    folder = os.path.join(out, f"{element}-{n}")
    os.makedirs(folder, exist_ok=True)
    path = os.path.join(folder, "problem.yaml")
    with open(path, "w") as f:
        f.write(PROBLEM.format(n=n, element=element, keys=(", " + keys) if keys else "",
                               out=os.path.join(folder, "results")))
    env = dict(os.environ)
    rc, wall, peak, log = timed([binary, "run", path, "-v"], folder, env, timeout)
    row = {"element": element, "n": n, "rc": rc, "wall_s": wall, "peak_gb": peak}
    m = re.search(r"(\d+) unknowns", log)
    row["unknowns"] = int(m.group(1)) if m else None
    row["gmres"] = [int(k) for k in re.findall(r"iteration \d+ .* linear its (\d+)", log)]
    try:
        with open(os.path.join(folder, "results", "summary.json")) as f:
            step = json.load(f)["steps"][0]
        row.update(newton=step["iterations"], setup_s=step["setup_seconds"],
                   solve_s=step["solve_seconds"], step_s=step["total_seconds"])
    except (OSError, KeyError, IndexError, ValueError):
        row["error"] = log[-2000:]
    return row


def main():
    a = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    a.add_argument("--mixcon", default=os.path.join(ROOT, "build", "apps", "mixcon"))
    a.add_argument("--runs", default="hex8:24,hex8:48,hex20:30")
    # The option for large compact meshes (docs/performance.md): 2.6x faster on the cube.
    a.add_argument("--solver-keys", default="aggressive_levels: 1, interpolation_max_elements: 4")
    a.add_argument("--timeout", type=float, default=3600.0)
    a.add_argument("--out", default=os.path.join(ROOT, "out", "mixed3d_newton"))
    a.add_argument("--json")
    args = a.parse_args()
    rows = []
    for spec in args.runs.split(","):
        element, n = spec.split(":")
        rows.append(run(os.path.abspath(args.mixcon), element, int(n), os.path.abspath(args.out),
                        args.solver_keys, args.timeout))
        print(json.dumps(rows[-1]), flush=True)
    lines = ["| element | N | unknowns | Newton | GMRES per Newton | setup s | solve s | "
             "s per Newton | wall s | peak GiB | KB per unknown |", "|" + "---|" * 11]
    for r in rows:
        if "newton" not in r:
            lines.append(f"| {r['element']} | {r['n']} | {r['unknowns']} | failed (rc {r['rc']}) "
                         "| | | | | | | |")
            continue
        per = r["step_s"] / r["newton"]
        kb = r["peak_gb"] * 1024 ** 3 / r["unknowns"] / 1e3 if r["unknowns"] else float("nan")
        lines.append(f"| {r['element']} | {r['n']} | {r['unknowns']:,} | {r['newton']} | "
                     f"{', '.join(map(str, r['gmres']))} | {r['setup_s']:.1f} | "
                     f"{r['solve_s']:.1f} | {per:.1f} | {r['wall_s']:.1f} | "
                     f"{r['peak_gb']:.2f} | {kb:.1f} |")
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "mixed3d_newton.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
