"""ParaView check of mixcon's results.xdmf (run by pvpython; see run_paraview_check.py).

For every output directory given: opens results.xdmf with ParaView's default reader, checks at
every time step the node/cell array names and component counts, finite ranges, the time values
(the load factors of summary.json), that Warp By Vector on the displacement moves every point by
exactly its displacement; then renders the deformed shape with examples/render_paraview.py
(coloured by stress xx and, for contact runs, by the contact pressure) and checks that the PNGs
show a coloured, not blank, image. Exit 0 when all holds, 1 otherwise.
"""
import json
import math
import os
import sys

import numpy as np
from paraview import simple as pv
from vtkmodules.numpy_interface import dataset_adapter as dsa
from vtkmodules.vtkIOImage import vtkPNGReader

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "examples"))
import render_paraview  # noqa: E402

failures = []


def check(ok, message):
    if not ok:
        failures.append(message)
        print("FAIL:", message)


def leaf(proxy):
    """The unstructured grid a source produced (first leaf of a composite)."""
    d = proxy.GetClientSideObject().GetOutputDataObject(0)
    while d.IsA("vtkCompositeDataSet"):
        it = d.NewIterator()
        it.InitTraversal()
        d = it.GetCurrentDataObject()
    return dsa.WrapDataObject(d)


def check_run(directory):
    name = os.path.basename(directory)
    summary = json.load(open(os.path.join(directory, "summary.json")))
    loads = [s["load_factor"] for s in summary["steps"]]
    contact = "contact" in summary["steps"][0]
    expected = {"displacement": 3, "reaction": 3, "stress": 3}
    if contact:
        expected.update({"contact_status": 1, "contact_gap": 1, "contact_normal_traction": 1,
                         "contact_tangential_traction": 1})
    reader = pv.OpenDataFile(os.path.join(directory, "results.xdmf"))
    times = render_paraview.timesteps(reader)
    check(len(times) == len(loads) and np.allclose(times, loads),
          f"{name}: time steps {times} vs load factors {loads}")
    warp = pv.WarpByVector(Input=reader, Vectors=["POINTS", "displacement"], ScaleFactor=1.0)
    peak_pressure = 0.0
    for t in times:
        warp.UpdatePipeline(t)
        grid = leaf(reader)
        arrays = {k: grid.PointData[k] for k in grid.PointData.keys()}
        check(set(arrays) == set(expected),
              f"{name} t={t}: node arrays {sorted(arrays)}, expected {sorted(expected)}")
        check(list(grid.CellData.keys()) == ["region"], f"{name} t={t}: cell arrays "
              f"{list(grid.CellData.keys())}")
        for k, ncomp in expected.items():
            if k not in arrays:
                continue
            a = np.asarray(arrays[k])
            got = 1 if a.ndim == 1 else a.shape[1]
            check(got == ncomp and len(a) == grid.GetNumberOfPoints(),
                  f"{name} t={t}: {k} has {got} components, {len(a)} rows")
            finite = a[np.isfinite(a)] if k == "contact_gap" else a  # gap: NaN off the contact
            check(finite.size > 0 and np.all(np.isfinite(finite)), f"{name} t={t}: {k} not finite")
            # The same through ParaView's array information (what the colour map uses).
            info = reader.PointData[k]
            for c in range(ncomp):
                lo, hi = info.GetRange(c)
                check(math.isfinite(lo) and math.isfinite(hi) and lo <= hi,
                      f"{name} t={t}: {k}[{c}] range ({lo}, {hi})")
        u = np.asarray(arrays["displacement"])
        check(np.all(u[:, 2] == 0.0) and np.abs(u).max() > 0.0,
              f"{name} t={t}: displacement z not 0 or displacement all 0")
        moved = np.asarray(leaf(warp).Points) - np.asarray(grid.Points)
        check(np.allclose(moved, u, rtol=0, atol=1e-12 * (1 + np.abs(u).max())),
              f"{name} t={t}: warped points differ from reference + displacement by "
              f"{np.abs(moved - u).max():g}")
        if contact:
            status = np.asarray(arrays["contact_status"])
            check(set(np.unique(status)) <= {-1, 0, 1, 2}, f"{name} t={t}: status {np.unique(status)}")
            p = np.asarray(arrays["contact_normal_traction"])
            check(np.all(p[status <= 0] == 0.0), f"{name} t={t}: traction off the closed nodes")
            peak_pressure = max(peak_pressure, p.max())
    if contact:
        check(peak_pressure > 0.0, f"{name}: no contact pressure in any step")
    pv.Delete(warp)
    pv.Delete(reader)
    written, _ = render_paraview.render(directory, "xx", None, (600, 400))
    check(len(written) == (2 if contact else 1), f"{name}: rendered {written}")
    for png in written:
        r = vtkPNGReader()
        r.SetFileName(png)
        r.Update()
        img = dsa.WrapDataObject(r.GetOutput()).PointData[0]
        rgb = np.asarray(img)[:, :3].astype(int)
        colours = len(np.unique(rgb[:, 0] * 65536 + rgb[:, 1] * 256 + rgb[:, 2]))
        body = np.mean(np.any(rgb < 200, axis=1))  # not the white background
        check(colours > 50 and body > 0.05,
              f"{png}: {colours} colours, {100 * body:.1f} % non-background pixels")
    print(f"{name}: {len(times)} steps, arrays {sorted(expected)}; rendered "
          + ", ".join(os.path.basename(w) for w in written))


for d in sys.argv[1:]:
    check_run(d)
print(f"{len(failures)} failures")
sys.exit(1 if failures else 0)
