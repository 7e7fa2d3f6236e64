#!/usr/bin/python3
"""bench/compare_builds.py OLD_BUILD NEW_BUILD [ROUNDS]: the same benchmark cases of two builds
(e.g. a release and main), run alternately on one thread (OMP_NUM_THREADS=1; order swapped every
round so that drift of a shared machine hits both), best real time of each over ROUNDS (3), as a
markdown table of the time ratio NEW / OLD. The cases: element matrices (K^L, K^sigma, mixed),
the nonlinear residual and tangent, one displacement Newton iteration, one mixed Newton step
(block-triangular GMRES), the Hertz examples end to end. Both builds need benchmarks
(-DMIXCON_ENABLE_BENCHMARKS=ON).
"""
import json
import os
import subprocess
import sys

if len(sys.argv) < 3:
    sys.exit(__doc__)
OLD = os.path.join(sys.argv[1], "bench")
NEW = os.path.join(sys.argv[2], "bench")
CASES = [
    ("mixcon_bench_linear_stiffness", "|".join([
        "KL/elementMatrices/threads/nodes:[48]/n:256/",
        "mixed/elementMatrices/threads/nodes:[48]/n:256/",
        "Ksigma/elementMatrices/threads/nodes:[48]/n:256/"])),
    ("mixcon_bench_nonlinear", "|".join([
        "KL/assembleCsr/baseline/nodes:[48]/n:512/",
        "NL/displacement/residualAndTangent/nodes:[48]/n:128/",
        "NL/mixed/residualAndJacobian/nodes:[48]/n:128/",
        "NL/displacement/newtonIteration/nodes:[48]/n:128/",
        "NL/mixed/newtonStep/nodes:4/n:128/a_percent:0/schur:0/"])),
    ("mixcon_bench_hertz", "hertz/endToEnd/case:[01]/"),
]
rounds = int(sys.argv[3]) if len(sys.argv) > 3 else 3
env = dict(os.environ, OMP_NUM_THREADS="1", OMP_PROC_BIND="false")
best = {}
for r in range(rounds):
    for tag, d in (("old", OLD), ("new", NEW)) if r % 2 == 0 else (("new", NEW), ("old", OLD)):
        for prog, filt in CASES:
            out = subprocess.run([os.path.join(d, prog), "--benchmark_format=json",
                                  "--benchmark_filter=" + filt, "--benchmark_min_time=0.2"],
                                 capture_output=True, text=True, env=env, cwd=d)
            try:
                js = json.loads(out.stdout)
            except json.JSONDecodeError:
                print("no json", prog, tag, out.stderr[-300:]); continue
            for b in js["benchmarks"]:
                k = (b["name"], tag)
                best[k] = min(best.get(k, 1e300), b["real_time"])
names = sorted({n for n, _ in best})
print("| benchmark | old (ms) | new (ms) | new / old time |")
print("|---|---|---|---|")
for n in names:
    o, w = best.get((n, "old")), best.get((n, "new"))
    if o and w:
        print(f"| {n.replace('/manual_time','')} | {o:.3f} | {w:.3f} | {w/o:.2f} |")
    else:
        print(f"| {n} | {o} | {w} | - |")
