/*
 * test_restart: the restart file (libsrc/case/case_restart.h).
 *
 * Format 4 (pieces of RST_RECORDS records with an index; the pressure and
 * density carried between steps, and the boundary's pressure, p / rho^2
 * and density): a round trip of two states whose lengths are not
 * multiples of a piece, and of a boundary, the same bytes however the
 * writer's sources hand out the data, every selection of rst_scan (parts,
 * positions only, a box and a wanted set) against the whole state; files
 * of formats 2 and 3 (the old writers, SLUICE_RESTART_FORMAT=2 and 3) read
 * by every reader, without carried values; a damaged piece (of a state,
 * of the boundary), a damaged index, a truncated file and a file with
 * bytes appended refused as damaged, naming the file; an empty state;
 * what a part of the records costs to read (bytes counted).
 * Run from the repository root; scratch files in tests/output/test_restart.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "case/case_restart.h"
#include "core/sl_log.h"
#include "io/time_dir.h"
#include "solver/pcs_snapshot.h"

#define N0 20000 /* 3 pieces, the last partial */
#define N1 8191  /* one piece, short by one */

static const char *root_ = "tests/output/test_restart";

typedef struct fixture {
    pcs_snapshot s[2];
    unsigned char ctrl[300];
    sl_boundary b; /* NB boundary particles */
} fixture;

#define NB 9000 /* two pieces */

/* State k: positions spread over a box, sorted along x by block (as the
 * solver's cell order makes them), velocities, a NaN, shuffled ids. */
static void make_state(pcs_snapshot *s, size_t n, int k)
{
    snap_init(s);
    snap_resize(s, n);
    s->time = 0.25 + k;
    s->dt = 1e-3 / (k + 1);
    s->step = 100 + k;
    for (size_t i = 0; i < n; i++) {
        s->x[i] = (double)i / (double)n + 1e-7 * (double)(i % 13);
        s->y[i] = sin(0.001 * (double)i) + k;
        s->z[i] = cos(0.002 * (double)i);
        s->vx[i] = 1e-3 * (double)(i % 101) - 0.05;
        s->vy[i] = -0.5 * s->vx[i];
        s->vz[i] = (double)k;
        s->id[i] = (uint32_t)((i * 7919u) % n);
        s->p[i] = i % 3 ? 0.0 : 100.0 * (double)i + k;
        s->rho[i] = 1000.0 + 1e-3 * (double)(i % 977);
    }
    s->carried = 1;
    if (n > 5) s->vz[5] = NAN;
}

/* A boundary of n particles: ids shuffled, pressures, p / rho^2, densities. */
static void make_boundary(sl_boundary *b, size_t n)
{
    prt_boundary_init(b);
    for (size_t i = 0; i < n; i++) {
        prt_boundary_push(b, 0.01 * (double)i, 0.0, 0.0, 0.0, 0.0, 1.0, 0);
        b->id[i] = (uint32_t)((i * 7907u) % n);
        b->rho[i] = i % 5 ? 0.0 : 1000.0 + 1e-4 * (double)i;
        b->p[i] = i % 5 ? 0.0 : 3.0 * (double)i;
        b->pt[i] = b->rho[i] > 0 ? b->p[i] / (b->rho[i] * b->rho[i]) : 0.0;
    }
}

static void fixture_make(fixture *f)
{
    make_state(&f->s[0], N0, 0);
    make_state(&f->s[1], N1, 1);
    make_boundary(&f->b, NB);
    for (size_t i = 0; i < sizeof f->ctrl; i++) f->ctrl[i] = (unsigned char)(i * 37u);
}

static void fixture_free(fixture *f)
{
    snap_free(&f->s[0]);
    snap_free(&f->s[1]);
    prt_boundary_free(&f->b);
}

static void dir_of(const char *name, char *buf, size_t size)
{
    sl_err err;
    snprintf(buf, size, "%s/%s", root_, name);
    assert_int_equal(tdir_mkdirs(buf, &err), 0);
}

static void file_of(const char *dir, char *buf, size_t size)
{
    snprintf(buf, size, "%s/uniform/restart", dir);
}

static void write_fixture(const fixture *f, const char *dir, const char *format)
{
    sl_err err;
    rst_state st[2];
    rst_bstate bs;
    rst_state_of(&st[0], &f->s[0]);
    rst_state_of(&st[1], &f->s[1]);
    rst_bstate_of(&bs, &f->b);
    if (format) setenv("SLUICE_RESTART_FORMAT", format, 1);
    const int rc = rst_write_states(dir, st, 2, &bs, f->ctrl, sizeof f->ctrl, &err);
    unsetenv("SLUICE_RESTART_FORMAT");
    if (rc) fail_msg("%s", err.msg);
}

/* ---- the boundary's records ---- */

typedef struct bcollect {
    size_t n, chunks;
    uint32_t id[NB];
    double p[NB], pt[NB], rho[NB];
} bcollect;

static void bcollect_chunk(void *ctx, size_t n, const uint32_t *id, const double *p,
                           const double *pt, const double *rho)
{
    bcollect *c = ctx;
    c->chunks++;
    assert_true(n > 0 && n <= RST_RECORDS && c->n + n <= NB);
    memcpy(c->id + c->n, id, n * sizeof *id);
    memcpy(c->p + c->n, p, n * sizeof *p);
    memcpy(c->pt + c->n, pt, n * sizeof *pt);
    memcpy(c->rho + c->n, rho, n * sizeof *rho);
    c->n += n;
}

/* rst_scan_boundary hands out the boundary written (format 4), or
 * nothing (formats 2 and 3). */
static void check_boundary(const fixture *f, const char *dir, int format)
{
    sl_err err;
    static bcollect c;
    size_t n = 1;
    memset(&c, 0, sizeof c);
    if (rst_scan_boundary(dir, bcollect_chunk, &c, &n, &err)) fail_msg("%s", err.msg);
    rst_scan_end();
    if (format < 4) {
        assert_int_equal(n, 0);
        assert_int_equal(c.chunks, 0);
        return;
    }
    assert_int_equal(n, NB);
    assert_int_equal(c.n, NB);
    assert_int_equal(c.chunks, 2);
    assert_memory_equal(c.id, f->b.id, NB * sizeof *c.id);
    assert_memory_equal(c.p, f->b.p, NB * sizeof *c.p);
    assert_memory_equal(c.pt, f->b.pt, NB * sizeof *c.pt);
    assert_memory_equal(c.rho, f->b.rho, NB * sizeof *c.rho);
}

static long file_size(const char *path)
{
    struct stat sb;
    assert_int_equal(stat(path, &sb), 0);
    return (long)sb.st_size;
}

static unsigned char *slurp(const char *path, long *size)
{
    *size = file_size(path);
    unsigned char *b = malloc((size_t)*size + 1);
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    assert_int_equal(fread(b, 1, (size_t)*size, fp), (size_t)*size);
    fclose(fp);
    return b;
}

static void spit(const char *path, const unsigned char *b, long size)
{
    FILE *fp = fopen(path, "wb");
    assert_non_null(fp);
    assert_int_equal(fwrite(b, 1, (size_t)size, fp), (size_t)size);
    fclose(fp);
}

/* The whole file read back equals what was written (formats 2 and 3:
 * without p and rho, which read as 0). */
static void check_read(const fixture *f, const char *dir, int format)
{
    sl_err err;
    pcs_snapshot got[2];
    unsigned char ctrl[sizeof f->ctrl];
    int n = 0;
    snap_init(&got[0]), snap_init(&got[1]);
    rst_status st = rst_read(dir, got, 2, &n, ctrl, sizeof ctrl, &err);
    if (st != RST_OK) fail_msg("%s", err.msg);
    assert_int_equal(n, 2);
    for (int k = 0; k < 2; k++) {
        pcs_snapshot want = f->s[k]; /* its arrays, carried as the format holds them */
        want.carried = format >= 4;
        assert_int_equal(got[k].carried, want.carried);
        assert_true(snap_equal(&got[k], &want));
        assert_true(got[k].time == f->s[k].time && got[k].dt == f->s[k].dt);
        assert_int_equal(got[k].step, f->s[k].step);
        for (size_t i = 0; format < 4 && i < got[k].n; i++)
            assert_true(got[k].p[i] == 0.0 && got[k].rho[i] == 0.0);
    }
    assert_memory_equal(ctrl, f->ctrl, sizeof ctrl);
    /* another case's run state is refused */
    assert_int_equal(rst_read(dir, got, 2, &n, ctrl, sizeof ctrl - 1, &err), RST_MISMATCH);
    /* checked only (listTimes -check) */
    assert_int_equal(rst_read(dir, NULL, 0, &n, NULL, 0, &err), RST_OK);
    snap_free(&got[0]), snap_free(&got[1]);
}

/* ---- rst_scan: what a selection hands out ---- */

typedef struct collect {
    pcs_snapshot out;
    size_t chunks, calls;
    int positions;
    int carried; /* p and rho handed out */
    double xcut; /* want: records with x < xcut */
} collect;

static void collect_chunk(void *ctx, size_t n, const double *const a[8], const uint32_t *id)
{
    collect *c = ctx;
    c->chunks++;
    assert_true(n > 0 && n <= RST_CHUNK);
    c->carried = a[6] != NULL;
    assert_true((a[6] == NULL) == (a[7] == NULL));
    for (size_t i = 0; i < n; i++) {
        if (c->positions) {
            assert_null(a[3]), assert_null(id), assert_null(a[6]);
            snap_push(&c->out, a[0][i], a[1][i], a[2][i], 0, 0, 0, 0);
        } else {
            snap_push(&c->out, a[0][i], a[1][i], a[2][i], a[3][i], a[4][i], a[5][i], id[i]);
            if (a[6]) c->out.p[c->out.n - 1] = a[6][i], c->out.rho[c->out.n - 1] = a[7][i];
        }
    }
}

static int want_left(void *ctx, double x, double y, double z)
{
    (void)y, (void)z;
    ((collect *)ctx)->calls++;
    return x < ((collect *)ctx)->xcut;
}

static int box_left(void *ctx, const double lo[3], const double hi[3])
{
    (void)hi;
    return lo[0] < ((collect *)ctx)->xcut;
}

static void scan_into(const char *dir, const pcs_snapshot *heads, int k, const rst_select *sel,
                      collect *c)
{
    sl_err err;
    snap_init(&c->out);
    c->chunks = c->calls = 0;
    c->positions = sel && sel->positions;
    if (rst_scan(dir, heads, k, sel, collect_chunk, c, &err)) fail_msg("%s", err.msg);
}

/* Records [i0, i0 + n) of c's output are s's [j0, j0 + n). */
static void assert_records(const collect *c, size_t i0, const pcs_snapshot *s, size_t j0, size_t n,
                           int positions)
{
    const double *a[6] = {c->out.x, c->out.y, c->out.z, c->out.vx, c->out.vy, c->out.vz};
    const double *b[6] = {s->x, s->y, s->z, s->vx, s->vy, s->vz};
    for (int j = 0; j < (positions ? 3 : 6); j++)
        assert_memory_equal(a[j] + i0, b[j] + j0, n * sizeof(double));
    if (!positions) assert_memory_equal(c->out.id + i0, s->id + j0, n * sizeof(uint32_t));
    if (!positions && c->carried) {
        assert_memory_equal(c->out.p + i0, s->p + j0, n * sizeof(double));
        assert_memory_equal(c->out.rho + i0, s->rho + j0, n * sizeof(double));
    }
}

static void check_scans(const fixture *f, const char *dir, int format)
{
    sl_err err;
    pcs_snapshot heads[2];
    unsigned char ctrl[sizeof f->ctrl];
    int n = 0;
    snap_init(&heads[0]), snap_init(&heads[1]);
    assert_int_equal(rst_probe(dir, heads, 2, &n, ctrl, sizeof ctrl, &err), RST_OK);
    assert_int_equal(n, 2);
    assert_int_equal(heads[0].n, N0);
    assert_int_equal(heads[1].n, N1);
    assert_null(heads[0].x);
    assert_memory_equal(ctrl, f->ctrl, sizeof ctrl);
    assert_int_equal(heads[0].carried, format >= 4);
    collect c;
    for (int k = 0; k < 2; k++) { /* every record, every field */
        scan_into(dir, heads, k, NULL, &c);
        assert_int_equal(c.out.n, f->s[k].n);
        assert_int_equal(c.carried, format >= 4);
        assert_records(&c, 0, &f->s[k], 0, f->s[k].n, 0);
        snap_free(&c.out);
    }
    /* parts of 1, 2, 3 and 5 ranks: positions of every record once, in order */
    for (int parts = 1; parts <= 5; parts += parts == 3 ? 2 : 1) {
        size_t at = 0;
        for (int part = 0; part < parts; part++) {
            rst_select sel = {.positions = 1, .part = part, .parts = parts};
            scan_into(dir, heads, 0, &sel, &c);
            assert_records(&c, 0, &f->s[0], at, c.out.n, 1);
            at += c.out.n;
            snap_free(&c.out);
        }
        assert_int_equal(at, N0);
    }
    /* a box and a wanted set: every wanted record is handed out, with its
     * block; format 3 hands out only the blocks holding one */
    collect w = {.xcut = 0.3};
    rst_select sel = {.box = box_left, .want = want_left};
    scan_into(dir, heads, 0, &sel, &w);
    size_t wanted = 0;
    for (size_t i = 0; i < N0; i++) wanted += f->s[0].x[i] < 0.3;
    size_t seen = 0;
    for (size_t i = 0; i < w.out.n; i++) seen += w.out.x[i] < 0.3;
    assert_int_equal(seen, wanted);
    if (format >= 3) {
        assert_int_equal(w.out.n, RST_RECORDS); /* the first block only: x < 0.3 is in it */
        assert_records(&w, 0, &f->s[0], 0, RST_RECORDS, 0);
        assert_true(w.calls <= 2 * RST_RECORDS); /* the second block refused by its box */
    } else assert_int_equal(w.out.n, N0);        /* format 2: every record */
    snap_free(&w.out);
}

/* ---- the tests ---- */

static void test_round_trip(void **state)
{
    (void)state;
    fixture f;
    char dir[256], path[300];
    fixture_make(&f);
    dir_of("v4", dir, sizeof dir);
    write_fixture(&f, dir, NULL);
    check_read(&f, dir, 4);
    check_scans(&f, dir, 4);
    check_boundary(&f, dir, 4);
    /* written again: the same bytes */
    file_of(dir, path, sizeof path);
    long s1, s2;
    unsigned char *a = slurp(path, &s1);
    write_fixture(&f, dir, "4");
    unsigned char *b = slurp(path, &s2);
    assert_int_equal(s1, s2);
    assert_memory_equal(a, b, (size_t)s1);
    free(a), free(b);
    /* a whole gzip file: gzip -t checks every member */
    char cmd[400];
    snprintf(cmd, sizeof cmd, "gzip -t %.300s", path);
    assert_int_equal(system(cmd), 0);
    fixture_free(&f);
}

/* The writer's sources hand out bytes in whatever pieces the writer asks
 * for; a source that copies from a window refilled at odd lengths (as the
 * streamed output's is, from the ranks) gives the same file. */
typedef struct window_src {
    const unsigned char *data;
    unsigned char win[1000];
    size_t w0, wn, reads;
} window_src;

static void window_read(void *ctx, size_t off, size_t len, void *out)
{
    window_src *w = ctx;
    unsigned char *o = out;
    w->reads++;
    while (len) {
        if (off < w->w0 || off >= w->w0 + w->wn) {
            w->w0 = off;
            w->wn = 777;
            memcpy(w->win, w->data + off, w->wn); /* past the end: the arrays have room */
        }
        const size_t take = len < w->w0 + w->wn - off ? len : w->w0 + w->wn - off;
        memcpy(o, w->win + (off - w->w0), take);
        o += take, off += take, len -= take;
    }
}

static void test_same_bytes_any_source(void **state)
{
    (void)state;
    fixture f;
    char d1[256], d2[256], p1[300], p2[300];
    sl_err err;
    fixture_make(&f);
    dir_of("src1", d1, sizeof d1);
    dir_of("src2", d2, sizeof d2);
    write_fixture(&f, d1, NULL);
    rst_state st[2];
    rst_bstate bs;
    static window_src w[3][RST_FIELDS];
    for (int k = 0; k < 2; k++) {
        /* room past the end for the window's over-read */
        pcs_snapshot *s = &f.s[k];
        const void *a[RST_FIELDS] = {s->x, s->y, s->z, s->vx, s->vy, s->vz, s->id, s->p, s->rho};
        st[k].n = s->n, st[k].time = s->time, st[k].dt = s->dt, st[k].step = s->step;
        for (int j = 0; j < RST_FIELDS; j++) {
            const size_t bytes = s->n * (j != 6 ? 8 : 4);
            unsigned char *copy = calloc(bytes + 1000, 1);
            memcpy(copy, a[j], bytes);
            w[k][j] = (window_src){.data = copy};
            st[k].col[j] = (sl_source){window_read, &w[k][j], NULL};
        }
    }
    const void *ba[RST_BFIELDS] = {f.b.id, f.b.p, f.b.pt, f.b.rho};
    bs.n = f.b.n;
    for (int j = 0; j < RST_BFIELDS; j++) {
        const size_t bytes = f.b.n * (j ? 8 : 4);
        unsigned char *copy = calloc(bytes + 1000, 1);
        memcpy(copy, ba[j], bytes);
        w[2][j] = (window_src){.data = copy};
        bs.col[j] = (sl_source){window_read, &w[2][j], NULL};
    }
    assert_int_equal(rst_write_states(d2, st, 2, &bs, f.ctrl, sizeof f.ctrl, &err), 0);
    file_of(d1, p1, sizeof p1);
    file_of(d2, p2, sizeof p2);
    long s1, s2;
    unsigned char *a = slurp(p1, &s1), *b = slurp(p2, &s2);
    assert_int_equal(s1, s2);
    assert_memory_equal(a, b, (size_t)s1);
    free(a), free(b);
    for (int k = 0; k < 2; k++)
        for (int j = 0; j < RST_FIELDS; j++) free((void *)w[k][j].data);
    for (int j = 0; j < RST_BFIELDS; j++) free((void *)w[2][j].data);
    fixture_free(&f);
}

/* A file of format 3 (SLUICE_RESTART_FORMAT=3: no carried values, no
 * boundary): read by rst_read, rst_probe and rst_scan as before, carried
 * 0, p and rho 0, no boundary records; smaller than format 4's. */
static void test_format3(void **state)
{
    (void)state;
    fixture f;
    char dir[256], d4[256], path[300], p4[300];
    fixture_make(&f);
    dir_of("v3", dir, sizeof dir);
    dir_of("v3as4", d4, sizeof d4);
    write_fixture(&f, dir, "3");
    write_fixture(&f, d4, NULL);
    file_of(dir, path, sizeof path);
    file_of(d4, p4, sizeof p4);
    char cmd[700];
    snprintf(cmd, sizeof cmd, "zcat %s | head -c 16 | grep -q SLUICE-RESTART-3", path);
    assert_int_equal(system(cmd), 0);
    snprintf(cmd, sizeof cmd, "zcat %s | head -c 16 | grep -q SLUICE-RESTART-4", p4);
    assert_int_equal(system(cmd), 0);
    print_message("format 3: %ld bytes, format 4: %ld bytes\n", file_size(path), file_size(p4));
    assert_true(file_size(path) < file_size(p4));
    check_read(&f, dir, 3);
    check_scans(&f, dir, 3);
    check_boundary(&f, dir, 3);
    fixture_free(&f);
}

/* A file of format 2 (the writer of before, kept): read by rst_read,
 * rst_probe and rst_scan (parts too) as before. */
static void test_old_format(void **state)
{
    (void)state;
    fixture f;
    char dir[256], path[300];
    fixture_make(&f);
    dir_of("v2", dir, sizeof dir);
    write_fixture(&f, dir, "2");
    file_of(dir, path, sizeof path);
    unsigned char magic[16];
    char cmd[700];
    snprintf(cmd, sizeof cmd, "zcat %s | head -c 16 > %s.magic", path, path);
    assert_int_equal(system(cmd), 0);
    snprintf(cmd, sizeof cmd, "%s.magic", path);
    FILE *fp = fopen(cmd, "rb");
    assert_non_null(fp);
    assert_int_equal(fread(magic, 1, 16, fp), 16);
    fclose(fp);
    assert_memory_equal(magic, "SLUICE-RESTART-2", 16);
    check_read(&f, dir, 2);
    check_scans(&f, dir, 2);
    check_boundary(&f, dir, 2);
    sl_err err;
    setenv("SLUICE_RESTART_FORMAT", "7", 1);
    const pcs_snapshot *snaps[1] = {&f.s[0]};
    assert_int_equal(rst_write(dir, snaps, 1, f.ctrl, sizeof f.ctrl, &err), 1);
    unsetenv("SLUICE_RESTART_FORMAT");
    assert_non_null(strstr(err.msg, "SLUICE_RESTART_FORMAT=7"));
    fixture_free(&f);
}

/* Every reader refuses the damaged file as damaged, naming it. */
static void assert_refused(const char *dir, const char *path, const char *what)
{
    sl_err err;
    pcs_snapshot got[2];
    unsigned char ctrl[300];
    int n = 0;
    snap_init(&got[0]), snap_init(&got[1]);
    rst_status st = rst_read(dir, got, 2, &n, ctrl, sizeof ctrl, &err);
    print_message("%s: %s\n", what, err.msg);
    assert_int_equal(st, RST_DAMAGED);
    assert_non_null(strstr(err.msg, path));
    assert_non_null(strstr(err.msg, "damaged"));
    snap_free(&got[0]), snap_free(&got[1]);
}

/* One byte of the middle of a piece inverted: rst_read refuses it; the
 * probe (head, index, run state) does not read the piece, a scan of its
 * state does and refuses it; a scan of the other parts does not meet it. */
static void test_damaged_piece(void **state)
{
    (void)state;
    fixture f;
    char dir[256], path[300];
    sl_err err;
    fixture_make(&f);
    dir_of("damaged", dir, sizeof dir);
    write_fixture(&f, dir, NULL);
    file_of(dir, path, sizeof path);
    long size;
    unsigned char *b = slurp(path, &size);
    b[size / 3] = (unsigned char)~b[size / 3]; /* inside state 1's pieces */
    spit(path, b, size);
    free(b);
    assert_refused(dir, path, "a piece");
    pcs_snapshot heads[2];
    int n = 0;
    snap_init(&heads[0]), snap_init(&heads[1]);
    assert_int_equal(rst_probe(dir, heads, 2, &n, NULL, 0, &err), RST_OK);
    collect c;
    snap_init(&c.out);
    c.positions = 0;
    int failed = rst_scan(dir, heads, 0, NULL, collect_chunk, &c, &err);
    assert_int_equal(failed, 1);
    print_message("scan: %s\n", err.msg);
    assert_non_null(strstr(err.msg, path));
    assert_non_null(strstr(err.msg, "damaged"));
    assert_non_null(strstr(err.msg, "state 1, field"));
    snap_free(&c.out);
    collect d;
    scan_into(dir, heads, 1, NULL, &d); /* the other state is whole */
    assert_records(&d, 0, &f.s[1], 0, N1, 0);
    snap_free(&d.out);
    fixture_free(&f);
}

/* One byte of the boundary's pieces inverted (of a file of one state the
 * last pieces, just before the index, which the tail locates: its
 * payload's third field): rst_read refuses the file, the probe and the
 * state's scan do not read them, rst_scan_boundary refuses them, naming
 * the file and the boundary. */
static void test_damaged_boundary(void **state)
{
    (void)state;
    fixture f;
    char dir[256], path[300];
    sl_err err;
    fixture_make(&f);
    dir_of("bdamaged", dir, sizeof dir);
    rst_state st;
    rst_bstate bs;
    rst_state_of(&st, &f.s[0]);
    rst_bstate_of(&bs, &f.b);
    if (rst_write_states(dir, &st, 1, &bs, f.ctrl, sizeof f.ctrl, &err)) fail_msg("%s", err.msg);
    file_of(dir, path, sizeof path);
    long size;
    unsigned char *b = slurp(path, &size);
    uint64_t index_off; /* tail payload: magic[16], head_len, index_off, ... (80 bytes) */
    memcpy(&index_off, b + size - 8 - 80 + 16 + 8, sizeof index_off);
    assert_true(index_off > 100 && (long)index_off < size);
    const long at = (long)index_off - 20; /* inside the boundary's last piece (rho) */
    b[at] = (unsigned char)~b[at];
    spit(path, b, size);
    free(b);
    assert_refused(dir, path, "a boundary piece");
    pcs_snapshot heads[2];
    int n = 0;
    snap_init(&heads[0]), snap_init(&heads[1]);
    assert_int_equal(rst_probe(dir, heads, 2, &n, NULL, 0, &err), RST_OK);
    assert_int_equal(n, 1);
    collect c;
    scan_into(dir, heads, 0, NULL, &c);
    assert_records(&c, 0, &f.s[0], 0, N0, 0);
    snap_free(&c.out);
    static bcollect bc;
    size_t nb = 0;
    memset(&bc, 0, sizeof bc);
    assert_int_equal(rst_scan_boundary(dir, bcollect_chunk, &bc, &nb, &err), 1);
    print_message("boundary scan: %s\n", err.msg);
    assert_non_null(strstr(err.msg, path));
    assert_non_null(strstr(err.msg, "damaged (boundary, field"));
    rst_scan_end();
    fixture_free(&f);
}

/* The end of the file: truncated by one byte, by half, to the head only,
 * bytes appended, the index or the tail damaged. */
static void test_truncated_and_tail(void **state)
{
    (void)state;
    fixture f;
    char dir[256], path[300];
    fixture_make(&f);
    dir_of("truncated", dir, sizeof dir);
    write_fixture(&f, dir, NULL);
    file_of(dir, path, sizeof path);
    long size;
    unsigned char *b = slurp(path, &size);
    const long cut[] = {size - 1, size / 2, 60};
    for (int i = 0; i < 3; i++) {
        spit(path, b, cut[i]);
        assert_refused(dir, path, "truncated");
        sl_err err;
        pcs_snapshot heads[2];
        int n;
        snap_init(&heads[0]), snap_init(&heads[1]);
        assert_int_equal(rst_probe(dir, heads, 2, &n, NULL, 0, &err), RST_DAMAGED);
        assert_non_null(strstr(err.msg, path));
    }
    unsigned char *more = malloc((size_t)size + 10);
    memcpy(more, b, (size_t)size);
    memset(more + size, 0, 10);
    spit(path, more, size + 10);
    assert_refused(dir, path, "bytes appended");
    free(more);
    const long at[] = {size - 40,  /* the tail */
                       size - 200, /* the run state, or the index */
                       size - 600};
    for (int i = 0; i < 3; i++) {
        b[at[i]] = (unsigned char)~b[at[i]];
        spit(path, b, size);
        assert_refused(dir, path, "the end damaged");
        b[at[i]] = (unsigned char)~b[at[i]];
    }
    spit(path, b, size);
    check_read(&f, dir, 4); /* restored: whole again */
    free(b);
    fixture_free(&f);
}

/* A state without a particle (an emitter's before it starts) and no run
 * state: empty members, read back as such, and scanned as nothing. */
static void test_empty_state(void **state)
{
    (void)state;
    char dir[256];
    sl_err err;
    pcs_snapshot s[2], got[2], heads[2];
    make_state(&s[0], 0, 0);
    make_state(&s[1], 3, 1);
    const pcs_snapshot *snaps[2] = {&s[0], &s[1]};
    dir_of("empty", dir, sizeof dir);
    assert_int_equal(rst_write(dir, snaps, 2, NULL, 0, &err), 0);
    int n = 0;
    snap_init(&got[0]), snap_init(&got[1]);
    if (rst_read(dir, got, 2, &n, NULL, 0, &err) != RST_OK) fail_msg("%s", err.msg);
    assert_int_equal(n, 2);
    assert_int_equal(got[0].n, 0);
    assert_true(snap_equal(&got[1], &s[1]));
    snap_init(&heads[0]), snap_init(&heads[1]);
    assert_int_equal(rst_probe(dir, heads, 2, &n, NULL, 0, &err), RST_OK);
    collect c;
    scan_into(dir, heads, 0, NULL, &c);
    assert_int_equal(c.out.n, 0);
    assert_int_equal(c.chunks, 0);
    snap_free(&c.out);
    scan_into(dir, heads, 1, NULL, &c);
    assert_records(&c, 0, &s[1], 0, 3, 0);
    snap_free(&c.out);
    for (int k = 0; k < 2; k++) snap_free(&s[k]), snap_free(&got[k]);
}

/* What a rank's reads cost (rst_counters): of a state of 100,000 records
 * (13 pieces a field), a part of 3 decompresses the positions of its
 * blocks only, and a scan wanting the middle third of x (the records
 * sorted along x, as the cells sort them) the blocks holding it: about a
 * third of the state each, not the whole. */
static int box_middle(void *ctx, const double lo[3], const double hi[3])
{
    (void)ctx;
    return lo[0] < 2.0 / 3.0 && hi[0] >= 1.0 / 3.0;
}

static int want_middle(void *ctx, double x, double y, double z)
{
    (void)ctx, (void)y, (void)z;
    return x >= 1.0 / 3.0 && x < 2.0 / 3.0;
}

static void test_part_costs(void **state)
{
    (void)state;
    enum { N = 100000 };
    char dir[256];
    sl_err err;
    pcs_snapshot s, heads[1];
    make_state(&s, N, 0);
    const pcs_snapshot *snaps[1] = {&s};
    const unsigned char ctrl[8] = {0};
    dir_of("costs", dir, sizeof dir);
    assert_int_equal(rst_write(dir, snaps, 1, ctrl, sizeof ctrl, &err), 0);
    int n;
    snap_init(&heads[0]);
    double before = rst_counters().inflated;
    assert_int_equal(rst_probe(dir, heads, 1, &n, NULL, 0, &err), RST_OK);
    const double probe = rst_counters().inflated - before, slack = 2.0 * RST_RECORDS;
    print_message("probe: %.0f bytes decompressed\n", probe);
    assert_true(probe < 20000); /* head, index, run state */
    collect c;
    for (int part = 0; part < 3; part++) {
        rst_select sel = {.positions = 1, .part = part, .parts = 3};
        before = rst_counters().inflated;
        scan_into(dir, heads, 0, &sel, &c);
        const double got = rst_counters().inflated - before;
        print_message("part %d of 3: %zu records, %.0f bytes decompressed (the state: %d)\n", part,
                      c.out.n, got, 68 * N);
        assert_true(got <= 24.0 * (N / 3.0 + slack));
        snap_free(&c.out);
    }
    rst_select sel = {.box = box_middle, .want = want_middle};
    before = rst_counters().inflated;
    scan_into(dir, heads, 0, &sel, &c);
    const double got = rst_counters().inflated - before;
    size_t wanted = 0, seen = 0;
    for (size_t i = 0; i < N; i++) wanted += want_middle(NULL, s.x[i], 0, 0);
    for (size_t i = 0; i < c.out.n; i++) seen += want_middle(NULL, c.out.x[i], 0, 0);
    print_message("the middle third: %zu records handed out, %.0f bytes decompressed\n", c.out.n,
                  got);
    assert_int_equal(seen, wanted);
    assert_true(got <= 68.0 * (N / 3.0 + slack)); /* 9 fields: 68 bytes a record */
    snap_free(&c.out);
    rst_scan_end();
    snap_free(&s);
}

int main(void)
{
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf %s", root_);
    if (system(cmd)) return 1;
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_same_bytes_any_source),
        cmocka_unit_test(test_format3),
        cmocka_unit_test(test_damaged_boundary),
        cmocka_unit_test(test_old_format),
        cmocka_unit_test(test_damaged_piece),
        cmocka_unit_test(test_truncated_and_tail),
        cmocka_unit_test(test_empty_state),
        cmocka_unit_test(test_part_costs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
