#!/usr/bin/python3
"""frontArrival.py: when the dam-break front reaches a gauge line, read
several ways, so that the reading can be told from the flow.

    /usr/bin/python3 cases/sphericTest2/frontArrival.py <case> [x_gauge] [-t0 T]
        [-data spheric_test2_kleefsman2005_exp.csv]

x_gauge defaults to H3 (x = 1.488 m); the front runs towards -x.  -t0 T
subtracts T from every time of the run (a run whose gate opens at T).  From
the case's written fluid.vtu (write often, e.g. every 0.005 s, through the
arrival) it prints

  tip      the time the first fluid particle passes x_gauge (the leading
           particle's x, linear in time between written times), and the
           tip's speed there;
  h_tip    the front's thickness where it passes the gauge: the highest
           particle within 2 r0 behind x_gauge at the first written time
           after the tip passed, plus r0/2, in m and in h = 2 r0;

and from every waterGauges function object of the case (one row per step)
the first time its height at the column of x_gauge exceeds 0.002, 0.01
and 0.02 m (0.02 m is compareExperiment's threshold; the experiment's H3
crosses them at 0.186, 0.194 and 0.218 s), with the object's colour
threshold.  With -data, the time shift that best fits the run's H3 and H4
heights (object `gauges`, columns 2 and 3) to the experiment's over
0.05-0.34 s after release (RMS before and after the shift): a pure time
offset of the whole flow shows at H4, in the reservoir, where neither the
thin front nor a threshold enters.  Needs Debian's python3-vtk9 and numpy
(/usr/bin/python3)."""
import glob
import os
import re
import sys

import numpy as np
from vtk.util.numpy_support import vtk_to_numpy
import vtk

HEIGHTS = (0.002, 0.01, 0.02)


def read_points(path):
    r = vtk.vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    return vtk_to_numpy(r.GetOutput().GetPoints().GetData())


def dict_value(path, key):
    """the value of a top-level `key value;` line (numbers only)"""
    with open(path) as f:
        for line in f:
            m = re.match(r"\s*%s\s+([-+0-9.eE]+)\s*;" % key, line)
            if m:
                return float(m.group(1))
    raise SystemExit("%s: no numeric entry '%s'" % (path, key))


def gauge_objects(case):
    """(name, colour threshold, column of x_gauge) of every waterGauges
    object, from the header of its waterGauges.dat"""
    out = []
    for path in sorted(glob.glob(os.path.join(case, "postProcessing", "*", "*",
                                              "waterGauges.dat"))):
        name = path.split(os.sep)[-3]
        colour, xs = None, []
        with open(path) as f:
            for line in f:
                if not line.startswith("#"):
                    break
                m = re.search(r"reaches ([0-9.]+)", line)
                if m and colour is None:
                    colour = float(m.group(1))
                xs += [float(v) for v in re.findall(r"\(\s*([-0-9.eE]+)\s+[-0-9.eE]+\s*\)",
                                                     line)]
        if out and out[-1][0] == name:  # a later session (-resume) of the same object
            out[-1][2].append(path)
        else:
            out.append((name, colour, [path], xs))
    return out


def main():
    if len(sys.argv) < 2:
        raise SystemExit(__doc__)
    args = sys.argv[1:]
    t0 = 0.0
    data = None
    if "-t0" in args:
        k = args.index("-t0")
        t0 = float(args[k + 1])
        del args[k:k + 2]
    if "-data" in args:
        k = args.index("-data")
        data = args[k + 1]
        del args[k:k + 2]
    case = args[0]
    xg = float(args[1]) if len(args) > 1 else 1.488
    props = os.path.join(case, "constant", "fluidProperties")
    try:
        r0 = dict_value(props, "r0")
    except SystemExit:
        r0 = dict_value(props, "particleSpacing")
    h = 2.0 * r0
    times = []
    for d in os.listdir(case):
        try:
            t = float(d)
        except ValueError:
            continue
        if os.path.exists(os.path.join(case, d, "fluid.vtu")):
            times.append((t - t0, d))
    times.sort()
    if len(times) < 2:
        raise SystemExit("%s: fewer than two written times with a fluid.vtu" % case)
    prev = None
    tip = speed = thick = None
    for t, d in times:
        p = read_points(os.path.join(case, d, "fluid.vtu"))
        xmin = p[:, 0].min()
        if prev and prev[1] > xg >= xmin:
            ta, x0 = prev
            tip = ta + (t - ta) * (x0 - xg) / (x0 - xmin)
            speed = (x0 - xmin) / (t - ta)
            behind = p[(p[:, 0] >= xg) & (p[:, 0] < xg + h)]
            thick = behind[:, 2].max() + 0.5 * r0 if len(behind) else float("nan")
            break
        prev = (t, xmin)
    print("case %s  r0 %g m  gauge x %g m" % (case, r0, xg))
    if tip is None:
        print("tip      not past the gauge by t = %g s" % times[-1][0])
    else:
        print("tip      %.4f s  (speed %.2f m/s)" % (tip, speed))
        print("h_tip    %.4f m = %.2f h  (at the first write after the tip passed)" %
              (thick, thick / h))
    for name, colour, paths, xs in gauge_objects(case):
        col = None
        for k, x in enumerate(xs):
            if abs(x - xg) < 1e-9:
                col = k
        if col is None:
            continue
        first = {}
        for path in paths:
            with open(path) as f:
                for line in f:
                    if line.startswith("#"):
                        continue
                    v = line.split()
                    t, hh = float(v[0]) - t0, float(v[1 + col])
                    for th in HEIGHTS:
                        if th not in first and hh > th:
                            first[th] = t
        print("gauge %-8s colour %-4s h > %s m at %s s" %
              (name, colour, " / ".join("%g" % th for th in HEIGHTS),
               " / ".join("%.4f" % first[th] if th in first else "-" for th in HEIGHTS)))
    if data:
        best_shift(case, data, t0)


def best_shift(case, data, t0, window=(0.05, 0.34)):
    rows = [l for l in open(data) if not l.startswith("#")]
    names = rows[0].strip().split(",")
    exp = np.array([[float(v) for v in l.split(",")] for l in rows[1:]])
    files = glob.glob(os.path.join(case, "postProcessing", "gauges", "*", "waterGauges.dat"))
    if not files:
        raise SystemExit("%s: no postProcessing/gauges/*/waterGauges.dat" % case)
    sim = np.concatenate([np.loadtxt(f, ndmin=2) for f in files])
    sim = sim[np.argsort(sim[:, 0], kind="stable")]
    ts = sim[:, 0] - t0
    te = exp[:, names.index("t_s")]
    m = (te >= window[0]) & (te <= window[1])
    for g, col in (("H3", 3), ("H4", 4)):
        hs = np.nan_to_num(sim[:, col])
        he = exp[m, names.index(g + "_m")]
        rms = lambda s: float(np.sqrt(np.mean((np.interp(te[m] + s, ts, hs) - he) ** 2)))
        shifts = np.arange(-0.06, 0.0605, 0.001)
        r = [rms(s) for s in shifts]
        k = int(np.argmin(r))
        print("shift %s  the run is late by %+.3f s (best fit over %g-%g s): RMS %.4f -> %.4f m" %
              (g, shifts[k], window[0], window[1], rms(0.0), r[k]))


if __name__ == "__main__":
    main()
