#!/usr/bin/python3
"""bench/compare_hypre.py THREADED_BUILD SEQUENTIAL_BUILD [ROUNDS] [NY]: threaded against sequential
hypre on the same runs (issue 20). Builds nothing: give two mixcon build directories, one configured
with cmake/build-hypre.sh's hypre (-DHYPRE_ROOT=...), one with Debian's libhypre-dev
(MIXCON_HYPRE=debian). Runs their `apps/mixcon` alternately (order swapped every round so that the
drift of a shared machine hits both), OMP_NUM_THREADS as set (default 2), ROUNDS rounds (3), and
prints a markdown table of the median and the best (smallest) of each figure over the rounds and
the ratios threaded / sequential (the best is the least disturbed by other load):
  strip       the linear displacement strip of bench/bench_mixed_solver.cpp (4 x 1, clamped at
              x = 0, end shear, E = 1, nu = 0.3, plane stress, Quad4, 4 NY x NY elements; NY = 352:
              about 1e6 unknowns), hypre PCG + BoomerAMG to 1e-8: assembly, BoomerAMG setup and
              PCG solve seconds (`mixcon run --verbose`, summary.json), PCG iterations, wall;
  hertz-amg   examples/hertz/hertz_refined.yaml with `solver: {type: amg}` (hypre GMRES +
              BoomerAMG; the shipped file uses the direct solver): wall seconds of the run, the
              seconds in hypre (setup + solve of every Newton and contact correction, summary.json)
              and their share of the wall time;
  hertz       the shipped hertz_refined.yaml (direct solver: no hypre; the control).
HDF5 output is off in every run. Each build's `mixcon --version` line and hypre threading are
printed first.
"""
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

if len(sys.argv) < 3:
    sys.exit(__doc__)
BUILDS = {"threaded": sys.argv[1], "sequential": sys.argv[2]}
ROUNDS = int(sys.argv[3]) if len(sys.argv) > 3 else 3
NY = int(sys.argv[4]) if len(sys.argv) > 4 else 352
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
env = dict(os.environ, OMP_PROC_BIND="false")
env.setdefault("OMP_NUM_THREADS", "2")
tmp = tempfile.mkdtemp(prefix="mixcon-compare-hypre-")

STRIP = f"""title: displacement strip for bench/compare_hypre.py
mesh:
  generator: {{type: rectangle, size: [4, 1], origin: [0, 0], divisions: [{4 * NY}, {NY}], element: quad4}}
model: {{formulation: displacement, analysis: plane_stress, thickness: 1.0}}
materials:
  - {{region: body, type: isotropic, E: 1.0, nu: 0.3}}
boundary_conditions:
  - {{boundary: left, ux: 0, uy: 0}}
loads:
  - {{boundary: right, traction: [0, 1.0e-3]}}
steps: {{increments: 1}}
solver: {{type: amg, tolerance: 1.0e-8, max_iterations: 5000}}
output: {{directory: out, hdf5: false}}
"""


def problem_files():
    files = {}
    files["strip"] = os.path.join(tmp, "strip.yaml")
    with open(files["strip"], "w") as f:
        f.write(STRIP)
    with open(os.path.join(ROOT, "examples/hertz/hertz_refined.yaml")) as f:
        hertz = f.read()
    for name, solver in (("hertz-amg", "solver: {type: amg}"), ("hertz", None)):
        text = hertz if solver is None else re.sub(r"^solver:.*$", solver, hertz, flags=re.M)
        text = re.sub(r"^output:.*$", "output: {directory: out, hdf5: false}", text, flags=re.M)
        files[name] = os.path.join(tmp, name + ".yaml")
        with open(files[name], "w") as f:
            f.write(text)
    return files


def run(build, case, path):
    out = os.path.join(tmp, f"{case}-{os.path.basename(os.path.normpath(build))}")
    t0 = time.perf_counter()
    p = subprocess.run([os.path.join(build, "apps", "mixcon"), "run", path, "--output", out,
                        "--verbose"], capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"{build}: mixcon run {path} failed ({p.returncode}):\n{p.stdout[-2000:]}"
                 f"{p.stderr[-2000:]}")
    with open(os.path.join(out, "summary.json")) as f:
        steps = json.load(f)["steps"]
    r = {"wall s": wall}
    if case == "strip":
        m = re.search(r"assembly ([0-9.]+) s, solver setup ([0-9.]+) s", p.stdout + p.stderr)
        r["assembly s"] = float(m.group(1))
        r["AMG setup s"] = float(m.group(2))
        r["PCG solve s"] = steps[0]["solve_seconds"]
        r["PCG iterations"] = steps[0]["linear_iterations"]
    elif case == "hertz-amg":
        r["hypre s"] = sum(s["setup_seconds"] + s["solve_seconds"] for s in steps)
        r["AMG setup s"] = sum(s["setup_seconds"] for s in steps)
        r["GMRES solve s"] = sum(s["solve_seconds"] for s in steps)
        r["hypre share"] = r["hypre s"] / wall
        r["corrections"] = sum(s["iterations"] for s in steps)
        r["GMRES iterations"] = sum(s["linear_iterations"] for s in steps)
    return r


files = problem_files()
for tag, build in BUILDS.items():
    v = subprocess.run([os.path.join(build, "apps", "mixcon"), "--version"], capture_output=True,
                       text=True, env=env)
    print(f"{tag}: {build}: {v.stdout.strip().splitlines()[0] if v.stdout else '?'}")
print(f"OMP_NUM_THREADS={env['OMP_NUM_THREADS']}, {ROUNDS} rounds, strip {4 * NY} x {NY} Quad4")
results = {}
for r in range(ROUNDS):
    order = list(BUILDS.items()) if r % 2 == 0 else list(BUILDS.items())[::-1]
    for case in ("strip", "hertz-amg", "hertz"):
        for tag, build in order:
            res = run(build, case, files[case])
            results.setdefault((case, tag), []).append(res)
            print(f"  round {r + 1} {case} {tag}: " +
                  ", ".join(f"{k} {v:.3g}" for k, v in res.items()), flush=True)

print()
print("| run | figure | threaded median (best) | sequential median (best) "
      "| threaded / sequential, median (best) |")
print("|---|---|---|---|---|")
for case in ("strip", "hertz-amg", "hertz"):
    for key in results[(case, "threaded")][0]:
        tv = [x[key] for x in results[(case, "threaded")]]
        sv = [x[key] for x in results[(case, "sequential")]]
        t, s = statistics.median(tv), statistics.median(sv)
        tb, sb = min(tv), min(sv)
        ratio = f"{t / s:.2f} ({tb / sb:.2f})" if s and sb else "-"
        print(f"| {case} | {key} | {t:.3g} ({tb:.3g}) | {s:.3g} ({sb:.3g}) | {ratio} |")
