"""Main driver: runs every experiment of the prototype in turn (about 10 minutes on 2 cores).
Outputs go to *.out files beside this script; results.md summarises them."""
import subprocess, sys, os
here = os.path.dirname(os.path.abspath(__file__))
py = sys.executable
steps = [("check.out", ["check.py"], {}),
         ("spectrum.out", ["spectrum.py"], {}),
         ("modes.out", ["modes.py"], {}),
         ("spec2.out", ["spec2.py"], {}),
         ("iters_a005.out", ["iters.py", "0.05"], {}),          # exact-inverse preconditioners, 16x4..256x64
         ("amg_a005.out", ["amgtest.py", "0.05"], {}),
         ("amg_a001.out", ["amgtest.py", "0.01"], {"NMESH": "4"}),
         ("amg_a02.out", ["amgtest.py", "0.2"], {"NMESH": "4"}),
         ("amg_a005_dist.out", ["amgtest.py", "0.05", "0.2"], {"NMESH": "4"}),
         ("amgvariants.out", ["amgvariants.py"], {})]
for out, args, env in steps:
    print("running", " ".join(args), "->", out, flush=True)
    with open(os.path.join(here, out), "w") as f:
        subprocess.run([py] + [os.path.join(here, args[0])] + args[1:], cwd=here, stdout=f,
                       stderr=subprocess.STDOUT, env={**os.environ, **env}, check=False)
print("done")
