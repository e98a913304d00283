#!/usr/bin/env python3
"""Where the kinetic energy of a run goes: the work of the pressure force and
of the other forces, from the `power` function object written every step
(etc/caseDicts/functions: `functions { power { type power; } }`), and what is
left (doc/verification.md, "Where the energy goes").

Over the run, with dt_n the time between rows n - 1 and n,

    W_pressure = sum_n dt_n pressurePower_n      (eq. 6's force)
    W_other    = sum_n dt_n otherPower_n         (viscosity, body forces, effects)
    rest       = kinetic(end) - kinetic(start) - W_pressure - W_other

rest is Euler-Cromer's own loss (-dt^2 m sum |a|^2 / 2 a step), collisions
and particleShifting's velocity correction.  Each is printed in J and over
the kinetic energy at the start (the initial state's row, whose powers are nan).
With -rate R (1/s) each is also given over R times the kinetic energy's time
integral: the energy an exact operator removing R per second would remove
from the run's own field (the Taylor-Green vortex: R = 4 nu k^2 for a
velocity that decays at 2 nu k^2), so that W_other over it is the viscous
sum's share of the exact dissipation.

  powerBudget.py [-rate R] <case or power.dat>...
"""
import glob
import os
import sys


def rows_of(path):
    """The numeric rows (time, kinetic, pressurePower, otherPower) of a power.dat,
    or of the one under <case>/postProcessing/*/<startTime>/power.dat."""
    if os.path.isdir(path):
        found = sorted(glob.glob(os.path.join(path, "postProcessing", "*", "*", "power.dat")))
        if len(found) != 1:
            sys.exit("%s: %s power.dat under postProcessing (need exactly one: a run from its "
                     "start with functions { power { type power; } })"
                     % (path, "no" if not found else "more than one"))
        path = found[0]
    names, rows = None, []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                names = line[1:].split()
                continue
            if line.strip():
                rows.append(line.split())
    if not names or names[:4] != ["Time", "kinetic", "pressurePower", "otherPower"]:
        sys.exit("%s: not a power.dat (its columns: %s)" % (path, names))
    out = []
    for r in rows:
        try:
            out.append([float(v) for v in r[:4]])
        except ValueError:
            sys.exit("%s: a row that does not read: %s" % (path, " ".join(r)))
    if len(out) < 3 or out[0][2] == out[0][2]:
        sys.exit("%s: need the initial state's row (power nan) and at least two steps after it"
                 % path)
    return path, out


def budget(path, rate):
    path, rows = rows_of(path)
    steps = rows[1:]  # row 0: the initial state (no step taken: power nan)
    wp = wo = ik = 0.0
    prev = rows[0]
    for r in steps:
        dt = r[0] - prev[0]
        if r[2] != r[2] or r[3] != r[3]:
            sys.exit("%s: power nan at t = %g (a row every step is needed: writeInterval 1)"
                     % (path, r[0]))
        wp += dt * r[2]
        wo += dt * r[3]
        ik += 0.5 * (prev[1] + r[1]) * dt
        prev = r
    k0, k1 = rows[0][1], rows[-1][1]
    rest = k1 - k0 - wp - wo
    line = ("%s: t %g..%g, %d steps: kinetic %.6g -> %.6g J; W_pressure %+.4g J (%+.5f of the "
            "start), W_other %+.4g J (%+.5f), rest %+.4g J (%+.5f)"
            % (path, rows[0][0], rows[-1][0], len(steps), k0, k1, wp, wp / k0, wo, wo / k0,
               rest, rest / k0))
    if rate:
        ex = rate * ik
        line += ("; over the exact %.6g J: pressure %+.5f, other %+.5f, rest %+.5f"
                 % (ex, wp / ex, wo / ex, rest / ex))
    print(line)


def main(argv):
    rate = 0.0
    if len(argv) > 1 and argv[0] == "-rate":
        rate = float(argv[1])
        argv = argv[2:]
    if not argv or argv[0].startswith("-"):
        sys.exit(__doc__)
    for p in argv:
        budget(p, rate)


if __name__ == "__main__":
    main(sys.argv[1:])
