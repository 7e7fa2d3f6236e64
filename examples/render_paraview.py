#!/usr/bin/env pvpython
"""Renders the deformed shape of mixcon results with ParaView (pvpython or pvbatch, headless).

For every output directory given (one holding results.xdmf), opens the last step, warps the mesh
by the displacement and writes
  <dir>/deformed_stress_<c>.png          coloured by the nodal stress component c (xx, yy, xy;
                                         3D: xx, yy, zz, yz, xz, xy)
  <dir>/deformed_contact_pressure.png    contact runs: coloured by the normal contact traction
The warp is the true displacement when it is visible (largest |u| at least 1 % of the model's
size), else magnified to 5 % of the size; the factor is printed and written on the image. A 2D
model is seen from +z, a 3D one from an oblique view.

Usage: pvpython --force-offscreen-rendering examples/render_paraview.py OUT_DIR [OUT_DIR ...]
           [--component xx|yy|zz|yz|xz|xy] [--scale FACTOR] [--size 1200 800]
Needs ParaView 5.10+ (Debian: apt-get install python3-paraview). Debian's ParaView renders
through X only: without a display, run it as `xvfb-run -a pvpython examples/render_paraview.py`.
"""
import argparse
import math
import os
import sys

from paraview import simple as pv

# The columns of the "stress" array as ParaView reads it (docs/output-format.md): 3 in 2D (Voigt
# order); in 3D the XDMF points at the copy in VTK's symmetric-tensor order (stress_vtk), which
# ParaView labels XX YY ZZ XY YZ XZ.
STRESS_COLUMNS = {3: ["xx", "yy", "xy"], 6: ["xx", "yy", "zz", "xy", "yz", "xz"]}
COMPONENTS = sorted(set(STRESS_COLUMNS[3] + STRESS_COLUMNS[6]))


def timesteps(reader):
    t = reader.TimestepValues
    if t is None:
        return [0.0]
    return list(t) if isinstance(t, (list, tuple)) or hasattr(t, "__len__") else [t]


def warp_factor(reader, time, scale=None):
    """Displacement scale: 1 when the deformation is visible, else magnified to 5 % of the size."""
    if scale is not None:
        return scale
    reader.UpdatePipeline(time)
    b = reader.GetDataInformation().GetBounds()
    size = max(b[1] - b[0], b[3] - b[2], b[5] - b[4])
    umax = reader.PointData["displacement"].GetRange(-1)[1]
    if umax <= 0.0 or umax >= 0.01 * size:
        return 1.0
    return 0.05 * size / umax


def render(directory, component="xx", scale=None, size=(1200, 800)):
    """Writes the PNGs of one output directory; returns their paths."""
    reader = pv.OpenDataFile(os.path.join(directory, "results.xdmf"))
    time = timesteps(reader)[-1]
    factor = warp_factor(reader, time, scale)
    warp = pv.WarpByVector(Input=reader, Vectors=["POINTS", "displacement"], ScaleFactor=factor)
    view = pv.CreateView("RenderView")
    view.ViewSize = list(size)
    view.ViewTime = time
    view.OrientationAxesVisibility = 0
    view.Background = [1.0, 1.0, 1.0]
    try:  # ParaView 5.10+: the background is the palette's unless told otherwise
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass
    display = pv.Show(warp, view)
    display.SetRepresentationType("Surface With Edges")
    display.EdgeColor = [0.3, 0.3, 0.3]
    stress = reader.PointData["stress"]
    columns = STRESS_COLUMNS[stress.GetNumberOfComponents()]
    if component not in columns:
        raise ValueError(f"{directory}: stress has no component {component} (columns {columns})")
    index = columns.index(component)
    fields = [("stress", index, f"stress {component}", f"deformed_stress_{component}.png")]
    b = reader.GetDataInformation().GetBounds()
    three_d = b[5] - b[4] > 0.0
    if "contact_normal_traction" in reader.PointData.keys():
        fields.append(("contact_normal_traction", None, "contact pressure (normal traction)",
                       "deformed_contact_pressure.png"))
    written = []
    for array, comp, title, name in fields:
        named = comp is not None
        pv.ColorBy(display, ("POINTS", array, stress.GetComponentName(comp)) if named else
                   ("POINTS", array))
        lut = pv.GetColorTransferFunction(array)
        if named:
            lut.VectorMode = "Component"
            lut.VectorComponent = comp
        display.RescaleTransferFunctionToDataRange(False, True)
        display.SetScalarBarVisibility(view, True)
        bar = pv.GetScalarBar(lut, view)
        bar.Title = title
        bar.ComponentTitle = ""
        bar.TitleColor = bar.LabelColor = [0.0, 0.0, 0.0]
        text = pv.Text(Text=f"{os.path.basename(os.path.normpath(directory))}: load factor "
                            f"{time:g}, displacement x {factor:.4g}")
        label = pv.Show(text, view)
        label.Color = [0.0, 0.0, 0.0]
        label.WindowLocation = "Upper Center"
        pv.ResetCamera(view)
        if three_d:
            view.InteractionMode = "3D"
            camera = view.GetActiveCamera()
            camera.Elevation(15.0)
            camera.Azimuth(30.0)
            pv.ResetCamera(view)
        else:
            view.InteractionMode = "2D"
        path = os.path.join(directory, name)
        pv.SaveScreenshot(path, view, ImageResolution=list(size))
        pv.Hide(text, view)
        pv.Delete(text)
        display.SetScalarBarVisibility(view, False)
        written.append(path)
    pv.Delete(warp)
    pv.Delete(view)
    pv.Delete(reader)
    return written, factor


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("directories", nargs="+")
    ap.add_argument("--component", choices=COMPONENTS, default="xx")
    ap.add_argument("--scale", type=float, default=None, help="displacement factor (default: auto)")
    ap.add_argument("--size", type=int, nargs=2, default=[1200, 800])
    args = ap.parse_args()
    for d in args.directories:
        if not os.path.exists(os.path.join(d, "results.xdmf")):
            print(f"render_paraview: {d}: no results.xdmf", file=sys.stderr)
            return 1
        written, factor = render(d, args.component, args.scale, tuple(args.size))
        for w in written:
            print(f"render_paraview: wrote {w} (displacement x {factor:.4g})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
