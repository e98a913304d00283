/* sl_mem: checked allocation (see sl_mem.h). */
#include "core/sl_mem.h"
#include "core/sl_log.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static size_t aligned_bytes_;

void *sl_malloc(size_t n, const char *what)
{
    void *p = malloc(n ? n : 1);
    if (!p) sl_fatal("out of memory allocating %zu bytes for %s", n, what);
    return p;
}

void *sl_calloc(size_t count, size_t size, const char *what)
{
    void *p = calloc(count ? count : 1, size ? size : 1);
    if (!p) sl_fatal("out of memory allocating %zu x %zu bytes for %s", count, size, what);
    return p;
}

void *sl_realloc(void *p, size_t n, const char *what)
{
    void *q = realloc(p, n ? n : 1);
    if (!q) sl_fatal("out of memory growing %s to %zu bytes", what, n);
    return q;
}

void *sl_alloc_aligned(size_t n, const char *what)
{
    size_t bytes = (n + 63) / 64 * 64 + 64;
    void *p = NULL;
    if (posix_memalign(&p, 64, bytes) != 0 || !p)
        sl_fatal("out of memory allocating %zu bytes for %s", n, what);
    memset(p, 0, bytes);
    /* Remember the size just before the block would be nicer; keep a
     * running total of the requested sizes instead. */
    aligned_bytes_ += bytes;
    return p;
}

void sl_free_aligned(void *p) { free(p); }

size_t sl_mem_aligned_bytes(void) { return aligned_bytes_; }

char *sl_strdup(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = sl_malloc(n, "a string");
    memcpy(d, s, n);
    return d;
}

size_t sl_mem_peak_rss(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    size_t kb = 0;
    if (!f) return 0;
    while (fgets(line, sizeof line, f))
        if (strncmp(line, "VmHWM:", 6) == 0) {
            kb = (size_t)strtoull(line + 6, NULL, 10);
            break;
        }
    fclose(f);
    return kb * 1024;
}
