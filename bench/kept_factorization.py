#!/usr/bin/env python3
"""Contact corrections on one kept factorization (issue 20; solver/CapacitanceSolve.hpp): the
shipped contact examples run with the default `solver: {type: direct}` (the kept factorization)
and with `reuse_factorization: false` (every correction factorized after elimination), in
alternating rounds. Per example: corrections, how many took the kept factorization
(summary.json `kept_factorization`), wall time of the whole run (/usr/bin/time) per round, the
ratio of the medians, and the largest difference of the nodal displacements and stresses over
all steps, relative to the largest value of the run without it.

Usage: python3 bench/kept_factorization.py [--mixcon build/apps/mixcon] [--rounds 3]
                                           [--out out/kept_factorization] [EXAMPLE ...]
EXAMPLE: a path under examples/ without .yaml (default: the contact examples below).
Prints a markdown table; needs h5py.
"""
import argparse
import json
import os
import re
import subprocess

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EXAMPLES = ["hertz/hertz_refined", "hertz/hertz_report", "cattaneo_mindlin/press_then_shear",
            "elastic_contact/hertz_two_body", "elastic_contact/pin_plate", "stages/press_slide",
            "wood_plate/report", "hybrid/hybrid"]


def run(mixcon, example, kept, out):
    """One run; returns (wall seconds, peak KB, summary, output folder)."""
    source = os.path.join(ROOT, "examples", example + ".yaml")
    text = open(source).read()
    if not kept:
        text, n = re.subn(r"^solver: \{type: (\w+)\}",
                          r"solver: {type: \1, reuse_factorization: false}", text, flags=re.M)
        assert n == 1, f"{example}: no one-line solver key to change"
    tag = "kept" if kept else "eliminated"
    # The file stays beside the example: its mesh and measured-data paths are relative.
    variant = os.path.join(os.path.dirname(source), f"_kept_factorization_{tag}.yaml")
    folder = os.path.join(out, example.replace("/", "_") + "_" + tag)
    with open(variant, "w") as f:
        f.write(text)
    try:
        r = subprocess.run(["/usr/bin/time", "-f", "%e %M", mixcon, "run", variant, "--output",
                            folder, "-q"], capture_output=True, text=True,
                           cwd=os.path.dirname(source))
    finally:
        os.remove(variant)
    if r.returncode != 0:
        raise SystemExit(f"{example} ({tag}) failed:\n{r.stdout[-2000:]}{r.stderr[-2000:]}")
    wall, kb = r.stderr.strip().split("\n")[-1].split()
    return float(wall), int(kb), json.load(open(os.path.join(folder, "summary.json"))), folder


def fields(folder):
    with h5py.File(os.path.join(folder, "results.h5"), "r") as h:
        return {(step, name): h["steps"][step][name][()] for step in h["steps"].keys()
                for name in ("displacement", "stress")}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mixcon", default=os.path.join(ROOT, "build", "apps", "mixcon"))
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--out", default=os.path.join("out", "kept_factorization"))
    ap.add_argument("examples", nargs="*", default=EXAMPLES)
    args = ap.parse_args()
    mixcon = os.path.abspath(args.mixcon)
    out = os.path.abspath(args.out)
    runs = {}
    for _ in range(args.rounds):
        for example in args.examples:
            for kept in (True, False):
                runs.setdefault((example, kept), []).append(run(mixcon, example, kept, out))
    print("| example | nodes | corrections | on the kept factorization / factorizations "
          "| kept: wall s | eliminated: wall s | ratio of medians | largest difference "
          "(displacement, stress) |")
    print("|---|---|---|---|---|---|---|---|")
    for example in args.examples:
        on, off = runs[(example, True)], runs[(example, False)]
        summary = on[-1][2]
        corrections = sum(s["iterations"] for s in summary["steps"])
        kept = summary.get("kept_factorization", {"corrections": 0, "factorizations": 0})
        a, b = fields(on[-1][3]), fields(off[-1][3])
        worst = {}
        for name in ("displacement", "stress"):
            scale = max(np.abs(v).max() for (s, n), v in b.items() if n == name)
            worst[name] = max(np.abs(a[k] - b[k]).max() for k in b if k[1] == name) / scale
        walls = lambda rs: " / ".join(f"{r[0]:.2f}" for r in rs)  # noqa: E731
        ratio = np.median([r[0] for r in off]) / np.median([r[0] for r in on])
        print(f"| {example} | {summary['nodes']} | {corrections} | {kept['corrections']} / "
              f"{kept['factorizations']} | {walls(on)} | {walls(off)} | {ratio:.2f} | "
              f"{worst['displacement']:.1e}, {worst['stress']:.1e} |")


if __name__ == "__main__":
    main()
