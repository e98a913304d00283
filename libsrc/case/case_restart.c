/* case_restart: the restart file <time>/uniform/restart (see case_restart.h). */
#include "case/case_restart.h"
#include "core/sl_mem.h"
#include "io/time_dir.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#define RST_MAGIC "SLUICE-RESTART-1"

typedef struct rst_header {
    char magic[16];
    uint64_t n, ctrl_size;
    double time, dt;
    int64_t step;
} rst_header;

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

static int get(gzFile g, void *data, size_t bytes)
{
    char *c = data;
    while (bytes > 0) {
        unsigned chunk = bytes > (1u << 30) ? 1u << 30 : (unsigned)bytes;
        if (gzread(g, c, chunk) != (int)chunk) return -1;
        c += chunk;
        bytes -= chunk;
    }
    return 0;
}

int rst_write(const char *dir, const pcs_snapshot *s, const void *ctrl, size_t ctrl_size,
              sl_err *err)
{
    char *path = rst_path(dir, 1, err);
    if (!path) return 1;
    gzFile g = gzopen(path, "wb1");
    int rc = g ? 0 : -1;
    rst_header h;
    memset(&h, 0, sizeof h);
    memcpy(h.magic, RST_MAGIC, sizeof h.magic);
    h.n = s->n;
    h.ctrl_size = ctrl_size;
    h.time = s->time;
    h.dt = s->dt;
    h.step = s->step;
    const size_t bytes = s->n * sizeof(double);
    if (!rc) rc = put(g, &h, sizeof h);
    const double *a[6] = {s->x, s->y, s->z, s->vx, s->vy, s->vz};
    for (int k = 0; k < 6 && !rc; k++) rc = put(g, a[k], bytes);
    if (!rc) rc = put(g, s->id, s->n * sizeof *s->id);
    if (!rc && ctrl_size) rc = put(g, ctrl, ctrl_size);
    if (g && gzclose(g) != Z_OK) rc = -1;
    if (rc) sl_err_set(err, "cannot write '%s': %s", path, strerror(errno ? errno : EIO));
    free(path);
    return rc ? 1 : 0;
}

int rst_read(const char *dir, pcs_snapshot *s, void *ctrl, size_t ctrl_size, sl_err *err)
{
    char *path = rst_path(dir, 0, err);
    gzFile g = gzopen(path, "rb");
    rst_header h;
    int rc = 0;
    if (!g) {
        sl_err_set(err, "cannot open restart file '%s': %s (was this time written by an older "
                        "Sluice, or by hand?)", path, strerror(errno));
        free(path);
        return 1;
    }
    if (get(g, &h, sizeof h) || memcmp(h.magic, RST_MAGIC, sizeof h.magic) ||
        h.ctrl_size != ctrl_size || h.n > ((uint64_t)1 << 34)) {
        sl_err_set(err, "'%s' is not a restart file of this version of Sluice", path);
        rc = 1;
    }
    if (!rc) {
        sl_fluid tmp;
        prt_fluid_init(&tmp);
        tmp.n = (size_t)h.n;
        /* grow the snapshot's buffers through a take of an empty fluid */
        prt_fluid_reserve(&tmp, (size_t)h.n ? (size_t)h.n : 1);
        snap_take(s, &tmp, h.time, h.dt, (long)h.step);
        prt_fluid_free(&tmp);
        const size_t bytes = (size_t)h.n * sizeof(double);
        double *a[6] = {s->x, s->y, s->z, s->vx, s->vy, s->vz};
        for (int k = 0; k < 6 && !rc; k++) rc = get(g, a[k], bytes);
        if (!rc) rc = get(g, s->id, (size_t)h.n * sizeof *s->id);
        if (!rc && ctrl_size) rc = get(g, ctrl, ctrl_size);
        if (rc) sl_err_set(err, "restart file '%s' is truncated or corrupt", path);
    }
    gzclose(g);
    free(path);
    return rc ? 1 : 0;
}
