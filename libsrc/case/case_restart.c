/* case_restart: the restart file <time>/uniform/restart (see case_restart.h):
 * formats 4 and 3, in pieces with an index; format 2 in case_restart_v2.c. */
#include "case/case_restart.h"
#include "case/case_restart_v2.h"
#include "core/sl_mem.h"
#include "io/time_dir.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <zlib.h>

#define RST_MAGIC3     RST_FAMILY "3"
#define RST_MAGIC4     RST_FAMILY "4"
#define RST_TAIL_MAGIC "SLUICE-RST-TAIL"

typedef struct rst3_head {
    char magic[16];
    uint64_t nsnaps, ctrl_size, records;
} rst3_head;

typedef struct rst3_snap {
    uint64_t n;
    double time, dt;
    int64_t step;
} rst3_snap;

/* One member of the file: where it is, its length, the CRC-32 of its
 * (compressed) bytes -- its gzip trailer holds the CRC-32 of the data, so
 * that every byte is checked -- and for a piece the least and largest
 * value it holds (lo, hi; a NaN makes them -inf and +inf). */
typedef struct rst3_entry {
    uint64_t off;
    uint32_t len, crc;
    double lo, hi;
} rst3_entry;

typedef struct rst3_tail {
    char magic[16];
    uint64_t head_len, index_off, index_len, entries, ctrl_off, ctrl_len;
    uint32_t head_crc, index_crc, ctrl_crc, spare;
} rst3_tail;

/* The tail's stored gzip member: header, block header, payload, CRC-32 and
 * length. */
#define TAIL_MEMBER (10 + 5 + sizeof(rst3_tail) + 8)

/* A state's fields (format 3: the first 7) and the boundary's (format 4). */
static const char *const field_name[RST_FIELDS] = {"x",  "y",  "z", "vx", "vy",
                                                   "vz", "id", "p", "rho"};
static const char *const bfield_name[RST_BFIELDS] = {"id", "p", "pt", "rho"};

static size_t width_of(int j) { return j == 6 ? sizeof(uint32_t) : sizeof(double); }
static size_t bwidth_of(int j) { return j == 0 ? sizeof(uint32_t) : sizeof(double); }
static int fields_of(int version) { return version >= 4 ? RST_FIELDS : 7; }

/* ---- counters ---- */

static rst_counts counts_;
static double clock_wall0_, clock_cpu0_;
static int clock_depth_;

static double now(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void clock_start(void)
{
    if (clock_depth_++) return;
    clock_wall0_ = now(CLOCK_MONOTONIC);
    clock_cpu0_ = now(CLOCK_PROCESS_CPUTIME_ID);
}

static void clock_stop(void)
{
    if (--clock_depth_) return;
    counts_.wall += now(CLOCK_MONOTONIC) - clock_wall0_;
    counts_.cpu += now(CLOCK_PROCESS_CPUTIME_ID) - clock_cpu0_;
}

rst_counts rst_counters(void) { return counts_; }

void rst_count_gz(gzFile g)
{
    const z_off_t u = gztell(g), c = gzoffset(g);
    if (u > 0) counts_.inflated += (double)u;
    if (c > 0) counts_.read += (double)c;
}

static char *rst_path(const char *dir, int mkdir_uniform, sl_err *err)
{
    size_t n = strlen(dir) + 32;
    char *p = sl_malloc(n, "path");
    snprintf(p, n, "%s/uniform", dir);
    if (mkdir_uniform && tdir_mkdirs(p, err)) {
        free(p);
        return NULL;
    }
    snprintf(p, n, "%s/uniform/restart", dir);
    return p;
}

static size_t blocks_of(uint64_t n, uint64_t records)
{
    return (size_t)((n + records - 1) / records);
}

/* ---- writing format 3 ---- */

typedef struct w3 {
    FILE *f;
    uint64_t off;
    z_stream z;
    unsigned char *out;
    size_t cap;
} w3;

/* data[0..len) appended as one gzip member: where it is, its length and
 * CRC-32 into e. */
static int w3_member(w3 *w, const void *data, size_t len, rst3_entry *e)
{
    static const char none;
    if (len > (1u << 31) || deflateReset(&w->z) != Z_OK) return -1;
    w->z.next_in = (Bytef *)(len ? data : &none);
    w->z.avail_in = (uInt)len;
    const uint64_t start = w->off;
    uLong crc = crc32(0L, Z_NULL, 0);
    int zr;
    do {
        w->z.next_out = w->out;
        w->z.avail_out = (uInt)w->cap;
        zr = deflate(&w->z, Z_FINISH);
        if (zr == Z_STREAM_ERROR) return -1;
        const size_t got = w->cap - w->z.avail_out;
        if (got && fwrite(w->out, 1, got, w->f) != got) return -1;
        crc = crc32(crc, w->out, (uInt)got);
        w->off += got;
    } while (zr != Z_STREAM_END);
    if (w->off - start > UINT32_MAX) return -1;
    e->off = start;
    e->len = (uint32_t)(w->off - start);
    e->crc = (uint32_t)crc; /* of the member's bytes (its trailer holds the data's) */
    return 0;
}

static void bounds_of(const unsigned char *buf, size_t m, size_t width, rst3_entry *e)
{
    double lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < m; i++) {
        double v;
        if (width == sizeof v) memcpy(&v, buf + i * sizeof v, sizeof v);
        else {
            uint32_t u;
            memcpy(&u, buf + i * sizeof u, sizeof u);
            v = (double)u;
        }
        if (isnan(v)) lo = -INFINITY, hi = INFINITY;
        else {
            if (v < lo) lo = v;
            if (v > hi) hi = v;
        }
    }
    e->lo = lo;
    e->hi = hi;
}

/* Fields [0, nf) of n records from col[]: each field in pieces of
 * RST_RECORDS records, read from its source in order (width: the bytes of
 * a value of field j). */
static int w3_fields(w3 *w, size_t n, const sl_source *col, int nf, size_t (*width)(int),
                     unsigned char *buf, rst3_entry *e)
{
    const size_t nb = blocks_of(n, RST_RECORDS);
    for (int j = 0; j < nf; j++) {
        const size_t wd = width(j);
        for (size_t p = 0; p < nb; p++, e++) {
            const size_t r0 = p * RST_RECORDS;
            const size_t m = n - r0 < RST_RECORDS ? n - r0 : RST_RECORDS;
            col[j].read(col[j].ctx, r0 * wd, m * wd, buf);
            bounds_of(buf, m, wd, e);
            if (w3_member(w, buf, m * wd, e)) return -1;
        }
    }
    return 0;
}

static void le32(unsigned char *o, uint32_t v)
{
    for (int i = 0; i < 4; i++) o[i] = (unsigned char)(v >> (8 * i));
}

/* The tail, a stored (uncompressed) gzip member of fixed size. */
static int w3_tail(w3 *w, const rst3_tail *t)
{
    unsigned char m[TAIL_MEMBER] = {0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 3, 1};
    const uint16_t len = (uint16_t)sizeof *t, nlen = (uint16_t)~len;
    m[11] = (unsigned char)len, m[12] = (unsigned char)(len >> 8);
    m[13] = (unsigned char)nlen, m[14] = (unsigned char)(nlen >> 8);
    memcpy(m + 15, t, sizeof *t);
    le32(m + 15 + sizeof *t, (uint32_t)crc32(0L, (const Bytef *)t, (uInt)sizeof *t));
    le32(m + 19 + sizeof *t, (uint32_t)sizeof *t);
    return fwrite(m, 1, sizeof m, w->f) == sizeof m ? 0 : -1;
}

/* Format `version` (3: a state's first 7 fields, no boundary; 4: every
 * field and the boundary's, bnd NULL: none). */
static int write3(const char *path, const rst_state *states, int nstates, const rst_bstate *bnd,
                  const void *ctrl, size_t ctrl_size, int version)
{
    w3 w = {0};
    const int nf = fields_of(version);
    const uint64_t nbnd = version >= 4 && bnd ? (uint64_t)bnd->n : 0;
    size_t ne = (size_t)RST_BFIELDS * blocks_of(nbnd, RST_RECORDS);
    for (int k = 0; k < nstates; k++) ne += (size_t)nf * blocks_of(states[k].n, RST_RECORDS);
    rst3_entry *e = sl_calloc(ne ? ne : 1, sizeof *e, "restart index");
    unsigned char *buf = sl_malloc(RST_RECORDS * sizeof(double), "restart output");
    unsigned char head[sizeof(rst3_head) + RST_MAX_SNAPSHOTS * sizeof(rst3_snap) + sizeof nbnd];
    rst3_head h = {.nsnaps = (uint64_t)nstates, .ctrl_size = ctrl_size, .records = RST_RECORDS};
    rst3_tail t;
    rst3_entry he, ie, ce;
    memcpy(h.magic, version >= 4 ? RST_MAGIC4 : RST_MAGIC3, strlen(RST_MAGIC3));
    memcpy(head, &h, sizeof h);
    size_t hl = sizeof h;
    for (int k = 0; k < nstates; k++, hl += sizeof(rst3_snap)) {
        const rst3_snap s = {states[k].n, states[k].time, states[k].dt, states[k].step};
        memcpy(head + hl, &s, sizeof s);
    }
    if (version >= 4) memcpy(head + hl, &nbnd, sizeof nbnd), hl += sizeof nbnd;
    memset(&t, 0, sizeof t);
    memcpy(t.magic, RST_TAIL_MAGIC, strlen(RST_TAIL_MAGIC));
    int rc = deflateInit2(&w.z, 1, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) == Z_OK ? 0 : -1;
    w.cap = 1 << 17;
    w.out = sl_malloc(w.cap, "restart output");
    errno = 0;
    if (!rc && !(w.f = fopen(path, "wb"))) rc = -1;
    if (!rc) rc = w3_member(&w, head, hl, &he);
    /* the first state, the boundary (the boundary's at the first state's
     * time), the others: the order -parallel's streamed writes read their
     * arrays in is then the same with one state and with two (its prefetch
     * guesses the next array from the last write's order) */
    size_t at = 0;
    for (int k = 0; k < nstates && !rc; k++) {
        rc = w3_fields(&w, states[k].n, states[k].col, nf, width_of, buf, e + at);
        at += (size_t)nf * blocks_of(states[k].n, RST_RECORDS);
        if (!rc && k == 0 && nbnd) {
            rc = w3_fields(&w, bnd->n, bnd->col, RST_BFIELDS, bwidth_of, buf, e + at);
            at += (size_t)RST_BFIELDS * blocks_of(nbnd, RST_RECORDS);
        }
    }
    if (!rc) rc = w3_member(&w, e, ne * sizeof *e, &ie);
    if (!rc) rc = w3_member(&w, ctrl, ctrl_size, &ce);
    if (!rc) {
        t.head_len = he.len, t.head_crc = he.crc;
        t.index_off = ie.off, t.index_len = ie.len, t.index_crc = ie.crc, t.entries = ne;
        t.ctrl_off = ce.off, t.ctrl_len = ce.len, t.ctrl_crc = ce.crc;
        rc = w3_tail(&w, &t);
    }
    if (w.f && fclose(w.f)) rc = -1;
    deflateEnd(&w.z);
    free(w.out);
    free(buf);
    free(e);
    return rc;
}

static void read_memory(void *ctx, size_t off, size_t len, void *out)
{
    memcpy(out, (const unsigned char *)ctx + off, len);
}

void rst_state_of(rst_state *st, const pcs_snapshot *s)
{
    const void *a[RST_FIELDS] = {s->x, s->y, s->z, s->vx, s->vy, s->vz, s->id, s->p, s->rho};
    st->n = s->n;
    st->time = s->time;
    st->dt = s->dt;
    st->step = s->step;
    for (int k = 0; k < RST_FIELDS; k++) st->col[k] = (sl_source){read_memory, (void *)a[k], NULL};
}

void rst_bstate_of(rst_bstate *st, const sl_boundary *b)
{
    const void *a[RST_BFIELDS] = {b->id, b->p, b->pt, b->rho};
    st->n = b->n;
    for (int k = 0; k < RST_BFIELDS; k++) st->col[k] = (sl_source){read_memory, (void *)a[k], NULL};
}

int rst_write_states(const char *dir, const rst_state *states, int nstates, const rst_bstate *bnd,
                     const void *ctrl, size_t ctrl_size, sl_err *err)
{
    const char *v = getenv("SLUICE_RESTART_FORMAT");
    if (v && *v && strcmp(v, "2") && strcmp(v, "3") && strcmp(v, "4")) {
        sl_err_set(err,
                   "SLUICE_RESTART_FORMAT=%s: 4 (the default: pieces with an index, the "
                   "pressures carried between steps included), 3 (without them, for a Sluice "
                   "that reads formats 2 and 3 only) or 2 (one stream, for a Sluice that reads "
                   "format 2 only)",
                   v);
        return 1;
    }
    char *path = rst_path(dir, 1, err);
    if (!path) return 1;
    rst_scan_end();
    int rc;
    if (v && !strcmp(v, "2")) rc = rst2_write(path, states, nstates, ctrl, ctrl_size, err);
    else if ((rc = write3(path, states, nstates, bnd, ctrl, ctrl_size,
                          v && !strcmp(v, "3") ? 3 : 4)) != 0)
        sl_err_set(err, "cannot write '%s': %s", path, strerror(errno ? errno : EIO));
    free(path);
    return rc ? 1 : 0;
}

int rst_write(const char *dir, const pcs_snapshot *const *snaps, int nsnaps, const void *ctrl,
              size_t ctrl_size, sl_err *err)
{
    rst_state st[RST_MAX_SNAPSHOTS];
    if (nsnaps < 1 || nsnaps > RST_MAX_SNAPSHOTS) {
        sl_err_set(err, "cannot write a restart file of %d states into '%s'", nsnaps, dir);
        return 1;
    }
    for (int k = 0; k < nsnaps; k++) rst_state_of(&st[k], snaps[k]);
    return rst_write_states(dir, st, nsnaps, NULL, ctrl, ctrl_size, err);
}

/* ---- reading format 3 ---- */

typedef struct r3 {
    FILE *f;
    const char *path;
    rst3_tail t;
    rst3_head h;
    rst3_snap s[RST_MAX_SNAPSHOTS];
    rst3_entry *e;
    size_t ne, base[RST_MAX_SNAPSHOTS], nb[RST_MAX_SNAPSHOTS];
    int version, nf;   /* 3 or 4; fields per state */
    uint64_t nbnd;     /* boundary records (format 4) */
    size_t bbase, bnb; /* their first entry, blocks */
    z_stream z;
    int zok;
    unsigned char *in;
    size_t incap;
} r3;

static rst_status damaged(const r3 *r, sl_err *err, const char *why)
{
    sl_err_set(err, "restart file '%s' is damaged (%s)", r->path, why);
    return RST_DAMAGED;
}

/* The member [off, off + len) decompressed into out (room bytes; *got its
 * length, or NULL: exactly room), its CRC-32 crc; `what` names it in the
 * error. */
static int r3_member(r3 *r, uint64_t off, uint64_t len, uint32_t crc, void *out, size_t room,
                     size_t *got, const char *what, sl_err *err)
{
    char why[256];
    if (len > (1u << 31) || room > (1u << 31)) {
        snprintf(why, sizeof why, "%s: a member of %llu bytes", what, (unsigned long long)len);
        return damaged(r, err, why), -1;
    }
    if (len > r->incap) {
        free(r->in);
        r->incap = (size_t)len;
        r->in = sl_malloc(r->incap, "restart input");
    }
    if (fseeko(r->f, (off_t)off, SEEK_SET) || fread(r->in, 1, (size_t)len, r->f) != len) {
        snprintf(why, sizeof why, "%s: it ends early", what);
        return damaged(r, err, why), -1;
    }
    counts_.read += (double)len;
    if ((uint32_t)crc32(0L, r->in, (uInt)len) != crc) {
        snprintf(why, sizeof why, "%s: its CRC-32 is not the one recorded", what);
        return damaged(r, err, why), -1;
    }
    inflateReset(&r->z);
    r->z.next_in = r->in;
    r->z.avail_in = (uInt)len;
    r->z.next_out = out;
    r->z.avail_out = (uInt)room;
    const int zr = inflate(&r->z, Z_FINISH);
    const size_t n = room - r->z.avail_out;
    counts_.inflated += (double)n;
    const char *bad = NULL;
    if (zr != Z_STREAM_END) bad = r->z.msg ? r->z.msg : "it ends early";
    else if (r->z.avail_in) bad = "bytes after its end";
    else if (!got && n != room) bad = "of the wrong length";
    if (bad) {
        snprintf(why, sizeof why, "%s: %s", what, bad);
        return damaged(r, err, why), -1;
    }
    if (got) *got = n;
    return 0;
}

static void r3_close(r3 *r)
{
    if (r->f) fclose(r->f);
    if (r->zok) inflateEnd(&r->z);
    free(r->e);
    free(r->in);
    memset(r, 0, sizeof *r);
}

static uint32_t get32(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

/* The tail at the end of the file, and where the others are. */
static rst_status r3_tail(r3 *r, sl_err *err)
{
    unsigned char m[TAIL_MEMBER];
    static const unsigned char hdr[11] = {0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 3, 1};
    if (fseeko(r->f, 0, SEEK_END)) return damaged(r, err, "it cannot be sought");
    const uint64_t size = (uint64_t)ftello(r->f);
    if (size < TAIL_MEMBER || fseeko(r->f, -(off_t)TAIL_MEMBER, SEEK_END) ||
        fread(m, 1, sizeof m, r->f) != sizeof m || memcmp(m, hdr, sizeof hdr) ||
        m[11] + 256u * m[12] != sizeof r->t || (m[13] ^ m[11]) != 0xff || (m[14] ^ m[12]) != 0xff ||
        get32(m + 15 + sizeof r->t) != (uint32_t)crc32(0L, m + 15, (uInt)sizeof r->t) ||
        get32(m + 19 + sizeof r->t) != sizeof r->t)
        return damaged(r, err, "no index at its end: truncated, or damaged there");
    memcpy(&r->t, m + 15, sizeof r->t);
    const rst3_tail *t = &r->t;
    if (memcmp(t->magic, RST_TAIL_MAGIC, strlen(RST_TAIL_MAGIC) + 1))
        return damaged(r, err, "no index at its end: truncated, or damaged there");
    if (t->ctrl_off + t->ctrl_len + TAIL_MEMBER != size ||
        t->index_off + t->index_len != t->ctrl_off || t->head_len > t->index_off) {
        char why[160];
        snprintf(why, sizeof why, "its index describes %llu bytes, it has %llu",
                 (unsigned long long)(t->ctrl_off + t->ctrl_len + TAIL_MEMBER),
                 (unsigned long long)size);
        return damaged(r, err, why);
    }
    return RST_OK;
}

/* The head: the number of states, their headers (format 4: and the
 * boundary's records). */
static rst_status r3_head(r3 *r, sl_err *err)
{
    unsigned char b[sizeof(rst3_head) + RST_MAX_SNAPSHOTS * sizeof(rst3_snap) + sizeof(uint64_t)];
    size_t got;
    if (r3_member(r, 0, r->t.head_len, r->t.head_crc, b, sizeof b, &got, "its header", err))
        return RST_DAMAGED;
    if (got < sizeof r->h) return damaged(r, err, "its header is short");
    memcpy(&r->h, b, sizeof r->h);
    const rst3_head *h = &r->h;
    r->version = !memcmp(h->magic, RST_MAGIC4, sizeof h->magic) ? 4
        : !memcmp(h->magic, RST_MAGIC3, sizeof h->magic)        ? 3
                                                                : 0;
    r->nf = fields_of(r->version);
    const size_t ext = r->version >= 4 ? sizeof r->nbnd : 0;
    if (!r->version || h->nsnaps < 1 || h->nsnaps > RST_MAX_SNAPSHOTS || h->records < 1 ||
        h->records > (1u << 24) || got != sizeof *h + h->nsnaps * sizeof(rst3_snap) + ext)
        return damaged(r, err, "its header");
    r->nbnd = 0;
    if (ext) memcpy(&r->nbnd, b + sizeof *h + h->nsnaps * sizeof(rst3_snap), ext);
    if (r->nbnd > ((uint64_t)1 << 34)) return damaged(r, err, "its header");
    r->bnb = blocks_of(r->nbnd, h->records);
    size_t ne = 0; /* the first state's pieces, the boundary's, the others' (write3) */
    for (size_t k = 0; k < h->nsnaps; k++) {
        memcpy(&r->s[k], b + sizeof *h + k * sizeof(rst3_snap), sizeof(rst3_snap));
        if (r->s[k].n > ((uint64_t)1 << 34)) return damaged(r, err, "its header");
        r->base[k] = ne;
        r->nb[k] = blocks_of(r->s[k].n, h->records);
        ne += (size_t)r->nf * r->nb[k];
        if (k == 0) r->bbase = ne, ne += (size_t)RST_BFIELDS * r->bnb;
    }
    if (ne != r->t.entries || ne * sizeof(rst3_entry) > (1u << 31))
        return damaged(r, err, "its index does not match its header");
    r->ne = ne;
    return RST_OK;
}

/* The index: every piece's member, contiguous from the head to the index. */
static rst_status r3_index(r3 *r, sl_err *err)
{
    r->e = sl_malloc((r->ne ? r->ne : 1) * sizeof *r->e, "restart index");
    if (r3_member(r, r->t.index_off, r->t.index_len, r->t.index_crc, r->e, r->ne * sizeof *r->e,
                  NULL, "its index", err))
        return RST_DAMAGED;
    uint64_t at = r->t.head_len;
    for (size_t i = 0; i < r->ne; at += r->e[i++].len)
        if (r->e[i].off != at) return damaged(r, err, "its index's offsets");
    return at == r->t.index_off ? RST_OK : damaged(r, err, "its index's offsets");
}

static rst_status r3_open(r3 *r, const char *path, sl_err *err)
{
    memset(r, 0, sizeof *r);
    r->path = path;
    errno = 0;
    if (!(r->f = fopen(path, "rb"))) {
        sl_err_set(err, "cannot open restart file '%s': %s", path,
                   strerror(errno ? errno : ENOMEM));
        return RST_MISSING;
    }
    if (inflateInit2(&r->z, 15 + 16) != Z_OK) return damaged(r, err, "zlib cannot start");
    r->zok = 1;
    rst_status st = r3_tail(r, err);
    if (st == RST_OK) st = r3_head(r, err);
    if (st == RST_OK) st = r3_index(r, err);
    return st;
}

/* Piece p of field j of state k into out. */
static int r3_piece(r3 *r, size_t k, int j, size_t p, void *out, sl_err *err)
{
    const rst3_entry *e = &r->e[r->base[k] + (size_t)j * r->nb[k] + p];
    const uint64_t R = r->h.records, r0 = p * R, m = r->s[k].n - r0 < R ? r->s[k].n - r0 : R;
    char what[160];
    snprintf(what, sizeof what, "state %zu, field %s, records %llu-%llu", k + 1, field_name[j],
             (unsigned long long)r0, (unsigned long long)(r0 + m - 1));
    return r3_member(r, e->off, e->len, e->crc, out, (size_t)m * width_of(j), NULL, what, err);
}

/* Piece p of the boundary's field j (format 4) into out. */
static int r3_bpiece(r3 *r, int j, size_t p, void *out, sl_err *err)
{
    const rst3_entry *e = &r->e[r->bbase + (size_t)j * r->bnb + p];
    const uint64_t R = r->h.records, r0 = p * R, m = r->nbnd - r0 < R ? r->nbnd - r0 : R;
    char what[160];
    snprintf(what, sizeof what, "boundary, field %s, records %llu-%llu", bfield_name[j],
             (unsigned long long)r0, (unsigned long long)(r0 + m - 1));
    return r3_member(r, e->off, e->len, e->crc, out, (size_t)m * bwidth_of(j), NULL, what, err);
}

/* Every piece of state k, into s's arrays (s NULL: decompressed and
 * checked only). */
static int r3_state(r3 *r, size_t k, pcs_snapshot *s, sl_err *err)
{
    const size_t n = (size_t)r->s[k].n, R = (size_t)r->h.records;
    unsigned char *scratch = s ? NULL : sl_malloc(R * sizeof(double), "restart input");
    if (s) {
        sl_fluid tmp;
        prt_fluid_init(&tmp); /* the snapshot's buffers grown as rst2_read grows them */
        tmp.n = n;
        prt_fluid_reserve(&tmp, n ? n : 1);
        snap_take(s, &tmp, r->s[k].time, r->s[k].dt, (long)r->s[k].step);
        prt_fluid_free(&tmp);
    }
    double *a[RST_FIELDS] = {NULL};
    if (s) {
        a[0] = s->x, a[1] = s->y, a[2] = s->z, a[3] = s->vx, a[4] = s->vy, a[5] = s->vz;
        a[7] = s->p, a[8] = s->rho;
        s->carried = r->nf == RST_FIELDS;
        if (!s->carried && n)
            memset(s->p, 0, n * sizeof *s->p), memset(s->rho, 0, n * sizeof *s->rho);
    }
    int rc = 0;
    for (int j = 0; j < r->nf && !rc; j++)
        for (size_t p = 0; p < r->nb[k] && !rc; p++) {
            void *to = scratch;
            if (s && j != 6) to = a[j] + p * R;
            else if (s) to = s->id + p * R;
            rc = r3_piece(r, k, j, p, to, err);
        }
    free(scratch);
    return rc;
}

/* The reader of the last probe or scan of a file of format 3, kept open
 * for the next scan of the same file (its tail, head and index read once)
 * until rst_scan_end. */
static r3 open_;
static char *open_path_;

void rst_scan_end(void)
{
    if (!open_path_) return;
    r3_close(&open_);
    free(open_path_);
    open_path_ = NULL;
}

static rst_status read3(const char *path, pcs_snapshot *snaps, int max, int *nsnaps, void *ctrl,
                        size_t ctrl_size, int arrays, sl_err *err)
{
    r3 local, *r = &local; /* a probe's is kept open for the scans */
    if (!arrays) {
        rst_scan_end();
        open_path_ = sl_malloc(strlen(path) + 1, "path");
        strcpy(open_path_, path);
        r = &open_;
    }
    rst_status st = r3_open(r, arrays ? path : open_path_, err);
    if (st == RST_OK && ctrl && r->h.ctrl_size != ctrl_size) {
        sl_err_set(err,
                   "restart file '%s' was written for a different case (%llu bytes of run "
                   "state, this case has %zu: emitters added or removed?)",
                   path, (unsigned long long)r->h.ctrl_size, ctrl_size);
        st = RST_MISMATCH;
    }
    *nsnaps = 0;
    for (size_t k = 0; st == RST_OK && k < r->h.nsnaps; k++) {
        const int keep = (int)k < max;
        if (keep) {
            snaps[k].n = (size_t)r->s[k].n;
            snaps[k].time = r->s[k].time;
            snaps[k].dt = r->s[k].dt;
            snaps[k].step = (long)r->s[k].step;
            snaps[k].carried = r->nf == RST_FIELDS;
        }
        if (arrays && r3_state(r, k, keep ? &snaps[k] : NULL, err)) st = RST_DAMAGED;
        *nsnaps += keep;
    }
    if (arrays && st == RST_OK && r->bnb) { /* the boundary's pieces: checked */
        void *scratch = sl_malloc((size_t)r->h.records * sizeof(double), "restart input");
        for (int j = 0; j < RST_BFIELDS && st == RST_OK; j++)
            for (size_t p = 0; p < r->bnb && st == RST_OK; p++)
                if (r3_bpiece(r, j, p, scratch, err)) st = RST_DAMAGED;
        free(scratch);
    }
    if (st == RST_OK) {
        void *to = ctrl ? ctrl : sl_malloc(r->h.ctrl_size ? (size_t)r->h.ctrl_size : 1, "restart");
        if (r3_member(r, r->t.ctrl_off, r->t.ctrl_len, r->t.ctrl_crc, to, (size_t)r->h.ctrl_size,
                      NULL, "its run state", err))
            st = RST_DAMAGED;
        if (!ctrl) free(to);
    }
    if (r != &open_) r3_close(r);
    else if (st != RST_OK) rst_scan_end();
    return st;
}

/* ---- either format ---- */

/* The file's format: 2, 3, or 0 with the status (and err) that refuses it. */
static int format_of(const char *path, rst_status *st, sl_err *err)
{
    char magic[16];
    errno = 0;
    gzFile g = gzopen(path, "rb");
    if (!g) {
        sl_err_set(err,
                   "cannot open restart file '%s': %s (was this time written by an older "
                   "Sluice, or by hand?)",
                   path, strerror(errno ? errno : ENOMEM));
        *st = RST_MISSING;
        return 0;
    }
    const int direct = gzdirect(g), got = direct ? 0 : gzread(g, magic, sizeof magic);
    int v = 0;
    *st = RST_DAMAGED;
    if (got != (int)sizeof magic) {
        int code;
        const char *msg = gzerror(g, &code);
        sl_err_set(err, "restart file '%s' is damaged (%s)", path,
                   direct                            ? "not a gzip stream"
                       : code != Z_OK && msg && *msg ? msg
                                                     : "it ends early");
    } else if (!memcmp(magic, RST_MAGIC2, sizeof magic)) v = 2;
    else if (!memcmp(magic, RST_MAGIC3, sizeof magic)) v = 3;
    else if (!memcmp(magic, RST_MAGIC4, sizeof magic)) v = 4;
    else if (!memcmp(magic, RST_FAMILY, strlen(RST_FAMILY))) {
        sl_err_set(err,
                   "restart file '%s' was written by another version of Sluice (format %.1s, "
                   "this one reads formats 2, 3 and 4)",
                   path, magic + strlen(RST_FAMILY));
        *st = RST_OTHER_VERSION;
    } else sl_err_set(err, "restart file '%s' is damaged (no Sluice restart header)", path);
    rst_count_gz(g);
    gzclose(g);
    if (v) *st = RST_OK;
    return v;
}

static rst_status read_file(const char *dir, pcs_snapshot *snaps, int max, int *nsnaps, void *ctrl,
                            size_t ctrl_size, int arrays, sl_err *err)
{
    char *path = rst_path(dir, 0, err);
    rst_status st;
    rst_scan_end();
    clock_start();
    const int v = format_of(path, &st, err);
    if (v >= 3) st = read3(path, snaps, max, nsnaps, ctrl, ctrl_size, arrays, err);
    else if (v == 2) {
        gzFile g = gzopen(path, "rb");
        st = g ? rst2_read(g, path, snaps, max, nsnaps, ctrl, ctrl_size, arrays, err) : RST_MISSING;
        if (!g) sl_err_set(err, "cannot open restart file '%s'", path);
        if (g) rst_count_gz(g), gzclose(g);
    }
    clock_stop();
    free(path);
    return st;
}

rst_status rst_read(const char *dir, pcs_snapshot *snaps, int max, int *nsnaps, void *ctrl,
                    size_t ctrl_size, sl_err *err)
{
    return read_file(dir, snaps, max, nsnaps, ctrl, ctrl_size, 1, err);
}

rst_status rst_probe(const char *dir, pcs_snapshot *snaps, int max, int *nsnaps, void *ctrl,
                     size_t ctrl_size, sl_err *err)
{
    return read_file(dir, snaps, max, nsnaps, ctrl, ctrl_size, 0, err);
}

/* rst_scan of a file of format 3: the selected blocks' pieces only. */
static int scan3(const char *path, const pcs_snapshot *snaps, int k, const rst_select *sel,
                 rst_chunk_fn fn, void *ctx, sl_err *err)
{
    if (!open_path_ || strcmp(open_path_, path)) {
        rst_scan_end();
        open_path_ = sl_malloc(strlen(path) + 1, "path");
        strcpy(open_path_, path);
        if (r3_open(&open_, open_path_, err) != RST_OK) {
            rst_scan_end();
            return 1;
        }
    }
    r3 *r = &open_;
    if ((size_t)k >= r->h.nsnaps || r->s[k].n != snaps[k].n) {
        damaged(r, err, "it changed since it was first read");
        rst_scan_end();
        return 1;
    }
    const size_t R = (size_t)r->h.records, n = (size_t)r->s[k].n, nb = r->nb[k];
    size_t b0 = 0, b1 = nb;
    if (sel && sel->parts > 1) {
        b0 = nb * (size_t)sel->part / (size_t)sel->parts;
        b1 = nb * (size_t)(sel->part + 1) / (size_t)sel->parts;
    }
    const int all = !sel || !sel->positions, nd = all ? (r->nf == RST_FIELDS ? 8 : 6) : 3;
    double *a[8] = {NULL};
    uint32_t *id = all ? sl_malloc(R * sizeof *id, "restart chunk") : NULL;
    for (int j = 0; j < nd; j++) a[j] = sl_malloc(R * sizeof *a[j], "restart chunk");
    int rc = 0;
    for (size_t p = b0; p < b1 && !rc; p++) {
        const size_t m = n - p * R < R ? n - p * R : R;
        if (sel && sel->box) {
            double lo[3], hi[3];
            for (int d = 0; d < 3; d++) {
                const rst3_entry *e = &r->e[r->base[k] + (size_t)d * nb + p];
                lo[d] = e->lo, hi[d] = e->hi;
            }
            if (!sel->box(ctx, lo, hi)) continue;
        }
        for (int j = 0; j < 3 && !rc; j++) rc = r3_piece(r, (size_t)k, j, p, a[j], err);
        if (rc) break;
        if (sel && sel->want) {
            size_t i = 0;
            while (i < m && !sel->want(ctx, a[0][i], a[1][i], a[2][i])) i++;
            if (i == m) continue;
        }
        for (int j = 3; j < 6 && all && !rc; j++) rc = r3_piece(r, (size_t)k, j, p, a[j], err);
        if (!rc && all) rc = r3_piece(r, (size_t)k, 6, p, id, err);
        for (int j = 6; j < nd && !rc; j++) rc = r3_piece(r, (size_t)k, j + 1, p, a[j], err);
        if (!rc) fn(ctx, m, (const double *const *)a, id);
    }
    for (int j = 0; j < 8; j++) free(a[j]);
    free(id);
    if (rc) rst_scan_end();
    return rc ? 1 : 0;
}

int rst_scan(const char *dir, const pcs_snapshot *snaps, int k, const rst_select *sel,
             rst_chunk_fn fn, void *ctx, sl_err *err)
{
    char *path = rst_path(dir, 0, err);
    rst_status st;
    clock_start();
    const int v = open_path_ && !strcmp(open_path_, path) ? 3 : format_of(path, &st, err);
    const int rc = v >= 3 ? scan3(path, snaps, k, sel, fn, ctx, err)
        : v == 2          ? rst2_scan(path, snaps, k, sel, fn, ctx, err)
                          : 1;
    clock_stop();
    free(path);
    return rc;
}

/* The boundary's records of a file of format 4, piece by piece. */
static int bscan3(const char *path, rst_bchunk_fn fn, void *ctx, size_t *n, sl_err *err)
{
    if (!open_path_ || strcmp(open_path_, path)) {
        rst_scan_end();
        open_path_ = sl_malloc(strlen(path) + 1, "path");
        strcpy(open_path_, path);
        if (r3_open(&open_, open_path_, err) != RST_OK) {
            rst_scan_end();
            return 1;
        }
    }
    r3 *r = &open_;
    const size_t R = (size_t)r->h.records;
    *n = (size_t)r->nbnd;
    uint32_t *id = sl_malloc(R * sizeof *id, "restart chunk");
    double *a[3];
    for (int j = 0; j < 3; j++) a[j] = sl_malloc(R * sizeof *a[j], "restart chunk");
    int rc = 0;
    for (size_t p = 0; p < r->bnb && !rc; p++) {
        const size_t m = *n - p * R < R ? *n - p * R : R;
        rc = r3_bpiece(r, 0, p, id, err);
        for (int j = 1; j < RST_BFIELDS && !rc; j++) rc = r3_bpiece(r, j, p, a[j - 1], err);
        if (!rc) fn(ctx, m, id, a[0], a[1], a[2]);
    }
    for (int j = 0; j < 3; j++) free(a[j]);
    free(id);
    if (rc) rst_scan_end();
    return rc ? 1 : 0;
}

int rst_scan_boundary(const char *dir, rst_bchunk_fn fn, void *ctx, size_t *n, sl_err *err)
{
    char *path = rst_path(dir, 0, err);
    rst_status st;
    clock_start();
    *n = 0;
    const int v = open_path_ && !strcmp(open_path_, path) ? 3 : format_of(path, &st, err);
    const int rc = v >= 3 ? bscan3(path, fn, ctx, n, err) : v == 2 ? 0 : 1;
    clock_stop();
    free(path);
    return rc;
}
