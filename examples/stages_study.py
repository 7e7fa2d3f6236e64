#!/usr/bin/env python3
"""Friction hysteresis of a load history (docs/problem-format.md, "stages"): runs mixcon on
examples/stages/press_slide.yaml (a block pressed onto a base, node-to-segment contact with
Coulomb friction mu = 0.3; its top driven down, then sideways to +a, back to -a, forth to +a,
back to the centre, then lifted) and plots the tangential reaction Q on the block's top against
its sideways displacement: the friction hysteresis loop. Writes hysteresis.csv and hysteresis.png.

Coulomb's law bounds the loop: |Q| <= mu P (P the normal reaction). What the history does, and
--check asserts:
  - gross slip at the ends of the sweeps: |Q| = mu P (within 1 %);
  - the interface sticks again after each reversal: Q changes with the stick stiffness of the
    first slide (within 5 %), every closed node in stick;
  - the loop closes: at +a after the full cycle, Q and the block's displacements equal those at
    +a after the first slide (1e-6);
  - back at the centre a friction force stays locked in (|Q| > mu P / 2), where a body without
    history would carry none;
  - lifted back to its start, the block lets go: P and Q below 1e-6 of the pressed P.

Usage: python3 examples/stages_study.py [--mixcon build/apps/mixcon] [--out out/stages] [--check]
"""
import argparse
import csv
import os
import sys

import h5py
import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from study_util import finish_figure, run_variant  # noqa: E402

MU = 0.3


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def history(result):
    """Per step: stage name, the top's ux, uy, Q (x reaction), P (compressive y reaction), the
    number of stick and slip nodes, and the displacement field."""
    rows = []
    with h5py.File(os.path.join(result, "results.h5"), "r") as f:
        x = f["mesh/nodes"][:]
        top = np.where(np.abs(x[:, 1] - x[:, 1].max()) < 1e-9)[0]  # the block's top edge
        for k in sorted(f["steps"].keys(), key=int):
            g = f["steps"][k]
            u, r = g["displacement"][:], g["reaction"][:]
            status = g["contact/status"][:]
            rows.append({"step": int(k), "stage": text(g.attrs["stage_name"]),
                         "time": float(g.attrs["time"]), "ux": u[top, 0].mean(),
                         "uy": u[top, 1].mean(), "Q": r[top, 0].sum(), "P": -r[top, 1].sum(),
                         "stick": int((status == 1).sum()), "slip": int((status == 2).sum()),
                         "u": u})
    return rows


def last_of(rows, stage):
    return [r for r in rows if r["stage"] == stage][-1]


def first_of(rows, stage):
    return [r for r in rows if r["stage"] == stage][0]


def checks(rows):
    """The assertions of the module docstring: a list of (what, passed, detail)."""
    out = []
    pressed = last_of(rows, "press")["P"]
    for stage in ("slide", "back", "forth"):
        r = last_of(rows, stage)
        ratio = abs(r["Q"]) / r["P"]
        out.append((f"gross slip at the end of '{stage}': |Q|/P = mu",
                    abs(ratio - MU) <= 0.01 * MU, f"|Q|/P = {ratio:.4f}"))
    # The stick stiffness: the first slide's first step, from the pressed state.
    s0 = first_of(rows, "slide")
    stiffness = s0["Q"] / s0["ux"]
    for before, stage in (("slide", "back"), ("back", "forth")):
        a, b = last_of(rows, before), first_of(rows, stage)
        slope = (b["Q"] - a["Q"]) / (b["ux"] - a["ux"])
        # The first step after the reversal sticks; the next ones stay on that slope.
        nxt = [r for r in rows if r["stage"] == stage][1]
        out.append((f"sticks after the reversal into '{stage}'",
                    abs(slope - stiffness) <= 0.05 * abs(stiffness) and nxt["slip"] == 0,
                    f"dQ/dux {slope:.2f} against {stiffness:.2f} at the start, "
                    f"{nxt['stick']} stick / {nxt['slip']} slip one step later"))
    a, b = last_of(rows, "slide"), last_of(rows, "forth")
    du = np.abs(a["u"] - b["u"]).max() / np.abs(a["u"]).max()
    out.append(("the loop closes at +a", abs(a["Q"] - b["Q"]) <= 1e-6 * abs(a["Q"]) and du <= 1e-6,
                f"Q {a['Q']:.6f} and {b['Q']:.6f}, displacements differ by {du:.1e}"))
    c = last_of(rows, "centre")
    out.append(("a friction force stays locked in at the centre", abs(c["Q"]) > 0.5 * MU * c["P"],
                f"Q = {c['Q']:.4f}, mu P = {MU * c['P']:.4f}"))
    e = rows[-1]
    out.append(("lifted, the block lets go",
                abs(e["P"]) <= 1e-6 * pressed and abs(e["Q"]) <= 1e-6 * pressed,
                f"P = {e['P']:.2e}, Q = {e['Q']:.2e} (pressed P = {pressed:.3f})"))
    return out


def plot(rows, path):
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    stages = []
    for r in rows:
        if r["stage"] not in stages:
            stages.append(r["stage"])
    previous = None
    for stage in stages:
        part = [r for r in rows if r["stage"] == stage]
        if previous is not None:
            part = [previous] + part
        ax.plot([1e3 * r["ux"] for r in part], [r["Q"] / (MU * r["P"]) if r["P"] > 1e-9 else 0.0
                                                for r in part], "o-", ms=3, label=stage)
        previous = part[-1]
    ax.axhline(1.0, color="0.5", lw=0.8, ls="--")
    ax.axhline(-1.0, color="0.5", lw=0.8, ls="--")
    finish_figure(fig, ax, path, "sideways displacement of the block's top  u_x  [1e-3]",
                  "tangential reaction  Q / (mu P)",
                  "Friction hysteresis of a load history (stages), mu = 0.3")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mixcon", default="build/apps/mixcon")
    ap.add_argument("--out", default="out/stages/study")
    ap.add_argument("--check", action="store_true", help="exit 1 when a check fails")
    a = ap.parse_args()
    result = run_variant(a.mixcon, os.path.join(HERE, "stages", "press_slide.yaml"), "press_slide",
                         a.out)
    rows = history(result)
    with open(os.path.join(a.out, "hysteresis.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["step", "stage", "time", "ux", "uy", "Q", "P", "stick", "slip"])
        for r in rows:
            w.writerow([r["step"], r["stage"], r["time"], r["ux"], r["uy"], r["Q"], r["P"],
                        r["stick"], r["slip"]])
    plot(rows, os.path.join(a.out, "hysteresis.png"))
    failed = 0
    for what, passed, detail in checks(rows):
        print(f"{'ok  ' if passed else 'FAIL'} {what}: {detail}")
        failed += not passed
    print(f"wrote {a.out}/hysteresis.csv, {a.out}/hysteresis.png")
    if a.check and failed:
        sys.exit(1)


if __name__ == "__main__":
    main()
