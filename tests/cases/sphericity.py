#!/usr/bin/python3
"""Sphericity of a droplet for each written time of a case:
   sphericity.py <case>
prints 'time sphericity spread' lines.  sphericity = r_eq / r_max, with
r_eq the radius of the ball of the fluid's volume (n r0^3, r0 read from the
particle count and the first time's extent is not needed: the volume per
particle is taken from the mean nearest spacing) and r_max the largest
distance from the centre reached by 98 % of the particles.
spread = std(|x - c|) / mean(|x - c|)."""
import os
import sys

import numpy as np
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
from vtkmodules.util.numpy_support import vtk_to_numpy

case = sys.argv[1]
times = sorted((float(d), d) for d in os.listdir(case)
               if d.replace('.', '', 1).replace('e-', '', 1).isdigit() and os.path.isfile(os.path.join(case, d, "fluid.vtu")))
for t, d in times:
    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(os.path.join(case, d, "fluid.vtu"))
    r.Update()
    p = vtk_to_numpy(r.GetOutput().GetPoints().GetData())
    c = p.mean(axis=0)
    dist = np.linalg.norm(p - c, axis=1)
    if d == times[0][1]:  # particle spacing from the initial lattice
        r0 = np.sort(np.linalg.norm(p[1:] - p[0], axis=1))[0]
    r_eq = (3.0 * len(p) * r0 ** 3 / (4.0 * np.pi)) ** (1.0 / 3.0) - 0.5 * r0
    # the outer 2 % may be particles torn off: measure the body
    print("%g %.5f %.5f" % (t, r_eq / np.percentile(dist, 98), dist.std() / dist.mean()))
