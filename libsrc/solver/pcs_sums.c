/* pcs_sums: sums over every fluid particle of a view (see pcs_sums.h). */
#include "solver/pcs_sums.h"

#include "core/sl_log.h"
#include "core/sl_reduce.h"
#include "solver/pcs_domain.h"

void pcs_sums_rows(const sl_fluid *f, size_t i0, size_t i1, size_t k, pcs_row_terms terms,
                   const void *ctx, double *run)
{
    double t[PCS_SUM_TERMS];
    for (size_t i = i0; i < i1; i++) {
        terms(ctx, f, i, t);
        for (size_t q = 0; q < k; q++) {
            run[q] += t[q];
            __asm__("" : "+m"(run[q])); /* one row at a time: -fassociative-math would not */
        }
    }
}

/* The block sums added to sum in block order, one at a time. */
static void add_blocks(const double *part, size_t nb, size_t k, double *sum)
{
    for (size_t b = 0; b < nb; b++)
        for (size_t q = 0; q < k; q++) {
            sum[q] += part[b * k + q];
            __asm__("" : "+m"(sum[q]));
        }
}

void pcs_sums_blocks(const double *part, size_t nb, size_t k, double *sum)
{
    for (size_t q = 0; q < k; q++) sum[q] = 0.0;
    add_blocks(part, nb, k, sum);
}

const sl_fluid *pcs_view_rows(const pcs_view *v) { return v->own ? v->own : v->f; }

size_t pcs_view_count(const pcs_view *v)
{
    return v->dom ? pcs_fluid_total(v->dom) : pcs_view_rows(v)->n;
}

void pcs_view_sum_rows(const pcs_view *v, size_t k, pcs_row_terms terms, const void *ctx,
                       double *sum)
{
    if (k > PCS_SUM_TERMS)
        sl_fatal("pcs_view_sum_rows: %zu terms, at most %d (internal error)", k, PCS_SUM_TERMS);
    if (v->dom) {
        pcd_sum_rows(v->dom, k, terms, ctx, sum);
        return;
    }
    const sl_fluid *f = pcs_view_rows(v);
    const size_t n = f->n, B = SL_REDUCE_BLOCK, nb = (n + B - 1) / B;
    enum { CHUNK = 64 }; /* block sums on the stack, a chunk at a time: no allocation */
    double part[CHUNK * PCS_SUM_TERMS];
    for (size_t q = 0; q < k; q++) sum[q] = 0.0;
    for (size_t b0 = 0; b0 < nb; b0 += CHUNK) {
        const size_t b1 = b0 + CHUNK < nb ? b0 + CHUNK : nb;
#pragma omp parallel for schedule(dynamic, 1)
        for (size_t b = b0; b < b1; b++) {
            double run[PCS_SUM_TERMS] = {0.0, 0.0, 0.0, 0.0};
            const size_t hi = (b + 1) * B < n ? (b + 1) * B : n;
            pcs_sums_rows(f, b * B, hi, k, terms, ctx, run);
            for (size_t q = 0; q < k; q++) part[(b - b0) * k + q] = run[q];
        }
        add_blocks(part, b1 - b0, k, sum);
    }
}

void pcs_view_sum_counts(const pcs_view *v, long *c, size_t n)
{
    if (v->dom) pcd_sum_longs(v->dom, c, n);
}

void pcs_view_max(const pcs_view *v, double *m, size_t n)
{
    if (v->dom) pcd_max_doubles(v->dom, m, n);
}
