/*
 * pcs_sums: sums and order statistics over every fluid particle of a view
 * (pcs_view), for the function objects that read the whole fluid
 * (densityError, energy), with one defined association that a rank of
 * -parallel's domain mode can continue: the same bits for any ranks x
 * threads.
 *
 * The rows are the serial array's (solver order: as sorted at the last
 * neighbour search, then the particles appended since, by id).  A sum of
 * a per-row term runs in blocks of SL_REDUCE_BLOCK rows, each block row by
 * row from 0, then the block sums in block order (the density error's
 * scheme, pcs_domain.h).  Serial: over v->own (or v->f).  Domain mode
 * (v->dom set): each rank its own rows, a block cut by a rank boundary
 * continued from the running sum the lower rank sends (k doubles), the
 * block sums gathered on rank 0 (N / 4096 x k doubles), the particles
 * appended since the sort (emitted: at most a step's worth) sent to rank 0
 * with their terms and ids, and rank 0 adds them in id order and the
 * block sums in order.  Counts and maxima are exact reductions.
 *
 * Every function is collective in the domain mode: every rank calls it in
 * the same order with the same sizes (the function objects' list runs the
 * objects that use them on every rank, fo.h fo_serve).
 */
#ifndef SL_PCS_SUMS_H
#define SL_PCS_SUMS_H

#include <stddef.h>

#include "solver/pcisph.h"

/* Most terms summed in one call. */
#define PCS_SUM_TERMS 4

/* The k terms of row i of f, into t[0..k). */
typedef void (*pcs_row_terms)(const void *ctx, const sl_fluid *f, size_t i, double *t);

/* The fluid rows this rank holds for the sums (v->own, else v->f). */
const sl_fluid *pcs_view_rows(const pcs_view *v);
/* The fluid particles of the whole case (every rank alike). */
size_t pcs_view_count(const pcs_view *v);
/* sum[q] = the sum over every fluid particle of term q, q < k <=
 * PCS_SUM_TERMS, in the association above; on rank 0 (the others' sum is
 * unspecified). */
void pcs_view_sum_rows(const pcs_view *v, size_t k, pcs_row_terms terms, const void *ctx,
                       double *sum);
/* c[0..n) summed over the ranks, in place, on every rank (exact). */
void pcs_view_sum_counts(const pcs_view *v, long *c, size_t n);
/* m[0..n) maximised over the ranks, in place, on every rank (exact). */
void pcs_view_max(const pcs_view *v, double *m, size_t n);

/* For pcs_domain.c: rows [i0, i1) of f added to run[0..k) one row at a
 * time (the association above), and the block sums part[b k + q] of nb
 * blocks added in block order into sum[0..k). */
void pcs_sums_rows(const sl_fluid *f, size_t i0, size_t i1, size_t k, pcs_row_terms terms,
                   const void *ctx, double *run);
void pcs_sums_blocks(const double *part, size_t nb, size_t k, double *sum);

#endif
