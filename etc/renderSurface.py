"""renderSurface: a ParaView picture of a case's reconstructed free surface.

    pvbatch etc/renderSurface.py <case> [-time t] [-output file.png] [-size W H]

Opens <case>/surface.pvd (written by reconstructSurface) with ParaView's own
PVD reader, colours the surface by the velocity magnitude interpolated to
its vertices, shows the walls and obstacles (<case>/boundary.pvd) as faint
points, and saves a screenshot.  Default time: the latest; default output:
<case>/surface.png.  Prints what it rendered (time, triangles, range).

Needs ParaView's pvbatch (paraview.simple); etc/renderSurface runs it,
under xvfb-run when there is no display.  Debian's python3-paraview
conflicts with python3-vtk9 (the tests' VTK), so doc/surface.md shows how
to unpack ParaView privately instead of installing it.
"""
import os
import sys

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetColorTransferFunction, GetScalarBar,
                             PVDReader, SaveScreenshot, Show, UpdatePipeline)


def usage(status):
    print(__doc__.split("\n\n")[1], file=sys.stderr if status else sys.stdout)
    sys.exit(status)


def parse_args(argv):
    opt = {"case": None, "time": None, "output": None, "size": [1400, 800]}
    i = 1
    while i < len(argv):
        a = argv[i]
        if a.startswith("--"):  # pvbatch 5.11 hands "-time" on as "--time"
            a = a[1:]
        if a in ("-h", "-help"):
            usage(0)
        elif a == "-time" and i + 1 < len(argv):
            opt["time"] = float(argv[i + 1])
            i += 1
        elif a == "-output" and i + 1 < len(argv):
            opt["output"] = argv[i + 1]
            i += 1
        elif a == "-size" and i + 2 < len(argv):
            opt["size"] = [int(argv[i + 1]), int(argv[i + 2])]
            i += 2
        elif not a.startswith("-") and opt["case"] is None:
            opt["case"] = a
        else:
            print("renderSurface: unexpected argument '%s'" % a, file=sys.stderr)
            usage(2)
        i += 1
    if opt["case"] is None:
        usage(2)
    return opt


def main():
    opt = parse_args(sys.argv)
    case = opt["case"]
    pvd = os.path.join(case, "surface.pvd")
    if not os.path.isfile(pvd):
        print("renderSurface: no %s: run reconstructSurface -case %s first" % (pvd, case),
              file=sys.stderr)
        return 1
    surf = PVDReader(FileName=pvd)
    times = list(surf.TimestepValues) if surf.TimestepValues else [0.0]
    t = times[-1] if opt["time"] is None else min(times, key=lambda x: abs(x - opt["time"]))
    view = GetActiveViewOrCreate("RenderView")
    view.ViewSize = opt["size"]
    view.ViewTime = t
    view.UseColorPaletteForBackground = 0
    view.Background = [1, 1, 1]
    view.OrientationAxesVisibility = 0
    UpdatePipeline(time=t, proxy=surf)
    ntri = surf.GetDataInformation().GetNumberOfCells()
    d = Show(surf, view)
    d.Representation = "Surface"
    d.Specular = 0.4
    ColorBy(d, ("POINTS", "velocity", "Magnitude"))
    lut = GetColorTransferFunction("velocity")
    lut.ApplyPreset("Blues", True)
    lut.InvertTransferFunction()
    vrange = surf.PointData["velocity"].GetRange(-1)
    lut.RescaleTransferFunction(0.0, max(vrange[1], 1e-6))
    d.SetScalarBarVisibility(view, True)
    bar = GetScalarBar(lut, view)
    bar.Title = "|velocity| (m/s)"
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    bpvd = os.path.join(case, "boundary.pvd")
    if os.path.isfile(bpvd):
        walls = PVDReader(FileName=bpvd)
        w = Show(walls, view)
        w.Representation = "Points"
        w.PointSize = 1.5
        w.ColorArrayName = ["POINTS", ""]
        w.AmbientColor = w.DiffuseColor = [0.55, 0.55, 0.55]
        w.Opacity = 0.25
    # from the front (-y), above, a little from the dam's side
    view.CameraPosition = [-0.55, -1.75, 1.75]
    view.CameraFocalPoint = [0.85, 0.3, 0.1]
    view.CameraViewUp = [0, 0, 1]
    view.CameraViewAngle = 30
    out = opt["output"] or os.path.join(case, "surface.png")
    SaveScreenshot(out, view, ImageResolution=opt["size"])
    print("renderSurface: %s at t = %g (%d times in surface.pvd): %d triangles, |velocity| up to "
          "%.3g m/s -> %s" % (pvd, t, len(times), ntri, vrange[1], out))
    return 0


if __name__ == "__main__":
    status = main()
    sys.stdout.flush()
    sys.stderr.flush()
    # pvbatch 5.11 under Xvfb fails in the GLX teardown after the picture is
    # written (X error GLXBadContext, exit status 1): leave without it.
    os._exit(status)
