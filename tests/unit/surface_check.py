#!/usr/bin/python3
"""Check a reconstructed surface with VTK, for tests/unit/test_surface.c.

    surface_check.py SURFACE.vtp [FLUID.vtu]

Reads the .vtp with vtkXMLPolyDataReader (ParaView's reader) and prints
key=value lines:

    points=N triangles=M            what VTK read
    open_edges=K                    boundary plus non-manifold edges
                                    (vtkFeatureEdges); 0 for a closed surface
    area=A volume=V                 vtkMassProperties
    velocity=1 pressure=1           the point arrays are there (1) or not (0)

With FLUID.vtu also which particles lie outside the surface and how far.
A particle counts as outside when both VTK tests say so: ray casting
(vtkSelectEnclosedPoints) and the sign of vtkImplicitPolyDataDistance
(from the normal at the nearest point).  Each alone misjudges a few
points: the sign deep inside a complicated surface, the rays (seen on a
dam break) for particles with 30 neighbours 3 r0 inside.

    particles=N max_outside=D       the largest distance outside (0 if none)
    outside=K                       particles outside at all

Any VTK error or warning makes the exit status non-zero.  Run with Debian's
/usr/bin/python3 (python3-vtk9) or ParaView's pvpython.
"""
import sys

import vtkmodules.vtkCommonCore as vcc
from vtkmodules.vtkFiltersCore import vtkFeatureEdges, vtkImplicitPolyDataDistance, vtkMassProperties
from vtkmodules.vtkFiltersModeling import vtkSelectEnclosedPoints
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLUnstructuredGridReader

problems = []


def watch(obj):
    for ev in ("ErrorEvent", "WarningEvent"):
        obj.AddObserver(ev, lambda o, e: problems.append(e))
    return obj


def read(cls, path):
    r = watch(cls())
    r.SetFileName(path)
    r.Update()
    if r.GetErrorCode() != 0:
        problems.append("error code %d" % r.GetErrorCode())
    return r.GetOutput()


def main():
    vcc.vtkObject.GlobalWarningDisplayOff()
    s = read(vtkXMLPolyDataReader, sys.argv[1])
    print("points=%d" % s.GetNumberOfPoints())
    print("triangles=%d" % s.GetNumberOfPolys())
    fe = watch(vtkFeatureEdges())
    fe.SetInputData(s)
    fe.BoundaryEdgesOn()
    fe.NonManifoldEdgesOn()
    fe.FeatureEdgesOff()
    fe.ManifoldEdgesOff()
    fe.Update()
    print("open_edges=%d" % fe.GetOutput().GetNumberOfCells())
    mp = watch(vtkMassProperties())
    mp.SetInputData(s)
    mp.Update()
    print("area=%.17g" % mp.GetSurfaceArea())
    print("volume=%.17g" % mp.GetVolume())
    pd = s.GetPointData()
    print("velocity=%d" % (pd.GetArray("velocity") is not None))
    print("pressure=%d" % (pd.GetArray("pressure") is not None))
    if len(sys.argv) > 2:
        f = read(vtkXMLUnstructuredGridReader, sys.argv[2])
        enc = watch(vtkSelectEnclosedPoints())
        enc.SetInputData(f)
        enc.SetSurfaceData(s)
        enc.CheckSurfaceOn()
        enc.Update()
        d = watch(vtkImplicitPolyDataDistance())
        d.SetInput(s)
        worst, outside = 0.0, 0
        for i in range(f.GetNumberOfPoints()):
            if enc.IsInside(i):
                continue
            v = d.EvaluateFunction(f.GetPoint(i))
            if v > 0:
                outside += 1
                worst = max(worst, v)
        print("particles=%d" % f.GetNumberOfPoints())
        print("max_outside=%.17g" % worst)
        print("outside=%d" % outside)
    if problems:
        print("VTK reported: %s" % ", ".join(problems), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
