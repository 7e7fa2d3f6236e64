#!/usr/bin/env python3
"""Elastic-elastic node-to-segment contact studies (issue 6): runs mixcon on
examples/elastic_contact/hertz_two_body.yaml (an elastic cylinder pressed on an elastic block)
and compares the contact pressure and half-width with the two-body Hertz solution
    1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2,  b = sqrt(4 P R / (pi E*)),  p0 = 2 P / (pi b)
(P: load per unit length on the whole cylinder, twice the quarter model's reaction), with the
contact pressure taken from the contactor's nodal multipliers (force over the node's share of
the contactor boundary) and p0, b fitted to the Hertz shape. Also runs the swapped surfaces (the
cylinder as contactor) and a stiff block (E2 x 1000, the target: the rigid-plane limit).
Writes hertz_two_body.csv and hertz_two_body.png.

Usage: python3 examples/elastic_contact_study.py [--mixcon build/apps/mixcon] [--out DIR] [--check]
"""
import argparse
import csv
import json
import os
import sys

import h5py
import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from hertz_study import contact_rows, loads  # noqa: E402
from study_util import run_variant  # noqa: E402

R = 1.0
E1, NU1 = 21000.0, 0.3
E2, NU2 = 10500.0, 0.25


def hertz(P, e2=E2):
    estar = 1.0 / ((1 - NU1 ** 2) / E1 + (1 - NU2 ** 2) / e2)
    b = np.sqrt(4 * P * R / (np.pi * estar))
    return b, 2 * P / (np.pi * b)


def amg_iterations(args, source):
    """The constraints are eliminated (x = T y + s), so the contact problem's matrix stays SPD:
    BoomerAMG-PCG iterations per Newton correction with contact against the same two bodies
    without the contact section (each then loaded on its own), on three meshes."""
    levels = ((0.5, "coarse"), (1, "medium"), (2, "fine"))
    with open(os.path.join(args.out, "amg_iterations.csv"), "w", newline="") as fp:
        w = csv.writer(fp)
        w.writerow(["mesh", "unknowns", "contact", "corrections", "pcg_iterations",
                    "per_correction", "max_per_step"])
        for scale, label in levels:
            subs = [("divisions: [48, 32]", f"divisions: [{int(48 * scale)}, {int(32 * scale)}]"),
                    ("divisions: [80, 48]", f"divisions: [{int(80 * scale)}, {int(48 * scale)}]"),
                    ("solver: {type: direct}", "solver: {type: amg}")]
            nocontact = subs + [("  - {type: node_to_segment, contactor: block.bottom, target: "
                                 "cylinder.arc, friction: 0}\n", ""), ("contact:\n", "")]
            for tag, sub in (("yes", subs), ("no", nocontact)):
                result = run_variant(args.mixcon, source, f"amg_{label}_{tag}", args.out, sub)
                summary = json.load(open(os.path.join(result, "summary.json")))
                its = sum(st["linear_iterations"] for st in summary["steps"])
                corr = sum(st["iterations"] for st in summary["steps"])
                worst = max(st["linear_iterations"] / max(st["iterations"], 1)
                            for st in summary["steps"])
                w.writerow([label, 2 * summary["nodes"], tag, corr, its, f"{its / corr:.1f}",
                            f"{worst:.1f}"])
                print(f"AMG {label} ({2 * summary['nodes']} unknowns), contact {tag}: {corr} "
                      f"corrections, {its / corr:.1f} PCG iterations per correction")


def contact_by_node(result):
    """Last step's rows of contact.csv by node id."""
    steps = contact_rows(result)
    return {r["node_id"]: r for r in steps[max(steps)]}


def pin_plate(args):
    """The pin-loaded wood plate with an elastic pin of growing modulus against the rigid,
    force-driven pin of examples/wood_plate/report.yaml (same plate, same 200 lb, both with
    small displacements and Newton iterations): the hole nodes' contact forces and the pin's
    motion converge to the rigid pin's."""
    rigid_subs = [("formulation: mixed", "formulation: displacement"),
                  ("  geometric_nonlinearity: true\n", ""),
                  ("steps: {increments: 18, iteration: none}", "steps: {increments: 4}")]
    rigid = run_variant(args.mixcon, os.path.join(HERE, "wood_plate", "report.yaml"),
                        "pin_rigid", args.out, rigid_subs)
    ref = contact_by_node(rigid)
    nmax = max(float(r["normal_force"]) for r in ref.values())
    motion = json.load(open(os.path.join(rigid, "summary.json")))["steps"][-1]["contact"]
    ref_motion = motion["obstacle_motion"][0][0]
    source = os.path.join(HERE, "elastic_contact", "pin_plate.yaml")
    ok = True
    with open(os.path.join(args.out, "pin_plate.csv"), "w", newline="") as fp:
        w = csv.writer(fp)
        w.writerow(["E_pin", "pin_segments", "closed", "stick", "same_statuses",
                    "max_force_difference", "pin_motion", "rigid_pin_motion"])
        motions, diffs = [], []
        # Growing modulus on the matching pin (12 arc segments), then finer pins (24, 48) at
        # the stiffest modulus: the limit of a stiff pin is a rigid polygon, which approaches
        # the rigid circle as its segments shrink.
        cases = [(e, 3) for e in (3e7, 3e8, 3e9, 3e10)] + [(3e10, 6), (3e10, 12)]
        for e, n in cases:
            name = f"pin_E{e:.0e}_n{n}".replace("+", "")
            result = run_variant(args.mixcon, source, name, args.out,
                                 [("type: isotropic, E: 3.0e7", f"type: isotropic, E: {e:.6g}"),
                                  ("divisions: [3, 3], element: quad4",
                                   f"divisions: [{n}, 3], element: quad4")])
            rows = contact_by_node(result)
            diff = max(abs(float(rows[k]["normal_force"]) - float(ref[k]["normal_force"]))
                       for k in ref) / nmax
            same = all(rows[k]["status"] == ref[k]["status"] for k in ref)
            closed = sum(r["status"] != "open" for r in rows.values())
            stick = sum(r["status"] == "stick" for r in rows.values())
            f = h5py.File(os.path.join(result, "results.h5"), "r")
            xy = f["mesh/nodes"][:]
            u = f["steps"][str(len(f["steps"]))]["displacement"][:]
            plate_nodes = node_count(rigid)
            centre = plate_nodes + np.argmin(np.hypot(xy[plate_nodes:, 0], xy[plate_nodes:, 1]))
            w.writerow([f"{e:.3g}", 4 * n, closed, stick, same, f"{diff:.5f}",
                        f"{u[centre, 0]:.6e}", f"{ref_motion:.6e}"])
            print(f"elastic pin E = {e:.3g} psi, {4 * n} arc segments: {closed} hole nodes closed "
                  f"({stick} stick){'' if same else ', statuses DIFFER from the rigid pin'}; "
                  f"contact forces within {100 * diff:.2f}% of the rigid pin's peak; pin centre "
                  f"moves {u[centre, 0]:.5e} in (rigid pin {ref_motion:.5e} in)")
            ok = ok and same
            if n == 3:
                motions.append(abs(u[centre, 0] / ref_motion - 1))
            else:
                diffs.append(diff)
    # The pin's motion converges to the rigid pin's as E grows; the force differences shrink
    # with the pin's polygon.
    ok = ok and all(b < a for a, b in zip(motions, motions[1:])) and motions[-1] < 5e-4
    return ok and diffs[0] < 0.03 and diffs[1] < 0.015


def node_count(result):
    """Nodes of a run's mesh (the plate alone: its nodes come first in the merged mesh)."""
    return len(h5py.File(os.path.join(result, "results.h5"), "r")["mesh/nodes"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mixcon", default=os.path.join(HERE, "..", "build", "apps", "mixcon"))
    ap.add_argument("--out", default=os.path.join("out", "elastic_contact", "study"))
    ap.add_argument("--iterations", action="store_true",
                    help="also tabulate BoomerAMG-PCG iterations per correction with and without "
                         "contact on three meshes (amg_iterations.csv)")
    ap.add_argument("--check", action="store_true",
                    help="exit 1 unless p0 and b are within 3%% of the two-body Hertz solution "
                         "and the elastic pin converges to the rigid pin")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    source = os.path.join(HERE, "elastic_contact", "hertz_two_body.yaml")
    swap = [("contactor: block.bottom, target: cylinder.arc",
             "contactor: cylinder.arc, target: block.bottom")]
    stiff = [("type: isotropic, E: 10500, nu: 0.25", "type: isotropic, E: 10500000, nu: 0.25")] \
        + swap
    cases = (("block_on_cylinder", (), E2, "ro-"),
             ("cylinder_on_block", swap, E2, "bs--"),
             ("stiff_block", stiff, E2 * 1000, "g^:"))
    fig, ax = plt.subplots(figsize=(6, 4.5))
    failed = False
    with open(os.path.join(args.out, "hertz_two_body.csv"), "w", newline="") as fp:
        w = csv.writer(fp)
        w.writerow(["case", "P", "b_hertz", "p0_hertz", "b_fe", "p0_fe", "b_err", "p0_err"])
        for name, subs, e2, style in cases:
            result = run_variant(args.mixcon, source, name, args.out, subs)
            P, _ = loads(result)
            steps = contact_rows(result)
            last = max(steps)
            rows = steps[last]
            # The pressure along the contactor: the block's base (x) or the cylinder's arc (its
            # x coordinate, the contact zone being nearly flat).
            b, p0 = hertz(P[last - 1], e2)
            closed = [(float(r["x"]), float(r["normal_stress"])) for r in rows
                      if r["status"] != "open"]
            xc = max(c[0] for c in closed)
            x_open = min(float(r["x"]) for r in rows
                         if r["status"] == "open" and float(r["x"]) > xc)
            # p0 and b of the FE solution: least-squares fit of the Hertz shape
            # p^2 = p0^2 (1 - x^2 / b^2) to the contactor's nodal tractions (force over the node's
            # share of the contactor boundary) at every closed node.
            xs_ = np.array([c[0] for c in closed])
            ts = np.array([c[1] for c in closed])
            a_, c_ = np.linalg.lstsq(np.c_[np.ones_like(xs_), -xs_ ** 2], ts ** 2, rcond=None)[0]
            p0_fe, b_fe = np.sqrt(a_), np.sqrt(a_ / c_)
            eb, ep = b_fe / b - 1, p0_fe / p0 - 1
            # The largest deviation of a nodal traction from the closed form, in units of p0.
            dev = max(abs(t - p0 * np.sqrt(max(0.0, 1 - (xx / b) ** 2))) for xx, t in closed) / p0
            w.writerow([name, f"{P[last - 1]:.4f}", f"{b:.5f}", f"{p0:.2f}", f"{b_fe:.5f}",
                        f"{p0_fe:.2f}", f"{eb:+.4f}", f"{ep:+.4f}"])
            print(f"{name}: P = {P[last - 1]:.2f}, Hertz b = {b:.4f}, p0 = {p0:.1f}; FE fit p0 = "
                  f"{p0_fe:.1f} ({100 * ep:+.1f}%), b = {b_fe:.4f} ({100 * eb:+.1f}%); closed up to "
                  f"x = {xc:.4f}, next node open at {x_open:.4f}; largest nodal traction deviation "
                  f"{100 * dev:.1f}% of p0")
            ax.plot(xs_ / b, ts / p0, style, ms=3, label=name.replace("_", " "))
            failed = failed or abs(ep) > 0.03 or abs(eb) > 0.03 or not xc <= b <= x_open
    xs = np.linspace(0, 1, 200)
    ax.plot(xs, np.sqrt(1 - xs ** 2), "k-", label="Hertz (two bodies)")
    ax.set_xlabel("x / b")
    ax.set_ylabel("p / p0")
    ax.set_xlim(0, 1.5)
    ax.set_title("Elastic cylinder on an elastic block: contact pressure")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "hertz_two_body.png"), dpi=120)
    print(f"wrote hertz_two_body.csv and hertz_two_body.png to {args.out}")
    if not pin_plate(args):
        failed = True
        print("the elastic pin does not converge to the rigid pin (within 1% at E = 3e10)")
    if args.iterations:
        amg_iterations(args, source)
    if args.check and failed:
        sys.exit("two-body Hertz off the closed form by more than 3%, or the elastic pin not "
                 "converging to the rigid pin")


if __name__ == "__main__":
    main()
