#!/usr/bin/python3
"""The shipped 2D examples give the results of release f4b0a44 (ctest regression.examples_2d).

Runs each example with the given mixcon program and compares the last step's nodal displacements
and nodal stresses (xx, yy, xy) with examples-f4b0a44.npz beside this script, written by f4b0a44
(the release before the dimension-generic core): the largest difference relative to the largest
reference value must stay below --tol (1e-6). Nodes are matched by their reference coordinates,
so a renumbering passes; displacements may have 2 or 3 components; stresses are picked by the
`components` attribute of the dataset. Exit 0 when every example matches, 1 otherwise, 77 (skip)
without h5py/numpy.
"""
import argparse
import os
import subprocess
import sys
import tempfile

try:
    import h5py
    import numpy as np
except ImportError as e:  # pragma: no cover
    print(f"skipped: {e}")
    sys.exit(77)

EXAMPLES = ["lame_cylinder", "lame_cylinder_mixed", "cantilever", "cantilever/report_mixed",
            "cantilever/report_displacement", "hertz/hertz_refined", "wood_plate/report",
            "elastic_contact/pin_plate", "hybrid/hybrid"]
BASELINE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "examples-f4b0a44.npz")


def plane_stress_components(ds):
    s = np.asarray(ds)
    names = ds.attrs.get("components")
    if names is None:
        return s[:, {3: [0, 1, 2], 4: [0, 1, 3], 6: [0, 1, 5]}[s.shape[1]]]
    names = [n.decode() if isinstance(n, bytes) else str(n) for n in np.atleast_1d(names)]
    col = {n.lower(): i for i, n in enumerate(names)}
    return s[:, [col["xx"], col["yy"], col["xy"]]]


def node_order(x_ref, x_new):
    """For every reference node, its index in x_new (matched by coordinates)."""
    scale = 1e-7 * (1 + np.abs(x_ref).max())
    kr = np.round(x_ref / scale).astype(np.int64)
    kn = np.round(x_new / scale).astype(np.int64)
    if len(kr) != len(kn):
        raise ValueError(f"{len(x_new)} nodes, the baseline has {len(x_ref)}")
    order_r, order_n = np.lexsort(kr.T[::-1]), np.lexsort(kn.T[::-1])
    if not np.array_equal(kr[order_r], kn[order_n]):
        raise ValueError("node coordinates differ from the baseline")
    idx = np.empty(len(x_ref), dtype=np.int64)
    idx[order_r] = order_n
    return idx


def errors(out_dir, base, name):
    with h5py.File(os.path.join(out_dir, "results.h5"), "r") as f:
        x = np.asarray(f["mesh/nodes"])[:, :2]
        steps = f["steps"]
        last = steps[sorted(steps.keys(), key=int)[-1]]
        new = {"u": np.asarray(last["displacement"])[:, :2],
               "s": plane_stress_components(last["stress"])}
    idx = node_order(base[name + "/x"], x)
    return {k: np.abs(v[idx] - base[name + "/" + k]).max() /
            max(np.abs(base[name + "/" + k]).max(), 1e-300) for k, v in new.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mixcon", required=True)
    ap.add_argument("--examples", required=True)
    ap.add_argument("--tol", type=float, default=1e-6)
    args = ap.parse_args()
    base = np.load(BASELINE)
    failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        for e in EXAMPLES:
            name = e.replace("/", "_")
            out = os.path.join(tmp, name)
            run = subprocess.run([os.path.abspath(args.mixcon), "run", e + ".yaml", "-q",
                                  "--output", out], cwd=args.examples, stdout=subprocess.PIPE,
                                 stderr=subprocess.STDOUT, text=True)
            try:
                if run.returncode != 0:
                    raise ValueError(f"exit {run.returncode}: {run.stdout.strip()[-300:]}")
                err = errors(out, base, name)
            except (KeyError, ValueError, OSError) as ex:
                print(f"FAIL {e}: {ex}")
                failed += 1
                continue
            ok = max(err.values()) <= args.tol
            failed += not ok
            print(f"{'ok  ' if ok else 'FAIL'} {e}: displacement {err['u']:.1e}, "
                  f"stress {err['s']:.1e} (tol {args.tol:g})")
    print(f"{len(EXAMPLES) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
