/*
 * particles: the particle sets as structure of arrays.
 *
 * sl_fluid holds every per-particle field of the fluid; the solver keeps it
 * sorted by grid cell (Z-order of cells, see neighbours/) by permuting all
 * arrays together with prt_fluid_permute().  Arrays are 64-byte aligned.
 * Capacity grows on demand (prt_fluid_reserve); nothing is silently capped.
 *
 * sl_boundary holds the boundary particles of the paper's Sec. 3.2: position,
 * normal (pointing into the fluid), mass m_b, the static part of the density
 * (from other boundary particles), and density and pressure, which take part
 * in the pressure solve (eq. 13).
 */
#ifndef SL_PARTICLES_H
#define SL_PARTICLES_H

#include <stddef.h>
#include <stdint.h>

/* Which particles a set stores as they are made (case/case_part.h: a
 * rank builds its part of a case): with a filter, every push counts in
 * `made` and takes it as its id (its creation index in the whole case),
 * and only those keep() accepts are stored.  Without one (NULL) every push
 * is stored with id = its index. */
typedef struct prt_filter {
    int (*keep)(void *ctx, double x, double y, double z);
    void *ctx;
    size_t made; /* particles pushed through the filter */
} prt_filter;

typedef struct sl_fluid {
    size_t n, cap;
    size_t nhalo;            /* halo copies (periodic images, other ranks' particles) at
                                 [n, n + nhalo): the neighbour search sees them, loops over
                                 n do not (domain/dom_periodic.h) */
    double *x, *y, *z;       /* position at t */
    double *vx, *vy, *vz;    /* velocity at t */
    double *xs, *ys, *zs;    /* predicted position x*(t + dt) */
    double *ax, *ay, *az;    /* non-pressure acceleration (gravity, viscosity, ...) */
    double *apx, *apy, *apz; /* pressure acceleration F^p / m */
    double *rho;             /* (predicted) density */
    double *p;               /* pressure */
    double *pt;              /* p / rho^2, for the pressure force */
    uint32_t *id;            /* stable particle id */
    uint32_t *cell;          /* grid cell (scratch for sorting) */
    double *scratch;         /* permutation scratch, cap doubles */
    uint32_t *scratch_u;     /* permutation scratch, cap uint32 */
    prt_filter *filter;      /* NULL: every push stored (see prt_filter) */
} sl_fluid;

typedef struct sl_boundary {
    size_t n, cap;
    size_t nimages; /* periodic images among the n: those with id >= n - nimages */
    double *x, *y, *z;
    double *nx, *ny, *nz; /* unit normal into the fluid */
    double *mass;         /* m_b */
    double *rho_static;   /* sum over boundary neighbours of m_k W_bk */
    double *rho;          /* predicted density (eq. 13) */
    double *p;            /* pressure */
    double *pt;           /* p / rho^2 */
    double *vx, *vy, *vz; /* wall velocity (moving bodies; 0 for static walls) */
    double *x0, *y0, *z0; /* position and normal at rest (body frame = world at t = 0) */
    double *nx0, *ny0, *nz0;
    uint32_t *body;  /* index of the geometry body it samples */
    uint32_t *id;    /* index at creation: the order within a cell */
    double *scratch; /* permutation scratch */
    uint32_t *scratch_u;
    size_t scratch_cap;
    prt_filter *filter; /* NULL: every push stored (see prt_filter) */
} sl_boundary;

/* Bytes per particle of the arrays above (for memory reports): the
 * fluid's 18 fields, its permutation scratch, id, cell and a uint32
 * scratch; the boundary's 20 fields, its permutation scratch, body, id and
 * a uint32 scratch. */
#define PRT_FLUID_BYTES    (19 * 8 + 3 * 4)
#define PRT_BOUNDARY_BYTES (21 * 8 + 3 * 4)

void prt_fluid_init(sl_fluid *f);
void prt_fluid_reserve(sl_fluid *f, size_t cap);
void prt_fluid_free(sl_fluid *f);
/* Append a particle at rest-state fields (p = 0, rho = 0); with a
 * filter, only if it keeps it (prt_filter). */
void prt_fluid_push(sl_fluid *f, double x, double y, double z, double vx, double vy, double vz);
/* Reorder every per-particle array so that new[i] = old[perm[i]]. */
void prt_fluid_permute(sl_fluid *f, const uint32_t *perm);

/* The fields that carry the state from one step to the next (x, v, rho,
 * p), each paired with a field that a step recomputes before it reads it
 * (x*, a, a^p), free to serve as its spare: a sort at the start of a step
 * gathers state[k] into spare[k] and swaps the two pointers (no copy
 * back).  Returns the number of pairs. */
#define PRT_STATE_PAIRS 8
int prt_fluid_state_pairs(sl_fluid *f, double **state[PRT_STATE_PAIRS],
                          double **spare[PRT_STATE_PAIRS]);

void prt_boundary_init(sl_boundary *b);
void prt_boundary_reserve(sl_boundary *b, size_t cap);
void prt_boundary_free(sl_boundary *b);
/* dst (uninitialised) becomes a deep copy of src's n particles. */
void prt_boundary_copy(sl_boundary *dst, const sl_boundary *src);
void prt_boundary_push(sl_boundary *b, double x, double y, double z, double nx, double ny,
                       double nz, uint32_t body);
void prt_boundary_permute(sl_boundary *b, const uint32_t *perm);

#endif
