#!/usr/bin/env python3
"""The scaling model of doc/parallel.md: predicted time per step and
efficiency of pcisph -parallel on P ranks (one core each), for the three
modes that exist: phase 1 (gather mode), phase 1b (halo mode) and phase 2
(the domain mode, the default: own + halo stored, halo exchanged
point-to-point; its ranks owning whole x-rows of cells, the default, or
blocks of cells, SLUICE_GRID_UNIT=block), and for phase 2 as designed (a 3-D partition with a
one-cell halo, not built).  Inputs measured on this machine are named
below; the interconnect figures are published ones (100 Gb/s InfiniBand,
1-2 us).  Run: python3 doc/parallel_model.py
"""
import math

# ---- measured here (doc/parallel.md, "Measured inputs") ----
C = 0.78e-6          # s per particle-step on one core (1.28 M particle-steps per CPU s, damBreak)
F_SPLIT = 0.75       # share of a serial step in the passes phase 1 splits (density + pressure)
ITER = 3.0           # PCISPH iterations per step (minIterations 3; damBreak mean 3.00)
ARRAYS = 7           # fluid arrays gathered per iteration: rho, p, p/rho^2, err; F^p x, y, z
ACTIVE = 0.21        # active boundary particles per fluid particle (3 doubles each gathered)
KAPPA = (3.8, 12.0)  # fluid halo per rank = kappa (N/P)^(2/3): RCB of damBreak (walls,
                     # free surface) .. a cube inside the fluid, 12 n^(2/3) (decomposeCase)
SEARCH = 0.10        # share of a step in the search (sort and lists), which the halo adds to
F_OWN = 0.90         # halo mode: share of a serial step in the own-row work (prediction,
                     # collision, density, pressure force, viscosity, integration: 0.55 of 0.61 s)
KAPPA_ROWS = 9.1     # halo of the rows partition: 1894 / 2995^(2/3) (decomposeCase, 8 ranks)
STATE = 8            # halo mode: arrays gathered once per step (x, v, p, rho)
# domain mode (phase 2 as built), measured by decomposeCase and the End summary:
KAPPA_STORED = (12.0, 24.0)  # stored halo (rows one cell deep around columns of whole
                     # x-rows) = kappa (N/P)^(2/3): tutorials/damBreak at r0 0.009 m
                     # (191,664 particles): 10,340 per rank on 8 ranks (12.4), 4,482 on 64
                     # (21.5); at r0 0.018 m 12.2 (8 ranks), 23.6 (64)
NBRS_DOMAIN = 16     # neighbour ranks of a rank (decomposeCase "ranks max": 12-15 at 64)
SEARCH_HALO = 0.10   # share of a particle's step a halo particle costs (sort and lists)
HALO_W = 40          # bytes per halo particle per iteration: x* (24), p/rho^2 and rho (16)
FILL_W = 72          # bytes per halo particle per step: x, v, rho, p, id (9 doubles)
KAPPA_H = (3.9, 14.0)  # own rows reading a halo value (border rows) = kappa_h (N/P)^(2/3):
                     # decomposeCase "overlap: own particles reading a halo value", damBreak:
                     # all ranks 17 % at 2 ranks (3.9), 27 % at 3 (5.4), 54 % at 8 (7.8); 191 k:
                     # 27 % at 8 (7.8), 69 % at 64 (9.9); the worst rank 37 % at 8 (10.7), 100 %
                     # at 64 (>= 14): 3.9 the mean of a small job, 14 the worst rank of a large
                     # one.  A run on 2 ranks computes 84 % of its own rows while the halo
                     # travels (End summary, "overlap"): 16 % border, decomposeCase 14-19 %.
# the same with blocks of 4x4x4 cells (SLUICE_GRID_UNIT=block; decomposeCase -unit
# row,block:4, 2026-12-04): a shell one cell thick around runs of blocks along a Hilbert curve
KAPPA_STORED_BLOCK = (9.8, 14.4)  # 191 k: 8,160 per rank on 8 ranks (9.8), 2,986 on 64
                     # (14.4); at r0 0.018 m 11.6 (8 ranks), 14.3 (64)
KAPPA_H_BLOCK = (6.1, 9.8)  # border rows, 191 k: all ranks 21 % at 8 (6.1), 50 % at 64
                     # (7.2); the worst rank 25 % at 8 (7.2), 68 % at 64 (9.8)
NBRS_BLOCK = 25      # neighbour ranks of a rank with blocks (decomposeCase "ranks max" at 64)
# ---- published: 100 Gb/s InfiniBand ----
ALPHA = 1.5e-6       # s latency per message
BW = 12.5e9          # bytes/s

def allgatherv(nbytes_total, p):
    """Ring allgather: P-1 steps, each rank receives (P-1)/P of the data."""
    return (p - 1) * ALPHA + (p - 1) / p * nbytes_total / BW

def allreduce(p):
    return 2 * math.log2(p) * ALPHA if p > 1 else 0.0

def phase1(n, p, f_split=F_SPLIT):
    """Replicated state: every rank does the unsplit share of the step on
    all n particles, its 1/P of the split share, and receives every other
    rank's rows of ARRAYS arrays (and the active boundary's 3) per
    iteration, plus one max-reduction."""
    compute = n * C * ((1 - f_split) + f_split / p)
    comm = ITER * (ARRAYS * allgatherv(8 * n, p) + allgatherv(24 * ACTIVE * n, p) + allreduce(p))
    return compute, comm

def phase1b(n, p):
    """Halo mode: every rank does the search and forces of all n particles
    (1 - F_OWN), its own rows' share of the rest; per iteration x* and
    p/rho^2 and rho of the rows partition's halo by personalised exchange
    (Alltoallv: P - 1 messages, most of them empty, at alpha each), the
    block sums (small) and a max; per step the state (STATE arrays of N)
    by Allgatherv."""
    nl = n / p
    halo = KAPPA_ROWS * nl ** (2.0 / 3.0) if p > 1 else 0.0
    compute = n * C * ((1 - F_OWN) + F_OWN / p)
    per_iter = 2 * (p - 1) * ALPHA + 40 * halo / BW + allgatherv(8 * p, p) + allreduce(p)
    per_step = STATE * allgatherv(8 * n, p) + allgatherv(24 * ACTIVE * n, p) + 3 * allreduce(p)
    return compute, ITER * per_iter + per_step

def phase2(n, p, kappa):
    """Halo decomposition (RCB by count): each rank computes n/P particles
    plus the search over its halo; per iteration two halo exchanges (x*
    after the prediction: 24 B, p/rho^2 after the density pass: 8 B per
    halo particle) with its neighbour ranks, and one max-reduction; per
    step the step-size reductions and migration (about the halo once)."""
    nl = n / p
    halo = kappa * nl ** (2.0 / 3.0) if p > 1 else 0.0
    nbrs = min(p - 1, 26)
    compute = nl * C * (1 + SEARCH * halo / nl)
    per_iter = nbrs * ALPHA * 2 + (24 + 8) * halo / BW + allreduce(p)
    per_step = 4 * allreduce(p) + nbrs * ALPHA + 80 * halo / BW
    return compute, ITER * per_iter + per_step

def small_alltoall(p):
    """Alltoall of one int per rank (Bruck's algorithm for small messages)."""
    return math.log2(p) * ALPHA if p > 1 else 0.0

def phase2_built(n, p, kappa, kappa_h=None, nbrs_max=NBRS_DOMAIN):
    """Domain mode as built (solver/pcs_domain.c): each rank computes its
    n/P own particles and sorts and searches its stored halo too; per
    iteration x* and then p/rho^2 and rho of the stored halo with its
    neighbour ranks (point-to-point), the block-sum chain (one double) and
    the block sums of the serial order (Allgatherv of N / 4096 doubles),
    one max-reduction; per step the migration and the halo fill (two
    Alltoalls of counts, the halo's 9 doubles each, an Allreduce of P
    counts, an Allgather of P counts, the step's reductions).  With
    kappa_h (the overlap): the point-to-point messages of an iteration
    travel while the own rows that read no halo particle (1 - kappa_h
    (N/P)^(-1/3) of them) compute their density and pressure force; only
    what the interior work does not cover is paid.  Static walls: the
    boundary is distributed once (and at rebalancings), not per step."""
    nl = n / p
    halo = kappa * nl ** (2.0 / 3.0) if p > 1 else 0.0
    nbrs = min(p - 1, nbrs_max)
    compute = nl * C + halo * C * SEARCH_HALO
    blocks = math.log2(p) * ALPHA + 8 * n / 4096 / BW if p > 1 else 0.0
    p2p = 2 * nbrs * ALPHA + HALO_W * halo / BW if p > 1 else 0.0
    if kappa_h is not None and p > 1:
        inner = max(0.0, 1.0 - kappa_h * nl ** (-1.0 / 3.0))
        p2p = max(0.0, p2p - inner * nl * C * F_SPLIT / ITER)
    per_iter = p2p + ALPHA + blocks + allreduce(p)
    per_step = (2 * small_alltoall(p) + 2 * nbrs * ALPHA + FILL_W * halo / BW
                + 2 * allreduce(p) + 4 * allreduce(p))
    return compute, ITER * per_iter + per_step

def table_built(title, n_of_p, ps, unit="rows", kappas=KAPPA_STORED, kappas_h=KAPPA_H,
                nbrs_max=NBRS_DOMAIN):
    print(f"\n{title}: phase 2 as built (domain mode, {unit}), kappa_stored "
          f"{kappas[0]}..{kappas[1]}")
    print(f"{'ranks':>6} {'N':>10} | {'s/step':>17} {'comm %':>7} {'efficiency':>12} |"
          f" {'stored / own':>12} | {'overlap: comm %':>15} {'efficiency':>12}")
    for p in ps:
        n = n_of_p(p)
        ideal = n * C / p
        r = [phase2_built(n, p, k, None, nbrs_max) for k in kappas]
        t = [c + m for c, m in r]
        nl = n / p
        st = [k * nl ** (2.0 / 3.0) / nl if p > 1 else 0.0 for k in kappas]
        ro = [phase2_built(n, p, k, kh, nbrs_max) for k, kh in zip(kappas, kappas_h)]
        to = [c + m for c, m in ro]
        print(f"{p:>6} {n:>10.3g} | {t[0]:>8.4g}-{t[1]:<8.4g} {100 * r[1][1] / t[1]:>6.1f}% "
              f"{100 * ideal / t[1]:>5.1f}-{100 * ideal / t[0]:<5.1f}% |"
              f" {1 + st[0]:>5.2f}-{1 + st[1]:<5.2f} | {100 * ro[1][1] / to[1]:>14.1f}% "
              f"{100 * ideal / to[1]:>5.1f}-{100 * ideal / to[0]:<5.1f}%")

def table(title, n_of_p, ps, ref_p):
    print(f"\n{title}")
    print(f"{'ranks':>6} {'N':>10} | {'phase 1: s/step':>15} {'comm %':>7} {'eff':>6} |"
          f" {'1b halo: s/step':>15} {'comm %':>7} {'eff':>6} |"
          f" {'phase 2 designed':>15} {'comm %':>7} {'eff':>6} (kappa {KAPPA[0]}..{KAPPA[1]})")
    base1 = base2 = None
    for p in ps:
        n = n_of_p(p)
        c1, m1 = phase1(n, p)
        t1 = c1 + m1
        t2 = [sum(phase2(n, p, k)) for k in KAPPA]
        m2 = [phase2(n, p, k)[1] for k in KAPPA]
        if base1 is None:
            # efficiency against ideal scaling from the serial code on ref_p ranks' work
            base1 = n * C / p
            base2 = n * C / p
        ideal = n_of_p(p) * C / p
        e1 = ideal / t1
        e2 = [ideal / t for t in t2]
        cb, mb = phase1b(n, p)
        tb = cb + mb
        print(f"{p:>6} {n:>10.3g} | {t1:>15.4g} {100 * m1 / t1:>6.1f}% {100 * e1:>5.1f}% |"
              f" {tb:>15.4g} {100 * mb / tb:>6.1f}% {100 * ideal / tb:>5.1f}% |"
              f" {t2[0]:>7.4g}-{t2[1]:<7.4g} {100 * m2[1] / t2[1]:>6.1f}% "
              f"{100 * e2[1]:>3.0f}-{100 * e2[0]:<3.0f}%")

if __name__ == "__main__":
    print("Efficiency = (serial time per step / P) / predicted time per step")
    table("Strong scaling, CBD large (1.7 M fluid particles)", lambda p: 1.7e6,
          [1, 8, 16, 32, 64], 1)
    table("Weak scaling, 97.7 k particles per rank (100 M on 1024 ranks)",
          lambda p: 97.7e3 * p, [64, 128, 256, 512, 1024], 64)
    table_built("Strong scaling, CBD large (1.7 M fluid particles)", lambda p: 1.7e6,
                [2, 8, 16, 32, 64])
    table_built("Weak scaling, 97.7 k particles per rank (100 M on 1024 ranks)",
                lambda p: 97.7e3 * p, [64, 128, 256, 512, 1024])
    blocks = dict(unit="blocks of 4x4x4 cells", kappas=KAPPA_STORED_BLOCK,
                  kappas_h=KAPPA_H_BLOCK, nbrs_max=NBRS_BLOCK)
    table_built("Strong scaling, CBD large (1.7 M fluid particles)", lambda p: 1.7e6,
                [2, 8, 16, 32, 64], **blocks)
    table_built("Weak scaling, 97.7 k particles per rank (100 M on 1024 ranks)",
                lambda p: 97.7e3 * p, [64, 128, 256, 512, 1024], **blocks)
    c, m = phase1(1.7e6, 64, f_split=0.97)
    print(f"\nPhase 1 with every phase split (f_split 0.97), CBD large on 64 ranks: "
          f"{c + m:.4g} s/step, efficiency {100 * 1.7e6 * C / 64 / (c + m):.0f} % "
          f"(the Allgatherv alone: {m:.3g} s)")
    print(f"Phase 1 memory: every rank holds all N particles (~450 B each, README): "
          f"100 M particles = {100e6 * 450 / 1e9:.0f} GB per rank")
