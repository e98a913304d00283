/*
 * neighbours: uniform-grid neighbour search (paper Sec. 3.4).
 *
 * The grid covers the scene's bounding box (fixed at set-up).  Cells are
 * grouped into units, each a contiguous range of the cell numbering, and
 * particles are kept sorted by that number: particles close in space are
 * close in memory.  SLUICE_GRID_UNIT chooses the units (nbr_unit_setting):
 * `row` (the default) whole x-rows of cells, the rows in Z-order (Morton
 * order of (y, z)); `block` (or `block:N`, N = 2..16 cells a side; `block`
 * is 4) cubes of cells, the blocks along the generalised Hilbert curve
 * of the box of blocks (a compact region per run of blocks), the cells
 * inside a block x fastest, the grid padded to whole blocks.  Either way a unit is a run of the sorted array, so a
 * run of units is one too (the domain decomposition's ranks own runs of
 * units: solver/pcs_domain.h), and the cells of one x-row inside a unit
 * form one contiguous range.  A particle
 * outside the box is clamped into the nearest border cell: clamping is
 * 1-Lipschitz on cell coordinates, so two particles closer than h still sit
 * in the same or adjacent cells and no neighbour is ever lost (only speed
 * suffers).
 *
 * Neighbour lists are compressed rows (start[i] .. start[i+1] into idx),
 * built once per step from x(t) and reused by every PCISPH iteration.  They
 * are gathered per particle (no atomics, no scatter).  Each chunk of
 * NBR_CHUNK rows fills its own buffer, taken by whichever thread is free;
 * the buffers are then concatenated in order, so the lists are identical
 * for any thread count.
 */
#ifndef SL_NEIGHBOURS_H
#define SL_NEIGHBOURS_H

#include <stddef.h>
#include <stdint.h>

#include "particles/particles.h"

/* Cells per support radius.  Cells of h/2 (searched 2 cells each way)
 * test fewer candidates (15.6 h^3 instead of 27 h^3 of space) but split
 * them into 25 short rows; measured on the damBreak tutorial, cells of h
 * (9 rows of ~24 candidates, tested 8 at a time) build the lists 1.8x
 * faster. */
#define NBR_CELLS_PER_H 1

typedef struct nbr_grid {
    double lo[3];
    double cell, inv_cell; /* cell size (h / NBR_CELLS_PER_H, larger for huge scenes) */
    int reach;             /* cells searched each way: ceil(h / cell) */
    double h2;             /* squared search radius */
    int nc[3];             /* cells along x, y, z (block units: whole blocks) */
    size_t ncells;
    int unit[3];            /* cells of a unit along x, y, z (rows: nc[0], 1, 1) */
    size_t ucells, nunits;  /* cells per unit, units (ncells = nunits ucells) */
    uint32_t *rank;         /* rank[linear cell] = position in Z-order */
    uint32_t *fstart;       /* fluid particles of rank k: [fstart[k], fstart[k+1]) */
    uint32_t *bstart;       /* boundary particles, likewise */
    const uint32_t *hstart; /* fluid halo copies at [n, n + nhalo), likewise (absolute
                                 indices; NULL: none; set by domain/) */
    uint32_t *count;        /* scratch, ncells + 1 */
    uint32_t *perm;         /* scratch permutation, fluid capacity */
    size_t perm_cap;
    uint32_t *bcell, *bperm; /* scratch for re-sorting moving boundaries */
    size_t bperm_cap;
} nbr_grid;

/* Rows per work unit of a list build.  Each chunk of rows fills its own
 * buffer, whichever thread takes it; the buffers are concatenated in
 * chunk order, so the lists are the same for any thread count. */
#define NBR_CHUNK 1024

/* One compressed-row neighbour list with per-chunk fill buffers. */
typedef struct nbr_list {
    size_t n; /* rows */
    size_t rows_cap;
    uint32_t *start; /* n + 1 */
    uint32_t *idx;   /* start[n] entries */
    size_t idx_cap;
    size_t nbuf; /* chunk buffers */
    uint32_t **buf;
    size_t *bcap, *blen; /* capacity; entries (then the chunk's offset) */
} nbr_list;

/* Set up a grid over [lo, hi] with search radius h; the cell size is h
 * unless that would need more than max_cells cells, in which case it grows.
 * Its units are those of nbr_unit_setting(). */
void nbr_grid_init(nbr_grid *g, const double lo[3], const double hi[3], double h, size_t max_cells);
/* The units SLUICE_GRID_UNIT asks for: 0 rows, else a block's cells a side
 * (a bad value stops the run with a message). */
int nbr_unit_setting(void);
/* "row" or "block:N" (the setting's spelling), for logs. */
const char *nbr_unit_name(const nbr_grid *g, char *buf, size_t len);
void nbr_grid_free(nbr_grid *g);

/* Sort the boundary particles by cell (once, at set-up) and fill bstart. */
void nbr_sort_boundary(nbr_grid *g, sl_boundary *b);
/* Sort the fluid by the key (cell, id) (permuting all its arrays) and fill
 * fstart: the order, hence every neighbour order, depends only on the
 * positions and the particles' ids, not on their previous order. */
void nbr_sort_fluid(nbr_grid *g, sl_fluid *f);

void nbr_list_init(nbr_list *l);
void nbr_list_free(nbr_list *l);

/* Fluid -> fluid neighbours (self excluded) within h, from x(t). */
void nbr_build_ff(const nbr_grid *g, const sl_fluid *f, nbr_list *l);
/* Both fluid rows (ff and fb) in one sweep over the cells; rows for the
 * n + nhalo particles (the halo copies' rows feed the boundary rows). */
void nbr_build_fluid(const nbr_grid *g, const sl_fluid *f, const sl_boundary *b, nbr_list *ff,
                     nbr_list *fb);
/* Fluid -> boundary neighbours within h. */
void nbr_build_fb(const nbr_grid *g, const sl_fluid *f, const sl_boundary *b, nbr_list *l);
/* Boundary -> fluid neighbours for every boundary particle; rows of
 * inactive boundary particles (no fluid within h) are empty.  active[] gets
 * the indices of the boundary particles with at least one fluid neighbour
 * and *nactive their count (paper Sec. 3.4: active boundary particles). */
void nbr_build_bf(const nbr_grid *g, const sl_fluid *f, const sl_boundary *b, nbr_list *l,
                  uint32_t *active, size_t *nactive);
/* The same boundary -> fluid lists and active set, by transposing the
 * fluid -> boundary lists (the relation is symmetric).  Serial, but it
 * touches only the fluid-boundary pairs, a small share of all pairs. */
void nbr_transpose(const nbr_list *fb, size_t nb, nbr_list *bf, uint32_t *active, size_t *nactive);
/* Boundary -> boundary neighbours (self included), for set-up only. */
void nbr_build_bb(const nbr_grid *g, const sl_boundary *b, nbr_list *l);

/* The cell rank (position in the sort order) of a point. */
uint32_t nbr_cell_rank(const nbr_grid *g, double x, double y, double z);

/* Total entries of a list (for statistics). */
static inline size_t nbr_list_size(const nbr_list *l) { return l->n ? l->start[l->n] : 0; }

#endif
