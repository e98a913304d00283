/*
 * sl_mem: allocation that never fails silently.  Out of memory is a fatal
 * error naming what was being allocated; there are no fixed capacities.
 * Particle arrays are 64-byte aligned so that loops over them vectorise.
 */
#ifndef SL_MEM_H
#define SL_MEM_H

#include <stddef.h>

void *sl_malloc(size_t n, const char *what);
void *sl_calloc(size_t count, size_t size, const char *what);
void *sl_realloc(void *p, size_t n, const char *what);
/* 64-byte aligned, zero-filled; free with sl_free_aligned. */
void *sl_alloc_aligned(size_t n, const char *what);
void sl_free_aligned(void *p);
char *sl_strdup(const char *s);

/* Bytes currently held by sl_alloc_aligned (for the memory report). */
size_t sl_mem_aligned_bytes(void);
/* Peak resident set size of the process in bytes (from /proc). */
size_t sl_mem_peak_rss(void);

#endif
