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
  secondMoment.py -pressure <fluid.vtu> <t>      (the pressure at time t against the exact
      rho0 U^2 F^2 (cos 2kx + cos 2ky) / 4: its mean (the background level), the share of
      particles at p <= 0 (clamped), the least-squares fit p = a exact + b and the rms about
      it (the particle noise, Pa), and the rms of vz (m/s); rho0 1000)
Pure Python (no numpy): about 1 s per 1000 particles.
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


def packing(path, r0):
    txt = open(path).read()
    m = re.search(r'Name="Points"[^>]*format="ascii"[^>]*>(.*?)</DataArray>', txt, re.S)
    if not m:
        sys.exit("%s: no ascii Points (write the case with writeFormat ascii)" % path)
    a = [float(s) for s in m.group(1).split()]
    h, vol = 2.0 * r0, r0 ** 3
    pts = [tuple(a[3 * i + c] % BOX[c] for c in range(3)) for i in range(len(a) // 3)]
    nc = [max(1, int(BOX[c] / h)) for c in range(3)]

    def cell(p):
        return tuple(int(p[c] / BOX[c] * nc[c]) % nc[c] for c in range(3))

    cells = {}
    for i, p in enumerate(pts):
        cells.setdefault(cell(p), []).append(i)
    k = 2.0 * math.pi / BOX[0]
    num = den = nnum = txx = tyy = tzz = gc2 = near_sum = 0.0
    near_min = 9.0
    for i, p in enumerate(pts):
        ci = cell(p)
        near = {((ci[0] + dx) % nc[0], (ci[1] + dy) % nc[1], (ci[2] + dz) % nc[2])
                for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)}
        t = [[0.0] * 3 for _ in range(3)]
        gc = [0.0] * 3
        dn = 9.0
        for cc in near:
            for j in cells.get(cc, ()):
                if j == i:
                    continue
                d = [p[c] - pts[j][c] for c in range(3)]
                d = [d[c] - BOX[c] * round(d[c] / BOX[c]) for c in range(3)]
                r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
                if r2 >= h * h:
                    continue
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


def ascii_arrays(path, *names):
    """The named DataArrays of an ascii vtu, each as a flat list of floats."""
    txt = open(path).read()
    out = []
    for name in names:
        m = re.search(r'Name="%s"[^>]*format="ascii"[^>]*>(.*?)</DataArray>' % name, txt, re.S)
        if not m:
            sys.exit("%s: no ascii %s (write the case with writeFormat ascii)" % (path, name))
        out.append([float(s) for s in m.group(1).split()])
    return out


def error(path, t, cell):
    p, v = ascii_arrays(path, "Points", "velocity")
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
    print("%s: error %.5f of U: in-plane %.5f, vz %.5f; averaged over %g m cells %.5f, the rest %.5f"
          % (path, rms(sum(a * a + b * b + c * c for a, b, c in e)),
             rms(sum(a * a + b * b for a, b, _ in e)), rms(sum(c * c for _, _, c in e)), cell,
             rms(smooth), rms(rest)))


def pressure(path, t):
    x, v, p = ascii_arrays(path, "Points", "velocity", "pressure")
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
    if len(sys.argv) == 2 and sys.argv[1] == "-lattice":
        lattice()
    elif len(sys.argv) in (4, 5) and sys.argv[1] == "-error":
        error(sys.argv[2], float(sys.argv[3]), float(sys.argv[4]) if len(sys.argv) == 5 else 0.01)
    elif len(sys.argv) == 4 and sys.argv[1] == "-pressure":
        pressure(sys.argv[2], float(sys.argv[3]))
    elif len(sys.argv) == 3:
        packing(sys.argv[1], float(sys.argv[2]))
    else:
        sys.exit(__doc__)
