#!/usr/bin/env python3
"""Write glass.obj: a concave glass (open at the top) for the glass case.

A tapered cup: a flat bottom of radius rb at z = 0 and a side wall whose
radius grows linearly to rt at height H, as a surface of revolution of
`nseg` segments.  Only the inner surface is meshed (the fluid is inside:
the case samples it with `side container`).  Triangles are wound so that
the normals point out of the cup.  Run: python3 makeGlass.py [file].
"""
import math
import sys

rb, rt, H = 0.06, 0.08, 0.18      # m
nseg, nring, nz = 48, 6, 18        # resolution of the mesh (not of the sampling)


def main(path):
    v, f = [], []
    v.append((0.0, 0.0, 0.0))                     # bottom centre
    rings = []
    for i in range(1, nring + 1):                 # bottom rings
        r = rb * i / nring
        rings.append([len(v) + k for k in range(nseg)])
        v += [(r * math.cos(2 * math.pi * k / nseg), r * math.sin(2 * math.pi * k / nseg), 0.0)
              for k in range(nseg)]
    for j in range(1, nz + 1):                    # side rings
        z = H * j / nz
        r = rb + (rt - rb) * j / nz
        rings.append([len(v) + k for k in range(nseg)])
        v += [(r * math.cos(2 * math.pi * k / nseg), r * math.sin(2 * math.pi * k / nseg), z)
              for k in range(nseg)]
    for k in range(nseg):                         # bottom fan: normal -z (out of the cup)
        a, b = rings[0][k], rings[0][(k + 1) % nseg]
        f.append((0, b, a))
    for i in range(len(rings) - 1):
        lo, hi = rings[i], rings[i + 1]
        for k in range(nseg):
            a, b = lo[k], lo[(k + 1) % nseg]
            c, d = hi[k], hi[(k + 1) % nseg]
            f += [(a, b, d), (a, d, c)]           # bottom annuli: -z; side: outward
    with open(path, "w") as out:
        out.write("# concave glass for the Sluice glass case (makeGlass.py)\n")
        for p in v:
            out.write("v %.6f %.6f %.6f\n" % p)
        for t in f:
            out.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))


main(sys.argv[1] if len(sys.argv) > 1 else "glass.obj")
