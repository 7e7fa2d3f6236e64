#!/usr/bin/python3
"""CTest driver of the ParaView check: runs mixcon on a linear, a nonlinear and a contact example,
then tests/paraview/check_paraview.py under pvpython on their results.xdmf.

Exits 77 (CTest SKIP_RETURN_CODE) with a message when pvpython is not installed (Debian:
apt-get install python3-paraview) or when there is neither an X display nor xvfb-run (Debian's
ParaView renders through X only; apt-get install xvfb).
Usage: run_paraview_check.py --mixcon build/apps/mixcon --out DIR
"""
import argparse
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(os.path.dirname(HERE))
EXAMPLES = ["lame_cylinder", "cantilever/report_displacement", "hertz/hertz_report"]
SKIP = 77


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mixcon", required=True)
    ap.add_argument("--out", required=True)
    args = ap.parse_args()
    pvpython = shutil.which("pvpython")
    if not pvpython:
        print("SKIPPED: pvpython not found (apt-get install python3-paraview)")
        return SKIP
    prefix = []
    if not os.environ.get("DISPLAY"):
        xvfb = shutil.which("xvfb-run")
        if not xvfb:
            print("SKIPPED: no X display and no xvfb-run for ParaView's offscreen rendering "
                  "(apt-get install xvfb)")
            return SKIP
        prefix = [xvfb, "-a"]
    dirs = []
    for e in EXAMPLES:
        out = os.path.join(args.out, e.replace("/", "_"))
        run = subprocess.run([args.mixcon, "run", os.path.join(SOURCE, "examples", e + ".yaml"),
                              "--output", out], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             text=True)
        if run.returncode != 0:
            print(run.stdout)
            print(f"FAIL: mixcon run {e} exited {run.returncode}")
            return 1
        dirs.append(out)
    check = prefix + [pvpython, os.path.join(HERE, "check_paraview.py")] + dirs
    return subprocess.run(check).returncode


if __name__ == "__main__":
    sys.exit(main())
