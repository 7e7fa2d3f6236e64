#!/usr/bin/env python3
"""Pin-loaded orthotropic wood plate (the report's Fig. 6-7): runs mixcon on
examples/wood_plate/report.yaml (the report's 124 Quad4 mesh, no equilibrium iterations) and
variants (Newton iterations; refined 1116 Quad4 mesh; frictionless; the pin held and the far end
loaded instead; the displacement model), and reports at the final load (400 lb per inch on the
whole plate):
  - the radial stress sigma_rr and the shear stress tau_rt around the hole versus the angle phi
    from the bearing point (phi = 0 on the load axis), from the nodal stresses (Fig. 7);
  - the contact arc, the stick and slip zones, the pin displacement;
  - the balance of the pin: the contact forces on the plate sum to the pin force.
For context (not a closed form for this orthotropic, frictional case) the cosine bearing
distribution sigma_rr = -(4 P / (pi d t)) cos(phi) of a neat-fit pin is drawn too.
Writes wood_radial_stress.csv, wood_summary.csv and the PNGs fig7_radial_stress.png,
wood_zones.png, wood_variants.png.

Usage: python3 examples/wood_plate_study.py [--mixcon build/apps/mixcon] [--out DIR] [--check]
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
from study_util import run_variant  # noqa: E402
P_WHOLE, D, T, MU, HALF_LOAD = 400.0, 1.0, 1.0, 0.7, -200.0


def run(mixcon, name, out, source=None, substitutions=()):
    """Runs mixcon on examples/wood_plate/<source or name>.yaml with textual substitutions."""
    return run_variant(mixcon, os.path.join(HERE, "wood_plate", (source or name) + ".yaml"), name, out,
                       substitutions)


def final_state(result):
    """Hole nodes at the last step, sorted by phi: dict of arrays (phi in degrees from the
    bearing point, sigma_rr, tau_rt, status, normal and tangential nodal forces, force sums)."""
    rows = list(csv.DictReader(open(os.path.join(result, "contact.csv"))))
    last = max(int(r["step"]) for r in rows)
    rows = [r for r in rows if int(r["step"]) == last]
    f = h5py.File(os.path.join(result, "results.h5"), "r")
    ids = list(f["mesh/node_ids"][:])
    step = f["steps"][str(last)]
    stress = step["stress"][:]
    motion = step["contact/obstacle_motion"][0]
    out = {k: [] for k in ("phi", "srr", "trt", "status", "N", "T")}
    fx = fy = 0.0
    for r in rows:
        theta = np.radians(float(r["angle_deg"]))
        n = np.array([np.cos(theta), np.sin(theta)])  # into the plate
        t = np.array([-n[1], n[0]])
        sxx, syy, sxy = stress[ids.index(int(r["node_id"]))]
        s = np.array([[sxx, sxy], [sxy, syy]])
        N, Tf = float(r["normal_force"]), float(r["tangential_force"])
        fx += N * n[0] + Tf * t[0]
        fy += N * n[1] + Tf * t[1]
        out["phi"].append(180.0 - np.degrees(theta))
        out["srr"].append(n @ s @ n)
        out["trt"].append(t @ s @ n)
        out["status"].append(r["status"])
        out["N"].append(N)
        out["T"].append(Tf)
    order = np.argsort(out["phi"])
    res = {k: np.array(v)[order] for k, v in out.items()}
    res["force"] = (fx, fy)
    res["pin"] = motion
    return res


def tributary(phi):
    """Arc length (in) each hole node stands for, from the node angles (degrees): half the
    distance to its neighbours on either side, one-sided at the ends (R = 0.5 in)."""
    rad = np.radians(phi)
    left = np.concatenate(([0.0], np.diff(rad))) / 2
    right = np.concatenate((np.diff(rad), [0.0])) / 2
    return 0.5 * (left + right)


def zones(st):
    """(contact arc, stick zone): the largest phi of the closed nodes, and of the stick nodes
    contiguous with the bearing point phi = 0 (degrees)."""
    closed = st["phi"][st["status"] != "open"]
    stick = 0.0
    for phi, status in zip(st["phi"], st["status"]):
        if status != "stick":
            break
        stick = phi
    return (closed.max() if len(closed) else 0.0), stick


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mixcon", default=os.path.join(HERE, "..", "build", "apps", "mixcon"))
    ap.add_argument("--out", default=os.path.join("out", "wood_plate", "study"))
    ap.add_argument("--check", action="store_true",
                    help="exit 1 unless the pin balances, Coulomb's law holds at every contact "
                         "node and the variants agree as documented")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    newton = [("iteration: none", "iteration: newton")]
    frictionless = [("friction: 0.7", "friction: 0.0")]
    held_pin = [("drive: {force: [-200, null], displacement: [null, 0]}",
                 "drive: {displacement: [0, 0]}"),
                ("  - {boundary: far, ux: 0}\n", ""),
                ("boundary_conditions:",
                 "loads:\n  - {boundary: far, traction: [100, 0]}\n"
                 "boundary_conditions:")]
    displacement = [("formulation: mixed", "formulation: displacement")]
    by_forces = [("friction: 0.7", "friction: 0.7\n    status_from: forces")]
    cases = (("report", "report", (), "bs--"),
             ("report_newton", "report", newton, "g^:"),
             ("refined", "refined", (), "ro-"),
             ("refined_status_from_forces", "refined", by_forces, "kd-"),
             ("refined_frictionless", "refined", frictionless, "c.-"),
             ("refined_held_pin", "refined", held_pin, "kx:"),
             ("refined_displacement", "refined", displacement, "mv:"))
    states = {}
    for name, source, subs, _ in cases:
        states[name] = final_state(run(args.mixcon, name, args.out, source, subs))

    failures = []
    with open(os.path.join(args.out, "wood_radial_stress.csv"), "w", newline="") as fr, \
            open(os.path.join(args.out, "wood_summary.csv"), "w", newline="") as fs:
        wr, ws = csv.writer(fr), csv.writer(fs)
        wr.writerow(["case", "phi_deg", "status", "sigma_rr", "tau_rt", "N", "T"])
        ws.writerow(["case", "contact_arc_deg", "stick_zone_deg", "peak_sigma_rr",
                     "sigma_rr_at_0", "pin_dx", "force_x", "force_y"])
        for name, _, _, _ in cases:
            st = states[name]
            for i in range(len(st["phi"])):
                wr.writerow([name, f"{st['phi'][i]:.3f}", st["status"][i],
                             f"{st['srr'][i]:.3f}", f"{st['trt'][i]:.3f}",
                             f"{st['N'][i]:.5f}", f"{st['T'][i]:.5f}"])
            arc, stick = zones(st)
            closed = st["status"] != "open"
            peak = st["srr"][closed].min() if closed.any() else 0.0
            ws.writerow([name, f"{arc:.1f}", f"{stick:.1f}", f"{peak:.2f}",
                         f"{st['srr'][0]:.2f}", f"{st['pin'][0]:.6g}",
                         f"{st['force'][0]:.6f}", f"{st['force'][1]:.6f}"])
            print(f"{name:22s} contact arc {arc:5.1f} deg, stick zone {stick:5.1f} deg, "
                  f"peak sigma_rr {peak:8.1f} psi, sigma_rr(0) {st['srr'][0]:8.1f} psi, "
                  f"pin dx {st['pin'][0]:.4g} in, contact force ({st['force'][0]:.4f}, "
                  f"{st['force'][1]:.4f}) lb")
            # The pin's balance: the contact forces on the plate sum to the pin force.
            if name != "refined_held_pin" and abs(st["force"][0] - HALF_LOAD) > 1e-4 * 200:
                failures.append(f"{name}: contact forces sum to {st['force'][0]} lb, "
                                f"not the pin force {HALF_LOAD}")
            # Coulomb's law at every closed node (forces): |T| <= mu N, = mu N in slip.
            mu = 0.0 if "frictionless" in name else MU
            for i in np.nonzero(closed)[0]:
                N, Tf = st["N"][i], st["T"][i]
                if N < -1e-9 * 200:
                    failures.append(f"{name}: tensile contact force {N} at phi {st['phi'][i]}")
                if st["status"][i] == "slip" and abs(abs(Tf) - mu * N) > 2e-3 * max(mu * N, 1e-9):
                    failures.append(f"{name}: slip node at phi {st['phi'][i]:.1f} has |T| "
                                    f"{abs(Tf)} != mu N {mu * N}")
            if mu > 0 and not (0 < stick < arc):
                failures.append(f"{name}: expected a stick zone at the bearing point and slip "
                                f"zones at the edges (stick to {stick}, contact to {arc})")
        # The held pin with the end loaded carries the same bearing stresses near the hole as the
        # force-driven pin with the end held (Saint-Venant: the ends are 8 and 4 hole radii
        # away), and the same pin force.
        a, b = states["refined"], states["refined_held_pin"]
        diff = np.abs(a["srr"] - b["srr"]).max() / np.abs(a["srr"]).max()
        print(f"held pin vs force-driven pin: max sigma_rr difference {100 * diff:.2f} % of "
              f"the peak; contact force {b['force'][0]:.4f} lb")
        if diff > 0.05:
            failures.append(f"held pin and force-driven pin differ by {100 * diff:.1f} %")
        if abs(abs(b["force"][0]) - 200) > 1e-3 * 200:
            failures.append(f"held pin: contact force {b['force'][0]} instead of 200 lb")

    # Fig. 7: radial stress around the hole at the final load.
    cosine_peak = 4 * P_WHOLE / (np.pi * D * T)
    phi = np.linspace(0, 90, 91)
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for name, _, _, style in cases[:4]:
        st = states[name]
        ax.plot(st["phi"], st["srr"], style, ms=4, label=name.replace("_", " "))
    ax.plot(phi, -cosine_peak * np.cos(np.radians(phi)), "k:", lw=1,
            label="cosine distribution (neat fit, isotropic, frictionless)")
    ax.set_xlabel("angle from the bearing point phi (deg)")
    ax.set_ylabel("radial stress sigma_rr at the hole (psi)")
    ax.set_title("Fig. 7: radial stress around the hole, P = 400 lb/in, mu = 0.7")
    ax.set_xlim(0, 180)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "fig7_radial_stress.png"), dpi=120)

    # Stick and slip zones on the refined mesh: tau_rt / sigma_rr against mu.
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(6.5, 6), sharex=True)
    for name, style in (("refined", "o"), ("report", "s")):
        st = states[name]
        for status, colour in (("stick", "tab:blue"), ("slip", "tab:red"),
                               ("open", "tab:gray")):
            m = st["status"] == status
            ax1.plot(st["phi"][m], (st["N"] / tributary(st["phi"]))[m], style,
                     color=colour, mfc="none" if name == "report" else colour, ms=4,
                     label=f"{name} {status}")
            ratio = np.where(st["N"] > 0, np.abs(st["T"]) / np.maximum(st["N"], 1e-300), 0)
            ax2.plot(st["phi"][m], ratio[m], style, color=colour,
                     mfc="none" if name == "report" else colour, ms=4)
    ax2.axhline(MU, color="k", lw=0.8, ls="--", label="mu = 0.7")
    ax1.set_ylabel("contact pressure N / (R dtheta) (psi)")
    ax2.set_ylabel("|T| / N")
    ax2.set_xlabel("angle from the bearing point phi (deg)")
    ax1.set_title("Contact zones at P = 400 lb/in: stick (blue), slip (red), open (grey)")
    ax1.legend(fontsize=7, ncol=2)
    ax2.legend(fontsize=8)
    for a_ in (ax1, ax2):
        a_.grid(alpha=0.3)
    ax2.set_xlim(0, 180)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "wood_zones.png"), dpi=120)

    # Variants on the refined mesh.
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    for name, _, _, style in cases[2:]:
        if name == "refined_status_from_forces":
            continue
        st = states[name]
        ax.plot(st["phi"], st["srr"], style, ms=3, label=name.replace("_", " "))
    ax.set_xlabel("angle from the bearing point phi (deg)")
    ax.set_ylabel("radial stress sigma_rr at the hole (psi)")
    ax.set_title("Refined mesh: friction, pin drive and formulation")
    ax.set_xlim(0, 180)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(args.out, "wood_variants.png"), dpi=120)
    print(f"wrote {args.out}/{{wood_radial_stress.csv, wood_summary.csv, fig7_radial_stress.png,"
          f" wood_zones.png, wood_variants.png}}")
    if failures:
        print("CHECK FAILED:\n  " + "\n  ".join(failures))
        return 1
    if args.check:
        print("check passed: pin balance, Coulomb's law at every contact node, stick at the "
              "bearing point with slip at the edges, held pin = force-driven pin")
    return 0


if __name__ == "__main__":
    sys.exit(main())
