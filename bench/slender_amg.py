#!/usr/bin/python3
"""Evidence for issue 20 (AMG for slender structures, hierarchy reuse), run through `mixcon run`.

  linear     PCG/GMRES iterations of linear strips of L/h = 10, 100, 1000, 10000 (Quad8, 2 elements
             through the depth h = 1, square elements, clamped left end, transverse traction on the
             top edge, E = 1e4, nu = 0.3, plane stress), displacement and linear mixed model, for
             five solver settings: old AMG (no rigid-body modes, coarsest 9, no direct fall back),
             the default, coarsest_size 500 and 2000 (with the rigid-body modes), and the default
             with `coarse_space: rigid_body`, and more (--settings picks them by letter; (b), the
             default, takes the direct solver where it is estimated cheaper, (i) does not). With --dim 3:
             the strips as solids of square section h x h (Hex20, 2 x 2 through the section,
             clamped face xmin, traction on ymax), both models (--models).
  nonlinear  examples/cantilever/slender_{displacement,mixed}.yaml at divisions [200, 2] with
             solver amg and direct (and the mixed one with stabilization 0.05): Newton and linear
             iterations, wall time, the solver's notes, tip deflection w/L against the elastica.
  reuse      reuse_hierarchy true against false on runs with many corrections, alternated.

Every run writes its problem file under --out and runs the binary; the step lines ("linear its",
"residual") and the solver notes (any stdout/stderr line that mentions the AMG, a rebuild or the
direct solver) are parsed. Prints markdown tables.
Usage: /usr/bin/python3 bench/slender_amg.py {linear,nonlinear,reuse} [--mixcon build/apps/mixcon]
       [--out out/slender_amg] [--lh 10 100 1000 10000] [--rounds 3] [--timeout 600] [--dim 3]
       [--settings abcde]
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import time

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

SETTINGS = [
    ("(a) old AMG", {"rigid_body_modes": False, "direct_fallback": False, "coarsest_size": 9}),
    ("(b) default", {}),  # since 2026-12-01: the direct solver where estimated cheaper, then the
    # coarse space; (c)-(h) keep the ladder without the estimate (direct_when_cheaper: false)
    ("(c) coarsest 500", {"coarsest_size": 500, "direct_when_cheaper": False}),
    ("(d) coarsest 2000", {"coarsest_size": 2000, "direct_when_cheaper": False}),
    ("(e) rigid-body coarse space", {"coarse_space": "rigid_body", "direct_when_cheaper": False}),
    ("(f) separate components", {"amg_matrix": "separate_components", "direct_when_cheaper": False}),
    ("(g) no coarse space (the default before 2026-11-29)", {"coarse_space": "none", "direct_when_cheaper": False}),
    ("(h) hypre's V-cycle (the default before `amg_cycle`)", {"amg_cycle": "hypre", "direct_when_cheaper": False}),
    ("(i) the ladder without the direct solver's estimate (the default before 2026-12-01)",
     {"direct_when_cheaper": False}),
]

STEP = re.compile(r"^step (\d+)/(\d+).*?iterations (\d+)\s+cuts (\d+)\s+linear its (\d+)\s+"
                  r"residual (\S+)\s+(\S+)")
NOTE = re.compile(r"AMG|rebuilt|direct|fall", re.I)


def run(binary, problem, out, timeout, hdf5=False):
    """Runs mixcon on a problem dict; returns a dict of what the run printed and wrote."""
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, "problem.yaml")
    problem = dict(problem)
    problem["output"] = {"directory": os.path.join(out, "res"), "hdf5": hdf5}
    with open(path, "w") as f:
        yaml.safe_dump(problem, f, sort_keys=False)
    t0 = time.perf_counter()
    try:
        p = subprocess.run([binary, "run", path], capture_output=True, text=True, timeout=timeout)
        rc, text = p.returncode, p.stdout + p.stderr
    except subprocess.TimeoutExpired as e:
        rc, text = "timeout", (e.stdout or b"").decode() if isinstance(e.stdout, bytes) else ""
    wall = time.perf_counter() - t0
    steps = [m.groups() for m in map(STEP.match, text.splitlines()) if m]
    notes = [l.strip() for l in text.splitlines() if NOTE.search(l) and l.startswith("    ")]
    summary = {}
    try:
        with open(os.path.join(out, "res", "summary.json")) as f:
            summary = json.load(f)
    except (OSError, ValueError):
        pass
    return {"rc": rc, "wall": wall, "text": text, "steps": steps, "notes": notes,
            "summary": summary}


def strip(lh, formulation, solver, dim=2):
    if dim == 3:  # the same strip as a solid of square section h x h, 2 x 2 Hex20 through it
        return {
            "title": f"solid strip L/h = {lh}",
            "mesh": {"generator": {"type": "box", "size": [float(lh), 1.0, 1.0],
                                   "divisions": [2 * lh, 2, 2], "element": "hex20"}},
            "model": {"formulation": formulation},
            "materials": [{"region": "body", "type": "isotropic", "E": 1.0e4, "nu": 0.3}],
            "boundary_conditions": [{"boundary": "xmin", "ux": 0, "uy": 0, "uz": 0}],
            "loads": [{"boundary": "ymax", "traction": [0, -1.0e-3, 0]}],
            "solver": dict({"type": "amg", "max_iterations": 3000}, **solver),
        }
    return {
        "title": f"strip L/h = {lh}",
        "mesh": {"generator": {"type": "rectangle", "size": [float(lh), 1.0], "origin": [0, 0],
                               "divisions": [2 * lh, 2], "element": "quad8"}},
        "model": {"formulation": formulation, "analysis": "plane_stress", "thickness": 1.0},
        "materials": [{"region": "body", "type": "isotropic", "E": 1.0e4, "nu": 0.3}],
        "boundary_conditions": [{"boundary": "left", "ux": 0, "uy": 0}],
        "loads": [{"boundary": "top", "traction": [0, -1.0e-3]}],
        "solver": dict({"type": "amg", "max_iterations": 3000}, **solver),
    }


def short(note):
    m = re.search(r"coarsest level of up to (\d+)", note)
    if m:
        return f"->{m.group(1)}"
    if "falling back to the direct" in note:
        return "->direct"
    return note


def linear(args):
    print("| model | L/h | unknowns | setting | linear its | converged | residual | s | ladder |")
    print("|---|---|---|---|---|---|---|---|---|")
    for formulation in args.models:
        for lh in args.lh:
            for name, s in SETTINGS:
                if name[1] not in args.settings or (name[1] == "i" and formulation == "mixed"):
                    continue  # (i): the mixed models' AMG is a preconditioner; the key is refused
                out = os.path.join(args.out, f"linear{args.dim}d", f"{formulation}_{lh}_{name[1]}")
                keys = dict(s, **({"tolerance": args.tolerance} if args.tolerance else {}))
                if formulation == "mixed" and args.dim == 2:  # the linear 2D mixed model has no
                    # direct fall back, and refuses the key
                    keys.pop("direct_when_cheaper", None)
                r = run(args.mixcon, strip(lh, formulation, keys, args.dim), out, args.timeout)
                m = re.search(r"(\d+) unknowns", r["text"])
                st = r["steps"][-1] if r["steps"] else None
                its = st[4] if st else "-"
                conv = st[6] if st else f"rc {r['rc']}"
                res = st[5] if st else "-"
                ladder = " ".join(short(n) for n in r["notes"]) or "none"
                print(f"| {formulation} | {lh} | {m.group(1) if m else '?'} | {name} | {its} | "
                      f"{conv} (rc {r['rc']}) | {res} | {r['wall']:.2f} | {ladder} |", flush=True)


def tip(out, length):
    """Tip deflection w/L at the last written step: mean -u_y of the nodes at x = L."""
    import h5py  # only here: the linear tables need no HDF5 reader
    import numpy as np
    d = os.path.join(out, "res", "results.d")
    try:
        xy = h5py.File(os.path.join(d, "mesh.h5"), "r")["mesh/nodes"][:]
        f = h5py.File(os.path.join(d, sorted(x for x in os.listdir(d) if x.startswith("step"))[-1]), "r")
        last = max(f["steps"].keys(), key=int)
        u = f[f"steps/{last}/displacement"][:]
    except (OSError, IndexError, KeyError, ValueError):
        return None
    at = np.abs(xy[:, 0] - xy[:, 0].max()) < 1e-9
    return -u[at, 1].mean() / length


def example(name):
    with open(os.path.join(ROOT, "examples", name)) as f:
        return yaml.safe_load(f)


def totals(r):
    st = r["summary"].get("steps", [])
    return (sum(x.get("iterations", 0) for x in st), sum(x.get("linear_iterations", 0) for x in st),
            sum(x.get("setup_seconds", 0) for x in st), st[-1]["load_factor"] if st else 0)


def nonlinear(args):
    print("| file | solver | converged (rc) | last load factor | Newton its | linear its | wall s "
          "| w/L (elastica 0.70020) | solver notes |")
    print("|---|---|---|---|---|---|---|---|---|")
    # the ladder before 2026-11-29, and before 2026-12-01 (no direct solver's estimate)
    none = {"type": "amg", "coarse_space": "none", "direct_when_cheaper": False}
    ladder = {"type": "amg", "direct_when_cheaper": False}
    cases = [("slender_displacement.yaml", {"type": "amg"}, None),
             ("slender_displacement.yaml", none, None),
             ("slender_displacement.yaml", {"type": "direct"}, None),
             ("slender_mixed.yaml", {"type": "amg"}, None),
             ("slender_mixed.yaml", none, None),
             ("slender_mixed.yaml", {"type": "direct"}, None),
             ("slender_mixed.yaml", {"type": "amg"}, 0.05),
             ("slender_mixed.yaml", none, 0.05),
             ("slender_mixed.yaml", {"type": "direct"}, 0.05),
             ("slender_displacement.yaml", ladder, None),
             ("slender_mixed.yaml", ladder, None),
             ("slender_mixed.yaml", ladder, 0.05)]
    if args.cases:
        cases = [cases[int(k)] for k in args.cases.split(",")]
    for name, solver, stab in cases:
        p = example("cantilever/" + name)
        p["mesh"]["generator"]["divisions"] = [200, 2]
        p["solver"] = solver
        if stab is not None:
            p["model"]["stabilization"] = stab
        label = (f"{name[:-5]}_{solver['type']}" + ("_nocoarse" if "coarse_space" in solver else "") +
                 ("_noestimate" if "direct_when_cheaper" in solver else "") +
                 (f"_stab{stab}" if stab is not None else ""))
        out = os.path.join(args.out, "nonlinear", label)
        r = run(args.mixcon, p, out, args.timeout, hdf5=True)
        newton, lin, _, lam = totals(r)
        w = tip(out, p["mesh"]["generator"]["size"][0])
        notes = "; ".join(sorted(set(re.sub(r"load factor \S+, iteration \d+: ", "", n)
                                     for n in r["notes"])))
        print(f"| {name}" + (f" stabilization {stab}" if stab is not None else "") +
              f" | {solver['type']}" + (", coarse_space: none" if "coarse_space" in solver else "") +
              (", direct_when_cheaper: false" if "direct_when_cheaper" in solver else "") +
              f" | {r['summary'].get('converged')} ({r['rc']}) | {lam} | {newton} "
              f"| {lin} | {r['wall']:.2f} | {w if w is None else f'{w:.5f}'} | {notes or 'none'} |",
              flush=True)


def reuse(args):
    cases = [("hertz/hertz_refined.yaml", None), ("cantilever/report_displacement.yaml", None),
             ("elastic_contact/hertz_two_body.yaml", None)]
    print("| file (solver amg) | reuse_hierarchy | converged | Newton/contact corrections | linear its "
          "| setup s (sum) | wall s | rounds |")
    print("|---|---|---|---|---|---|---|---|")
    for name, _ in cases:
        rows = {True: [], False: []}
        for k in range(args.rounds):
            for flag in (True, False):
                p = example(name)
                p["solver"] = {"type": "amg", "reuse_hierarchy": flag}
                out = os.path.join(args.out, "reuse", f"{os.path.basename(name)[:-5]}_{flag}")
                r = run(args.mixcon, p, out, args.timeout)
                rows[flag].append((r, totals(r)))
        for flag in (True, False):
            rs = rows[flag]
            med = lambda xs: statistics.median(xs)
            print(f"| {name} | {flag} | {all(r['rc'] == 0 for r, _ in rs)} | "
                  f"{'/'.join(sorted(set(str(t[0]) for _, t in rs)))} | "
                  f"{'/'.join(sorted(set(str(t[1]) for _, t in rs)))} | "
                  f"{med([t[2] for _, t in rs]):.3f} | {med([r['wall'] for r, _ in rs]):.2f} "
                  f"(min {min(r['wall'] for r, _ in rs):.2f}) | {len(rs)} |", flush=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("what", choices=["linear", "nonlinear", "reuse"])
    ap.add_argument("--mixcon", default=os.path.join(ROOT, "build", "apps", "mixcon"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "slender_amg"))
    ap.add_argument("--lh", type=int, nargs="+", default=[10, 100, 1000, 10000])
    ap.add_argument("--models", nargs="+", default=["displacement", "mixed"])
    ap.add_argument("--dim", type=int, choices=[2, 3], default=2,
                    help="linear: 3 runs the strips as Hex20 solids of square section")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--tolerance", type=float, default=None,
                    help="linear: the solver tolerance (default mixcon's, 1e-8)")
    ap.add_argument("--settings", default="abcdefghi",
                    help="linear: the settings to run, by letter (default all: abcdefghi)")
    ap.add_argument("--cases", default="",
                    help="nonlinear: the cases to run, by index, comma-separated (default all)")
    ap.add_argument("--timeout", type=float, default=600)
    args = ap.parse_args()
    {"linear": linear, "nonlinear": nonlinear, "reuse": reuse}[args.what](args)


if __name__ == "__main__":
    main()
