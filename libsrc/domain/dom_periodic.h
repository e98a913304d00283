/*
 * dom_periodic: periodic boundaries as halo copies (issue 17).
 *
 * A periodic axis is a halo exchange with oneself.  After the fluid has
 * been sorted by cell, every owned fluid particle within the search radius
 * h of a periodic face gets an image shifted by the period (corner
 * particles of two or three periodic axes get one per combination).  The
 * images are appended after the n owned particles, at [n, n + nhalo),
 * sorted by cell with their own cell starts (nbr_grid.hstart), so the
 * neighbour search sees them and every loop over f->n does not: the
 * solver's passes, output, snapshots and function objects see the owned
 * particles only, and the mass is exact.  What a pass of the next
 * iteration reads of a neighbour is refreshed from its original each
 * iteration: the predicted positions after the prediction, density,
 * pressure and p / rho^2 after the density pass.  After integration the
 * positions are wrapped into [lo, hi).
 *
 * Boundary particles get images too, once at set-up (moving bodies move
 * them with their body: exact for translations); their mass and static
 * density are those of their originals, their density and pressure are
 * refreshed with the fluid's.  Boundary images are sorted with the real
 * boundary particles; their ids are >= n - nimages (output skips them).
 *
 * The case reader checks what this needs: the period along each periodic
 * axis is a whole number of particle spacings and at least 2 h, no wall
 * lies across a periodic face (containers open on it), every other shape
 * and every fluid region inside the period.
 */
#ifndef SL_DOM_PERIODIC_H
#define SL_DOM_PERIODIC_H

#include <stddef.h>
#include <stdint.h>

#include "kernel/kernel.h"
#include "neighbours/neighbours.h"
#include "particles/particles.h"

/* What a case asks for (constant/boundaryProperties: periodic (x y);). */
typedef struct dom_periodic {
    unsigned axes;       /* bit d set: axis d is periodic */
    double lo[3], hi[3]; /* the period [lo, hi) along the periodic axes */
} dom_periodic;

/* The images of one step and of the set-up. */
typedef struct dom_halo {
    dom_periodic per;
    double h;                       /* halo width: the search radius */
    double shift[27][3];            /* shift of image code (k0+1) + 3 (k1+1) + 9 (k2+1) */
    size_t n, cap;                  /* fluid images, and room for them */
    uint32_t *src;                  /* owned index of the original of image k */
    uint8_t *code;                  /* its shift */
    uint32_t *cand_src, *cand_cell; /* scratch: images before sorting */
    uint8_t *cand_code;
    uint32_t *count;  /* scratch, ncells + 1 */
    uint32_t *hstart; /* cell starts of the images (absolute indices), ncells + 1 */
    size_t ncells;
    size_t nb_real, nb_img; /* boundary: real particles (ids < nb_real) and images */
    uint32_t *bsrc;         /* id of the original of boundary image id nb_real + k */
    uint8_t *bcode;
    uint32_t *bpos; /* index of boundary id (after the last sort) */
    /* -parallel's domain mode (solver/pcs_domain.c): a rank stores a part of
     * the boundary, and its images' originals among it; bpairs set: the
     * refresh copies, for each pair, bpair[2k + 1] into bpair[2k] (local
     * indices) instead of going through bpos */
    int bpairs;
    uint32_t *bpair;
    size_t nbpair, bpair_cap;
    long steps;        /* statistics: searches with images */
    double images_sum; /* fluid images summed over them */
} dom_halo;

/* Periodic axes named in `axes` text form ("x", "xy", ...) for the log. */
void dom_periodic_axes_text(unsigned axes, char *buf, size_t len);

/* Wrap n positions into [lo, hi) along the periodic axes. */
void dom_periodic_wrap(const dom_periodic *p, size_t n, double *x, double *y, double *z);

/* Set up (h: search radius); nothing to do when p->axes == 0. */
void dom_halo_init(dom_halo *hl, const dom_periodic *p, double h);
void dom_halo_free(dom_halo *hl);
static inline int dom_halo_on(const dom_halo *hl) { return hl->per.axes != 0; }

/* Set-up, before the boundary is sorted: drop the boundary particles
 * outside the period (the images stand for them) and append the images. */
void dom_boundary_images(dom_halo *hl, sl_boundary *b);
/* Set-up, after bnd_set_mass: images take their originals' masses, and
 * the static density of every boundary particle is summed again with
 * them (c_static: the calibration's factor). */
void dom_boundary_images_mass(dom_halo *hl, const nbr_grid *g, const krn_kernel *k, double c_static,
                              sl_boundary *b);

/* After the fluid is sorted: build the fluid images at [f->n, f->n +
 * f->nhalo) (growing the capacity if needed) and point g->hstart at their
 * cell starts. */
void dom_fluid_images(dom_halo *hl, nbr_grid *g, sl_fluid *f, const sl_boundary *b);
/* Each iteration: the images' predicted positions from their originals. */
void dom_refresh_predicted(const dom_halo *hl, sl_fluid *f);
/* Rows of width doubles per fluid particle (a[width * i ...]): the
 * images' from their originals (n = f->n: the first image's row), as
 * they are, for a quantity a translation leaves unchanged. */
void dom_refresh_rows(const dom_halo *hl, size_t n, double *a, int width);
/* Each iteration: density, pressure and p / rho^2 of fluid and boundary
 * images from their originals. */
void dom_refresh_pressure(const dom_halo *hl, sl_fluid *f, sl_boundary *b);
/* After integration: positions wrapped into the period; images dropped. */
void dom_after_integrate(const dom_halo *hl, sl_fluid *f);

#endif
