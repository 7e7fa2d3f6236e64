#!/usr/bin/env python3
"""Plots a hybrid-mode run (docs/hybrid.md): the friction coefficient inferred around the
measured boundary versus angle, one curve per measured load, from <run>/hybrid.csv; both
measures (reaction tractions, nodal stresses); undetermined points (nan) are left out.
Writes <run>/hybrid_mu.png.

Usage: python3 examples/plot_hybrid.py out/hybrid
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    run = sys.argv[1]
    rows = list(csv.DictReader(open(os.path.join(run, "hybrid.csv"))))
    steps = {}
    for r in rows:
        steps.setdefault(int(r["step"]), []).append(r)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), sharey=True)
    cmap = plt.get_cmap("viridis")
    last = max(steps)
    for s, rs in sorted(steps.items()):
        rs = sorted(rs, key=lambda r: float(r["angle_deg"]))
        for ax, key in zip(axes, ("mu_force", "mu_stress")):
            pts = [(float(r["angle_deg"]), float(r[key])) for r in rs
                   if not math.isnan(float(r[key]))]
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", ms=3,
                        color=cmap(s / last), label=f"load {float(rs[0]['load']):.4g}")
    axes[0].set_title("mu = |t_t / t_n| (reaction tractions)")
    axes[1].set_title("mu = |tau_rt / sigma_rr| (nodal stresses)")
    for ax in axes:
        ax.set_xlabel("angle about the centre (deg)")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("inferred friction coefficient")
    axes[1].legend(fontsize=6, ncol=2)
    fig.tight_layout()
    out = os.path.join(run, "hybrid_mu.png")
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
