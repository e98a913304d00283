#!/usr/bin/python3
"""Check every written time of a Sluice case, for the stability and fault
tests (tests/unit/test_stability.c, test_faults.c).

  check_run.py <case> [--domain x0 y0 z0 x1 y1 z1] [--box x0 y0 z0 x1 y1 z1]...
               [--sphere cx cy cz r]... [--count x0 y0 z0 x1 y1 z1] [--pvd]

Reads <case>/<time>/fluid.vtu for every time folder with VTK and prints one
line per time, in time order,

  time=T n=N nan=K outside=K solid=K count=K ke=E zmean=Z xmax=X ymax=Y zmax=Z
  vmax=V errmax=E

nan: non-finite values in any point or array; outside: particles not in the
closed box --domain (the container's inside); solid: particles strictly
inside a --box or --sphere solid; count: particles in the --count box (e.g.
the dry side of a wall); ke: kinetic energy per unit particle mass, sum of
|v|^2 / 2; errmax: largest densityError (percent).  A file VTK cannot read
prints `time=T unreadable=1`.  With --pvd the last line is

  pvd=OK|BAD n=N missing=K unlisted=K

checking that fluid.pvd is XML, its times increase, every listed file
exists, and every time folder holding a fluid.vtu is listed."""
import math
import os
import sys
import xml.etree.ElementTree as ET

import numpy as np
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.util.numpy_support import vtk_to_numpy


def times(case):
    out = []
    for d in os.listdir(case):
        try:
            t = float(d)
        except ValueError:
            continue
        if os.path.isfile(os.path.join(case, d, "fluid.vtu")):
            out.append((t, d))
    return sorted(out)


def read(path):
    errors = []
    r = vtkXMLUnstructuredGridReader()
    r.AddObserver("ErrorEvent", lambda o, e: errors.append(e))
    r.SetFileName(path)
    r.Update()
    if errors or r.GetErrorCode():
        return None
    g = r.GetOutput()
    pts = vtk_to_numpy(g.GetPoints().GetData()) if g.GetNumberOfPoints() else np.zeros((0, 3))
    pd = g.GetPointData()
    return pts, {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())}


def in_box(p, b):
    return np.all((p > b[:3]) & (p < b[3:]), axis=1)


def check_pvd(case):
    path = os.path.join(case, "fluid.pvd")
    try:
        root = ET.parse(path).getroot()
        sets = root.find("Collection").findall("DataSet")
        listed = [(float(s.get("timestep")), s.get("file")) for s in sets]
    except Exception:  # noqa: BLE001 - any parse problem makes the file bad
        return "pvd=BAD n=0 missing=0 unlisted=0"
    ok = all(a[0] < b[0] for a, b in zip(listed, listed[1:]))
    missing = sum(not os.path.isfile(os.path.join(case, f)) for _, f in listed)
    names = {os.path.dirname(f) for _, f in listed}
    unlisted = sum(d not in names for _, d in times(case))
    ok = ok and missing == 0
    return "pvd=%s n=%d missing=%d unlisted=%d" % ("OK" if ok else "BAD", len(listed), missing, unlisted)


def main():
    args = sys.argv[1:]
    case = args.pop(0)
    domain, boxes, spheres, count, pvd = None, [], [], None, False
    while args:
        a = args.pop(0)
        if a == "--pvd":
            pvd = True
            continue
        n = 4 if a == "--sphere" else 6
        v = np.array([float(args.pop(0)) for _ in range(n)])
        if a == "--domain":
            domain = v
        elif a == "--box":
            boxes.append(v)
        elif a == "--sphere":
            spheres.append(v)
        elif a == "--count":
            count = v
        else:
            sys.exit("check_run.py: unknown option " + a)
    for t, d in times(case):
        got = read(os.path.join(case, d, "fluid.vtu"))
        if got is None:
            print("time=%s unreadable=1" % d)
            continue
        p, arr = got
        nan = int(np.count_nonzero(~np.isfinite(p)) + sum(np.count_nonzero(~np.isfinite(a)) for a in arr.values()))
        fin = np.all(np.isfinite(p), axis=1)
        q = p[fin]
        outside = 0
        if domain is not None:
            outside = int(np.count_nonzero(~np.all((q >= domain[:3]) & (q <= domain[3:]), axis=1)))
        solid = np.zeros(len(q), dtype=bool)
        for b in boxes:
            solid |= in_box(q, b)
        for s in spheres:
            solid |= np.linalg.norm(q - s[:3], axis=1) < s[3]
        cnt = int(np.count_nonzero(in_box(q, count))) if count is not None else 0
        v = arr["velocity"]
        speed = np.linalg.norm(v, axis=1) if len(v) else np.zeros(0)
        ok = np.isfinite(speed)
        print("time=%s n=%d nan=%d outside=%d solid=%d count=%d ke=%.9g zmean=%.9g xmax=%.9g ymax=%.9g zmax=%.9g vmax=%.9g errmax=%.9g" % (
            d, len(p), nan, outside, int(np.count_nonzero(solid)), cnt,
            0.5 * float(np.sum(speed[ok] ** 2)),
            float(q[:, 2].mean()) if len(q) else math.nan,
            float(q[:, 0].max()) if len(q) else math.nan,
            float(q[:, 1].max()) if len(q) else math.nan,
            float(q[:, 2].max()) if len(q) else math.nan,
            float(speed[ok].max()) if np.any(ok) else math.nan,
            float(np.nanmax(arr["densityError"])) if len(p) else math.nan))
    if pvd:
        print(check_pvd(case))


main()
