/* case_restart_v2: restart files of format 2 (see case_restart_v2.h). */
#include "case/case_restart_v2.h"
#include "core/sl_mem.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct rst_header {
    char magic[16];
    uint64_t nsnaps, ctrl_size;
} rst_header;

typedef struct rst_snap_header {
    uint64_t n;
    double time, dt;
    int64_t step;
} rst_snap_header;

static int put(gzFile g, const void *data, size_t bytes)
{
    const char *c = data;
    while (bytes > 0) {
        unsigned chunk = bytes > (1u << 30) ? 1u << 30 : (unsigned)bytes;
        if (gzwrite(g, c, chunk) != (int)chunk) return -1;
        c += chunk;
        bytes -= chunk;
    }
    return 0;
}

/* Read `bytes` (into data, or skipped when data is NULL); -1 on a short
 * read or a zlib error. */
static int get(gzFile g, void *data, size_t bytes)
{
    char *c = data, sink[4096];
    while (bytes > 0) {
        size_t room = data ? (size_t)1 << 30 : sizeof sink;
        unsigned chunk = (unsigned)(bytes > room ? room : bytes);
        if (gzread(g, data ? c : sink, chunk) != (int)chunk) return -1;
        if (data) c += chunk;
        bytes -= chunk;
    }
    return 0;
}

/* The pieces an array is written in (and read from its source in). */
#define RST_PIECE 65536

static int put_state(gzFile g, const rst_state *s, unsigned char *buf)
{
    rst_snap_header h = {s->n, s->time, s->dt, s->step};
    int rc = put(g, &h, sizeof h);
    for (int k = 0; k < 7 && !rc; k++) {
        const size_t bytes = s->n * (k < 6 ? sizeof(double) : sizeof(uint32_t));
        for (size_t off = 0; off < bytes && !rc; off += RST_PIECE) {
            const size_t len = bytes - off < RST_PIECE ? bytes - off : RST_PIECE;
            s->col[k].read(s->col[k].ctx, off, len, buf);
            rc = put(g, buf, len);
        }
    }
    return rc;
}

int rst2_write(const char *path, const rst_state *states, int nstates, const void *ctrl,
               size_t ctrl_size, sl_err *err)
{
    errno = 0;
    gzFile g = gzopen(path, "wb1");
    int rc = g ? 0 : -1;
    rst_header h;
    unsigned char *buf = sl_malloc(RST_PIECE, "restart output");
    memset(&h, 0, sizeof h);
    memcpy(h.magic, RST_MAGIC2, strlen(RST_MAGIC2));
    h.nsnaps = (uint64_t)nstates;
    h.ctrl_size = ctrl_size;
    if (!rc) rc = put(g, &h, sizeof h);
    for (int k = 0; k < nstates && !rc; k++) rc = put_state(g, &states[k], buf);
    if (!rc && ctrl_size) rc = put(g, ctrl, ctrl_size);
    if (g && gzclose(g) != Z_OK) rc = -1;
    if (rc) sl_err_set(err, "cannot write '%s': %s", path, strerror(errno ? errno : EIO));
    free(buf);
    return rc ? 1 : 0;
}

/* zlib's reason for the last failure, or "it ends early". */
static const char *why(gzFile g)
{
    int code;
    const char *msg = gzerror(g, &code);
    return code != Z_OK && msg && *msg ? msg : "it ends early";
}

/* One snapshot: into s (keep; 2: its header only, the arrays skipped) or
 * skipped. */
static int get_snapshot(gzFile g, pcs_snapshot *s, int keep)
{
    rst_snap_header h;
    if (get(g, &h, sizeof h) || h.n > ((uint64_t)1 << 34)) return -1;
    const size_t n = (size_t)h.n, bytes = n * sizeof(double);
    if (keep == 2) {
        s->n = n;
        s->time = h.time;
        s->dt = h.dt;
        s->step = (long)h.step;
        s->carried = 0;
    }
    if (keep != 1) return get(g, NULL, 6 * bytes + n * sizeof(uint32_t));
    sl_fluid tmp;
    prt_fluid_init(&tmp); /* grow the snapshot's buffers through a take of an empty fluid */
    tmp.n = n;
    prt_fluid_reserve(&tmp, n ? n : 1);
    snap_take(s, &tmp, h.time, h.dt, (long)h.step);
    prt_fluid_free(&tmp);
    double *a[6] = {s->x, s->y, s->z, s->vx, s->vy, s->vz};
    s->carried = 0; /* no p, rho in this format */
    if (n) memset(s->p, 0, bytes), memset(s->rho, 0, bytes);
    int rc = 0;
    for (int k = 0; k < 6 && !rc; k++) rc = get(g, a[k], bytes);
    if (!rc) rc = get(g, s->id, n * sizeof *s->id);
    return rc;
}

rst_status rst2_read(gzFile g, const char *path, pcs_snapshot *snaps, int max, int *nsnaps,
                     void *ctrl, size_t ctrl_size, int arrays, sl_err *err)
{
    rst_header h;
    char tail;
    if (gzdirect(g) || get(g, &h, sizeof h)) {
        sl_err_set(err, "restart file '%s' is damaged (%s)", path,
                   gzdirect(g) ? "not a gzip stream" : why(g));
        return RST_DAMAGED;
    }
    if (h.nsnaps < 1 || h.nsnaps > RST_MAX_SNAPSHOTS) {
        sl_err_set(err, "restart file '%s' is damaged (%llu states)", path,
                   (unsigned long long)h.nsnaps);
        return RST_DAMAGED;
    }
    if (ctrl && h.ctrl_size != ctrl_size) {
        sl_err_set(err,
                   "restart file '%s' was written for a different case (%llu bytes of run "
                   "state, this case has %zu: emitters added or removed?)",
                   path, (unsigned long long)h.ctrl_size, ctrl_size);
        return RST_MISMATCH;
    }
    *nsnaps = 0;
    for (uint64_t k = 0; k < h.nsnaps; k++) {
        int keep = (int)k < max;
        if (get_snapshot(g, keep ? &snaps[k] : NULL, keep ? (arrays ? 1 : 2) : 0)) {
            sl_err_set(err, "restart file '%s' is damaged (%s)", path, why(g));
            return RST_DAMAGED;
        }
        *nsnaps += keep;
    }
    /* the rest, then the end: zlib checks the trailer's CRC-32 and length */
    int more = get(g, ctrl, (size_t)h.ctrl_size) ? -1 : gzread(g, &tail, 1);
    if (more != 0) {
        sl_err_set(err, "restart file '%s' is damaged (%s)", path,
                   more < 0 ? why(g) : "data after its end");
        return RST_DAMAGED;
    }
    return RST_OK;
}

/* Where snapshot k's arrays start in the uncompressed file. */
static uint64_t snapshot_offset(const pcs_snapshot *snaps, int k)
{
    uint64_t off = sizeof(rst_header);
    for (int q = 0; q < k; q++)
        off += sizeof(rst_snap_header) + (uint64_t)snaps[q].n * (6 * sizeof(double) + 4);
    return off + sizeof(rst_snap_header);
}

int rst2_scan(const char *path, const pcs_snapshot *snaps, int k, const rst_select *sel,
              rst_chunk_fn fn, void *ctx, sl_err *err)
{
    const int F = sel && sel->positions ? 3 : 7; /* streams: x, y, z, or every field */
    const size_t n = snaps[k].n, nb = (n + RST_RECORDS - 1) / RST_RECORDS;
    size_t r0 = 0, r1 = n; /* the records of the part */
    if (sel && sel->parts > 1) {
        r0 = nb * (size_t)sel->part / (size_t)sel->parts * RST_RECORDS;
        r1 = nb * (size_t)(sel->part + 1) / (size_t)sel->parts * RST_RECORDS;
        if (r1 > n) r1 = n;
        if (r0 > r1) r0 = r1;
    }
    const uint64_t at = snapshot_offset(snaps, k);
    gzFile g[7] = {NULL};
    double *a[6] = {NULL};
    uint32_t *id = F == 7 ? sl_malloc(RST_CHUNK * sizeof *id, "restart chunk") : NULL;
    for (int j = 0; j < (F == 7 ? 6 : 3); j++)
        a[j] = sl_malloc(RST_CHUNK * sizeof *a[j], "restart chunk");
    int rc = 0;
    for (int j = 0; j < F && !rc; j++) { /* one stream per field, at its first value */
        g[j] = gzopen(path, "rb");
        const z_off_t off = (z_off_t)(at + (uint64_t)j * n * sizeof(double));
        if (!g[j] || gzseek(g[j], off, SEEK_SET) != off) rc = -1;
    }
    for (size_t i = 0; i < r1 && !rc; i += RST_CHUNK) {
        const size_t m = r1 - i < RST_CHUNK ? r1 - i : RST_CHUNK;
        for (int j = 0; j < F && j < 6 && !rc; j++) rc = get(g[j], a[j], m * sizeof(double));
        if (!rc && F == 7) rc = get(g[6], id, m * sizeof *id);
        if (rc || i + m <= r0) continue;
        const size_t s = i < r0 ? r0 - i : 0; /* the part's first record in this chunk */
        const double *b[8] = {NULL};
        for (int j = 0; j < 6; j++) b[j] = a[j] ? a[j] + s : NULL;
        fn(ctx, m - s, b, id ? id + s : NULL);
    }
    if (rc) sl_err_set(err, "restart file '%s' is damaged (%s)", path, g[0] ? why(g[0]) : "");
    for (int j = 0; j < F; j++)
        if (g[j]) {
            rst_count_gz(g[j]);
            gzclose(g[j]);
        }
    for (int j = 0; j < 6; j++) free(a[j]);
    free(id);
    return rc ? 1 : 0;
}
