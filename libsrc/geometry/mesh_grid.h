/*
 * mesh_grid: a hashed uniform grid of points for distance queries during
 * mesh work (vertex welding, Poisson-disk sampling, spacing statistics).
 *
 * Points are numbered in insertion order and never removed.  Cells of size
 * h are hashed into a power-of-two bucket table that doubles as points are
 * added, so the grid needs no bounding box and has no capacity limit.  Two
 * cells may share a bucket; queries check true distances, so a collision
 * only costs time.
 */
#ifndef SL_MESH_GRID_H
#define SL_MESH_GRID_H

#include <stddef.h>

#define MGRID_NONE ((size_t)-1)

typedef struct mgrid {
    double h, inv_h; /* cell size */
    size_t n, cap;   /* points held, allocated */
    double *x;       /* 3 * cap coordinates */
    size_t *next;    /* next point in the same bucket */
    size_t *head;    /* first point of each bucket */
    size_t nb;       /* buckets (a power of two) */
} mgrid;

/* h > 0 and finite; `expected` is a hint for the first allocation. */
void mgrid_init(mgrid *g, double h, size_t expected);
void mgrid_free(mgrid *g);
/* Adds x (finite coordinates) and returns its number. */
size_t mgrid_insert(mgrid *g, const double x[3]);
/* The point nearest to x among those closer than or at distance r, except
 * point `skip` (MGRID_NONE to skip none); MGRID_NONE if there is none.
 * *dist (may be NULL) receives its distance. */
size_t mgrid_nearest_within(const mgrid *g, const double x[3], double r, size_t skip, double *dist);
/* The nearest point other than `skip` at any distance (MGRID_NONE if the
 * grid holds no other point). */
size_t mgrid_nearest(const mgrid *g, const double x[3], size_t skip, double *dist);

/* Calls visit(ctx, id, distance) for every point within r of x, once
 * each (fast for r <= h; larger r visits every point). */
void mgrid_visit(const mgrid *g, const double x[3], double r,
                 void (*visit)(void *ctx, size_t id, double dist), void *ctx);

#endif
