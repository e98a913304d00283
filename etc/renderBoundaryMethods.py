#!/usr/bin/env python3
"""renderBoundaryMethods: the boundary methods side by side, as in Fig. 2 of
Ihmsen et al. 2010 -- fluid particles coloured by sqrt(p / p_max(t)) (the
`pressureRatio` array of fluid.vtu), white at 0, red at 1, each method
normalised by its own p_max as in the paper.

    renderBoundaryMethods.py <case> [-time t] [-methods a,b,c] [-slice diagonal|none]
                             [-output file.png] [-size W H]

<case> is a case on which `stableTimeStep` has run: the pictures come from
its runs at a common deltaT, <case>/postProcessing/stableTimeStep/common/
<method>/.  Default time: the written time nearest to the largest average
compression (rhoErrAvg) of the first method's run, i.e. the hardest impact.
Default slice: the particles within 1.5 r0 of the vertical plane through the
tank's diagonal from the corner where the dam stands (a corner breaking dam
flows along it), seen from the side; `-slice none` shows all particles.
Default output: <case>/postProcessing/stableTimeStep/methods.png.

Uses only VTK's Python modules, so it runs with Debian's python3-vtk9
(`/usr/bin/python3 etc/renderBoundaryMethods.py ...`) and with ParaView's
`pvbatch` or `pvpython`, which ship the same modules (checked with Debian's
paraview 5.11: `xvfb-run -a pvbatch etc/renderBoundaryMethods.py <case>`).
Rendering is offscreen; VTK on Debian still needs an X display, so without
one the script runs itself again under `xvfb-run` (Debian package xvfb).
"""

import math
import os
import shutil
import sys

METHODS = ["ihmsen2010", "becker2009", "harada2007"]
TITLES = {
    "ihmsen2010": "ihmsen2010 (proposed)",
    "becker2009": "becker2009 [BTT09]",
    "harada2007": "harada2007 [HKK07]",
}


def usage(status):
    print(__doc__.split("\n\n")[1], file=sys.stderr if status else sys.stdout)
    sys.exit(status)


def parse_args(argv):
    opt = {"case": None, "time": None, "methods": None, "slice": "diagonal",
           "output": None, "size": None}
    i = 1
    while i < len(argv):
        a = argv[i]
        if a in ("-h", "-help", "--help"):
            usage(0)
        elif a == "-time" and i + 1 < len(argv):
            opt["time"] = float(argv[i + 1])
            i += 1
        elif a == "-methods" and i + 1 < len(argv):
            opt["methods"] = [m for m in argv[i + 1].split(",") if m]
            i += 1
        elif a == "-slice" and i + 1 < len(argv) and argv[i + 1] in ("diagonal", "none"):
            opt["slice"] = argv[i + 1]
            i += 1
        elif a == "-output" and i + 1 < len(argv):
            opt["output"] = argv[i + 1]
            i += 1
        elif a == "-size" and i + 2 < len(argv):
            opt["size"] = (int(argv[i + 1]), int(argv[i + 2]))
            i += 2
        elif not a.startswith("-") and opt["case"] is None:
            opt["case"] = a
        else:
            print("renderBoundaryMethods: unknown option or missing value: " + a, file=sys.stderr)
            usage(2)
        i += 1
    if opt["case"] is None:
        usage(2)
    return opt


def ensure_display():
    """VTK's X render window needs a display even offscreen: rerun under
    xvfb-run when there is none."""
    if os.environ.get("DISPLAY") or os.environ.get("SLUICE_RENDER_NO_XVFB"):
        return
    xvfb = shutil.which("xvfb-run")
    if not xvfb:
        sys.exit("renderBoundaryMethods: no X display and no xvfb-run: "
                 "install Debian's xvfb (apt-get install xvfb) or set DISPLAY")
    os.environ["SLUICE_RENDER_NO_XVFB"] = "1"
    os.execv(xvfb, [xvfb, "-a", "-s", "-screen 0 1920x1080x24", sys.executable] + sys.argv)


# ---- the runs -------------------------------------------------------------------

def time_dirs(run):
    """(time, name) of the time directories of a run holding a fluid.vtu."""
    out = []
    for name in os.listdir(run):
        try:
            t = float(name)
        except ValueError:
            continue
        if math.isfinite(t) and os.path.isfile(os.path.join(run, name, "fluid.vtu")):
            out.append((t, name))
    return sorted(out)


def record_rows(run):
    """Rows (time, deltaT, rhoErrAvg) of the run's timeStep.dat."""
    base = os.path.join(run, "postProcessing", "timeStep")
    rows = []
    if not os.path.isdir(base):
        return rows
    for start in sorted(os.listdir(base)):
        path = os.path.join(base, start, "timeStep.dat")
        if not os.path.isfile(path):
            continue
        with open(path) as f:
            for line in f:
                if line.startswith("#"):
                    continue
                v = line.split()
                if len(v) >= 8 and v[7] == "0":
                    rows.append((float(v[0]), float(v[1]), float(v[3])))
    return rows


def impact_time(run, times):
    rows = record_rows(run)
    if not rows:
        return times[-1][0]
    t_max = max(rows, key=lambda r: r[2])[0]
    return min(times, key=lambda tn: abs(tn[0] - t_max))[0]


def read_vtu(path):
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    if g.GetNumberOfPoints() == 0 and not os.path.isfile(path):
        sys.exit("renderBoundaryMethods: cannot read " + path)
    return g


# ---- the picture -------------------------------------------------------------------

def slab(grid, box, r0, mode):
    """vtkPolyData of the particles to show (all, or the diagonal slab),
    with their pressureRatio, and the 2D frame of the tank in that view."""
    from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
    pr = grid.GetPointData().GetArray("pressureRatio")
    if pr is None:
        sys.exit("renderBoundaryMethods: fluid.vtu has no 'pressureRatio' array "
                 "(written by the solver since the Fig. 2 colouring was added)")
    lo, hi = box
    ux, uy = hi[0] - lo[0], hi[1] - lo[1]
    n = math.hypot(ux, uy)
    ux, uy = ux / n, uy / n
    pts, vals = vtkPoints(), vtkDoubleArray()
    vals.SetName("pressureRatio")
    for i in range(grid.GetNumberOfPoints()):
        x, y, z = grid.GetPoint(i)
        if mode == "diagonal" and abs((x - lo[0]) * uy - (y - lo[1]) * ux) > 1.5 * r0:
            continue
        pts.InsertNextPoint(x, y, z)
        vals.InsertNextValue(pr.GetValue(i))
    verts = vtkCellArray()
    for i in range(pts.GetNumberOfPoints()):
        verts.InsertNextCell(1)
        verts.InsertCellPoint(i)
    pd = vtkPolyData()
    pd.SetPoints(pts)
    pd.SetVerts(verts)
    pd.GetPointData().SetScalars(vals)
    return pd, (ux, uy)


def frame_actor(box, mode):
    """The tank's walls: its outline, or in the diagonal view the rectangle
    of the diagonal plane."""
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
    from vtkmodules.vtkFiltersSources import vtkOutlineSource
    from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper
    lo, hi = box
    mapper = vtkPolyDataMapper()
    if mode == "diagonal":
        pts = vtkPoints()
        for (x, y, z) in ((lo[0], lo[1], lo[2]), (hi[0], hi[1], lo[2]),
                          (hi[0], hi[1], hi[2]), (lo[0], lo[1], hi[2])):
            pts.InsertNextPoint(x, y, z)
        lines = vtkCellArray()
        lines.InsertNextCell(5)
        for k in (0, 1, 2, 3, 0):
            lines.InsertCellPoint(k)
        pd = vtkPolyData()
        pd.SetPoints(pts)
        pd.SetLines(lines)
        mapper.SetInputData(pd)
    else:
        o = vtkOutlineSource()
        o.SetBounds(lo[0], hi[0], lo[1], hi[1], lo[2], hi[2])
        mapper.SetInputConnection(o.GetOutputPort())
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(0.2, 0.2, 0.2)
    actor.GetProperty().SetLineWidth(2)
    return actor


def white_to_red():
    from vtkmodules.vtkRenderingCore import vtkColorTransferFunction
    ctf = vtkColorTransferFunction()
    ctf.AddRGBPoint(0.0, 1.0, 1.0, 1.0)
    ctf.AddRGBPoint(1.0, 0.85, 0.0, 0.0)
    return ctf


def particles_actor(pd, r0, ctf):
    from vtkmodules.vtkFiltersSources import vtkSphereSource
    from vtkmodules.vtkRenderingCore import vtkActor, vtkGlyph3DMapper
    s = vtkSphereSource()
    s.SetRadius(0.5 * r0)
    s.SetThetaResolution(10)
    s.SetPhiResolution(8)
    m = vtkGlyph3DMapper()
    m.SetInputData(pd)
    m.SetSourceConnection(s.GetOutputPort())
    m.ScalingOff()
    m.SetLookupTable(ctf)
    m.SetScalarRange(0.0, 1.0)
    m.SetScalarModeToUsePointData()
    m.ScalarVisibilityOn()
    a = vtkActor()
    a.SetMapper(m)
    a.GetProperty().SetAmbient(0.55)  # mostly flat colour: the value, not the shading
    a.GetProperty().SetDiffuse(0.5)
    return a


def text_actor(lines, size, pos):
    from vtkmodules.vtkRenderingCore import vtkTextActor
    t = vtkTextActor()
    t.SetInput("\n".join(lines))
    t.GetTextProperty().SetFontSize(size)
    t.GetTextProperty().SetColor(0.0, 0.0, 0.0)
    t.SetPosition(*pos)
    return t


def lattice_spacing(grid):
    """r0: nearest-neighbour distance of the first particle in the initial
    lattice."""
    if grid.GetNumberOfPoints() < 2:
        return 0.02
    x0 = grid.GetPoint(0)
    return min(math.dist(x0, grid.GetPoint(i)) for i in range(1, grid.GetNumberOfPoints()))


def default_size(runs, mode):
    """1800 pixels wide; tall enough for the tank's view in each panel plus
    the captions."""
    b = read_vtu(os.path.join(runs[0][1], runs[0][2][0][1], "boundary.vtu")).GetBounds() \
        if os.path.isfile(os.path.join(runs[0][1], runs[0][2][0][1], "boundary.vtu")) else None
    if not b or mode != "diagonal":
        return (1800, int(1800 / len(runs)) + 100)
    width, height = math.hypot(b[1] - b[0], b[3] - b[2]), b[5] - b[4]
    return (1800, int(1800 / len(runs) * height / width * 1.15) + 150)


def run_label(run):
    rows = record_rows(run)
    return rows[0][1] if rows else float("nan")


def main():
    opt = parse_args(sys.argv)
    ensure_display()
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (the OpenGL back end)
    from vtkmodules.vtkIOImage import vtkPNGWriter
    from vtkmodules.vtkRenderingAnnotation import vtkScalarBarActor
    from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow, vtkWindowToImageFilter

    out_dir = os.path.join(opt["case"], "postProcessing", "stableTimeStep")
    common = os.path.join(out_dir, "common")
    methods = opt["methods"] or [m for m in METHODS if os.path.isdir(os.path.join(common, m))]
    if not methods:
        sys.exit("renderBoundaryMethods: no runs in %s: run stableTimeStep on the case first" % common)
    runs = []
    for m in methods:
        run = os.path.join(common, m)
        times = time_dirs(run)
        if not times:
            sys.exit("renderBoundaryMethods: %s has no time directory with a fluid.vtu" % run)
        runs.append((m, run, times))
    t_show = opt["time"] if opt["time"] is not None else impact_time(runs[0][1], runs[0][2])

    rw = vtkRenderWindow()
    rw.SetOffScreenRendering(1)
    rw.SetSize(*(opt["size"] or default_size(runs, opt["slice"])))
    rw.SetMultiSamples(0)
    ctf = white_to_red()
    camera = None
    n = len(runs)
    for k, (m, run, times) in enumerate(runs):
        t, name = min(times, key=lambda tn: abs(tn[0] - t_show))
        fluid = read_vtu(os.path.join(run, name, "fluid.vtu"))
        r0 = lattice_spacing(read_vtu(os.path.join(run, times[0][1], "fluid.vtu")))
        bpath = os.path.join(run, times[0][1], "boundary.vtu")
        if os.path.isfile(bpath):  # boundary particles sit r0/2 behind the walls
            b = read_vtu(bpath).GetBounds()
            box = ([b[0] + r0 / 2, b[2] + r0 / 2, b[4] + r0 / 2],
                   [b[1] - r0 / 2, b[3] - r0 / 2, b[5] - r0 / 2])
        else:
            b = fluid.GetBounds()
            box = ([b[0], b[2], b[4]], [b[1], b[3], b[5]])
        pd, (ux, uy) = slab(fluid, box, r0, opt["slice"])
        ren = vtkRenderer()
        ren.SetViewport(k / n, 0.0, (k + 1) / n, 1.0)
        ren.SetBackground(1.0, 1.0, 1.0)
        ren.AddActor(particles_actor(pd, r0, ctf))
        ren.AddActor(frame_actor(box, opt["slice"]))
        p = fluid.GetPointData().GetArray("pressure")
        pmax = p.GetRange()[1] if p is not None else float("nan")
        ren.AddViewProp(text_actor([TITLES.get(m, m),
                                    "deltaT %.4g s, t = %.3g s" % (run_label(run), t),
                                    "p_max %.3g Pa" % pmax], 20, (12, 12)))
        if camera is None:
            camera = ren.GetActiveCamera()
            c = [(box[0][i] + box[1][i]) / 2 for i in range(3)]
            size = [box[1][i] - box[0][i] for i in range(3)]
            d = 3.0 * max(size)
            if opt["slice"] == "diagonal":  # look at the diagonal plane from its side
                camera.SetPosition(c[0] + uy * d, c[1] - ux * d, c[2])
                width, height = math.hypot(size[0], size[1]), size[2]
            else:  # from the front, a little above, opposite the dam's corner
                camera.SetPosition(c[0] + 0.6 * d, c[1] - 0.9 * d, c[2] + 0.5 * d)
                width = height = math.sqrt(sum(v * v for v in size))
            camera.SetFocalPoint(*c)
            camera.SetViewUp(0, 0, 1)
            camera.ParallelProjectionOn()
            aspect = (rw.GetSize()[0] / n) / rw.GetSize()[1]
            camera.SetParallelScale(0.55 * max(height + 4 * r0, width / aspect))
            camera.SetClippingRange(0.01 * d, 10 * d)
        else:
            ren.SetActiveCamera(camera)
        if k == n - 1:
            bar = vtkScalarBarActor()
            bar.SetLookupTable(ctf)
            bar.SetTitle("sqrt(p/p_max)")
            bar.SetNumberOfLabels(3)
            bar.SetOrientationToHorizontal()
            bar.SetPosition(0.45, 0.86)
            bar.SetWidth(0.5)
            bar.SetHeight(0.12)
            bar.GetTitleTextProperty().SetColor(0, 0, 0)
            bar.GetLabelTextProperty().SetColor(0, 0, 0)
            ren.AddViewProp(bar)
        rw.AddRenderer(ren)
    rw.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(rw)
    grab.Update()
    out = opt["output"] or os.path.join(out_dir, "methods.png")
    w = vtkPNGWriter()
    w.SetFileName(out)
    w.SetInputConnection(grab.GetOutputPort())
    w.Write()
    print("renderBoundaryMethods: %s (t = %.4g s, %s)" % (out, t_show, ", ".join(methods)))


if __name__ == "__main__":
    main()
