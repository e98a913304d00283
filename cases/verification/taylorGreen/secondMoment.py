#!/usr/bin/env python3
"""The laminar (Morris) viscosity's dissipation of the Taylor-Green field on
a packing, against the exact nu |grad v|^2 (doc/verification.md, "Particle
shifting": what limits the order).

For each fluid particle T_i = -sum_j V_j F_ij r_ij r_ij^T with
F = gradf(r) r^2 / (r^2 + 0.01 h^2) (libsrc/effects/laminar_viscosity.c;
cubic spline, support h = 2 r0, V = r0^3, the periodic box 0.1 x 0.1 x
0.04 m of cases/verification/taylorGreen).  The Morris sum's dissipation
of a smooth field is nu sum_i tr(grad v T_i grad v^T), so the factor

    sum_i sum_b g_b^T T_i g_b / sum_i sum_b |g_b|^2   (g_b = grad v_b, exact)

is the ratio of its energy decay to the viscous one at long waves (1 for
the continuous kernel without the 0.01 h^2; 0.9915 on the cubic lattice).
The same with each particle's T_i divided by its tau_i = tr(T_i) / 3 (the
divisor of `laminarViscosity { normalized on; }`): its factor on the
packing (1 on any isotropic packing at long waves; below 1 where the
packing's in-plane moment is below its mean, which the scalar divisor
cannot see).  Also the mean T_xx, T_yy, T_zz, the rms of grad C r0 (the
shift's disorder) and the nearest neighbour's distance over r0.

  secondMoment.py <case>/<time>/fluid.vtu <r0>   (an ascii vtu: writeFormat ascii)
  secondMoment.py -lattice                       (the cubic lattice at k r0 of the sweeps)
  secondMoment.py -error <fluid.vtu> <t> [bin]   (the velocity error at time t: rms over U of
      its in-plane part and of vz, and of its average over cells of side bin (default 0.01 m,
      the smooth part) and of the rest (the particle-scale part); U 0.1, nu 0.001)
  secondMoment.py -tensor <fluid.vtu> <r0> [every]   (on every 25th particle (or every
      [every]th), the matrix A_i of `normalized tensor` (laminar_viscosity.c): the mean of
      A_i tau_i's diagonal and the spread of its eigenvalues, (largest - least) tau_i, its
      percentiles: 0 on the cubic lattice, where A_i = I / tau_i)
  secondMoment.py -pressure <fluid.vtu> <t>      (the pressure at time t against the exact
      rho0 U^2 F^2 (cos 2kx + cos 2ky) / 4: its mean (the background level), the share of
      particles at p <= 0 (clamped), the least-squares fit p = a exact + b and the rms about
      it (the particle noise, Pa), and the rms of vz (m/s); rho0 1000)
  Before any of these, -boxz Z for a box Z deep instead of 0.04 m (the thin box of
  doc/verification.md, "What tensor corrects at the finest level": -boxz 0.01).
The error also gives the vortex's amplitude over the exact one (the least-squares
projection of the velocity on the exact field): below 1 the vortex has lost more
than the viscous decay.  Pure Python: about 1 s per 1000 particles; a binary vtu
(writeFormat binary) is read with VTK's reader where it imports (Debian's
python3-vtk9 under /usr/bin/python3), an ascii one without it.
"""
import math
import re
import sys

BOX = (0.1, 0.1, 0.04)


def gradf(r, h):
    """(dW/dr) / r of the cubic spline with support h (kernel/kernel.h)."""
    q, s = r / h, 8.0 / (math.pi * h ** 3)
    if q <= 0.5:
        return s / h ** 2 * (18.0 * q - 12.0)
    return -6.0 * s * (1.0 - q) ** 2 / (h * r) if q < 1.0 else 0.0


def lattice():
    """The cubic lattice's factor for sin(kx) cos(ky) at k r0 (r0 = 1)."""
    h = 2.0
    for kr0, r0 in ((0.6283, 0.01), (0.3142, 0.005), (0.1571, 0.0025), (0.0785, 0.00125)):
        s = 0.0
        for i in range(-2, 3):
            for j in range(-2, 3):
                for k in range(-2, 3):
                    r2 = i * i + j * j + k * k
                    if r2:
                        f = gradf(math.sqrt(r2), h) * r2 / (r2 + 0.01 * h * h)
                        s += f * (1.0 - math.cos(kr0 * i) * math.cos(kr0 * j))
        print("cubic lattice, r0 %g (k r0 %.4f): factor %.4f" % (r0, kr0, -s / kr0 ** 2))


def neighbour_grid(path, r0):
    """The points wrapped into the box, and pairs(i): each neighbour of point i
    within h = 2 r0 as (its nearest image's offset p_i - p_j, its square)."""
    (a,) = arrays(path, "Points")
    pts = [tuple(a[3 * i + c] % BOX[c] for c in range(3)) for i in range(len(a) // 3)]
    nc = [max(1, int(BOX[c] / (2.0 * r0))) for c in range(3)]

    def cell(p):
        return tuple(int(p[c] / BOX[c] * nc[c]) % nc[c] for c in range(3))

    cells = {}
    for i, p in enumerate(pts):
        cells.setdefault(cell(p), []).append(i)

    def pairs(i):
        p, ci, h2 = pts[i], cell(pts[i]), 4.0 * r0 * r0
        for cc in {((ci[0] + dx) % nc[0], (ci[1] + dy) % nc[1], (ci[2] + dz) % nc[2])
                   for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)}:
            for j in cells.get(cc, ()):
                if j == i:
                    continue
                d = [p[c] - pts[j][c] for c in range(3)]
                d = [d[c] - BOX[c] * round(d[c] / BOX[c]) for c in range(3)]
                r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
                if r2 < h2:
                    yield d, r2

    return pts, pairs


def packing(path, r0):
    h, vol = 2.0 * r0, r0 ** 3
    pts, pairs = neighbour_grid(path, r0)
    k = 2.0 * math.pi / BOX[0]
    num = den = nnum = txx = tyy = tzz = gc2 = near_sum = 0.0
    near_min = 9.0
    for i, p in enumerate(pts):
        t = [[0.0] * 3 for _ in range(3)]
        gc = [0.0] * 3
        dn = 9.0
        for d, r2 in pairs(i):
            g = gradf(math.sqrt(r2), h)
            dn = min(dn, math.sqrt(r2) / r0)
            w = -vol * g * r2 / (r2 + 0.01 * h * h)
            for a_ in range(3):
                gc[a_] += vol * g * d[a_]
                for b_ in range(3):
                    t[a_][b_] += w * d[a_] * d[b_]
        x, y = p[0], p[1]
        gu = (k * math.cos(k * x) * math.cos(k * y), -k * math.sin(k * x) * math.sin(k * y), 0.0)
        gv = (k * math.sin(k * x) * math.sin(k * y), -k * math.cos(k * x) * math.cos(k * y), 0.0)
        tau = (t[0][0] + t[1][1] + t[2][2]) / 3.0  # laminarViscosity normalized's divisor
        for gg in (gu, gv):
            q = sum(gg[a_] * t[a_][b_] * gg[b_] for a_ in range(3) for b_ in range(3))
            num += q
            nnum += q / tau if tau > 0.5 else q
            den += sum(c * c for c in gg)
        txx += t[0][0]
        tyy += t[1][1]
        tzz += t[2][2]
        gc2 += sum(c * c for c in gc)
        near_sum += dn
        near_min = min(near_min, dn)
    n = len(pts)
    print("%s: dissipation factor %.4f (normalized %.4f), mean T_xx %.4f T_yy %.4f T_zz %.4f, "
          "rms |grad C| r0 %.4f, nearest / r0 mean %.3f, least %.3f (%d particles)"
          % (path, num / den, nnum / den, txx / n, tyy / n, tzz / n, math.sqrt(gc2 / n) * r0,
             near_sum / n, near_min, n))


def arrays(path, *names):
    """The named DataArrays of a vtu ("Points" or a point field), each as a flat
    list of floats: an ascii file read here, any other with VTK's reader."""
    with open(path, "rb") as f:
        head = f.read(4096)
    if b'format="ascii"' in head or b"format='ascii'" in head:
        txt = open(path).read()
        out = []
        for name in names:
            m = re.search(r'Name="%s"[^>]*format="ascii"[^>]*>(.*?)</DataArray>' % name, txt, re.S)
            if not m:
                sys.exit("%s: no ascii %s" % (path, name))
            out.append([float(s) for s in m.group(1).split()])
        return out
    try:
        from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    except ImportError:
        sys.exit("%s: not ascii, and VTK's python modules do not import here (write the case "
                 "with writeFormat ascii, or run this under /usr/bin/python3 with python3-vtk9)" % path)
    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(path)
    r.Update()
    grid = r.GetOutput()
    out = []
    for name in names:
        d = grid.GetPoints().GetData() if name == "Points" else grid.GetPointData().GetArray(name)
        if d is None:
            sys.exit("%s: no array %s" % (path, name))
        out.append([d.GetComponent(i, c) for i in range(d.GetNumberOfTuples())
                    for c in range(d.GetNumberOfComponents())])
    return out


def solve(K, b):
    """K x = b by Gaussian elimination with partial pivoting."""
    n = len(b)
    m = [K[r][:] + [b[r]] for r in range(n)]
    for c in range(n):
        piv = max(range(c, n), key=lambda r: abs(m[r][c]))
        m[c], m[piv] = m[piv], m[c]
        for r in range(c + 1, n):
            f = m[r][c] / m[c][c]
            for e in range(c, n + 1):
                m[r][e] -= f * m[c][e]
    x = [0.0] * n
    for r in range(n - 1, -1, -1):
        x[r] = (m[r][n] - sum(m[r][e] * x[e] for e in range(r + 1, n))) / m[r][r]
    return x


def eigenvalues3(a):
    """The eigenvalues of a symmetric 3x3 matrix (Jacobi rotations), least first."""
    a = [row[:] for row in a]
    for _ in range(50):
        if a[0][1] ** 2 + a[0][2] ** 2 + a[1][2] ** 2 < 1e-24:
            break
        for p, q in ((0, 1), (0, 2), (1, 2)):
            if abs(a[p][q]) < 1e-300:
                continue
            th = 0.5 * math.atan2(2.0 * a[p][q], a[q][q] - a[p][p])
            c, s = math.cos(th), math.sin(th)
            for k in range(3):
                a[k][p], a[k][q] = c * a[k][p] - s * a[k][q], s * a[k][p] + c * a[k][q]
            for k in range(3):
                a[p][k], a[q][k] = c * a[p][k] - s * a[q][k], s * a[p][k] + c * a[q][k]
    return sorted(a[i][i] for i in range(3))


def tensor(path, r0, every):
    """A_i of `normalized tensor`: sum_j w_ij (r^T A_i r / r^2) r r^T = I, six equations
    in the fourth moment Q_abcd = sum_j w_ij r_a r_b r_c r_d / r^2."""
    h, vol = 2.0 * r0, r0 ** 3
    pts, pairs = neighbour_grid(path, r0)
    pa, pb = (0, 1, 2, 0, 0, 1), (0, 1, 2, 1, 2, 2)
    spread, least, most, diag = [], [], [], [0.0, 0.0, 0.0]
    for i in range(0, len(pts), every):
        q4, tau = {}, 0.0
        for d, r2 in pairs(i):
            w = -vol * gradf(math.sqrt(r2), h) * r2 / (r2 + 0.01 * h * h)
            tau += w * r2 / 3.0
            for r in range(6):
                for c in range(r, 6):
                    q4[(r, c)] = q4.get((r, c), 0.0) + w * d[pa[r]] * d[pb[r]] * d[pa[c]] * d[pb[c]] / r2
        k6 = [[q4[(min(r, c), max(r, c))] * (1 if c < 3 else 2) for c in range(6)] for r in range(6)]
        x = solve(k6, [1.0, 1.0, 1.0, 0.0, 0.0, 0.0])
        a = [[x[0], x[3], x[4]], [x[3], x[1], x[5]], [x[4], x[5], x[2]]]
        ev = eigenvalues3(a)
        least.append(ev[0] * tau)
        most.append(ev[2] * tau)
        spread.append((ev[2] - ev[0]) * tau)
        for c in range(3):
            diag[c] += a[c][c] * tau
    n = len(spread)
    for v in (spread, least, most):
        v.sort()
    pc = lambda v, f: v[min(n - 1, int(f * n))]
    print("%s: %d particles sampled; A tau mean diagonal %.4f %.4f %.4f; spread (largest - least "
          "eigenvalue) tau p50 %.4f p90 %.4f p99 %.4f max %.4f; least eigenvalue tau min %.4f, "
          "largest max %.4f" % (path, n, diag[0] / n, diag[1] / n, diag[2] / n, pc(spread, 0.5),
                                pc(spread, 0.9), pc(spread, 0.99), spread[-1], least[0], most[-1]))


def error(path, t, cell):
    p, v = arrays(path, "Points", "velocity")
    n, k, u = len(p) // 3, 2.0 * math.pi / BOX[0], 0.1
    f = u * math.exp(-2.0 * 0.001 * k * k * t)
    e = []
    for i in range(n):
        x, y = p[3 * i], p[3 * i + 1]
        e.append((v[3 * i] - f * math.sin(k * x) * math.cos(k * y),
                  v[3 * i + 1] + f * math.cos(k * x) * math.sin(k * y), v[3 * i + 2]))
    nb = [max(1, int(round(BOX[c] / cell))) for c in range(3)]
    key = [tuple(int((p[3 * i + c] % BOX[c]) / BOX[c] * nb[c]) % nb[c] for c in range(3))
           for i in range(n)]
    acc = {}
    for i in range(n):
        a = acc.setdefault(key[i], [0.0, 0.0, 0.0, 0])
        for c in range(3):
            a[c] += e[i][c]
        a[3] += 1
    smooth = rest = 0.0
    for i in range(n):
        a = acc[key[i]]
        for c in range(3):
            m = a[c] / a[3]
            smooth += m * m
            rest += (e[i][c] - m) ** 2
    rms = lambda s: math.sqrt(s / n) / u
    # the velocity's projection on the exact field: v . v_exact / |v_exact|^2
    proj = norm = 0.0
    for i in range(n):
        ex, ey = v[3 * i] - e[i][0], v[3 * i + 1] - e[i][1]
        proj += v[3 * i] * ex + v[3 * i + 1] * ey
        norm += ex * ex + ey * ey
    print("%s: error %.5f of U: in-plane %.5f, vz %.5f; averaged over %g m cells %.5f, the rest %.5f; "
          "amplitude / exact %.5f"
          % (path, rms(sum(a * a + b * b + c * c for a, b, c in e)),
             rms(sum(a * a + b * b for a, b, _ in e)), rms(sum(c * c for _, _, c in e)), cell,
             rms(smooth), rms(rest), proj / norm))


def pressure(path, t):
    x, v, p = arrays(path, "Points", "velocity", "pressure")
    n, k, u = len(p), 2.0 * math.pi / BOX[0], 0.1
    f = u * math.exp(-2.0 * 0.001 * k * k * t)
    ex = [250.0 * f * f * (math.cos(2 * k * x[3 * i]) + math.cos(2 * k * x[3 * i + 1]))
          for i in range(n)]
    me, mp = sum(ex) / n, sum(p) / n
    sxx = sum((e - me) ** 2 for e in ex)
    a = sum((e - me) * (q - mp) for e, q in zip(ex, p)) / sxx
    b = mp - a * me
    noise = math.sqrt(sum((q - a * e - b) ** 2 for e, q in zip(ex, p)) / n)
    vz = math.sqrt(sum(v[3 * i + 2] ** 2 for i in range(n)) / n)
    print("%s: p mean %.3f Pa (exact %.3f to %.3f), at or below 0: %.1f %%; fit a %.3f, "
          "level b %.3f Pa, noise %.3f Pa; vz rms %.2e m/s"
          % (path, mp, min(ex), max(ex), 100.0 * sum(q <= 0.0 for q in p) / n, a, b, noise, vz))


if __name__ == "__main__":
    if len(sys.argv) > 2 and sys.argv[1] == "-boxz":
        BOX = (BOX[0], BOX[1], float(sys.argv[2]))
        del sys.argv[1:3]
    if len(sys.argv) in (4, 5) and sys.argv[1] == "-tensor":
        tensor(sys.argv[2], float(sys.argv[3]), int(sys.argv[4]) if len(sys.argv) == 5 else 25)
    elif len(sys.argv) == 2 and sys.argv[1] == "-lattice":
        lattice()
    elif len(sys.argv) in (4, 5) and sys.argv[1] == "-error":
        error(sys.argv[2], float(sys.argv[3]), float(sys.argv[4]) if len(sys.argv) == 5 else 0.01)
    elif len(sys.argv) == 4 and sys.argv[1] == "-pressure":
        pressure(sys.argv[2], float(sys.argv[3]))
    elif len(sys.argv) == 3:
        packing(sys.argv[1], float(sys.argv[2]))
    else:
        sys.exit(__doc__)
