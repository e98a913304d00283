/*
 * test_restart: the restart file (libsrc/case/case_restart.h).
 *
 * Format 3 (pieces of RST_RECORDS records with an index): a round trip of
 * two states whose lengths are not multiples of a piece, the same bytes
 * however the writer's sources hand out the data, every selection of
 * rst_scan (parts, positions only, a box and a wanted set) against the
 * whole state; a file of format 2 (the old writer, SLUICE_RESTART_FORMAT=2)
 * read by every reader; a damaged piece, a damaged index, a truncated file
 * and a file with bytes appended refused as damaged, naming the file; an
 * empty state; what a part of the records costs to read (bytes counted).
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
} fixture;

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
    }
    if (n > 5) s->vz[5] = NAN;
}

static void fixture_make(fixture *f)
{
    make_state(&f->s[0], N0, 0);
    make_state(&f->s[1], N1, 1);
    for (size_t i = 0; i < sizeof f->ctrl; i++) f->ctrl[i] = (unsigned char)(i * 37u);
}

static void fixture_free(fixture *f)
{
    snap_free(&f->s[0]);
    snap_free(&f->s[1]);
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
    const pcs_snapshot *snaps[2] = {&f->s[0], &f->s[1]};
    if (format) setenv("SLUICE_RESTART_FORMAT", format, 1);
    const int rc = rst_write(dir, snaps, 2, f->ctrl, sizeof f->ctrl, &err);
    unsetenv("SLUICE_RESTART_FORMAT");
    if (rc) fail_msg("%s", err.msg);
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

/* The whole file read back equals what was written. */
static void check_read(const fixture *f, const char *dir)
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
        assert_true(snap_equal(&got[k], &f->s[k]));
        assert_true(got[k].time == f->s[k].time && got[k].dt == f->s[k].dt);
        assert_int_equal(got[k].step, f->s[k].step);
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
    double xcut; /* want: records with x < xcut */
} collect;

static void collect_chunk(void *ctx, size_t n, const double *const a[6], const uint32_t *id)
{
    collect *c = ctx;
    c->chunks++;
    assert_true(n > 0 && n <= RST_CHUNK);
    for (size_t i = 0; i < n; i++) {
        if (c->positions) {
            assert_null(a[3]), assert_null(id);
            snap_push(&c->out, a[0][i], a[1][i], a[2][i], 0, 0, 0, 0);
        } else snap_push(&c->out, a[0][i], a[1][i], a[2][i], a[3][i], a[4][i], a[5][i], id[i]);
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
    collect c;
    for (int k = 0; k < 2; k++) { /* every record, every field */
        scan_into(dir, heads, k, NULL, &c);
        assert_int_equal(c.out.n, f->s[k].n);
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
    if (format == 3) {
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
    dir_of("v3", dir, sizeof dir);
    write_fixture(&f, dir, NULL);
    check_read(&f, dir);
    check_scans(&f, dir, 3);
    /* written again: the same bytes */
    file_of(dir, path, sizeof path);
    long s1, s2;
    unsigned char *a = slurp(path, &s1);
    write_fixture(&f, dir, "3");
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
    window_src w[2][7];
    for (int k = 0; k < 2; k++) {
        /* room past the end for the window's over-read */
        pcs_snapshot *s = &f.s[k];
        const void *a[7] = {s->x, s->y, s->z, s->vx, s->vy, s->vz, s->id};
        st[k].n = s->n, st[k].time = s->time, st[k].dt = s->dt, st[k].step = s->step;
        for (int j = 0; j < 7; j++) {
            const size_t bytes = s->n * (j < 6 ? 8 : 4);
            unsigned char *copy = calloc(bytes + 1000, 1);
            memcpy(copy, a[j], bytes);
            w[k][j] = (window_src){.data = copy};
            st[k].col[j] = (sl_source){window_read, &w[k][j], NULL};
        }
    }
    assert_int_equal(rst_write_states(d2, st, 2, f.ctrl, sizeof f.ctrl, &err), 0);
    file_of(d1, p1, sizeof p1);
    file_of(d2, p2, sizeof p2);
    long s1, s2;
    unsigned char *a = slurp(p1, &s1), *b = slurp(p2, &s2);
    assert_int_equal(s1, s2);
    assert_memory_equal(a, b, (size_t)s1);
    free(a), free(b);
    for (int k = 0; k < 2; k++)
        for (int j = 0; j < 7; j++) free((void *)w[k][j].data);
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
    check_read(&f, dir);
    check_scans(&f, dir, 2);
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
    check_read(&f, dir); /* restored: whole again */
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
                      c.out.n, got, 52 * N);
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
    assert_true(got <= 52.0 * (N / 3.0 + slack));
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
        cmocka_unit_test(test_round_trip),         cmocka_unit_test(test_same_bytes_any_source),
        cmocka_unit_test(test_old_format),         cmocka_unit_test(test_damaged_piece),
        cmocka_unit_test(test_truncated_and_tail), cmocka_unit_test(test_empty_state),
        cmocka_unit_test(test_part_costs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
