#!/usr/bin/python3
"""Issue 20, section 1c of docs/performance.md: the 3D displacement model's AMG on thin and bulky
parts, through `mixcon run`, for one or more binaries (alternated per problem).

Problems: the shipped 3D examples with `solver: {type: amg}` forced (plate_hole_3d in Hex20 and
Hex8, cantilever_3d{,_hex20,_tet10}, lame_sphere, lame_cylinder_3d, bracket_3d, NAFEMS LE10), the
plate with a hole refined ([24, 24] in plane with 4 layers, Hex8 and Hex20; [48, 48] with 4 layers
of Hex20; [64, 64] with 8 layers of Hex8; the example's overall grading 1.3^5 spread over the
radial divisions), a thick version of it (length 5, 6 layers, Hex20) and boxes (Hex8 N^3 clamped
at xmin with a traction on xmax, Hex20 12^3, Tet10 16^3 and 24^3). Each run's linear iterations,
AMG setup and solve seconds (summary.json), wall seconds, peak memory (/usr/bin/time) and the
solver's notes are printed as JSON lines and, at the end, as a markdown table.

Usage: /usr/bin/python3 bench/amg_3d_shapes.py [--mixcon NAME=BIN ...] [--problems a,b]
       [--keys '{"aggressive_levels": 1}'] [--out out/amg_3d_shapes]
A binary built elsewhere runs with its own libraries: NAME=BIN:LIBDIR sets LD_LIBRARY_PATH.
"""
import argparse
import json
import os
import re
import subprocess
import time

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLES = os.path.join(ROOT, "examples")


def example(name):
    path = os.path.join(EXAMPLES, name)
    with open(path) as f:
        d = yaml.safe_load(f)
    mesh = d.get("mesh", {})
    if "file" in mesh and not os.path.isabs(mesh["file"]):
        mesh["file"] = os.path.join(os.path.dirname(path), mesh["file"])
    return d


def plate(divisions, thickness, layers, element="hex20"):
    d = example("plate_hole_3d.yaml")
    g = d["mesh"]["generator"]
    g.update(divisions=divisions, element=element, extrude={"length": thickness, "divisions": layers})
    g["grading"] = round(1.3 ** (5.0 / (divisions[0] - 1)), 4)  # the example's overall grading
    return d


def box(n, element="hex8"):
    return {"title": f"box {n}^3 {element}",
            "mesh": {"generator": {"type": "box", "size": [1, 1, 1], "divisions": [n, n, n],
                                   "element": element}},
            "materials": [{"region": "body", "type": "isotropic", "E": 1000, "nu": 0.3}],
            "boundary_conditions": [{"boundary": "xmin", "ux": 0, "uy": 0, "uz": 0}],
            "loads": [{"boundary": "xmax", "traction": [1, 0.5, 0]}]}


PROBLEMS = {
    "plate_hex20": lambda: plate([6, 6], 0.2, 2),
    "plate_hex8": lambda: plate([6, 6], 0.2, 2, "hex8"),
    "thick_plate_hex20": lambda: plate([6, 6], 5.0, 6),
    "cantilever_3d": lambda: example("cantilever_3d.yaml"),
    "cantilever_3d_hex20": lambda: example("cantilever_3d_hex20.yaml"),
    "cantilever_3d_tet10": lambda: example("cantilever_3d_tet10.yaml"),
    "lame_sphere": lambda: example("lame_sphere.yaml"),
    "lame_cylinder_3d": lambda: example("lame_cylinder_3d.yaml"),
    "bracket": lambda: example("bracket_3d/bracket.yaml"),
    "le10": lambda: example("nafems_le10/le10.yaml"),
    "plate_hex8_24": lambda: plate([24, 24], 0.2, 4, "hex8"),
    "plate_hex20_24": lambda: plate([24, 24], 0.2, 4),
    "box_hex20_12": lambda: box(12, "hex20"),
    "box_tet10_16": lambda: box(16, "tet10"),
    "box_hex8_24": lambda: box(24),
    "box_hex8_32": lambda: box(32),
    "plate_hex8_64": lambda: plate([64, 64], 0.2, 8, "hex8"),
    "plate_hex20_48": lambda: plate([48, 48], 0.2, 4),
    "box_tet10_24": lambda: box(24, "tet10"),
    "box_hex8_48": lambda: box(48),
}

NOTE = re.compile(r"AMG|interpolation vectors|3D AMG settings")


def run(binary, libdir, name, keys, out):
    d = PROBLEMS[name]()
    solver = dict(d.get("solver") or {})
    solver["type"] = "amg"
    solver.update(keys)
    d["solver"] = solver
    directory = os.path.join(out, name)
    os.makedirs(directory, exist_ok=True)
    d["output"] = {"directory": directory}
    problem = os.path.join(directory, "problem.yaml")
    with open(problem, "w") as f:
        yaml.safe_dump(d, f)
    summary = os.path.join(directory, "summary.json")
    if os.path.exists(summary):
        os.remove(summary)
    env = dict(os.environ, OMP_NUM_THREADS=os.environ.get("OMP_NUM_THREADS", "2"),
               OMP_WAIT_POLICY="passive")
    if libdir:
        env["LD_LIBRARY_PATH"] = libdir
    start = time.time()
    p = subprocess.run(["/usr/bin/time", "-f", "peak-kB %M", binary, "run", problem],
                       capture_output=True, text=True, env=env)
    wall = time.time() - start
    text = p.stdout + p.stderr
    row = {"problem": name, "rc": p.returncode, "wall": round(wall, 2)}
    m = re.search(r"(\d+) unknowns", text)
    row["unknowns"] = int(m.group(1)) if m else None
    m = re.search(r"peak-kB (\d+)", text)
    row["peak_MB"] = int(m.group(1)) // 1024 if m else None
    if os.path.exists(summary):
        with open(summary) as f:
            steps = json.load(f)["steps"]
        row["iterations"] = sum(s["linear_iterations"] for s in steps)
        row["setup"] = round(sum(s["setup_seconds"] for s in steps), 3)
        row["solve"] = round(sum(s["solve_seconds"] for s in steps), 3)
    row["notes"] = [line.strip() for line in text.splitlines() if NOTE.search(line)]
    return row


def main():
    a = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    a.add_argument("--mixcon", nargs="+", default=["new=" + os.path.join(ROOT, "build/apps/mixcon")])
    a.add_argument("--problems", default=",".join(PROBLEMS))
    a.add_argument("--keys", default="{}", help="solver keys on top of the defaults (JSON)")
    a.add_argument("--out", default=os.path.join(ROOT, "out/amg_3d_shapes"))
    args = a.parse_args()
    keys = json.loads(args.keys)
    binaries = []
    for spec in args.mixcon:
        label, _, path = spec.partition("=")
        path, _, libdir = path.partition(":")
        binaries.append((label, os.path.abspath(path), libdir))
    rows = []
    for name in args.problems.split(","):
        for label, binary, libdir in binaries:
            r = run(binary, libdir, name, keys, os.path.join(args.out, label))
            r["binary"] = label
            print(json.dumps(r), flush=True)
            rows.append(r)
    print("\n| problem | unknowns | " + " | ".join(
        f"{b[0]}: its, setup + solve s, wall s, MB" for b in binaries) + " |")
    print("|---|---|" + "---|" * len(binaries))
    for name in args.problems.split(","):
        cells = []
        for label, _, _ in binaries:
            r = next(x for x in rows if x["problem"] == name and x["binary"] == label)
            cells.append(f"{r.get('iterations')}, {r.get('setup')} + {r.get('solve')}, {r['wall']}, "
                         f"{r['peak_MB']}" + ("" if r["rc"] == 0 else f" (exit {r['rc']})"))
        unknowns = next(x["unknowns"] for x in rows if x["problem"] == name)
        print(f"| {name} | {unknowns} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
