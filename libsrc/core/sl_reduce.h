/*
 * sl_reduce: sums over particles that give the same bits for any number of
 * threads.  The array is cut into blocks of a fixed size (independent of
 * the thread count), each block is summed in order, and the block sums are
 * added in order.  An OpenMP reduction(+) would depend on the team size.
 */
#ifndef SL_REDUCE_H
#define SL_REDUCE_H

#include <stddef.h>

#define SL_REDUCE_BLOCK 4096

double sl_sum(const double *a, size_t n);
double sl_max(const double *a, size_t n); /* -INFINITY for n == 0 */

#endif
