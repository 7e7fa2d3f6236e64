"""ParaView check of mixcon's results.xdmf (run by pvpython; see run_paraview_check.py).

For every output directory given: opens results.xdmf with ParaView's default reader, checks the
mesh against results.h5 (read with h5py: the VTK cell type of the element, e.g. 12 hexahedron
for Hex8, the points per cell, the numbers of cells and points, the connectivity and the
coordinates), at every time step the node/cell array names and component counts (stress: 3
columns in 2D, 6 in 3D, with the component labels docs/output-format.md gives), finite ranges,
the time values (the load factors of summary.json), that the values ParaView reads equal those of
results.h5 -- the stress column ParaView labels L equals the results.h5 /steps/<k>/stress column
whose `components` name is L (3D: stress_XY is column 5 = xy, stress_YZ column 3 = yz, stress_XZ
column 4 = xz), also through ParaView's legacy Xdmf2 reader in 3D --, that Warp By Vector on the
displacement moves every point by exactly its displacement and that a Calculator on the stress
components by their labels (xx; in 3D zz, xy, yz, xz and the von Mises stress) gives what the
HDF5 columns of those names give; then renders the deformed shape with
examples/render_paraview.py (coloured by stress xx and, for contact runs, by the contact
pressure) and checks that the PNGs show a coloured, not blank, image. The runs KNOWN names (by
their folder) are checked against known values too: the cell type and the numbers of cells and
points of their mesh, whether results.h5 holds the mixed model's nodal stress unknowns (then 9
components per point: displacement 3, stress 6) and values against a closed form (the Tet4
cantilever's total reaction, Lame's thick sphere for the 3D mixed model). Exit 0 when all holds,
1 otherwise.
"""
import json
import math
import os
import sys

import h5py
import numpy as np
from paraview import simple as pv
from vtkmodules.numpy_interface import dataset_adapter as dsa
from vtkmodules.vtkIOImage import vtkPNGReader

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "examples"))
import render_paraview  # noqa: E402

failures = []

# VTK cell type of each (dimension, nodes per element) mixcon writes (the XDMF topologies of
# io/OutputLayout.cpp: Quadrilateral, Quadrilateral_8, Hexahedron, Hexahedron_20, Tetrahedron,
# Tetrahedron_10).
VTK_CELL = {(2, 4): 9, (2, 8): 23, (3, 8): 12, (3, 20): 25, (3, 4): 10, (3, 10): 24}
# ParaView's labels of the stress columns (by position; docs/output-format.md, "ParaView") and
# the stress component each must show, by its name in the `components` attribute of results.h5's
# /steps/<k>/stress (2D X Y Z: xx yy xy, as VTK names a 3-vector; 3D VTK's symmetric tensor).
STRESS_LABELS = {2: ["X", "Y", "Z"], 3: ["XX", "YY", "ZZ", "XY", "YZ", "XZ"]}
STRESS_MEANING = {2: ["xx", "yy", "xy"], 3: ["xx", "yy", "zz", "xy", "yz", "xz"]}
# The column order of /steps/<k>/stress, which the issue requires and docs/output-format.md gives.
VOIGT = {2: ["xx", "yy", "xy"], 3: ["xx", "yy", "zz", "yz", "xz", "xy"]}


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


def check_mesh(name, grid, h5):
    """The grid ParaView read against /mesh of results.h5."""
    nodes, elements = h5["mesh/nodes"][()], h5["mesh/elements"][()]
    dim, npe = nodes.shape[1], elements.shape[1]
    check(grid.GetNumberOfPoints() == len(nodes) and grid.GetNumberOfCells() == len(elements),
          f"{name}: {grid.GetNumberOfPoints()} points, {grid.GetNumberOfCells()} cells; "
          f"results.h5 {len(nodes)} nodes, {len(elements)} elements")
    cell_types = np.unique(np.asarray(grid.CellTypes))
    check(list(cell_types) == [VTK_CELL.get((dim, npe))],
          f"{name}: VTK cell types {list(cell_types)}, expected {VTK_CELL.get((dim, npe))} "
          f"for {npe}-node elements in {dim}D")
    conn = np.asarray(grid.Cells)  # legacy layout: n, ids..., n, ids...
    if len(conn) == len(elements) * (npe + 1):
        conn = conn.reshape(len(elements), npe + 1)
        check(np.all(conn[:, 0] == npe), f"{name}: cells with other than {npe} points")
        check(np.array_equal(conn[:, 1:], elements), f"{name}: connectivity differs from HDF5")
    else:
        check(False, f"{name}: {len(conn)} cell entries, expected {len(elements)} cells of "
              f"{npe} points")
    points = np.asarray(grid.Points)
    padded = np.zeros((len(nodes), 3))
    padded[:, :dim] = nodes
    check(np.array_equal(points, padded), f"{name}: point coordinates differ from HDF5")
    return dim


def stress_columns(name, h5, step, dim):
    """results.h5's /steps/<step>/stress and, by the names of its `components` attribute, the
    column each ParaView label must show (STRESS_MEANING)."""
    ds = h5[f"steps/{step}/stress"]
    names = [n.decode() if isinstance(n, bytes) else str(n) for n in ds.attrs["components"]]
    check(names == VOIGT[dim], f"{name} step {step}: stress components {names}, documented "
          f"{VOIGT[dim]}")
    return ds[()], {label: names.index(meaning) if meaning in names else 0
                    for label, meaning in zip(STRESS_LABELS[dim], STRESS_MEANING[dim])}


def check_calculator(name, reader, t, stress, column, dim):
    """A Calculator on the stress components by their labels (as users apply it) against the
    HDF5 columns of the components those labels name."""
    c = {label: stress[:, k] for label, k in column.items()}
    formulas = {"stress_X": c["X"]} if dim == 2 else {
        "stress_ZZ": c["ZZ"], "stress_XY": c["XY"], "stress_YZ": c["YZ"], "stress_XZ": c["XZ"],
        "sqrt(0.5*((stress_XX-stress_YY)^2+(stress_YY-stress_ZZ)^2+(stress_ZZ-stress_XX)^2)"
        "+3*(stress_XY^2+stress_YZ^2+stress_XZ^2))": np.sqrt(
            0.5 * ((c["XX"] - c["YY"])**2 + (c["YY"] - c["ZZ"])**2 + (c["ZZ"] - c["XX"])**2) +
            3.0 * (c["XY"]**2 + c["YZ"]**2 + c["XZ"]**2))}
    for formula, want in formulas.items():
        calc = pv.Calculator(Input=reader, ResultArrayName="result", Function=formula)
        calc.UpdatePipeline(t)
        got = leaf(calc).PointData["result"]
        got = np.asarray(got) if got is not None else np.zeros(0)
        check(got.shape == want.shape and
              np.allclose(got, want, rtol=1e-12, atol=1e-12 * np.abs(want).max()),
              f"{name} t={t}: Calculator '{formula}' differs from HDF5")
        pv.Delete(calc)


def check_legacy_reader(name, directory, t, stress):
    """ParaView's legacy Xdmf2 reader (XDMFReader) reads the same 6 stress columns, labelled the
    same: the XDMF declares them a Matrix, which it, unlike a Tensor6 (XDMF order xx xy xz yy yz
    zz, expanded to 3 x 3), leaves as written."""
    legacy = pv.XDMFReader(FileNames=[os.path.join(directory, "results.xdmf")])
    legacy.PointArrayStatus = ["stress"]
    legacy.UpdatePipeline(t)
    got = leaf(legacy).PointData["stress"]
    got = np.asarray(got) if got is not None else np.zeros((0, 0))
    info = legacy.PointData["stress"]
    labels = [info.GetComponentName(c) for c in range(info.GetNumberOfComponents())] if info \
        else []
    check(got.shape == stress.shape and np.array_equal(got, stress) and
          labels == STRESS_LABELS[3],
          f"{name} t={t}: the Xdmf2 reader's stress ({got.shape}, labels {labels}) differs from "
          f"the Xdmf3 reader's")
    pv.Delete(legacy)


def check_total_reaction(name, t, grid, arrays):
    """cantilever_3d_tet4: the reactions balance the end shear P = -1 (traction -1 on the 1 x 1
    face xmax): their sum is (0, 1, 0), and only the clamped nodes (x = 0) carry any."""
    r = np.asarray(arrays["reaction"])
    clamped = np.asarray(grid.Points)[:, 0] == 0.0
    total = r.sum(axis=0)
    check(np.allclose(total, [0.0, 1.0, 0.0], rtol=0, atol=1e-8),
          f"{name} t={t}: total reaction {total}, expected (0, 1, 0)")
    check(clamped.sum() == 9 and np.abs(r[~clamped]).max() < 1e-8,
          f"{name} t={t}: {clamped.sum()} nodes on x = 0, reaction up to "
          f"{np.abs(r[~clamped]).max():g} off them")
    return f"total reaction ({total[0]:.1e}, {total[1]:.9f}, {total[2]:.1e})"


def check_lame_sphere(name, t, grid, arrays, a=1.0, b=2.0, p=10.0, e=1000.0, nu=0.3,
                      tolerance=0.025):
    """lame_sphere_mixed: Lame's closed form of the pressurized thick sphere (Timoshenko &
    Goodier, sec. 136; the example's verification and tolerance): the radial displacement and the
    radial and hoop stresses averaged over the nodes on r = a and on r = b, from ParaView's
    arrays by their labels (n.sigma.n takes every shear column: a swapped one shows). Stresses
    within tolerance * p, the displacement within tolerance of its value."""
    x = np.asarray(grid.Points)
    r = np.linalg.norm(x, axis=1)
    n = x / r[:, None]
    s = {label: np.asarray(arrays["stress"])[:, j] for j, label in enumerate(STRESS_LABELS[3])}
    sigma = np.array([[s["XX"], s["XY"], s["XZ"]], [s["XY"], s["YY"], s["YZ"]],
                      [s["XZ"], s["YZ"], s["ZZ"]]])  # 3 x 3 x points
    sigma_r = np.einsum("pi,ijp,pj->p", n, sigma, n)
    got = {"u_r": np.sum(np.asarray(arrays["displacement"]) * n, axis=1), "sigma_r": sigma_r,
           "sigma_theta": 0.5 * (s["XX"] + s["YY"] + s["ZZ"] - sigma_r)}
    worst = 0.0
    for radius in (a, b):
        on = np.abs(r - radius) < 1e-9 * b
        c, k = p * a**3 / (b**3 - a**3), b**3 / radius**3
        want = {"u_r": c * radius / e * ((1 - 2 * nu) + (1 + nu) * k / 2),
                "sigma_r": -c * (k - 1), "sigma_theta": c * (k / 2 + 1)}
        for q, value in want.items():
            mean = got[q][on].mean() if on.any() else math.nan
            error = abs(mean - value) / (abs(value) if q == "u_r" else p)
            worst = max(worst, error) if math.isfinite(error) else math.inf
            check(on.sum() == 61 and error <= tolerance,
                  f"{name} t={t}: {q}(r = {radius}) {mean:g} over {on.sum()} nodes, Lame "
                  f"{value:g} (error {100 * error:.2f} %)")
    return f"Lame within {100 * worst:.2f} %"


# Known values of runs by their folder (run_paraview_check.py's names): the VTK cell type and the
# numbers of cells and points ParaView must show, whether the run is the mixed model (results.h5
# says so in each step's `stress_source`) and a check against a closed form.
KNOWN = {
    # 20 x 2 x 2 box cells of 6 Tet4 each; 21 x 3 x 3 nodes.
    "cantilever_3d_tet4": {"cell_type": 10, "cells": 480, "points": 189, "mixed": False,
                           "values": check_total_reaction},
    # 3 cubed-sphere patches of 4 x 4 cells, 4 layers: 192 Hex8; 5 spheres of 61 nodes.
    "lame_sphere_mixed": {"cell_type": 12, "cells": 192, "points": 305, "mixed": True,
                          "values": check_lame_sphere},
}
MIXED_SOURCE = "nodal stress unknowns of the mixed model"


def check_known(name, step, t, grid, arrays, h5):
    """The run's KNOWN entry; returns what its values check found."""
    known = KNOWN[name]
    cell_types = sorted(set(np.asarray(grid.CellTypes).tolist()))
    check(cell_types == [known["cell_type"]] and grid.GetNumberOfCells() == known["cells"] and
          grid.GetNumberOfPoints() == known["points"],
          f"{name} t={t}: VTK cell types {cell_types}, {grid.GetNumberOfCells()} cells, "
          f"{grid.GetNumberOfPoints()} points; expected type {known['cell_type']}, "
          f"{known['cells']} cells, {known['points']} points")
    source = h5[f"steps/{step}"].attrs["stress_source"]
    source = source.decode() if isinstance(source, bytes) else str(source)
    check(source.startswith(MIXED_SOURCE) == known["mixed"],
          f"{name} step {step}: stress_source '{source}', "
          f"{'' if known['mixed'] else 'not '}expected the mixed model's")
    if known["mixed"]:
        per_point = sum(np.asarray(arrays[k]).shape[1] for k in ("displacement", "stress")
                        if k in arrays)
        check(per_point == 9, f"{name} t={t}: {per_point} displacement and stress components "
              "per point, the 3D mixed model has 9 unknowns per node")
    return known["values"](name, t, grid, arrays)


def check_run(directory):
    name = os.path.basename(directory)
    summary = json.load(open(os.path.join(directory, "summary.json")))
    loads = [s["load_factor"] for s in summary["steps"]]
    contact = "contact" in summary["steps"][0]
    h5 = h5py.File(os.path.join(directory, "results.h5"), "r")
    dim = h5["mesh/nodes"].shape[1]
    expected = {"displacement": 3, "reaction": 3, "stress": 3 if dim == 2 else 6}
    if contact:
        expected.update({"contact_status": 1, "contact_gap": 1, "contact_normal_traction": 1,
                         "contact_tangential_traction": 1})
    reader = pv.OpenDataFile(os.path.join(directory, "results.xdmf"))
    times = render_paraview.timesteps(reader)
    check(len(times) == len(loads) and np.allclose(times, loads),
          f"{name}: time steps {times} vs load factors {loads}")
    warp = pv.WarpByVector(Input=reader, Vectors=["POINTS", "displacement"], ScaleFactor=1.0)
    peak_pressure = 0.0
    found = []
    for step, t in enumerate(times, start=1):
        warp.UpdatePipeline(t)
        grid = leaf(reader)
        if step == 1:
            check_mesh(name, grid, h5)
        check(list(h5["mesh/element_region"][()]) == list(np.asarray(grid.CellData["region"])),
              f"{name} t={t}: region differs from HDF5")
        info = reader.PointData["stress"]
        labels = [info.GetComponentName(c) for c in range(expected["stress"])]
        check(labels == STRESS_LABELS[dim], f"{name}: ParaView labels stress {labels}, documented "
              f"{STRESS_LABELS[dim]}")
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
            if k in ("displacement", "reaction"):
                check(np.array_equal(a, h5[f"steps/{step}/{k}"][()]),
                      f"{name} t={t}: {k} differs from results.h5 /steps/{step}/{k}")
        stress, column = stress_columns(name, h5, step, dim)
        if "stress" in arrays:
            a = np.asarray(arrays["stress"])
            for j, label in enumerate(STRESS_LABELS[dim]):
                check(a.shape[1] == len(STRESS_LABELS[dim]) and
                      np.array_equal(a[:, j], stress[:, column[label]]),
                      f"{name} t={t}: ParaView's stress {label} (column {j}) is not results.h5 "
                      f"/steps/{step}/stress column {column[label]} "
                      f"({STRESS_MEANING[dim][j]})")
            if dim == 3:
                check_legacy_reader(name, directory, t, a)
        u = np.asarray(arrays["displacement"])
        check((dim == 3 or np.all(u[:, 2] == 0.0)) and np.abs(u).max() > 0.0,
              f"{name} t={t}: displacement z not 0 in 2D or displacement all 0")
        check_calculator(name, reader, t, stress, column, dim)
        if name in KNOWN:
            found.append(check_known(name, step, t, grid, arrays, h5))
        moved = np.asarray(leaf(warp).Points) - np.asarray(grid.Points)
        check(np.allclose(moved, u, rtol=0, atol=1e-12 * (1 + np.abs(u).max())),
              f"{name} t={t}: warped points differ from reference + displacement by "
              f"{np.abs(moved - u).max():g}")
        if contact:
            status = np.asarray(arrays["contact_status"])
            check(set(np.unique(status)) <= {-1, 0, 1, 2},
                  f"{name} t={t}: status {np.unique(status)}")
            p = np.asarray(arrays["contact_normal_traction"])
            check(np.all(p[status <= 0] == 0.0), f"{name} t={t}: traction off the closed nodes")
            peak_pressure = max(peak_pressure, p.max())
    if contact:
        check(peak_pressure > 0.0, f"{name}: no contact pressure in any step")
    pv.Delete(warp)
    pv.Delete(reader)
    h5.close()
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
    print(f"{name}: {dim}D, {len(times)} steps, arrays {sorted(expected)}; rendered "
          + ", ".join(os.path.basename(w) for w in written)
          + (f"; known values ({'mixed model, ' if KNOWN[name]['mixed'] else ''}VTK cell type "
             f"{KNOWN[name]['cell_type']}): " + ", ".join(found) if name in KNOWN else ""))


for d in sys.argv[1:]:
    check_run(d)
print(f"{len(failures)} failures")
sys.exit(1 if failures else 0)
