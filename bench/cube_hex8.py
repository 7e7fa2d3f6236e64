#!/usr/bin/env python3
"""The 3D cube benchmark of issue 17: the unit cube of N^3 Hex8 elements, linear displacement model.

The problem: `mesh: {generator: {type: box, size: [1, 1, 1], divisions: [N, N, N]}}`, isotropic
E = 1, nu = 0.3, the face x = 0 clamped (ux = uy = uz = 0), a uniform shear traction
(0, -1e-3, 0) on the face x = 1 (a short cantilever), `solver: {type: amg, tolerance: 1e-8}`
(hypre PCG + BoomerAMG with the rigid-body modes; --solver-keys adds keys to that map). Each
size runs `mixcon run FILE` alone under `/usr/bin/time -v` (peak memory: "Maximum resident set
size"), one run at a time; the table has N, unknowns, PCG iterations, assembly, AMG setup and
solve seconds (mixcon's own log lines and summary.json), the whole run's wall time and its peak
resident memory.

Before a size is run, its peak memory is extrapolated linearly in the unknowns from the two
largest sizes run so far; a size whose estimate exceeds --max-gb is skipped (and said so), and a
run longer than --timeout seconds is stopped, its process group killed, and the sweep ends there.

--calculix SIZES runs the same cube in CalculiX (ccx, Debian `calculix-ccx`): C3D8 elements (full
integration, as mixcon's Hex8), the same material, the clamped face, the traction as its
consistent nodal forces (*CLOAD: h^2 t at interior nodes of the face, half on its edges, a quarter
at its corners, exact for a uniform traction on bilinear faces), solved with SPOOLES (ccx's
direct solver) and with `*STATIC, SOLVER=ITERATIVE CHOLESKY`; ccx runs with OMP_NUM_THREADS and
CCX_NPROC_EQUATION_SOLVER set to --threads. For these sizes mixcon writes results.h5 too, and
the displacement of the loaded face (its centre node's uy and the largest |u| on it) is
compared between the codes.

Usage: python3 bench/cube_hex8.py [--mixcon build/apps/mixcon] [--sizes 16,24,32,48,64,80,100]
       [--threads 2] [--calculix 16,24,32] [--out out/cube_hex8] [--json FILE]
Writes <out>/cube_hex8.md (the tables) and, with --json, the rows as JSON.
"""
import argparse
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
E, NU, TRACTION = 1.0, 0.3, -1e-3


def timed(cmd, cwd, env, timeout):
    """Runs cmd under /usr/bin/time -v in its own process group; returns (rc, wall s, peak GB,
    output). rc is None when the run was stopped after `timeout` seconds."""
    t0 = time.perf_counter()
    p = subprocess.Popen(["/usr/bin/time", "-v"] + cmd, cwd=cwd, env=env, stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True, start_new_session=True)
    try:
        out, _ = p.communicate(timeout=timeout)
        rc = p.returncode
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        out, _ = p.communicate()
        rc = None
    wall = time.perf_counter() - t0
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", out)
    peak = int(m.group(1)) / 1024 ** 2 if m else float("nan")
    return rc, wall, peak, out


def face_displacement(nodes, u):
    """(uy at the node closest to the centre of the face x = 1, largest |u| on that face)."""
    face = np.abs(nodes[:, 0] - 1.0) < 1e-9
    centre = np.argmin(np.where(face, np.hypot(nodes[:, 1] - 0.5, nodes[:, 2] - 0.5), np.inf))
    return float(u[centre, 1]), float(np.max(np.linalg.norm(u[face], axis=1)))


def mixcon_run(binary, n, out, env, hdf5, timeout, solver_keys=""):
    d = os.path.join(out, f"mixcon_n{n}")
    os.makedirs(d, exist_ok=True)
    problem = os.path.join(d, "cube.yaml")
    with open(problem, "w") as f:
        f.write(f"""title: unit cube {n}^3 Hex8 (bench/cube_hex8.py)
mesh:
  generator: {{type: box, size: [1, 1, 1], divisions: [{n}, {n}, {n}]}}
materials:
  - {{region: body, type: isotropic, E: {E}, nu: {NU}}}
boundary_conditions:
  - {{boundary: xmin, ux: 0, uy: 0, uz: 0}}
loads:
  - {{boundary: xmax, traction: [0, {TRACTION}, 0]}}
solver: {{type: amg, tolerance: 1e-8{", " + solver_keys if solver_keys else ""}}}
output: {{directory: {os.path.join(d, "out")}, hdf5: {"true" if hdf5 else "false"}}}
""")
    rc, wall, peak, log = timed([binary, "run", problem], d, env, timeout)
    open(os.path.join(d, "log.txt"), "w").write(log)
    row = {"code": "mixcon", "N": n, "rc": rc, "wall_s": wall, "peak_gb": peak}
    if rc != 0:
        return row, log
    m = re.search(r"(\d+) unknowns", log)
    row["unknowns"] = int(m.group(1))
    m = re.search(r"assembly ([\d.e+-]+) s, solver setup ([\d.e+-]+) s", log)
    row["assembly_s"], row["setup_s"] = float(m.group(1)), float(m.group(2))
    m = re.search(r"linear its (\d+)", log)
    row["iterations"] = int(m.group(1))
    summary = json.load(open(os.path.join(d, "out", "summary.json")))
    step = summary["steps"][-1]
    row["solve_s"] = step["solve_seconds"]
    row["summary_iterations"] = step["linear_iterations"]
    if hdf5:
        import h5py  # only needed for the comparison with CalculiX
        with h5py.File(os.path.join(d, "out", "results.h5"), "r") as f:
            row["tip_uy"], row["face_max_u"] = face_displacement(
                f["mesh/nodes"][:], f[f"steps/{len(summary['steps'])}/displacement"][:])
    return row, log


def calculix_deck(n, path, iterative):
    """The cube as a CalculiX deck: nodes (i, j, k) numbered 1 + i + (n+1)(j + (n+1)k)."""
    m = n + 1
    h = 1.0 / n
    nid = lambda i, j, k: 1 + i + m * (j + m * k)  # noqa: E731
    lines = ["*HEADING", f"unit cube {n}^3 C3D8 (bench/cube_hex8.py)", "*NODE"]
    lines += [f"{nid(i, j, k)}, {i * h:.15g}, {j * h:.15g}, {k * h:.15g}"
              for k in range(m) for j in range(m) for i in range(m)]
    lines.append("*ELEMENT, TYPE=C3D8, ELSET=EALL")
    e = 0
    for k in range(n):
        for j in range(n):
            for i in range(n):
                e += 1
                c = [nid(i, j, k), nid(i + 1, j, k), nid(i + 1, j + 1, k), nid(i, j + 1, k),
                     nid(i, j, k + 1), nid(i + 1, j, k + 1), nid(i + 1, j + 1, k + 1),
                     nid(i, j + 1, k + 1)]
                lines.append(f"{e}, " + ", ".join(map(str, c)))

    def listing(header, ids):
        lines.append(header)
        ids = list(ids)
        lines.extend(", ".join(str(i) for i in ids[k:k + 16]) for k in range(0, len(ids), 16))

    listing("*NSET, NSET=FIX", [nid(0, j, k) for k in range(m) for j in range(m)])
    listing("*NSET, NSET=TIP", [nid(n, j, k) for k in range(m) for j in range(m)])
    solver = "ITERATIVE CHOLESKY" if iterative else "SPOOLES"
    lines += ["*MATERIAL, NAME=M", "*ELASTIC", f"{E}, {NU}",
              "*SOLID SECTION, ELSET=EALL, MATERIAL=M", "*BOUNDARY", "FIX, 1, 3, 0.",
              "*STEP", f"*STATIC, SOLVER={solver}", "*CLOAD"]
    for k in range(m):
        for j in range(m):
            w = (0.5 if j in (0, n) else 1.0) * (0.5 if k in (0, n) else 1.0)
            lines.append(f"{nid(n, j, k)}, 2, {TRACTION * h * h * w:.12g}")
    lines += ["*NODE PRINT, NSET=TIP", "U", "*END STEP"]
    with open(path, "w") as out:
        out.write("\n".join(lines) + "\n")


def calculix_run(n, out, threads, iterative, timeout):
    name = f"cube_n{n}_{'iterative' if iterative else 'spooles'}"
    d = os.path.join(out, "calculix")
    os.makedirs(d, exist_ok=True)
    calculix_deck(n, os.path.join(d, name + ".inp"), iterative)
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), CCX_NPROC_EQUATION_SOLVER=str(threads))
    rc, wall, peak, log = timed(["ccx", name], d, env, timeout)
    open(os.path.join(d, name + ".log"), "w").write(log)
    row = {"code": "calculix", "solver": "iterative cholesky" if iterative else "spooles",
           "N": n, "rc": rc, "wall_s": wall, "peak_gb": peak, "unknowns": 3 * (n + 1) ** 3}
    if rc != 0 or "*ERROR" in log:
        row["rc"] = rc if rc else 1
        return row, log
    # The .dat file: a header line, a blank line, then "node ux uy uz" for every node of TIP.
    dat = open(os.path.join(d, name + ".dat")).read().split("displacements")[-1].splitlines()
    rows = [r.split() for r in dat[1:] if len(r.split()) == 4]
    ids = np.array([int(r[0]) for r in rows])
    u = np.array([[float(v) for v in r[1:]] for r in rows])
    m = n + 1
    j, k = (ids - 1) // m % m, (ids - 1) // (m * m)
    nodes = np.column_stack([np.ones(len(ids)), j / n, k / n])
    row["tip_uy"], row["face_max_u"] = face_displacement(nodes, u)
    return row, log


def fmt(v, spec):
    return format(v, spec) if isinstance(v, (int, float)) else "-"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mixcon", default=os.path.join(ROOT, "build", "apps", "mixcon"))
    ap.add_argument("--sizes", default="16,24,32,48,64,80,100",
                    help="comma-separated N for mixcon ('' for none)")
    ap.add_argument("--threads", type=int, default=2, help="OMP_NUM_THREADS of every run")
    ap.add_argument("--calculix", default="", help="comma-separated N for the CalculiX comparison")
    ap.add_argument("--calculix-solvers", default="spooles,iterative")
    ap.add_argument("--max-gb", type=float, default=16.0,
                    help="skip a size whose extrapolated peak memory exceeds this")
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds per run")
    ap.add_argument("--solver-keys", default="",
                    help="more keys of mixcon's solver map, e.g. 'interpolation_max_elements: 4'")
    ap.add_argument("--out", default=os.path.join("out", "cube_hex8"))
    ap.add_argument("--json", help="also write every row to this JSON file")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    env = dict(os.environ, OMP_NUM_THREADS=str(args.threads))
    sizes = [int(s) for s in args.sizes.split(",") if s]
    ccx_sizes = [int(s) for s in args.calculix.split(",") if s]
    if ccx_sizes and not shutil.which("ccx"):
        sys.exit("ccx not found: apt-get install calculix-ccx")
    rows, text = [], []

    if sizes:
        text += ["| N | unknowns | PCG its | assembly s | AMG setup s | solve s | wall s | "
                 "peak RSS GB |", "|---|---|---|---|---|---|---|---|"]
    done = []
    for n in sizes:
        unknowns = 3 * (n + 1) ** 3
        if len(done) >= 2:
            (u0, g0), (u1, g1) = done[-2], done[-1]
            estimate = g1 + (g1 - g0) / (u1 - u0) * (unknowns - u1)
            print(f"N = {n}: estimated peak {estimate:.2f} GB", flush=True)
            if estimate > args.max_gb:
                text.append(f"| {n} | {unknowns:,} | skipped: estimated peak {estimate:.1f} GB > "
                            f"{args.max_gb} GB | | | | | |")
                continue
        row, log = mixcon_run(args.mixcon, n, args.out, env, n in ccx_sizes, args.timeout,
                              args.solver_keys)
        rows.append(row)
        if row["rc"] != 0:
            why = "stopped after the time limit" if row["rc"] is None else f"exit {row['rc']}"
            print(f"N = {n}: {why}\n{log[-1500:]}", flush=True)
            text.append(f"| {n} | {unknowns:,} | {why} after {row['wall_s']:.0f} s | | | | | |")
            break
        done.append((row["unknowns"], row["peak_gb"]))
        line = (f"| {n} | {row['unknowns']:,} | {row['iterations']} | {row['assembly_s']:.2f} | "
                f"{row['setup_s']:.2f} | {row['solve_s']:.2f} | {row['wall_s']:.2f} | "
                f"{row['peak_gb']:.2f} |")
        print(line, flush=True)
        text.append(line)

    if ccx_sizes:
        text += ["| N | unknowns | code, solver | wall s | peak RSS GB | centre uy of x = 1 | "
                 "max abs u on x = 1 | uy / mixcon - 1 |", "|---|---|---|---|---|---|---|---|"]
        if sizes:
            text.insert(len(text) - 2, "")
        for n in ccx_sizes:
            base = next((r for r in rows if r["code"] == "mixcon" and r["N"] == n
                         and "tip_uy" in r), None)
            if base is None:
                base, _ = mixcon_run(args.mixcon, n, args.out, env, True, args.timeout,
                                     args.solver_keys)
                rows.append(base)
            cases = [base]
            for s in args.calculix_solvers.split(","):
                row, log = calculix_run(n, args.out, args.threads, s == "iterative", args.timeout)
                rows.append(row)
                if row["rc"] != 0:
                    print(f"ccx N = {n} {s}: rc {row['rc']}\n{log[-1500:]}", flush=True)
                cases.append(row)
            for r in cases:
                label = "mixcon, AMG-PCG" if r["code"] == "mixcon" else f"CalculiX, {r['solver']}"
                if r["rc"] != 0 or "tip_uy" not in r:
                    why = "stopped after the time limit" if r["rc"] is None else f"exit {r['rc']}"
                    text.append(f"| {n} | {3 * (n + 1) ** 3:,} | {label} | {why} after "
                                f"{r['wall_s']:.0f} s | {fmt(r['peak_gb'], '.2f')} | | | |")
                    continue
                rel = r["tip_uy"] / base["tip_uy"] - 1 if "tip_uy" in base else float("nan")
                line = (f"| {n} | {3 * (n + 1) ** 3:,} | {label} | {r['wall_s']:.2f} | "
                        f"{r['peak_gb']:.2f} | {r['tip_uy']:.6e} | {r['face_max_u']:.6e} | "
                        f"{rel:+.1e} |")
                print(line, flush=True)
                text.append(line)

    body = "\n".join(text) + "\n"
    open(os.path.join(args.out, "cube_hex8.md"), "w").write(body)
    print(body)
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"threads": args.threads, "solver_keys": args.solver_keys, "rows": rows}, f,
                      indent=1)


if __name__ == "__main__":
    main()
