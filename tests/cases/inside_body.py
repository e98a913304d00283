#!/usr/bin/python3
"""Count fluid particles inside a box-shaped boundary body at a written time:
   inside_body.py <case> <time> <body index>
The body's extent is the bounding box of its boundary particles (which sit
r0/2 inside its surface), so a fluid particle inside that box has
penetrated the body by more than r0/2.  Prints 'inside=N' and the box."""
import sys

import numpy as np
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.util.numpy_support import vtk_to_numpy


def read(path):
    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    g = r.GetOutput()
    pd = g.GetPointData()
    return vtk_to_numpy(g.GetPoints().GetData()), {pd.GetArrayName(i): vtk_to_numpy(pd.GetArray(i)) for i in range(pd.GetNumberOfArrays())}


case, time, body = sys.argv[1], sys.argv[2], int(sys.argv[3])
bp, ba = read("%s/%s/boundary.vtu" % (case, time))
fp, _ = read("%s/%s/fluid.vtu" % (case, time))
sel = bp[ba["body"] == body]
lo, hi = sel.min(axis=0), sel.max(axis=0)
inside = np.all((fp > lo) & (fp < hi), axis=1)
print("inside=%d" % np.count_nonzero(inside))
print("lo=%s hi=%s" % (" ".join("%.4f" % v for v in lo), " ".join("%.4f" % v for v in hi)))
