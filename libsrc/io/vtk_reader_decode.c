/* vtk_reader_decode: the arrays' bytes (see vtk_reader.c). */
#include "io/vtk_reader_internal.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h>

/* ---- decoding ---------------------------------------------------------- */

static double value_at(vtkr_type t, const unsigned char *p)
{
    double d;
    float f;
    int32_t i32;
    uint32_t u32;
    int64_t i64;
    switch (t) {
    case T_F64:
        memcpy(&d, p, 8);
        return d;
    case T_F32:
        memcpy(&f, p, 4);
        return (double)f;
    case T_I32:
        memcpy(&i32, p, 4);
        return (double)i32;
    case T_U32:
        memcpy(&u32, p, 4);
        return (double)u32;
    case T_I64:
        memcpy(&i64, p, 8);
        return (double)i64;
    case T_U8:
    case T_NTYPES:
        break;
    }
    return (double)*p;
}

/* Expected byte count of d, or check a count read from the file. */
static int check_nbytes(rd *r, desc *d, uint64_t nbytes)
{
    size_t es = vtkr_type_sizes[d->type], ts = es * (size_t)d->ncomp, want;
    if (!d->known) {
        if (nbytes % ts)
            return vtkr_fail(r, "array '%s': %llu bytes is not a whole number of values", d->name,
                             (unsigned long long)nbytes);
        d->ntuples = (size_t)(nbytes / ts);
        return 0;
    }
    if (__builtin_mul_overflow(d->ntuples, ts, &want) || nbytes != want)
        return vtkr_fail(r, "array '%s': holds %llu bytes, expected %zu tuples of %zu bytes",
                         d->name, (unsigned long long)nbytes, d->ntuples, ts);
    return 0;
}

static int alloc_values(rd *r, desc *d)
{
    d->nvalues = d->ntuples * (size_t)d->ncomp;
    d->data = malloc((d->nvalues ? d->nvalues : 1) * sizeof *d->data);
    if (!d->data) return vtkr_fail(r, "array '%s': out of memory", d->name);
    return 0;
}

static void convert(desc *d, const unsigned char *bytes)
{
    size_t es = vtkr_type_sizes[d->type];
    for (size_t i = 0; i < d->nvalues; i++) d->data[i] = value_at(d->type, bytes + i * es);
}

static int read_u64(rd *r, const desc *d, size_t at, uint64_t *v)
{
    if (at > r->dend || r->dend - at < 8)
        return vtkr_fail(
            r, "array '%s': header runs past the end of the appended data (truncated?)", d->name);
    memcpy(v, r->buf + at, 8);
    return 0;
}

/* Plain appended: [UInt64 nbytes][bytes]; returns the end position. */
static int decode_raw(rd *r, desc *d, size_t at, size_t *end)
{
    uint64_t nbytes = 0;
    if (read_u64(r, d, at, &nbytes) || check_nbytes(r, d, nbytes)) return 1;
    at += 8;
    if (nbytes > r->dend - at)
        return vtkr_fail(r, "array '%s': data run past the end of the appended data (truncated?)",
                         d->name);
    if (alloc_values(r, d)) return 1;
    convert(d, (const unsigned char *)r->buf + at);
    *end = at + (size_t)nbytes;
    return 0;
}

/* zlib appended: [nblocks, block, last, csize_1..n][blocks]. */
static int decode_zlib(rd *r, desc *d, size_t at, size_t *end)
{
    uint64_t nb = 0, bs = 0, last = 0, total = 0, csum = 0;
    if (read_u64(r, d, at, &nb) || read_u64(r, d, at + 8, &bs) || read_u64(r, d, at + 16, &last))
        return 1;
    size_t avail = r->dend - at - 24;
    if (nb > avail / 8)
        return vtkr_fail(r, "array '%s': block count %llu runs past the end of the data", d->name,
                         (unsigned long long)nb);
    const size_t hdr = at + 24, data = hdr + 8 * (size_t)nb;
    if (nb > 0) {
        if (bs == 0 || last >= bs)
            return vtkr_fail(r, "array '%s': bad compression header (block %llu, last %llu)",
                             d->name, (unsigned long long)bs, (unsigned long long)last);
        if (__builtin_mul_overflow(nb - 1, bs, &total) ||
            __builtin_add_overflow(total, last ? last : bs, &total))
            return vtkr_fail(r, "array '%s': bad compression header", d->name);
    }
    for (uint64_t b = 0; b < nb; b++) {
        uint64_t c;
        memcpy(&c, r->buf + hdr + 8 * b, 8);
        if (c > avail || __builtin_add_overflow(csum, c, &csum) || csum > r->dend - data)
            return vtkr_fail(r,
                             "array '%s': compressed blocks run past the end of the appended data "
                             "(truncated?)",
                             d->name);
    }
    if (check_nbytes(r, d, total)) return 1;
    if (total / VTKR_MAX_RATIO > csum + 64 * nb)
        return vtkr_fail(r, "array '%s': %llu compressed bytes cannot hold %llu bytes", d->name,
                         (unsigned long long)csum, (unsigned long long)total);
    unsigned char *raw = malloc(total ? (size_t)total : 1);
    if (!raw) return vtkr_fail(r, "array '%s': out of memory", d->name);
    size_t src = data;
    for (uint64_t b = 0; b < nb; b++) {
        uint64_t c;
        memcpy(&c, r->buf + hdr + 8 * b, 8);
        uLongf want = (uLongf)(b + 1 < nb || !last ? bs : last), got = want;
        uLong used = (uLong)c;
        int rc = uncompress2(raw + b * bs, &got, (const Bytef *)r->buf + src, &used);
        if (rc != Z_OK || got != want || used != c) {
            free(raw);
            return vtkr_fail(r,
                             "array '%s': block %llu of %llu does not inflate to its %lu bytes "
                             "(corrupt data)",
                             d->name, (unsigned long long)b + 1, (unsigned long long)nb,
                             (unsigned long)want);
        }
        src += (size_t)c;
    }
    int rc = alloc_values(r, d);
    if (!rc) convert(d, raw);
    free(raw);
    *end = src;
    return rc;
}

/* One ascii value of type t from s; *next is past it. */
static int parse_ascii_value(vtkr_type t, const char *s, char **next, double *v)
{
    errno = 0;
    if (t == T_F64) {
        *v = strtod(s, next);
        return *next == s;
    }
    if (t == T_F32) { /* rounded to float as VTK does: the text is the float's */
        *v = (double)strtof(s, next);
        return *next == s;
    }
    if (t == T_U32 || t == T_U8) {
        if (*s == '-') return 1;
        unsigned long long u = strtoull(s, next, 10);
        unsigned long long lim = t == T_U8 ? 255ULL : 4294967295ULL;
        *v = (double)u;
        return *next == s || errno || u > lim;
    }
    long long i = strtoll(s, next, 10);
    *v = (double)i;
    return *next == s || errno || (t == T_I32 && (i < INT32_MIN || i > INT32_MAX));
}

static int decode_ascii(rd *r, desc *d)
{
    size_t cap, n = 0, pos = d->tbeg;
    if (d->known) {
        if (__builtin_mul_overflow(d->ntuples, (size_t)d->ncomp, &cap) ||
            cap > (d->tend - d->tbeg + 1) / 2 + 1)
            return vtkr_fail(r, "array '%s': too few values for %zu tuples", d->name, d->ntuples);
    } else {
        cap = (d->tend - d->tbeg + 1) / 2 + 1;
    }
    d->data = malloc((cap ? cap : 1) * sizeof *d->data);
    if (!d->data) return vtkr_fail(r, "array '%s': out of memory", d->name);
    for (;;) {
        while (pos < d->tend && vtkr_is_ws(r->buf[pos])) pos++;
        if (pos >= d->tend) break;
        if (n == cap) return vtkr_fail(r, "array '%s': more values than expected", d->name);
        char *next;
        if (parse_ascii_value(d->type, r->buf + pos, &next, &d->data[n]) ||
            (size_t)(next - r->buf) > d->tend ||
            ((size_t)(next - r->buf) < d->tend && !vtkr_is_ws(*next)))
            return vtkr_fail(r, "array '%s': value %zu is not a valid %s", d->name, n + 1,
                             vtkr_type_names[d->type]);
        pos = (size_t)(next - r->buf);
        n++;
    }
    if (!d->known) {
        if (n % (size_t)d->ncomp)
            return vtkr_fail(r, "array '%s': %zu values is not a whole number of tuples", d->name,
                             n);
        d->ntuples = n / (size_t)d->ncomp;
    } else if (n != cap) {
        return vtkr_fail(r, "array '%s': %zu values, expected %zu", d->name, n, cap);
    }
    d->nvalues = n;
    return 0;
}

int vtkr_decode_all(rd *r)
{
    size_t last_end = r->dbeg;
    for (size_t i = 0; i < r->nd; i++) {
        desc *d = &r->d[i];
        if (d->ascii) {
            if (decode_ascii(r, d)) return 1;
            continue;
        }
        size_t end;
        if (d->offset > r->dend - r->dbeg)
            return vtkr_fail(r,
                             "array '%s': offset %zu is past the end of the appended data "
                             "(truncated?)",
                             d->name, d->offset);
        if ((r->compress ? decode_zlib : decode_raw)(r, d, r->dbeg + d->offset, &end)) return 1;
        if (end > last_end) last_end = end;
    }
    if (r->have_appended && !vtkr_only_ws(r, last_end, r->dend))
        return vtkr_fail(r, "unexpected bytes after the last array of the appended data");
    return 0;
}
