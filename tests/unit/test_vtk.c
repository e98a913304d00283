/*
 * test_vtk: the output library libsrc/io (VTK .vtu writer, .pvd/.vtu.series
 * collection, time directories).
 *
 * Files written here are read back by a real VTK reader: tests/unit/
 * vtk_readback.py run with Debian's /usr/bin/python3 (python3-vtk9; set
 * SL_VTK_PYTHON to use another, e.g. ParaView's pvpython).  It fails on any
 * VTK error or warning and dumps every value as a hex float or integer, which
 * this file compares bit for bit with what was written.  Run from the
 * repository root; scratch files live in tests/output/test_vtk.XXXXXX and
 * are removed at the end.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <errno.h>
#include <float.h>
#include <ftw.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "io/time_dir.h"
#include "io/vtk_collection.h"
#include "io/vtk_writer.h"

static char *root_; /* this run's scratch folder */

/* ---- helpers: paths and files ---------------------------------------- */

/* root_/<formatted name>, allocated. */
__attribute__((format(printf, 1, 2))) static char *tpath(const char *fmt, ...)
{
    va_list ap;
    char *rel, *path;
    int rc;
    va_start(ap, fmt);
    rc = vasprintf(&rel, fmt, ap);
    va_end(ap);
    if (rc < 0 || asprintf(&path, "%s/%s", root_, rel) < 0) fail_msg("out of memory");
    free(rel);
    return path;
}

static int exists(const char *path)
{
    struct stat st;
    return lstat(path, &st) == 0;
}

/* Names in dir containing `part` (all names when part is ""). */
static int count_entries(const char *dir, const char *part)
{
    DIR *d = opendir(dir);
    struct dirent *de;
    int n = 0;
    assert_non_null(d);
    while ((de = readdir(d)) != NULL)
        if (strcmp(de->d_name, ".") && strcmp(de->d_name, "..") && strstr(de->d_name, part)) n++;
    closedir(d);
    return n;
}

static char *slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    char *buf = NULL;
    size_t cap = 0, n = 0, got;
    assert_non_null(f);
    do {
        if (cap - n < 4096) buf = sl_realloc(buf, cap = 2 * cap + 4096, "a test file");
        got = fread(buf + n, 1, cap - n - 1, f);
        n += got;
    } while (got > 0);
    fclose(f);
    buf[n] = '\0';
    if (len) *len = n;
    return buf;
}

static void make_file(const char *path)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs("x\n", f);
    fclose(f);
}

static int rm_entry(const char *path, const struct stat *st, int flag, struct FTW *ftw)
{
    (void)st;
    (void)flag;
    (void)ftw;
    return remove(path);
}

static void rm_tree(const char *path)
{
    if (exists(path)) nftw(path, rm_entry, 16, FTW_DEPTH | FTW_PHYS);
}

/* ---- helpers: the VTK read-back --------------------------------------- */

typedef struct rb_array {
    char *name, *type;
    int ncomp;
    size_t ntuples;
    double *d;    /* values of float arrays (exact: read from hex floats) */
    long long *i; /* values of integer arrays */
} rb_array;

typedef struct rb_grid {
    long long npoints, ncells;
    int has_time;
    double time;
    rb_array *arr;
    size_t narr;
    long long *cell; /* per cell: type, npts, first point id */
} rb_grid;

static FILE *rb_open(const char *args)
{
    const char *py = getenv("SL_VTK_PYTHON") ? getenv("SL_VTK_PYTHON") : "/usr/bin/python3";
    size_t len = strlen(py) + strlen(args) + 64;
    char *cmd = sl_malloc(len, "a command");
    FILE *p;
    if (!exists("tests/unit/vtk_readback.py"))
        fail_msg("tests/unit/vtk_readback.py not found: run the test from the repository root");
    snprintf(cmd, len, "'%s' tests/unit/vtk_readback.py %s", py, args);
    fflush(NULL);
    p = popen(cmd, "r");
    free(cmd);
    assert_non_null(p);
    return p;
}

static void rb_close(FILE *p, const char *what)
{
    int st = pclose(p);
    if (st != 0) fail_msg("VTK read-back of %s failed (status 0x%x)", what, (unsigned)st);
}

/* The next line without its newline, or fail at end of output. */
static char *rb_line(FILE *p, char **buf, size_t *cap)
{
    ssize_t len = getline(buf, cap, p);
    if (len < 0) fail_msg("VTK read-back output ended early");
    if (len > 0 && (*buf)[len - 1] == '\n') (*buf)[len - 1] = '\0';
    return *buf;
}

static void rb_read_array(FILE *p, const char *head, rb_array *a, char **buf, size_t *cap)
{
    memset(a, 0, sizeof *a);
    if (sscanf(head, "array %ms %ms %d %zu", &a->name, &a->type, &a->ncomp, &a->ntuples) != 4)
        fail_msg("bad read-back line '%s'", head);
    a->d = sl_calloc(a->ntuples * (size_t)a->ncomp, sizeof *a->d, "read-back values");
    a->i = sl_calloc(a->ntuples * (size_t)a->ncomp, sizeof *a->i, "read-back values");
    for (size_t t = 0; t < a->ntuples; t++) {
        char *s = rb_line(p, buf, cap), *end;
        for (int k = 0; k < a->ncomp; k++, s = end) {
            size_t at = t * (size_t)a->ncomp + (size_t)k;
            if (a->type[0] == 'F') a->d[at] = strtod(s, &end);
            else a->i[at] = strtoll(s, &end, 10);
            if (end == s) fail_msg("array %s tuple %zu: too few values", a->name, t);
        }
    }
}

static void rb_add_cell(rb_grid *g, const char *line, size_t *ncell)
{
    long long *v;
    g->cell = sl_realloc(g->cell, (*ncell + 1) * 3 * sizeof *g->cell, "read-back cells");
    v = g->cell + 3 * *ncell;
    if (sscanf(line, "cell %lld %lld %lld", &v[0], &v[1], &v[2]) != 3)
        fail_msg("bad read-back line '%s'", line);
    ++*ncell;
}

/* Read path with VTK and parse the dump. */
static void rb_read_vtu(const char *path, rb_grid *g)
{
    char *args = sl_malloc(strlen(path) + 3, "a command"), *buf = NULL, *line;
    size_t cap = 0, ncell = 0;
    FILE *p;
    sprintf(args, "'%s'", path);
    p = rb_open(args);
    free(args);
    memset(g, 0, sizeof *g);
    if (sscanf(rb_line(p, &buf, &cap), "npoints %lld", &g->npoints) != 1 ||
        sscanf(rb_line(p, &buf, &cap), "ncells %lld", &g->ncells) != 1)
        fail_msg("bad read-back header for %s", path);
    line = rb_line(p, &buf, &cap);
    g->has_time = strcmp(line, "time none") != 0;
    if (g->has_time) g->time = strtod(line + 5, NULL);
    while (strcmp(line = rb_line(p, &buf, &cap), "end") != 0) {
        if (strncmp(line, "array ", 6) == 0) {
            g->arr = sl_realloc(g->arr, (g->narr + 1) * sizeof *g->arr, "read-back arrays");
            rb_read_array(p, line, &g->arr[g->narr++], &buf, &cap);
        } else if (strncmp(line, "cell ", 5) == 0) {
            rb_add_cell(g, line, &ncell);
        } else {
            fail_msg("bad read-back line '%s'", line);
        }
    }
    if ((long long)ncell != g->ncells)
        fail_msg("%s: %zu cells listed of %lld", path, ncell, g->ncells);
    free(buf);
    rb_close(p, path);
}

static void rb_free(rb_grid *g)
{
    for (size_t i = 0; i < g->narr; i++) {
        free(g->arr[i].name);
        free(g->arr[i].type);
        free(g->arr[i].d);
        free(g->arr[i].i);
    }
    free(g->arr);
    free(g->cell);
    memset(g, 0, sizeof *g);
}

static const rb_array *rb_find(const rb_grid *g, const char *name)
{
    for (size_t i = 0; i < g->narr; i++)
        if (strcmp(g->arr[i].name, name) == 0) return &g->arr[i];
    fail_msg("array '%s' missing from the read-back", name);
    return NULL;
}

/* Read an index file (.pvd or .vtu.series) back: times and names. */
typedef struct rb_index {
    size_t n;
    double *time;
    char **file;
} rb_index;

static void rb_read_index(const char *mode, const char *path, rb_index *x)
{
    char *args = sl_malloc(strlen(mode) + strlen(path) + 4, "a command"), *buf = NULL, *line;
    size_t cap = 0;
    FILE *p;
    sprintf(args, "%s '%s'", mode, path);
    p = rb_open(args);
    free(args);
    memset(x, 0, sizeof *x);
    while (strcmp(line = rb_line(p, &buf, &cap), "end") != 0) {
        char *end, *name;
        if (strncmp(line, "entry ", 6) != 0) fail_msg("bad read-back line '%s'", line);
        x->time = sl_realloc(x->time, (x->n + 1) * sizeof *x->time, "read-back times");
        x->file = sl_realloc(x->file, (x->n + 1) * sizeof *x->file, "read-back files");
        x->time[x->n] = strtod(line + 6, &end);
        name = end + (*end == ' ');
        x->file[x->n++] = sl_strdup(name);
    }
    free(buf);
    rb_close(p, path);
}

static void rb_index_free(rb_index *x)
{
    for (size_t i = 0; i < x->n; i++) free(x->file[i]);
    free(x->file);
    free(x->time);
}

/* ---- helpers: test data and checks ------------------------------------ */

static int same_double(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

static double bits_double(uint64_t u)
{
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}

static float bits_float(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* Component k of field f at point i, as the text a mismatch message shows,
 * and whether the read-back value at[idx] equals it exactly. */
static int check_value(const vtk_field *f, int k, size_t i, const rb_array *a, size_t idx,
                       char *msg, size_t len)
{
    const void *c = f->comp[k];
    switch (f->type) {
    case VTK_FLOAT64:
        snprintf(msg, len, "%a vs %a", ((const double *)c)[i], a->d[idx]);
        return same_double(((const double *)c)[i], a->d[idx]);
    case VTK_FLOAT32: {
        float got = (float)a->d[idx], want = ((const float *)c)[i];
        snprintf(msg, len, "%a vs %a", (double)want, a->d[idx]);
        return memcmp(&got, &want, sizeof got) == 0 && (double)got == a->d[idx];
    }
    case VTK_INT32:
        snprintf(msg, len, "%d vs %lld", ((const int32_t *)c)[i], a->i[idx]);
        return ((const int32_t *)c)[i] == a->i[idx];
    case VTK_UINT32:
        snprintf(msg, len, "%u vs %lld", ((const uint32_t *)c)[i], a->i[idx]);
        return ((const uint32_t *)c)[i] == a->i[idx];
    case VTK_INT64:
        snprintf(msg, len, "%lld vs %lld", (long long)((const int64_t *)c)[i], a->i[idx]);
        return ((const int64_t *)c)[i] == a->i[idx];
    case VTK_UINT8:
        snprintf(msg, len, "%u vs %lld", ((const uint8_t *)c)[i], a->i[idx]);
        return ((const uint8_t *)c)[i] == a->i[idx];
    }
    return 0;
}

static const char *type_name(vtk_type t)
{
    static const char *const names[] = {"Float64", "Float32", "Int32", "UInt32", "Int64", "UInt8"};
    return names[t];
}

static void check_field(const rb_grid *g, const vtk_field *f, size_t n)
{
    const rb_array *a = rb_find(g, f->name);
    char msg[160];
    assert_string_equal(a->type, type_name(f->type));
    assert_int_equal(a->ncomp, f->ncomp);
    assert_int_equal(a->ntuples, n);
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < f->ncomp; k++)
            if (!check_value(f, k, i, a, i * (size_t)f->ncomp + (size_t)k, msg, sizeof msg))
                fail_msg("field '%s' point %zu component %d: wrote %s read back", f->name, i, k,
                         msg);
}

/* A data set covering every vtk_type, 1 and 3 components, awkward values
 * (-0, subnormals, extremes) and a name that needs XML escaping. */
enum { NFIELD = 8 };
typedef struct dataset {
    size_t n;
    double *x, *y, *z, *vel[3], *rho;
    float *mass, *acc[3];
    int32_t *id;
    uint32_t *uid;
    int64_t *big;
    uint8_t *flag;
    vtk_field f[NFIELD];
} dataset;

static void dataset_fill(dataset *d)
{
    uint64_t s = 0x9E3779B97F4A7C15u;
    for (size_t i = 0; i < d->n; i++) {
        double r;
        s = s * 6364136223846793005u + 1442695040888963407u;
        r = (double)(s >> 11) * 0x1p-53;
        d->x[i] = r - 0.5;
        d->y[i] = 1e3 * r * r;
        d->z[i] = (double)i / 3.0;
        for (int k = 0; k < 3; k++) d->vel[k][i] = sin((double)(3 * i + (size_t)k) + r) / 7.0;
        for (int k = 0; k < 3; k++) d->acc[k][i] = (float)(r * (double)(k + 1)) / 3.0f;
        d->rho[i] = 1000.0 + r;
        d->mass[i] = (float)r * 1e-3f;
        d->id[i] = (int32_t)i - 7;
        d->uid[i] = (uint32_t)(s >> 32);
        d->big[i] = (int64_t)(s >> 1) - (int64_t)(UINT64_C(1) << 61);
        d->flag[i] = (uint8_t)(i * 37);
    }
    /* Built from bits: -fno-signed-zeros may fold a literal -0.0 to 0. */
    if (d->n > 0) {
        d->x[0] = bits_double(UINT64_C(0x8000000000000000)); /* -0 */
        d->y[0] = bits_double(1);                            /* smallest subnormal */
        d->z[0] = DBL_MAX;
        d->rho[0] = 0.1;
        d->mass[0] = bits_float(1); /* smallest float subnormal */
        d->acc[0][0] = FLT_MAX;
        d->id[0] = INT32_MIN;
        d->uid[0] = UINT32_MAX;
        d->big[0] = INT64_MIN;
        d->flag[0] = 255;
    }
    if (d->n > 1) {
        d->x[1] = -DBL_MAX;
        d->id[1] = INT32_MAX;
        d->big[1] = INT64_MAX;
    }
}

static void dataset_make(dataset *d, size_t n)
{
    memset(d, 0, sizeof *d);
    d->n = n;
#define DS_ALLOC(p) (p) = sl_calloc(n + 1, sizeof *(p), "test data")
    DS_ALLOC(d->x);
    DS_ALLOC(d->y);
    DS_ALLOC(d->z);
    DS_ALLOC(d->rho);
    DS_ALLOC(d->mass);
    DS_ALLOC(d->id);
    DS_ALLOC(d->uid);
    DS_ALLOC(d->big);
    DS_ALLOC(d->flag);
    for (int k = 0; k < 3; k++) {
        DS_ALLOC(d->vel[k]);
        DS_ALLOC(d->acc[k]);
    }
#undef DS_ALLOC
    dataset_fill(d);
    d->f[0] = (vtk_field){"velocity", 3, VTK_FLOAT64, {d->vel[0], d->vel[1], d->vel[2]}};
    d->f[1] = (vtk_field){"rho", 1, VTK_FLOAT64, {d->rho, NULL, NULL}};
    d->f[2] = (vtk_field){"mass", 1, VTK_FLOAT32, {d->mass, NULL, NULL}};
    d->f[3] = (vtk_field){"acc", 3, VTK_FLOAT32, {d->acc[0], d->acc[1], d->acc[2]}};
    d->f[4] = (vtk_field){"id", 1, VTK_INT32, {d->id, NULL, NULL}};
    d->f[5] = (vtk_field){"uid", 1, VTK_UINT32, {d->uid, NULL, NULL}};
    d->f[6] = (vtk_field){"big", 1, VTK_INT64, {d->big, NULL, NULL}};
    d->f[7] = (vtk_field){"flag<&>\"'", 1, VTK_UINT8, {d->flag, NULL, NULL}};
}

static void dataset_free(dataset *d)
{
    free(d->x);
    free(d->y);
    free(d->z);
    free(d->rho);
    free(d->mass);
    free(d->id);
    free(d->uid);
    free(d->big);
    free(d->flag);
    for (int k = 0; k < 3; k++) {
        free(d->vel[k]);
        free(d->acc[k]);
    }
}

/* Everything VTK read from path equals what write_dataset wrote. */
static void check_grid(const char *path, const dataset *d, const vtk_options *o)
{
    rb_grid g;
    vtk_field points = {"Points", 3, VTK_FLOAT64, {d->x, d->y, d->z}};
    int vertices = o ? o->vertices : 1;
    rb_read_vtu(path, &g);
    assert_int_equal(g.npoints, d->n);
    assert_int_equal(g.ncells, vertices ? d->n : 0);
    if (!o || isnan(o->time)) {
        assert_false(g.has_time);
    } else {
        assert_true(g.has_time);
        assert_true(same_double(g.time, o->time));
    }
    for (int i = 0; i < NFIELD; i++) check_field(&g, &d->f[i], d->n);
    assert_int_equal(g.narr, NFIELD + 1); /* and "Points" */
    check_field(&g, &points, d->n);
    for (long long c = 0; c < g.ncells; c++) {
        const long long *v = g.cell + 3 * c;
        if (v[0] != 1 || v[1] != 1 || v[2] != c)
            fail_msg("cell %lld: type %lld, %lld points from %lld; want a vertex of point %lld", c,
                     v[0], v[1], v[2], c);
    }
    rb_free(&g);
}

static int write_dataset(const char *path, const dataset *d, const vtk_options *o, sl_err *err)
{
    return vtk_write_points(path, d->n, d->x, d->y, d->z, d->f, NFIELD, o, err);
}

/* Write n points with options o, read back with VTK, compare everything. */
static void roundtrip(const char *name, size_t n, const vtk_options *o)
{
    dataset d;
    sl_err err = {""};
    char *path = tpath("%s", name);
    dataset_make(&d, n);
    if (write_dataset(path, &d, o, &err)) fail_msg("%s", err.msg);
    check_grid(path, &d, o);
    assert_int_equal(count_entries(root_, ".tmp"), 0);
    dataset_free(&d);
    free(path);
}

/* The first UInt64 words of the first array of the appended data. */
static void first_header(const char *path, uint64_t *h, size_t nwords)
{
    size_t len;
    char *buf = slurp(path, &len), *at = strstr(buf, "<AppendedData encoding=\"raw\">");
    assert_non_null(at);
    at = strchr(at, '_');
    assert_non_null(at);
    assert_true((size_t)(at + 1 - buf) + nwords * 8 <= len);
    memcpy(h, at + 1, nwords * 8);
    free(buf);
}

static vtk_options opts(int ascii, int compress, size_t block)
{
    vtk_options o;
    vtk_options_default(&o);
    o.ascii = ascii;
    o.compress = compress;
    o.block_size = block;
    return o;
}

/* ---- tests: time directories ------------------------------------------ */

static void test_tdir_name(void **state)
{
    static const struct {
        double t;
        int prec;
        const char *name;
    } cases[] = {
        {0, 6, "0"},
        {0.05, 6, "0.05"},
        {1, 6, "1"},
        {0.1, 6, "0.1"},
        {1e-05, 6, "1e-05"},
        {2.5, 6, "2.5"},
        {0.30000000000000004, 6, "0.3"},
        {0.1 + 0.2, 0, "0.3"},
        {123.456789, 6, "123.457"},
        {123.456789, 9, "123.456789"},
        {1e6, 6, "1e+06"},
        {100, 6, "100"},
        {0.000123, 6, "0.000123"},
        {1.0 / 3.0, 3, "0.333"},
        {2.0 / 3.0, 17, "0.66666666666666663"},
    };
    char buf[32];
    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        tdir_name(cases[i].t, cases[i].prec, buf, sizeof buf);
        if (strcmp(buf, cases[i].name) != 0)
            fail_msg("tdir_name(%.17g, %d) = '%s', want '%s'", cases[i].t, cases[i].prec, buf,
                     cases[i].name);
    }
    tdir_name(bits_double(UINT64_C(0x8000000000000000)), 6, buf, sizeof buf);
    assert_string_equal(buf, "0");
    tdir_name(0.125, 6, buf, 4); /* truncated, still terminated */
    assert_string_equal(buf, "0.1");
}

static void test_tdir_mkdirs(void **state)
{
    sl_err err = {""};
    char *deep = tpath("mk/a/b//c/"), *file = tpath("mk/file"), *below = tpath("mk/file/x/y");
    (void)state;
    assert_int_equal(tdir_mkdirs(deep, &err), 0);
    assert_int_equal(tdir_mkdirs(deep, &err), 0); /* exists already: fine */
    assert_true(exists(deep));
    make_file(file);
    assert_int_not_equal(tdir_mkdirs(below, &err), 0);
    assert_non_null(strstr(err.msg, below));
    assert_non_null(strstr(err.msg, strerror(ENOTDIR)));
    assert_int_not_equal(tdir_mkdirs(file, &err), 0);
    assert_int_not_equal(tdir_mkdirs("", &err), 0);
    free(deep);
    free(file);
    free(below);
}

static void test_tdir_list(void **state)
{
    static const char *const dirs[] = {"0",     "0.05", "1",           "1e-05",  "0.1",
                                       "10",    "2.5",  "constant",    "system", "postProcessing",
                                       ".0.2",  "abc",  "0.1.tmp.123", "0.3",    "nan",
                                       "1e-3x", "0x10", ".5"};
    static const char *const want[] = {"0", "1e-05", "0.05", "0.1", "1", "2.5", "10"};
    sl_err err = {""};
    tdir_list l;
    char *c = tpath("case"), *p;
    (void)state;
    for (size_t i = 0; i < sizeof dirs / sizeof dirs[0]; i++) {
        p = tpath("case/%s", dirs[i]);
        assert_int_equal(tdir_mkdirs(p, &err), 0);
        free(p);
        /* every time-like folder is complete except "0.3" */
        if (strcmp(dirs[i], "0.3") == 0) continue;
        p = tpath("case/%s/fluid.vtu", dirs[i]);
        make_file(p);
        free(p);
    }
    p = tpath("case/42"); /* a file, not a folder */
    make_file(p);
    free(p);
    assert_int_equal(tdir_list_read(c, "fluid.vtu", &l, &err), 0);
    assert_int_equal(l.n, sizeof want / sizeof want[0]);
    for (size_t i = 0; i < l.n; i++) {
        assert_string_equal(l.name[i], want[i]);
        assert_true(same_double(l.time[i], strtod(want[i], NULL)));
    }
    tdir_list_free(&l);
    /* without a marker the incomplete "0.3" counts too */
    assert_int_equal(tdir_list_read(c, NULL, &l, &err), 0);
    assert_int_equal(l.n, sizeof want / sizeof want[0] + 1);
    assert_string_equal(l.name[4], "0.3");
    tdir_list_free(&l);
    free(c);
    c = tpath("no-such-case");
    assert_int_not_equal(tdir_list_read(c, NULL, &l, &err), 0);
    assert_non_null(strstr(err.msg, c));
    assert_int_equal(l.n, 0);
    free(c);
}

/* ---- tests: .vtu files read back by VTK ------------------------------- */

/* Several zlib blocks of 64 bytes, the arrays' sizes not multiples of it:
 * the header's last-block field is the size of the partial block. */
static void test_vtk_zlib_partial_blocks(void **state)
{
    vtk_options o = opts(0, 1, 64);
    uint64_t h[3];
    char *path = tpath("zlib_partial.vtu");
    (void)state;
    o.time = 0.05;
    roundtrip("zlib_partial.vtu", 641, &o);
    first_header(path, h, 3); /* TimeValue: 8 bytes */
    assert_int_equal(h[0], 1);
    assert_int_equal(h[1], 64);
    assert_int_equal(h[2], 8);
    free(path);
    o.time = NAN;
    roundtrip("zlib_partial.vtu", 641, &o);
    path = tpath("zlib_partial.vtu");
    first_header(path, h, 3); /* velocity: 641 * 24 = 240 blocks + 24 bytes */
    assert_int_equal(h[0], 241);
    assert_int_equal(h[1], 64);
    assert_int_equal(h[2], 24);
    free(path);
}

/* Every array an exact multiple of the block size: VTK's convention is a
 * last-block size of 0, not the block size. */
static void test_vtk_zlib_exact_blocks(void **state)
{
    vtk_options o = opts(0, 1, 64);
    uint64_t h[3];
    char *path = tpath("zlib_exact.vtu");
    (void)state;
    roundtrip("zlib_exact.vtu", 640, &o);
    first_header(path, h, 3); /* velocity: 640 * 24 bytes = 240 blocks */
    assert_int_equal(h[0], 240);
    assert_int_equal(h[1], 64);
    assert_int_equal(h[2], 0);
    free(path);
}

/* Smaller than one block (and the default options, whose block is 32768). */
static void test_vtk_zlib_small(void **state)
{
    vtk_options o;
    (void)state;
    vtk_options_default(&o);
    roundtrip("zlib_small.vtu", 3, &o);
    roundtrip("zlib_null_opt.vtu", 5, NULL);
}

/* Several default-sized blocks, with a time value. */
static void test_vtk_zlib_large(void **state)
{
    vtk_options o;
    (void)state;
    vtk_options_default(&o);
    o.time = 1e-05;
    o.level = 9;
    roundtrip("zlib_large.vtu", 5000, &o);
}

static void test_vtk_empty_and_single(void **state)
{
    vtk_options zlib = opts(0, 1, 64), raw = opts(0, 0, 0), ascii = opts(1, 0, 0);
    uint64_t h[3];
    char *path = tpath("n0_zlib.vtu");
    (void)state;
    roundtrip("n0_zlib.vtu", 0, &zlib);
    first_header(path, h, 3); /* like vtkXMLWriter: no blocks */
    assert_int_equal(h[0], 0);
    assert_int_equal(h[1], 64);
    assert_int_equal(h[2], 0);
    roundtrip("n0_raw.vtu", 0, &raw);
    roundtrip("n0_ascii.vtu", 0, &ascii);
    roundtrip("n1_zlib.vtu", 1, &zlib);
    roundtrip("n1_raw.vtu", 1, &raw);
    roundtrip("n1_ascii.vtu", 1, &ascii);
    zlib.vertices = 0;
    roundtrip("n1_zlib_novert.vtu", 1, &zlib);
    free(path);
}

static void test_vtk_raw(void **state)
{
    vtk_options o = opts(0, 0, 100); /* blocks only bound the scratch buffer here */
    uint64_t h[1];
    char *path = tpath("raw.vtu");
    (void)state;
    o.time = 2.5;
    roundtrip("raw.vtu", 1001, &o);
    first_header(path, h, 1); /* TimeValue: one Float64 */
    assert_int_equal(h[0], 8);
    o.vertices = 0;
    roundtrip("raw_novert.vtu", 33, &o);
    free(path);
}

static void test_vtk_ascii(void **state)
{
    vtk_options o = opts(1, 1, 0); /* compress is ignored for ascii */
    char *path = tpath("ascii.vtu"), *text;
    (void)state;
    o.time = 0.1;
    roundtrip("ascii.vtu", 50, &o);
    text = slurp(path, NULL);
    assert_null(strstr(text, "AppendedData"));
    assert_null(strstr(text, "compressor"));
    assert_non_null(strstr(text, "format=\"ascii\""));
    free(text);
    free(path);
}

/* ---- tests: failures leave nothing behind ----------------------------- */

static void test_vtk_atomic_success(void **state)
{
    char *dir = tpath("atomic"), *path = tpath("atomic/fluid.vtu");
    dataset d;
    sl_err err = {""};
    (void)state;
    dataset_make(&d, 10);
    assert_int_equal(tdir_mkdirs(dir, &err), 0);
    assert_int_equal(write_dataset(path, &d, NULL, &err), 0);
    assert_int_equal(write_dataset(path, &d, NULL, &err), 0); /* replaces */
    assert_int_equal(count_entries(dir, ""), 1);
    assert_int_equal(count_entries(dir, "fluid.vtu"), 1);
    dataset_free(&d);
    free(dir);
    free(path);
}

/* A write that fails returns an error naming path and leaves no file. */
static void expect_write_error(const char *path, const char *dir, const char *reason)
{
    dataset d;
    sl_err err = {""};
    dataset_make(&d, 10);
    assert_int_not_equal(write_dataset(path, &d, NULL, &err), 0);
    if (!strstr(err.msg, path) || (reason && !strstr(err.msg, reason)))
        fail_msg("error message '%s' lacks '%s' or '%s'", err.msg, path, reason ? reason : "");
    assert_false(exists(path));
    if (dir && exists(dir)) assert_int_equal(count_entries(dir, ""), 0);
    dataset_free(&d);
}

static void test_vtk_missing_dir(void **state)
{
    char *dir = tpath("missing"), *path = tpath("missing/fluid.vtu");
    (void)state;
    expect_write_error(path, dir, strerror(ENOENT));
    assert_false(exists(dir));
    free(dir);
    free(path);
}

static void test_vtk_parent_is_file(void **state)
{
    char *file = tpath("plainfile"), *path = tpath("plainfile/fluid.vtu");
    (void)state;
    make_file(file);
    expect_write_error(path, NULL, strerror(ENOTDIR));
    free(file);
    free(path);
}

static void test_vtk_readonly_dir(void **state)
{
    char *dir = tpath("readonly"), *path = tpath("readonly/fluid.vtu");
    sl_err err = {""};
    struct stat st;
    (void)state;
    assert_int_equal(tdir_mkdirs(dir, &err), 0);
    if (geteuid() != 0) {
        assert_int_equal(chmod(dir, 0555), 0);
        expect_write_error(path, dir, strerror(EACCES));
        chmod(dir, 0755);
    } else if (stat("/sys", &st) == 0 && S_ISDIR(st.st_mode)) {
        /* Permission bits do not bind root, but sysfs refuses new files. */
        expect_write_error("/sys/sluice_test_vtk.vtu", NULL, NULL);
    } else {
        skip();
    }
    free(dir);
    free(path);
}

/* A failure in the middle of the data (file size limit) removes the temp
 * file and leaves the previous version of the file untouched. */
static void test_vtk_fails_midway(void **state)
{
    char *dir = tpath("midway"), *path = tpath("midway/fluid.vtu"), *before, *after;
    dataset d;
    sl_err err = {""};
    struct rlimit old, lim;
    void (*old_handler)(int);
    size_t len0, len1;
    (void)state;
    dataset_make(&d, 3000);
    assert_int_equal(tdir_mkdirs(dir, &err), 0);
    assert_int_equal(vtk_write_points(path, 2, d.x, d.y, d.z, d.f, NFIELD, NULL, &err), 0);
    before = slurp(path, &len0);
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
    lim = old;
    lim.rlim_cur = 20000; /* the file needs more, even compressed */
    old_handler = signal(SIGXFSZ, SIG_IGN);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &lim), 0);
    assert_int_not_equal(write_dataset(path, &d, NULL, &err), 0);
    setrlimit(RLIMIT_FSIZE, &old);
    signal(SIGXFSZ, old_handler);
    if (!strstr(err.msg, path) || !strstr(err.msg, strerror(EFBIG)))
        fail_msg("error message '%s'", err.msg);
    after = slurp(path, &len1);
    assert_int_equal(len0, len1);
    assert_memory_equal(before, after, len0);
    assert_int_equal(count_entries(dir, ""), 1);
    free(before);
    free(after);
    dataset_free(&d);
    free(dir);
    free(path);
}

static void test_vtk_bad_input(void **state)
{
    dataset d;
    sl_err err = {""};
    char *path = tpath("bad.vtu");
    (void)state;
    dataset_make(&d, 4);
    d.f[3].comp[2] = NULL;
    assert_int_not_equal(write_dataset(path, &d, NULL, &err), 0);
    assert_non_null(strstr(err.msg, "acc"));
    d.f[3].comp[2] = d.acc[2];
    d.f[1].ncomp = 4;
    assert_int_not_equal(write_dataset(path, &d, NULL, &err), 0);
    assert_non_null(strstr(err.msg, "rho"));
    assert_int_not_equal(vtk_write_points(path, 4, d.x, NULL, d.z, NULL, 0, NULL, &err), 0);
    assert_false(exists(path));
    assert_int_equal(count_entries(root_, ".tmp"), 0);
    dataset_free(&d);
    free(path);
}

/* ---- tests: collection files ------------------------------------------ */

static void check_index(const char *mode, const char *path, const double *t,
                        const char *const *files, size_t n)
{
    rb_index x;
    rb_read_index(mode, path, &x);
    assert_int_equal(x.n, n);
    for (size_t i = 0; i < n; i++) {
        if (!same_double(x.time[i], t[i]))
            fail_msg("%s entry %zu: time %a, want %a", path, i, x.time[i], t[i]);
        assert_string_equal(x.file[i], files[i]);
    }
    rb_index_free(&x);
}

static void test_vtk_collection(void **state)
{
    static const double t[] = {0, 1e-05, 0.05, 0.1, 0.30000000000000004, 1, 12345.678};
    static const char *const f[] = {"0/fluid.vtu",         "1e-05/fluid.vtu",  "0.05/fluid.vtu",
                                    "0.1/fluid.vtu",       "0.3/a&b<\"'>.vtu", "1/fluid.vtu",
                                    "12345.7/fluid\\x.vtu"};
    char *pvd = tpath("fluid.pvd"), *series = tpath("fluid.vtu.series"), *text;
    sl_err err = {""};
    const double bad[] = {NAN};
    (void)state;
    assert_int_equal(vtk_collection_write(pvd, series, t, f, 0, &err), 0);
    check_index("--pvd", pvd, t, f, 0);
    check_index("--series", series, t, f, 0);
    for (size_t n = 1; n <= 7; n += 3) { /* rewritten as the run goes on */
        assert_int_equal(vtk_collection_write(pvd, series, t, f, n, &err), 0);
        check_index("--pvd", pvd, t, f, n);
        check_index("--series", series, t, f, n);
    }
    text = slurp(series, NULL); /* times are short: 0.1, not 0.10000000000000001 */
    assert_non_null(strstr(text, "\"time\" : 0.1 }"));
    assert_non_null(strstr(text, "\"time\" : 1e-05 }"));
    free(text);
    assert_int_not_equal(vtk_collection_write(pvd, series, bad, f, 1, &err), 0);
    check_index("--pvd", pvd, t, f, 7); /* untouched */
    assert_int_equal(count_entries(root_, ".tmp"), 0);
    free(pvd);
    pvd = tpath("missing/fluid.pvd");
    assert_int_not_equal(vtk_collection_write(pvd, NULL, t, f, 2, &err), 0);
    assert_non_null(strstr(err.msg, pvd));
    free(pvd);
    free(series);
}

/* ---- main ------------------------------------------------------------- */

static int group_setup(void **state)
{
    sl_err err = {""};
    const char *tmpl = "tests/output/test_vtk.XXXXXX";
    (void)state;
    if (tdir_mkdirs("tests/output", &err)) {
        fprintf(stderr, "%s\n", err.msg);
        return -1;
    }
    root_ = sl_strdup(tmpl);
    if (!mkdtemp(root_)) {
        perror(root_);
        return -1;
    }
    return 0;
}

static int group_teardown(void **state)
{
    (void)state;
    rm_tree(root_);
    free(root_);
    return 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tdir_name),
        cmocka_unit_test(test_tdir_mkdirs),
        cmocka_unit_test(test_tdir_list),
        cmocka_unit_test(test_vtk_zlib_partial_blocks),
        cmocka_unit_test(test_vtk_zlib_exact_blocks),
        cmocka_unit_test(test_vtk_zlib_small),
        cmocka_unit_test(test_vtk_zlib_large),
        cmocka_unit_test(test_vtk_empty_and_single),
        cmocka_unit_test(test_vtk_raw),
        cmocka_unit_test(test_vtk_ascii),
        cmocka_unit_test(test_vtk_atomic_success),
        cmocka_unit_test(test_vtk_missing_dir),
        cmocka_unit_test(test_vtk_parent_is_file),
        cmocka_unit_test(test_vtk_readonly_dir),
        cmocka_unit_test(test_vtk_fails_midway),
        cmocka_unit_test(test_vtk_bad_input),
        cmocka_unit_test(test_vtk_collection),
    };
    return cmocka_run_group_tests(tests, group_setup, group_teardown);
}
