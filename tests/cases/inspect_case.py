#!/usr/bin/python3
"""Read the latest (or a given) time directory of a Sluice case with VTK and
print key=value facts for the case tests:

  inspect_case.py <case> [time] [--r0 R] [--lo x y z --hi x y z]

n, nan (count of non-finite values), vmax, vmean, zmin..., pressure near the
bottom (p_bottom: mean fluid pressure of the lowest layer, z < zmin + r0/2),
the top layer's mean height and density (z_top, rho_top: z > zmax - r0/2),
outside (particles outside the box lo..hi), density error statistics."""
import math
import sys

import numpy as np
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.util.numpy_support import vtk_to_numpy


def latest_time(case):
    import os
    best = None
    for d in os.listdir(case):
        try:
            t = float(d)
        except ValueError:
            continue
        if os.path.isfile(os.path.join(case, d, "fluid.vtu")) and (best is None or t > best[0]):
            best = (t, d)
    return best[1]


def read(path):
    errors = []
    r = vtkXMLUnstructuredGridReader()
    r.AddObserver("ErrorEvent", lambda o, e: errors.append(e))
    r.SetFileName(path)
    r.Update()
    if errors or r.GetErrorCode():
        sys.exit("VTK could not read %s" % path)
    g = r.GetOutput()
    pts = vtk_to_numpy(g.GetPoints().GetData()) if g.GetNumberOfPoints() else np.zeros((0, 3))
    pd = g.GetPointData()
    arrays = {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())}
    return pts, arrays


def main():
    args = sys.argv[1:]
    case = args.pop(0)
    r0 = None
    lo = hi = None
    time = None
    while args:
        a = args.pop(0)
        if a == "--r0":
            r0 = float(args.pop(0))
        elif a == "--lo":
            lo = [float(args.pop(0)) for _ in range(3)]
        elif a == "--hi":
            hi = [float(args.pop(0)) for _ in range(3)]
        else:
            time = a
    time = time or latest_time(case)
    pts, arr = read("%s/%s/fluid.vtu" % (case, time))
    v = arr["velocity"]
    speed = np.linalg.norm(v, axis=1)
    out = {"time": time, "n": len(pts)}
    out["nan"] = int(np.count_nonzero(~np.isfinite(pts)) + sum(np.count_nonzero(~np.isfinite(a)) for a in arr.values()))
    out["vmax"] = float(speed.max()) if len(speed) else 0.0
    out["vmean"] = float(speed.mean()) if len(speed) else 0.0
    out["ke"] = float(0.5 * np.sum(speed ** 2))
    for k, name in enumerate("xyz"):
        out[name + "min"] = float(pts[:, k].min())
        out[name + "max"] = float(pts[:, k].max())
    err = arr["densityError"]
    out["err_mean"] = float(np.mean(np.maximum(err, 0)))
    out["err_max"] = float(err.max())
    if r0:
        z0 = pts[:, 2].min()
        low = pts[:, 2] < z0 + 0.5 * r0
        out["p_bottom"] = float(arr["pressure"][low].mean())
        out["z_bottom"] = float(pts[low, 2].mean())
        top = pts[:, 2] > pts[:, 2].max() - 0.5 * r0
        out["z_top"] = float(pts[top, 2].mean())
        out["rho_top"] = float(arr["density"][top].mean())
    if lo and hi:
        inside = np.all((pts >= np.array(lo)) & (pts <= np.array(hi)), axis=1)
        out["outside"] = int(np.count_nonzero(~inside))
    for k, v in out.items():
        print("%s=%s" % (k, v))


main()
