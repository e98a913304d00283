/*
 * test_function_objects: the post-processing chain -- the VTK reader
 * (libsrc/io/vtk_reader), the function objects (libsrc/functionObjects) and
 * the postProcess and densityError utilities.
 *
 *  - vtk_reader reads back, value for value, what vtk_write_points writes
 *    (zlib with many blocks, raw binary, ascii; every value type; 0, 1 and
 *    many points) and rejects every truncation of a file and a list of
 *    targeted corruptions with an error naming the file; random byte flips
 *    must never crash it (run under ASan by `make test-debug`).
 *  - Point queries over the solver's grid equal a search over all
 *    particles, also after the particles moved within a cell; a grid that
 *    no longer describes the particles is detected.
 *  - Rows rolled back by the solver's shock handling are replaced.
 *  - A short run of tests/cases/hydrostaticTank (bin/pcisph, or
 *    $SLUICE_BIN/pcisph) with all four function objects: every .dat has as
 *    many values per row as its header names columns, and the values at the
 *    write times equal a direct computation from the written fluid.vtu and
 *    boundary.vtu (relative 1e-8: the files hold 10 digits); postProcess on
 *    the written times reproduces the run's rows; densityError writes its
 *    .dat and .png; a restart opens a new start-time folder.
 *  - Runs, restarts and the End summary (tests/cases copies under
 *    tests/output/functionObjects/runs/, one thread): a restart at an
 *    awkward time (writeInterval 0.0017, from 0.0187) and one right before
 *    a shock (which goes back past the restart time; also with the
 *    warm-started divergence source) give VTK files byte
 *    for byte equal to an uninterrupted run's; with writeControl runTime a
 *    shorter run is the exact start of a longer one with another write
 *    interval; the state at endTime is always written; time names are
 *    unique and true (precision raised); the End summary counts this
 *    session and the whole run, the steps taken and why iterations stopped.
 *  - A 0.5 s hydrostatic run: the probe pressure at depth 0.3 m, averaged
 *    over 0.25..0.5 s, is within 10 % of rho0 g (H - z), and the gauge reads
 *    the column height H within r0/2.
 * Run from the repository root; scratch goes to tests/output/.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "hostile_table.h"
#include "dictionary/dict.h"
#include "functionObjects/fo.h"
#include "functionObjects/fo_query.h"
#include "io/time_dir.h"
#include "io/vtk_reader.h"
#include "io/vtk_writer.h"
#include "kernel/kernel.h"
#include "neighbours/neighbours.h"
#include "solver/pcisph.h"

#define OUT  "tests/output/functionObjects"
#define TANK OUT "/tank"

/* ---- small helpers -------------------------------------------------- */

static const char *bin_dir(void)
{
    const char *b = getenv("SLUICE_BIN");
    return b && *b ? b : "bin";
}

static int quick(void)
{
    const char *q = getenv("SLUICE_QUICK");
    return q && !strcmp(q, "1");
}

__attribute__((format(printf, 1, 2))) static int sh(const char *fmt, ...)
{
    char cmd[4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cmd, sizeof cmd, fmt, ap);
    va_end(ap);
    fflush(NULL);
    int rc = system(cmd);
    return rc == -1 ? -1 : WIFEXITED(rc) ? WEXITSTATUS(rc) : 128;
}

static int exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

static char *slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f) fail_msg("cannot read %s", path);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = sl_malloc((size_t)n + 1, "file");
    if (fread(buf, 1, (size_t)n, f) != (size_t)n) fail_msg("short read of %s", path);
    fclose(f);
    buf[n] = '\0';
    if (len) *len = (size_t)n;
    return buf;
}

static void spit(const char *path, const char *buf, size_t len)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(buf, 1, len, f), len);
    assert_int_equal(fclose(f), 0);
}

/* Equal within rel (and 1e-12 absolute), NaN equal to NaN. */
static int close_to(double a, double b, double rel)
{
    if (isnan(a) || isnan(b)) return isnan(a) && isnan(b);
    return fabs(a - b) <= rel * fmax(fabs(a), fabs(b)) + 1e-12;
}

#define assert_close(a, b, rel)                                                            \
    do {                                                                                   \
        double a_ = (a), b_ = (b);                                                         \
        if (!close_to(a_, b_, rel))                                                        \
            fail_msg("%s = %.17g but %s = %.17g (rel %g)", #a, a_, #b, b_, (double)(rel)); \
    } while (0)

/* ---- reading .dat files ---------------------------------------------- */

typedef struct dat {
    int ncols;
    char col[64][32];
    int nrows;
    double (*v)[64];
    char header[8192]; /* all '#' lines */
} dat;

/* Reads an OpenFOAM-style .dat; fails unless the last '#' line names the
 * columns and every row has exactly that many tab-separated values. */
static void dat_read_any(const char *path, dat *d, int time_first)
{
    FILE *f = fopen(path, "r");
    char line[16384];
    int cap = 64;
    memset(d, 0, sizeof *d);
    if (!f) fail_msg("no file %s", path);
    d->v = sl_malloc((size_t)cap * sizeof *d->v, "rows");
    while (fgets(line, sizeof line, f)) {
        size_t len = strlen(line);
        if (len && line[len - 1] == '\n') line[--len] = '\0';
        if (line[0] == '#') {
            if (d->nrows) fail_msg("%s: header line after data", path);
            size_t used = strlen(d->header);
            snprintf(d->header + used, sizeof d->header - used, "%s\n", line);
            d->ncols = 0;
            char *save, *tok = strtok_r(line + 2, "\t", &save);
            while (tok && d->ncols < 64) {
                snprintf(d->col[d->ncols++], sizeof d->col[0], "%s", tok);
                tok = strtok_r(NULL, "\t", &save);
            }
            continue;
        }
        if (d->nrows == cap) d->v = sl_realloc(d->v, (size_t)(cap *= 2) * sizeof *d->v, "rows");
        int n = 0;
        char *save, *tok = strtok_r(line, "\t", &save);
        while (tok) {
            char *end;
            if (n >= 64) fail_msg("%s: too many values", path);
            d->v[d->nrows][n++] = strtod(tok, &end);
            if (*end) fail_msg("%s row %d: '%s' is not a number", path, d->nrows + 1, tok);
            tok = strtok_r(NULL, "\t", &save);
        }
        if (n != d->ncols)
            fail_msg("%s row %d: %d values, the header names %d columns", path, d->nrows + 1, n,
                     d->ncols);
        d->nrows++;
    }
    fclose(f);
    if (time_first && strcmp(d->col[0], "Time"))
        fail_msg("%s: the first column is '%s', not Time", path, d->col[0]);
}

static void dat_read(const char *path, dat *d) { dat_read_any(path, d, 1); }

static int dat_col(const dat *d, const char *name)
{
    for (int k = 0; k < d->ncols; k++)
        if (!strcmp(d->col[k], name)) return k;
    fail_msg("no column '%s'", name);
    return -1;
}

static const double *dat_row(const dat *d, double t)
{
    for (int r = 0; r < d->nrows; r++)
        if (fabs(d->v[r][0] - t) < 1e-9) return d->v[r];
    fail_msg("no row at time %g", t);
    return NULL;
}

static void dat_free(dat *d) { free(d->v); }

/* ======================================================================
 * VTK reader
 * ====================================================================== */

enum { FMT_ZLIB_SMALL, FMT_ZLIB, FMT_RAW, FMT_ASCII, NFMT };
static const char *const fmt_name[NFMT] = {"zlib64", "zlib", "raw", "ascii"};

static void fmt_options(int fmt, vtk_options *o, double time)
{
    vtk_options_default(o);
    o->time = time;
    if (fmt == FMT_ZLIB_SMALL) o->block_size = 64; /* many blocks, some ending exactly */
    if (fmt == FMT_RAW) o->compress = 0;
    if (fmt == FMT_ASCII) o->ascii = 1;
}

/* n points carrying one field of every type; values include -0, NaN,
 * infinities, extremes and denormals. */
typedef struct sample_data {
    size_t n;
    double *x, *y, *z, *u, *v, *w, *f64;
    float *f32;
    int32_t *i32;
    uint32_t *u32;
    int64_t *i64;
    uint8_t *u8;
} sample_data;

static void sample_make(sample_data *s, size_t n)
{
    static const double special[] = {0.0,     -0.0,        NAN, INFINITY, -INFINITY,
                                     DBL_MAX, DBL_MIN / 4, 0.1, 1e-300,   -123456.789};
    s->n = n;
    s->x = sl_calloc(n + 1, sizeof(double), "t");
    s->y = sl_calloc(n + 1, sizeof(double), "t");
    s->z = sl_calloc(n + 1, sizeof(double), "t");
    s->u = sl_calloc(n + 1, sizeof(double), "t");
    s->v = sl_calloc(n + 1, sizeof(double), "t");
    s->w = sl_calloc(n + 1, sizeof(double), "t");
    s->f64 = sl_calloc(n + 1, sizeof(double), "t");
    s->f32 = sl_calloc(n + 1, sizeof(float), "t");
    s->i32 = sl_calloc(n + 1, sizeof(int32_t), "t");
    s->u32 = sl_calloc(n + 1, sizeof(uint32_t), "t");
    s->i64 = sl_calloc(n + 1, sizeof(int64_t), "t");
    s->u8 = sl_calloc(n + 1, sizeof(uint8_t), "t");
    for (size_t i = 0; i < n; i++) {
        double a = (double)i;
        s->x[i] = 0.1 * a + 1.0 / 3.0;
        s->y[i] = -0.7 * a;
        s->z[i] = 1e-3 * a * a;
        s->u[i] = sin(a);
        s->v[i] = cos(a) * 1e5;
        s->w[i] = -a / 7.0;
        s->f64[i] = special[i % (sizeof special / sizeof *special)];
        s->f32[i] = (float)(a / 3.0) - 2.5f;
        s->i32[i] = (int32_t)(i % 2 ? -2147483647 - 1 : 2147483647) / (int32_t)(i + 1);
        s->u32[i] = i % 3 ? 4294967295u - (uint32_t)i : (uint32_t)i;
        s->i64[i] = (int64_t)(i % 2 ? -1 : 1) * ((int64_t)1 << 52) + (int64_t)i;
        s->u8[i] = (uint8_t)(i * 37);
    }
}

static void sample_free(sample_data *s)
{
    free(s->x);
    free(s->y);
    free(s->z);
    free(s->u);
    free(s->v);
    free(s->w);
    free(s->f64);
    free(s->f32);
    free(s->i32);
    free(s->u32);
    free(s->i64);
    free(s->u8);
}

static void sample_write(const sample_data *s, const char *path, int fmt, double time)
{
    vtk_options o;
    sl_err err;
    vtk_field fields[] = {
        {"velocity", 3, VTK_FLOAT64, {s->u, s->v, s->w}},
        {"special", 1, VTK_FLOAT64, {s->f64, NULL, NULL}},
        {"single", 1, VTK_FLOAT32, {s->f32, NULL, NULL}},
        {"int32", 1, VTK_INT32, {s->i32, NULL, NULL}},
        {"id & <name> \"quoted\"", 1, VTK_UINT32, {s->u32, NULL, NULL}},
        {"int64", 1, VTK_INT64, {s->i64, NULL, NULL}},
        {"bytes", 1, VTK_UINT8, {s->u8, NULL, NULL}},
        {"pair", 2, VTK_FLOAT64, {s->x, s->y, NULL}},
    };
    fmt_options(fmt, &o, time);
    if (vtk_write_points(path, s->n, s->x, s->y, s->z, fields, sizeof fields / sizeof *fields, &o,
                         &err))
        fail_msg("%s", err.msg);
}

static int same_double(double a, double b)
{
    return (isnan(a) && isnan(b)) || memcmp(&a, &b, sizeof a) == 0;
}

static void check_array(const vtkr_file *f, const char *name, int ncomp, const double *expect)
{
    const vtkr_array *a = vtkr_find(f, name);
    if (!a) fail_msg("no array '%s'", name);
    assert_int_equal(a->ncomp, ncomp);
    for (size_t i = 0; i < f->npoints * (size_t)ncomp; i++)
        if (!same_double(a->data[i], expect[i]))
            fail_msg("array '%s' value %zu: %.17g, expected %.17g", name, i, a->data[i], expect[i]);
}

static void check_sample(const sample_data *s, const vtkr_file *f, double time)
{
    size_t n = s->n;
    double *e = sl_calloc(3 * n + 1, sizeof *e, "expected");
    assert_int_equal(f->npoints, n);
    assert_int_equal(f->narrays, 8);
    if (isnan(time)) assert_true(isnan(f->time));
    else assert_true(same_double(f->time, time));
    for (size_t i = 0; i < n; i++) {
        double p[3] = {s->x[i], s->y[i], s->z[i]};
        for (int k = 0; k < 3; k++)
            if (!same_double(f->points[3 * i + (size_t)k], p[k])) fail_msg("point %zu differs", i);
    }
    for (size_t i = 0; i < n; i++) {
        e[3 * i] = s->u[i];
        e[3 * i + 1] = s->v[i];
        e[3 * i + 2] = s->w[i];
    }
    check_array(f, "velocity", 3, e);
    check_array(f, "special", 1, s->f64);
    for (size_t i = 0; i < n; i++) e[i] = (double)s->f32[i];
    check_array(f, "single", 1, e);
    for (size_t i = 0; i < n; i++) e[i] = (double)s->i32[i];
    check_array(f, "int32", 1, e);
    for (size_t i = 0; i < n; i++) e[i] = (double)s->u32[i];
    check_array(f, "id & <name> \"quoted\"", 1, e);
    for (size_t i = 0; i < n; i++) e[i] = (double)s->i64[i];
    check_array(f, "int64", 1, e);
    for (size_t i = 0; i < n; i++) e[i] = (double)s->u8[i];
    check_array(f, "bytes", 1, e);
    for (size_t i = 0; i < n; i++) {
        e[2 * i] = s->x[i];
        e[2 * i + 1] = s->y[i];
    }
    check_array(f, "pair", 2, e);
    assert_null(vtkr_find(f, "nothing"));
    free(e);
}

static void test_vtkr_roundtrip(void **state)
{
    (void)state;
    const size_t sizes[] = {0, 1, 5, 1000};
    assert_int_equal(sh("mkdir -p " OUT), 0);
    for (int fmt = 0; fmt < NFMT; fmt++)
        for (size_t k = 0; k < sizeof sizes / sizeof *sizes; k++) {
            char path[256];
            sample_data s;
            vtkr_file f;
            sl_err err;
            double time = k % 2 ? 0.125 : (double)NAN;
            snprintf(path, sizeof path, OUT "/rt_%s_%zu.vtu", fmt_name[fmt], sizes[k]);
            sample_make(&s, sizes[k]);
            sample_write(&s, path, fmt, time);
            if (vtkr_read(path, &f, &err)) fail_msg("%s", err.msg);
            check_sample(&s, &f, time);
            vtkr_free(&f);
            sample_free(&s);
        }
}

static void expect_error(const char *path, const char *what)
{
    vtkr_file f;
    sl_err err;
    if (vtkr_read(path, &f, &err) == 0) fail_msg("%s was accepted: %s", what, path);
    if (strncmp(err.msg, path, strlen(path)))
        fail_msg("error for %s does not name the file: %s", what, err.msg);
    assert_null(f.points);
    assert_int_equal(f.narrays, 0);
}

static void test_vtkr_missing(void **state)
{
    (void)state;
    assert_int_equal(sh("mkdir -p " OUT "/adir"), 0);
    expect_error(OUT "/no_such_file.vtu", "a missing file");
    expect_error(OUT "/adir", "a directory");
    spit(OUT "/empty.vtu", "", 0);
    expect_error(OUT "/empty.vtu", "an empty file");
    spit(OUT "/text.vtu", "hello", 5);
    expect_error(OUT "/text.vtu", "a text file");
}

static void test_vtkr_truncated(void **state)
{
    (void)state;
    for (int fmt = 0; fmt < NFMT; fmt++) {
        char path[256], cut[256];
        size_t len;
        sample_data s;
        snprintf(path, sizeof path, OUT "/tr_%s.vtu", fmt_name[fmt]);
        snprintf(cut, sizeof cut, OUT "/tr_%s_cut.vtu", fmt_name[fmt]);
        sample_make(&s, 5);
        sample_write(&s, path, fmt, 1.5);
        sample_free(&s);
        char *buf = slurp(path, &len);
        /* Every proper prefix is an error.  (The whitespace after the
         * closing tag is optional, so the prefix missing only the final
         * newline is a complete file.) */
        for (size_t n = 0; n + 1 < len; n++) {
            char what[64];
            spit(cut, buf, n);
            snprintf(what, sizeof what, "%s cut to %zu of %zu bytes", fmt_name[fmt], n, len);
            expect_error(cut, what);
        }
        free(buf);
    }
}

typedef struct mutation {
    int fmt; /* -1: all */
    const char *from, *to, *what;
} mutation;

/* Replace the first occurrence of from by to in buf (len), into out. */
static int replace_once(const char *buf, size_t len, const char *from, const char *to, char **out,
                        size_t *olen)
{
    const char *p = memmem(buf, len, from, strlen(from));
    if (!p) return 0;
    size_t a = (size_t)(p - buf), fl = strlen(from), tl = strlen(to);
    *olen = len - fl + tl;
    *out = sl_malloc(*olen + 1, "mutation");
    memcpy(*out, buf, a);
    memcpy(*out + a, to, tl);
    memcpy(*out + a + tl, p + fl, len - a - fl);
    return 1;
}

/* Where the appended data begin (after "_"), or fail. */
static size_t appended_start(const char *buf, size_t len)
{
    const char *p = memmem(buf, len, "<AppendedData encoding=\"raw\">", 29);
    assert_non_null(p);
    p = memchr(p, '_', len - (size_t)(p - buf));
    assert_non_null(p);
    return (size_t)(p - buf) + 1;
}

static void poke_u64(char *buf, size_t at, uint64_t v) { memcpy(buf + at, &v, 8); }
static uint64_t peek_u64(const char *buf, size_t at)
{
    uint64_t v;
    memcpy(&v, buf + at, 8);
    return v;
}

static void test_vtkr_corrupted(void **state)
{
    (void)state;
    static const mutation muts[] = {
        {-1, "header_type=\"UInt64\"", "header_type=\"UInt32\"", "UInt32 headers"},
        {-1, "type=\"UnstructuredGrid\"", "type=\"PolyData\"", "another dataset type"},
        {-1, "<UnstructuredGrid>", "<PolyData>", "another dataset element"},
        {-1, "NumberOfPoints=\"5\"", "NumberOfPoints=\"6\"", "a wrong point count"},
        {-1, "NumberOfPoints=\"5\"", "NumberOfPoints=\"5x\"", "a malformed point count"},
        {-1, "NumberOfPoints=\"5\"", "NumberOfPoints=\"99999999999999999999999\"",
         "a huge point count"},
        {-1, "NumberOfPoints=\"5\"", "NumberOfPoints=\"18446744073709551615\"",
         "a point count of 2^64-1"},
        {-1, "type=\"Float64\" Name=\"velocity\"", "type=\"Float65\" Name=\"velocity\"",
         "an unknown type"},
        {-1, "Name=\"velocity\" NumberOfComponents=\"3\"",
         "Name=\"velocity\" NumberOfComponents=\"0\"", "zero components"},
        {-1, "Name=\"Points\" NumberOfComponents=\"3\"", "Name=\"Points\" NumberOfComponents=\"2\"",
         "2D points"},
        {-1, "</Piece>", "</Peace>", "a misspelt closing tag"},
        {-1, "<Points>", "<Pints>", "an unknown section"},
        {-1, "</VTKFile>", "</VTKFilf>", "a wrong final tag"},
        {-1, "<?xml version=\"1.0\"?>", "<?xml version=\"1.0\"", "an unterminated declaration"},
        {-1, "Name=\"single\"", "Name=\"velocity\"", "two arrays of the same name"},
        {-1, "Name=\"bytes\"", "Name=\"a&bogus;b\"", "an unknown entity"},
        {-1, "Name=\"bytes\"", "Name=\"bytes", "an unterminated attribute"},
        {-1, "Name=\"connectivity\"", "Name=\"connectivities\"", "no connectivity"},
        {-1, "<Cells>",
         "<Cells><DataArray type=\"Int64\" Name=\"x\" format=\"ascii\">1 2</DataArray>",
         "a stray cell array"},
        {FMT_ASCII, "format=\"ascii\">", "format=\"ascii\">1 ", "an extra ascii value"},
        {FMT_ASCII, "format=\"ascii\">\n          ", "format=\"ascii\">\n          x",
         "a non-number"},
        {FMT_ASCII, "Name=\"bytes\" format=\"ascii\">\n          0 ",
         "Name=\"bytes\" format=\"ascii\">\n          256 ", "a UInt8 out of range"},
        {FMT_ASCII, "Name=\"int32\" format=\"ascii\">\n          2147483647",
         "Name=\"int32\" format=\"ascii\">\n          2147483648", "an Int32 out of range"},
        {FMT_ASCII,
         "Name=\"id &amp; &lt;name&gt; &quot;quoted&quot;\" format=\"ascii\">\n          0 ",
         "Name=\"id &amp; &lt;name&gt; &quot;quoted&quot;\" format=\"ascii\">\n          -1 ",
         "a negative UInt32"},
        {FMT_ASCII, "format=\"ascii\">", "format=\"binary\">", "inline binary"},
        {FMT_ZLIB, "format=\"appended\"", "format=\"binary\"", "inline binary"},
        {FMT_ZLIB, "encoding=\"raw\"", "encoding=\"base64\"", "base64 appended data"},
        {FMT_ZLIB, "offset=\"0\"", "offset=\"99999\"", "an offset past the data"},
        {FMT_ZLIB, "offset=\"0\"", "offset=\"-1\"", "a negative offset"},
        {FMT_ZLIB, " compressor=\"vtkZLibDataCompressor\"", "", "compressed data read as raw"},
        {FMT_ZLIB, "compressor=\"vtkZLibDataCompressor\"", "compressor=\"vtkLZ4DataCompressor\"",
         "another compressor"},
        {FMT_RAW, "byte_order=\"LittleEndian\"", "byte_order=\"BigEndian\"", "big-endian data"},
        {FMT_RAW, "header_type=\"UInt64\"",
         "header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\"",
         "raw data read as compressed"},
        {FMT_RAW, "</AppendedData>", "</AppendedData> ", "a space inside the trailer is fine"},
    };
    for (size_t m = 0; m < sizeof muts / sizeof *muts; m++)
        for (int fmt = FMT_ZLIB; fmt < NFMT; fmt++) {
            if (muts[m].fmt >= 0 && muts[m].fmt != fmt) continue;
            char path[256], bad[256], *out;
            size_t len, olen;
            sample_data s;
            snprintf(path, sizeof path, OUT "/co_%s.vtu", fmt_name[fmt]);
            snprintf(bad, sizeof bad, OUT "/co_%s_bad.vtu", fmt_name[fmt]);
            sample_make(&s, 5);
            sample_write(&s, path, fmt, 2.0);
            sample_free(&s);
            char *buf = slurp(path, &len);
            if (!replace_once(buf, len, muts[m].from, muts[m].to, &out, &olen))
                fail_msg("mutation '%s' does not apply to the %s file", muts[m].what,
                         fmt_name[fmt]);
            spit(bad, out, olen);
            if (strstr(muts[m].what, "is fine")) {
                vtkr_file f;
                sl_err err;
                if (vtkr_read(bad, &f, &err)) fail_msg("%s: %s", muts[m].what, err.msg);
                vtkr_free(&f);
            } else {
                expect_error(bad, muts[m].what);
            }
            free(out);
            free(buf);
        }

    /* Binary headers: the first array's sizes and the data after it. */
    for (int fmt = FMT_ZLIB; fmt <= FMT_RAW; fmt++) {
        char path[256], bad[256];
        size_t len;
        sample_data s;
        snprintf(path, sizeof path, OUT "/hd_%s.vtu", fmt_name[fmt]);
        snprintf(bad, sizeof bad, OUT "/hd_%s_bad.vtu", fmt_name[fmt]);
        sample_make(&s, 5);
        sample_write(&s, path, fmt, 2.0);
        sample_free(&s);
        char *buf = slurp(path, &len);
        size_t at = appended_start(buf, len); /* TimeValue: 1 Float64 */
        struct {
            size_t off;
            uint64_t delta;
            const char *what;
        } edits[] = {
            {0, 1, "a byte count or block count one too large"},
            {0, (uint64_t)-1, "a byte count or block count one too small"},
            {0, (uint64_t)1 << 62, "a huge byte or block count"},
            {16, 1, "a wrong last-block size or a data byte"},
            {24, 1, "a wrong compressed size"},
        };
        for (size_t e = 0; e < sizeof edits / sizeof *edits; e++) {
            if (fmt == FMT_RAW && edits[e].off > 0) continue; /* data bytes are not checkable */
            char *c = sl_malloc(len, "copy");
            memcpy(c, buf, len);
            poke_u64(c, at + edits[e].off, peek_u64(c, at + edits[e].off) + edits[e].delta);
            spit(bad, c, len);
            expect_error(bad, edits[e].what);
            free(c);
        }
        /* garbage between the last array and </AppendedData> */
        char *c = NULL;
        size_t clen;
        assert_true(
            replace_once(buf, len, "\n  </AppendedData>", "X\n  </AppendedData>", &c, &clen));
        spit(bad, c, clen);
        expect_error(bad, "bytes after the last array");
        free(c);
        /* a flipped bit inside the compressed stream of the last array */
        if (fmt == FMT_ZLIB) {
            char *d = sl_malloc(len, "copy");
            memcpy(d, buf, len);
            const char *end = memmem(buf, len, "\n  </AppendedData>", 18);
            d[(size_t)(end - buf) - 3] ^= 0x10;
            spit(bad, d, len);
            expect_error(bad, "a corrupt zlib block");
            free(d);
        }
        free(buf);
    }

    /* Random single-byte changes: anything but a crash (ASan watches). */
    srand(12345);
    for (int fmt = FMT_ZLIB_SMALL; fmt < NFMT; fmt++) {
        char path[256], bad[256];
        size_t len;
        sample_data s;
        int rejected = 0, trials = quick() ? 300 : 1500;
        snprintf(path, sizeof path, OUT "/rnd_%s.vtu", fmt_name[fmt]);
        snprintf(bad, sizeof bad, OUT "/rnd_%s_bad.vtu", fmt_name[fmt]);
        sample_make(&s, 7);
        sample_write(&s, path, fmt, 3.0);
        sample_free(&s);
        char *buf = slurp(path, &len);
        for (int k = 0; k < trials; k++) {
            size_t at = (size_t)rand() % len;
            char old = buf[at];
            buf[at] = (char)(rand() & 0xff);
            spit(bad, buf, len);
            buf[at] = old;
            vtkr_file f;
            sl_err err;
            if (vtkr_read(bad, &f, &err)) {
                rejected++;
                assert_int_equal(strncmp(err.msg, bad, strlen(bad)), 0);
            } else {
                assert_true(f.npoints == 7 || f.npoints < 100);
            }
            vtkr_free(&f);
        }
        print_message("%s: %d of %d random byte changes rejected\n", fmt_name[fmt], rejected,
                      trials);
        free(buf);
    }
}

/* ======================================================================
 * Function objects on a synthetic particle set
 * ====================================================================== */

typedef struct world {
    sl_fluid f;
    sl_boundary b;
    pcs_solver s;
    pcs_view v; /* what the function objects read */
} world;

static double urand(void) { return (double)rand() / ((double)RAND_MAX + 1.0); }

/* A jittered block of fluid over a floor of boundary particles, sorted in
 * a grid, with the boundary -> fluid lists built (as after a step). */
static void world_make(world *w, int nx, int ny, int nz)
{
    const double r0 = 0.1;
    memset(w, 0, sizeof *w);
    prt_fluid_init(&w->f);
    prt_boundary_init(&w->b);
    pcs_solver *s = &w->s;
    s->prm.rho0 = 1000;
    s->prm.r0 = r0;
    s->prm.gravity[2] = -9.81;
    s->h = 2 * r0;
    s->mass = 1000 * r0 * r0 * r0;
    krn_init(&s->k, s->h);
    s->f = &w->f;
    s->b = &w->b;
    for (int i = 0; i < nx; i++)
        for (int j = 0; j < ny; j++) {
            prt_boundary_push(&w->b, (i + 0.5) * r0, (j + 0.5) * r0, -0.5 * r0, 0, 0, 1, 0);
            w->b.mass[w->b.n - 1] = 0.8 * s->mass;
            w->b.rho[w->b.n - 1] = 1000 + 10 * urand();
            w->b.p[w->b.n - 1] = 500 + 100 * urand();
            for (int k = 0; k < nz; k++) {
                prt_fluid_push(&w->f, (i + 0.5 + 0.2 * (urand() - 0.5)) * r0,
                               (j + 0.5 + 0.2 * (urand() - 0.5)) * r0,
                               (k + 0.5 + 0.2 * (urand() - 0.5)) * r0, urand(), urand(), urand());
                w->f.rho[w->f.n - 1] = 990 + 20 * urand();
                w->f.p[w->f.n - 1] = 1000 * urand();
            }
        }
    const double lo[3] = {-r0, -r0, -r0}, hi[3] = {(nx + 1) * r0, (ny + 1) * r0, (nz + 1) * r0};
    nbr_grid_init(&s->grid, lo, hi, s->h, 1 << 20);
    nbr_sort_boundary(&s->grid, &w->b);
    nbr_sort_fluid(&s->grid, &w->f);
    nbr_list_init(&s->bf);
    s->active = sl_alloc_aligned((w->b.n + 1) * sizeof *s->active, "active");
    nbr_build_bf(&s->grid, &w->f, &w->b, &s->bf, s->active, &s->nactive);
    w->v = pcs_view_of(s);
}

static void world_free(world *w)
{
    nbr_grid_free(&w->s.grid);
    nbr_list_free(&w->s.bf);
    sl_free_aligned(w->s.active);
    prt_fluid_free(&w->f);
    prt_boundary_free(&w->b);
}

/* Grid queries equal brute force at random points (and outside). */
static void compare_queries(fo_index *ix, int npts)
{
    for (int q = 0; q < npts; q++) {
        double x = -0.3 + 1.6 * urand(), y = -0.3 + 1.6 * urand(), z = -0.3 + 1.3 * urand();
        fo_sample a, b;
        ix->use_grid = 1;
        fo_query_sample(ix, x, y, z, &a);
        double ca = fo_query_colour(ix, x, y, z);
        ix->use_grid = 0;
        fo_query_sample(ix, x, y, z, &b);
        double cb = fo_query_colour(ix, x, y, z);
        assert_int_equal(a.n, b.n);
        assert_close(a.pressure, b.pressure, 1e-12);
        assert_close(a.density, b.density, 1e-12);
        for (int k = 0; k < 3; k++) assert_close(a.velocity[k], b.velocity[k], 1e-12);
        assert_close(ca, cb, 1e-12);
    }
}

static void test_fo_query_grid(void **state)
{
    (void)state;
    world w;
    fo_index ix = {0};
    srand(7);
    world_make(&w, 10, 10, 6);
    fo_index_update(&ix, &w.v);
    assert_true(ix.use_grid);
    compare_queries(&ix, 400);
    /* far away: nothing within h */
    fo_sample far;
    fo_query_sample(&ix, 50, 50, 50, &far);
    assert_int_equal(far.n, 0);
    assert_true(isnan(far.pressure) && isnan(far.velocity[2]));
    /* inside the fluid the colour is about 1 */
    double c = fo_query_colour(&ix, 0.5, 0.5, 0.3);
    assert_true(c > 0.8 && c < 1.2);
    /* particles moved by up to 0.9 cells since the sort: still usable */
    for (size_t i = 0; i < w.f.n; i++) {
        w.f.x[i] += 0.9 * w.s.grid.cell * (2 * urand() - 1);
        w.f.z[i] += 0.9 * w.s.grid.cell * (2 * urand() - 1);
    }
    fo_index_update(&ix, &w.v);
    assert_true(ix.use_grid);
    compare_queries(&ix, 400);
    /* one particle jumped three cells: the grid no longer describes it */
    w.f.x[3] += 3 * w.s.grid.cell;
    fo_index_update(&ix, &w.v);
    assert_false(ix.use_grid);
    w.f.x[3] -= 3 * w.s.grid.cell;
    /* particles in another order (a restored state): detected */
    double t = w.f.x[0];
    w.f.x[0] = w.f.x[w.f.n - 1];
    w.f.x[w.f.n - 1] = t;
    fo_index_update(&ix, &w.v);
    assert_false(ix.use_grid);
    /* a particle more than the grid knows */
    w.f.n--;
    fo_index_update(&ix, &w.v);
    assert_false(ix.use_grid);
    fo_index_free(&ix);
    world_free(&w);
}

static fo_list *list_from(const char *text, const char *dir)
{
    sl_err err;
    dict *d = dict_parse_string(text, "test functions", &err);
    if (!d) fail_msg("%s", err.msg);
    fo_list *l = fo_read_dict(dict_sub(d, "functions"), dir, 6);
    dict_free(d);
    return l;
}

static void test_fo_read(void **state)
{
    (void)state;
    sl_err err;
    assert_null(fo_read_dict(NULL, OUT, 6));
    assert_null(list_from("functions { }", OUT));
    assert_null(list_from("functions { a { type energy; enabled off; } }", OUT));
    fo_execute(NULL, NULL, 0.0, 0, 1); /* no objects: nothing happens */
    fo_free(NULL);
    assert_int_equal(fo_needs(NULL), 0);
    /* the annotated file names every type, and is valid */
    dict *d = dict_read_file("etc/caseDicts/functions", &err);
    if (!d) fail_msg("%s", err.msg);
    fo_list *l = fo_read_dict(dict_sub(d, "functions"), OUT "/etc", 6);
    dict_free(d);
    assert_non_null(l);
    assert_int_equal(fo_count(l), 5);
    const char *types[5] = {"densityError", "probes", "waterGauges", "energy", "power"};
    for (size_t i = 0; i < 5; i++) assert_string_equal(fo_type_name(l, i), types[i]);
    assert_int_equal(fo_needs(l), FO_NEED_BOUNDARY | FO_NEED_GRID | FO_NEED_POWER);
    fo_free(l);
}

/* Rows a shock rolls back are replaced; writeTime control counts writes;
 * a new start time opens a new folder. */
static void test_fo_rows(void **state)
{
    (void)state;
    world w;
    srand(3);
    world_make(&w, 3, 3, 3);
    assert_int_equal(sh("rm -rf " OUT "/rows && mkdir -p " OUT "/rows"), 0);
    fo_list *l = list_from("functions { e { type energy; }"
                           " w { type energy; writeControl writeTime; writeInterval 2; }"
                           " d { type densityError; writeInterval 2; percentiles (); histogram on;"
                           " histogramBins 4; histogramRange (-2 2); } }",
                           OUT "/rows");
    const double times[] = {0, 1, 2, 3, 4, 3, 4, 5, 6};
    const long steps[] = {0, 1, 2, 3, 4, 3, 4, 5, 6};
    for (size_t k = 0; k < sizeof times / sizeof *times; k++)
        fo_execute(l, &w.v, times[k], steps[k], (long)times[k] % 2 == 0);
    fo_free(l);
    dat e, wt, de;
    dat_read(OUT "/rows/postProcessing/e/0/energy.dat", &e);
    assert_int_equal(e.nrows, 7);
    for (int r = 0; r < e.nrows; r++) assert_close(e.v[r][0], (double)r, 0);
    assert_int_equal(e.ncols, 4);
    /* potential = m g sum z */
    double pot = 0;
    for (size_t i = 0; i < w.f.n; i++) pot += w.s.mass * 9.81 * w.f.z[i];
    assert_close(e.v[6][dat_col(&e, "potential")], pot, 1e-9);
    dat_read(OUT "/rows/postProcessing/w/0/energy.dat", &wt);
    /* write times 0 2 4 (4 again after the roll back) 6: every second */
    assert_int_equal(wt.nrows, 2);
    assert_close(wt.v[0][0], 0, 0);
    dat_read(OUT "/rows/postProcessing/d/0/densityError.dat", &de);
    assert_int_equal(de.ncols, 6);
    assert_int_equal(de.nrows, 4); /* steps 0 2 4 6 */
    assert_true(exists(OUT "/rows/postProcessing/d/0/histogram_4.dat"));
    dat h;
    dat_read_any(OUT "/rows/postProcessing/d/0/histogram_6.dat", &h, 0);
    assert_int_equal(h.nrows, 4);
    dat_free(&h);
    dat_free(&e);
    dat_free(&wt);
    dat_free(&de);
    /* a restart at t = 6: a new folder, and no row for the start */
    l = list_from("functions { e { type energy; } }", OUT "/rows");
    fo_start(l, &w.v, 6);
    fo_execute(l, &w.v, 7, 7, 0);
    fo_free(l);
    dat_read(OUT "/rows/postProcessing/e/6/energy.dat", &e);
    assert_int_equal(e.nrows, 1);
    assert_close(e.v[0][0], 7, 0);
    dat_free(&e);
    dat_read(OUT "/rows/postProcessing/e/0/energy.dat", &e);
    assert_int_equal(e.nrows, 7);
    dat_free(&e);
    world_free(&w);
}

/* Bad entries stop postProcess (and the solver, which reads them the same
 * way) with file, line and key. */
static void test_fo_errors(void **state)
{
    (void)state;
    /* line: whether the message must name the entry's line */
    static const struct {
        const char *entry, *expect;
        int line;
    } bad[] = {
        {"x { type pressureProbe; }",
         "keyword 'type' in function object 'x': unknown type 'pressureProbe'; valid types: "
         "densityError, probes, waterGauges, energy, power",
         1},
        {"x { type probes; }",
         "controlDict: missing required keyword 'probeLocations' in function object 'x'", 0},
        {"x { type probes; probeLocations ((1 2) (3 4)); }",
         "keyword 'probeLocations' in function object 'x': every point must be (x y z)", 1},
        {"x { type probes; probeLocations (); }", "needs at least one point", 1},
        {"x { type probes; probeLocations ((0 0 0)); fields (pressure temperature); }",
         "unknown field 'temperature'; valid fields: pressure density velocity", 1},
        {"x { type waterGauges; gaugeLocations ((0 0 0)); }", "every location must be (x y)", 1},
        {"x { type energy; writeControl runTime; }",
         "keyword 'writeControl' in function object 'x': 'runTime' is not one of: timeStep "
         "writeTime",
         1},
        {"x { type energy; writeInterval 0; }",
         "keyword 'writeInterval' in function object 'x': must be a whole number", 1},
        {"x { type densityError; percentiles (50 101); }",
         "every percentile must be between 0 and 100", 1},
        {"x { type densityError; histogramRange (1 0); }", "keyword 'histogramRange'", 1},
        {"x 3;", "function object 'x' must be a dictionary", 1},
    };
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        assert_int_equal(sh("rm -rf " OUT "/bad && mkdir -p " OUT
                            " && cp -r tests/cases/hydrostaticTank " OUT "/bad"),
                         0);
        /* the entry's line: after the file's lines and "functions", "{" */
        char *old = slurp(OUT "/bad/system/controlDict", NULL);
        int line = 1;
        for (const char *c = old; *c; c++) line += *c == '\n';
        if (old[0] && old[strlen(old) - 1] != '\n') line++;
        free(old);
        FILE *f = fopen(OUT "/bad/system/controlDict", "a");
        assert_non_null(f);
        fprintf(f, "\nfunctions\n{\n%s\n}\n", bad[k].entry);
        fclose(f);
        line += 3;
        char where[64];
        snprintf(where, sizeof where, "controlDict:%d: ", line);
        int rc = sh("%s/postProcess -case " OUT "/bad > " OUT "/bad/log 2>&1", bin_dir());
        char *text = slurp(OUT "/bad/log", NULL);
        if (rc == 0 || !strstr(text, bad[k].expect) || (bad[k].line && !strstr(text, where)))
            fail_msg("entry '%s': exit %d, expected '%s%s' in:\n%s", bad[k].entry, rc,
                     bad[k].line ? where : "", bad[k].expect, text);
        hostile_record("system/controlDict functions", bad[k].entry, text);
        free(text);
        /* the solver stops on it too, before writing anything */
        rc = sh("%s/pcisph -case " OUT "/bad -quiet > " OUT "/bad/log 2>&1", bin_dir());
        assert_int_not_equal(rc, 0);
        assert_false(exists(OUT "/bad/0"));
    }
    /* -func naming neither an entry nor a type */
    int rc =
        sh("%s/postProcess -case tests/cases/hydrostaticTank -func nothing > " OUT "/bad/log 2>&1",
           bin_dir());
    char *text = slurp(OUT "/bad/log", NULL);
    assert_int_not_equal(rc, 0);
    assert_non_null(strstr(text, "'nothing' is neither a function object"));
    free(text);
}

/* ======================================================================
 * A short solver run, checked against its own VTK files
 * ====================================================================== */

static const char tank_functions[] =
    "endTime 0.1;\n"
    "writeInterval 0.05;\n"
    "functions\n"
    "{\n"
    "    densityError { type densityError; writeControl timeStep; writeInterval 1;\n"
    "                   percentiles (50 90 99); histogram on; }\n"
    "    probes { type probes; fields (pressure density velocity);\n"
    "             probeLocations ((0.15 0.15 0.1) (0.05 0.2 0.0) (0.15 0.15 0.55)); }\n"
    "    gauges { type waterGauges; gaugeLocations ((0.15 0.15) (0.03 0.27)); zRange (0 0.6); }\n"
    "    energy { type energy; writeControl writeTime; }\n"
    "}\n";

static const double R0 = 0.025, RHO0 = 1000, G = 9.81;

typedef struct snapshot {
    vtkr_file f, b;
    const double *rho, *p, *v, *brho, *bp, *bm;
} snapshot;

static void snap_load(snapshot *s, const char *time)
{
    char path[256];
    sl_err err;
    snprintf(path, sizeof path, TANK "/%s/fluid.vtu", time);
    if (vtkr_read(path, &s->f, &err)) fail_msg("%s", err.msg);
    snprintf(path, sizeof path, TANK "/%s/boundary.vtu", time);
    if (vtkr_read(path, &s->b, &err)) fail_msg("%s", err.msg);
    s->rho = vtkr_find(&s->f, "density")->data;
    s->p = vtkr_find(&s->f, "pressure")->data;
    s->v = vtkr_find(&s->f, "velocity")->data;
    s->brho = vtkr_find(&s->b, "density")->data;
    s->bp = vtkr_find(&s->b, "pressure")->data;
    s->bm = vtkr_find(&s->b, "mass")->data;
}

static void snap_unload(snapshot *s)
{
    vtkr_free(&s->f);
    vtkr_free(&s->b);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Linear interpolation between order statistics (as GSL). */
static double quantile(const double *sorted, size_t n, double f)
{
    double idx = f * (double)(n - 1);
    size_t lo = (size_t)floor(idx);
    double d = idx - (double)lo;
    return lo + 1 < n ? (1 - d) * sorted[lo] + d * sorted[lo + 1] : sorted[lo];
}

static void check_density_error(const dat *d, const snapshot *s, double t)
{
    const double *row = dat_row(d, t);
    size_t n = s->f.npoints;
    double *c = sl_malloc(n * sizeof *c, "c"), sum = 0, sums = 0, mx = -INFINITY, mn = INFINITY;
    for (size_t i = 0; i < n; i++) {
        double e = 100 * (s->rho[i] - RHO0) / RHO0;
        c[i] = e > 0 ? e : 0;
        sum += c[i];
        sums += e;
        mx = fmax(mx, e);
        mn = fmin(mn, e);
    }
    qsort(c, n, sizeof *c, cmp_double);
    assert_close(row[dat_col(d, "average")], sum / (double)n, 1e-8);
    assert_close(row[dat_col(d, "maximum")], c[n - 1], 1e-8);
    assert_close(row[dat_col(d, "averageSigned")], sums / (double)n, 1e-8);
    assert_close(row[dat_col(d, "minimumSigned")], mn, 1e-8);
    assert_close(row[dat_col(d, "maximumSigned")], mx, 1e-8);
    assert_close(row[dat_col(d, "p50")], quantile(c, n, 0.5), 1e-8);
    assert_close(row[dat_col(d, "p90")], quantile(c, n, 0.9), 1e-8);
    assert_close(row[dat_col(d, "p99")], quantile(c, n, 0.99), 1e-8);
    free(c);
}

static void check_energy(const dat *d, const snapshot *s, double t)
{
    const double *row = dat_row(d, t), m = RHO0 * R0 * R0 * R0;
    double kin = 0, pot = 0;
    for (size_t i = 0; i < s->f.npoints; i++) {
        const double *v = s->v + 3 * i;
        kin += 0.5 * m * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        pot += m * G * s->f.points[3 * i + 2];
    }
    assert_close(row[dat_col(d, "kinetic")], kin, 1e-8);
    assert_close(row[dat_col(d, "potential")], pot, 1e-8);
    assert_close(row[dat_col(d, "total")], kin + pot, 1e-8);
}

static double dist2(const double *a, double x, double y, double z)
{
    return (a[0] - x) * (a[0] - x) + (a[1] - y) * (a[1] - y) + (a[2] - z) * (a[2] - z);
}

/* Shepard interpolation over all particles; a boundary particle counts if
 * some fluid particle is within h of it. */
static void shepard(const snapshot *s, const double q[3], double out[5])
{
    const double h = 2 * R0, m = RHO0 * R0 * R0 * R0;
    krn_kernel k;
    double vw = 0, acc[5] = {0};
    krn_init(&k, h);
    for (size_t j = 0; j < s->f.npoints; j++) {
        double r2 = dist2(s->f.points + 3 * j, q[0], q[1], q[2]);
        if (r2 >= h * h) continue;
        double w = m / s->rho[j] * krn_w(&k, sqrt(r2));
        vw += w;
        acc[0] += w * s->p[j];
        acc[1] += w * s->rho[j];
        for (int c = 0; c < 3; c++) acc[2 + c] += w * s->v[3 * j + (size_t)c];
    }
    for (size_t j = 0; j < s->b.npoints; j++) {
        const double *x = s->b.points + 3 * j;
        double r2 = dist2(x, q[0], q[1], q[2]);
        if (r2 >= h * h) continue;
        int active = 0;
        for (size_t i = 0; i < s->f.npoints && !active; i++)
            active = dist2(s->f.points + 3 * i, x[0], x[1], x[2]) < h * h;
        if (!active) continue;
        double w = s->bm[j] / s->brho[j] * krn_w(&k, sqrt(r2));
        vw += w;
        acc[0] += w * s->bp[j];
        acc[1] += w * s->brho[j];
    }
    for (int c = 0; c < 5; c++) out[c] = vw > 0 ? acc[c] / vw : (double)NAN;
}

static const double probe_at[3][3] = {{0.15, 0.15, 0.1}, {0.05, 0.2, 0.0}, {0.15, 0.15, 0.55}};

static void check_probes(const dat *d, const snapshot *s, double t)
{
    const double *row = dat_row(d, t);
    for (int i = 0; i < 3; i++) {
        double e[5], got[5];
        char name[64];
        shepard(s, probe_at[i], e);
        snprintf(name, sizeof name, "pressure_%d", i);
        got[0] = row[dat_col(d, name)];
        snprintf(name, sizeof name, "density_%d", i);
        got[1] = row[dat_col(d, name)];
        for (int c = 0; c < 3; c++) {
            snprintf(name, sizeof name, "velocity_%d_%c", i, "xyz"[c]);
            got[2 + c] = row[dat_col(d, name)];
        }
        for (int c = 0; c < 5; c++) assert_close(got[c], e[c], 1e-8);
    }
    assert_true(isnan(row[dat_col(d, "pressure_2")]));  /* 0.55: above the water */
    assert_false(isnan(row[dat_col(d, "pressure_1")])); /* on the floor */
}

static double colour(const snapshot *s, double x, double y, double z)
{
    const double h = 2 * R0, m = RHO0 * R0 * R0 * R0;
    krn_kernel k;
    double c = 0;
    krn_init(&k, h);
    for (size_t j = 0; j < s->f.npoints; j++) {
        double r2 = dist2(s->f.points + 3 * j, x, y, z);
        if (r2 < h * h) c += m / s->rho[j] * krn_w(&k, sqrt(r2));
    }
    return c;
}

/* The documented scan over multiples of r0/4 in zRange (0 0.6). */
static double gauge(const snapshot *s, double x, double y)
{
    const double dz = R0 / 4;
    double above = NAN;
    for (long k = (long)floor(0.6 / dz); k >= 0; k--) {
        double z = (double)k * dz, c = colour(s, x, y, z);
        if (c >= 0.5) return isnan(above) ? z : z + dz * (c - 0.5) / (c - above);
        above = c;
    }
    return NAN;
}

static void check_gauges(const dat *d, const snapshot *s, double t)
{
    const double *row = dat_row(d, t);
    assert_close(row[dat_col(d, "height_0")], gauge(s, 0.15, 0.15), 1e-8);
    assert_close(row[dat_col(d, "height_1")], gauge(s, 0.03, 0.27), 1e-8);
    assert_true(fabs(row[dat_col(d, "height_0")] - 0.4) < R0 / 2);
}

static int run_tank(const char *functions, const char *extra_dict)
{
    if (sh("rm -rf " TANK " && mkdir -p " OUT " && cp -r tests/cases/hydrostaticTank " TANK))
        return -1;
    FILE *f = fopen(TANK "/system/controlDict", "a");
    if (!f) return -1;
    fprintf(f, "\n%s%s", functions, extra_dict ? extra_dict : "");
    fclose(f);
    return sh("%s/pcisph -case " TANK " -quiet > " TANK "/log.pcisph 2>&1", bin_dir());
}

static void test_run_short(void **state)
{
    (void)state;
    assert_int_equal(run_tank(tank_functions, NULL), 0);
    if (!exists(TANK "/postProcessing/densityError/0/densityError.dat"))
        fail_msg("pcisph wrote no function-object output: does applications/solvers/pcisph/"
                 "pcisph.c call fo_read/fo_execute?");
    dat de, pr, ga, en;
    dat_read(TANK "/postProcessing/densityError/0/densityError.dat", &de);
    dat_read(TANK "/postProcessing/probes/0/probes.dat", &pr);
    dat_read(TANK "/postProcessing/gauges/0/waterGauges.dat", &ga);
    dat_read(TANK "/postProcessing/energy/0/energy.dat", &en);
    /* rows: every step (0.1 s of 0.002 s and the start) or every write */
    dat ts;
    dat_read(TANK "/postProcessing/timeStep/0/timeStep.dat", &ts);
    assert_int_equal(de.nrows, ts.nrows + 1);
    assert_int_equal(pr.nrows, ts.nrows + 1);
    assert_int_equal(ga.nrows, ts.nrows + 1);
    assert_int_equal(en.nrows, 3);
    dat_free(&ts);
    assert_int_equal(de.ncols, 9);
    assert_int_equal(pr.ncols, 1 + 3 * 5);
    assert_int_equal(ga.ncols, 3);
    assert_int_equal(en.ncols, 4);
    assert_non_null(strstr(de.header, "max(rho - rho0, 0) / rho0"));
    assert_non_null(strstr(pr.header, "# Probe 1 (0.05 0.2 0)"));
    const char *times[2] = {"0.05", "0.1"};
    for (int k = 0; k < 2; k++) {
        snapshot s;
        double t = atof(times[k]);
        char path[256];
        snap_load(&s, times[k]);
        check_density_error(&de, &s, t);
        check_energy(&en, &s, t);
        check_probes(&pr, &s, t);
        check_gauges(&ga, &s, t);
        /* the histogram counts every particle */
        dat h;
        snprintf(path, sizeof path, TANK "/postProcessing/densityError/0/histogram_%s.dat",
                 times[k]);
        dat_read_any(path, &h, 0);
        assert_string_equal(h.col[0], "binStart");
        double count = 0;
        for (int r = 0; r < h.nrows; r++) count += h.v[r][2];
        assert_int_equal((size_t)count, s.f.npoints);
        dat_free(&h);
        snap_unload(&s);
    }
    assert_true(exists(TANK "/postProcessing/densityError/0/histogram_0.dat"));

    /* postProcess on the written times reproduces the run's rows */
    assert_int_equal(
        sh("%s/postProcess -case " TANK " -time 0.05:1 > " TANK "/log.postProcess 2>&1", bin_dir()),
        0);
    const char *files[4][2] = {{"densityError", "densityError"},
                               {"probes", "probes"},
                               {"gauges", "waterGauges"},
                               {"energy", "energy"}};
    const dat *run[4] = {&de, &pr, &ga, &en};
    for (int k = 0; k < 4; k++) {
        char path[256];
        dat p;
        snprintf(path, sizeof path, TANK "/postProcessing/%s/0.05/%s.dat", files[k][0],
                 files[k][1]);
        dat_read(path, &p);
        assert_int_equal(p.nrows, 2);
        assert_int_equal(p.ncols, run[k]->ncols);
        for (int r = 0; r < 2; r++) {
            const double *a = p.v[r], *b = dat_row(run[k], p.v[r][0]);
            for (int c = 0; c < p.ncols; c++)
                if (!close_to(a[c], b[c], 1e-8))
                    fail_msg("%s column %s at t = %g: postProcess %.10g, run %.10g", files[k][0],
                             p.col[c], a[0], a[c], b[c]);
        }
        dat_free(&p);
    }
    /* -func with a type's defaults, -latestTime */
    assert_int_equal(sh("%s/postProcess -case " TANK " -func energy -func densityError "
                        "-latestTime > " TANK "/log.postProcess 2>&1",
                        bin_dir()),
                     0);
    assert_true(exists(TANK "/postProcessing/energy/0.1/energy.dat"));

    /* a restart writes a new start-time folder and leaves the old one */
    assert_int_equal(sh("sed -i 's/^endTime 0.1;/endTime 0.15;/' " TANK "/system/controlDict && "
                        "echo 'startFrom latestTime;' >> " TANK "/system/controlDict && "
                        "%s/pcisph -case " TANK " -quiet > " TANK "/log.restart 2>&1",
                        bin_dir()),
                     0);
    dat again;
    dat_read(TANK "/postProcessing/densityError/0.1/densityError.dat", &again);
    assert_true(again.nrows > 10);
    assert_close(again.v[0][0], 0.102, 0); /* the state at 0.1 is in the first run's file */
    dat_free(&again);
    dat_read(TANK "/postProcessing/densityError/0/densityError.dat", &again);
    assert_int_equal(again.nrows, de.nrows);
    dat_free(&again);

    /* densityError: all times, same columns, a plot */
    assert_int_equal(
        sh("%s/densityError -case " TANK " -time :0.1 > " TANK "/log.densityError 2>&1", bin_dir()),
        0);
    dat u;
    dat_read(TANK "/postProcessing/densityError/0/densityError.dat", &u);
    assert_int_equal(u.nrows, 3);
    assert_int_equal(u.ncols, de.ncols);
    for (int c = 0; c < u.ncols; c++) assert_string_equal(u.col[c], de.col[c]);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < u.ncols; c++) assert_close(u.v[r][c], dat_row(&de, u.v[r][0])[c], 1e-8);
    dat_free(&u);
    if (sh("command -v gnuplot > /dev/null") == 0) {
        size_t len;
        char *png = slurp(TANK "/postProcessing/densityError/0/densityError.png", &len);
        assert_true(len > 1000 && !memcmp(png, "\x89PNG", 4));
        free(png);
    } else {
        print_message("gnuplot not installed: densityError.png not checked\n");
    }
    dat_free(&de);
    dat_free(&pr);
    dat_free(&ga);
    dat_free(&en);
}


/* ======================================================================
 * Runs, restarts and the End summary
 * ====================================================================== */

#define RUNS OUT "/runs"

/* RUNS/<name>: a copy of tests/cases/<src>, the shell `edit` run in it. */
static void run_copy(const char *src, const char *name, const char *edit)
{
    assert_int_equal(sh("rm -rf " RUNS "/%s && mkdir -p " RUNS " && cp -r tests/cases/%s " RUNS
                        "/%s && cd " RUNS "/%s && %s",
                        name, src, name, name, edit),
                     0);
}

/* Set `key value;` in system/controlDict of RUNS/<name>. */
static void control(const char *name, const char *key, const char *value)
{
    assert_int_equal(sh("cd " RUNS "/%s && (grep -v '^%s ' system/controlDict; echo '%s %s;') > "
                        "c.new && mv c.new system/controlDict",
                        name, key, key, value),
                     0);
}

/* Run the solver (one thread) on RUNS/<name>; its output goes to
 * RUNS/<name>.<log>.log and is returned (free it). */
static char *solve(const char *name, const char *args, const char *log)
{
    int rc = sh("OMP_NUM_THREADS=1 %s/pcisph -case " RUNS "/%s -quiet %s > " RUNS "/%s.%s.log 2>&1",
                bin_dir(), name, args, name, log);
    char path[512];
    snprintf(path, sizeof path, RUNS "/%s.%s.log", name, log);
    char *text = slurp(path, NULL);
    if (rc != 0) fail_msg("pcisph on %s %s: exit %d:\n%s", name, args, rc, text);
    return text;
}

static int same_bytes(const char *a, const char *b) { return sh("cmp -s %s %s", a, b) == 0; }

/* Every time directory of RUNS/<a> from time `from` on is in RUNS/<b>
 * under the same name with the same fluid.vtu and boundary.vtu, byte for
 * byte; returns how many were compared. */
static int compare_from(const char *a, const char *b, double from)
{
    char path[512];
    snprintf(path, sizeof path, RUNS "/%s", a);
    tdir_list l;
    sl_err err;
    if (tdir_list_read(path, "fluid.vtu", &l, &err)) fail_msg("%s", err.msg);
    int n = 0;
    for (size_t i = 0; i < l.n; i++) {
        if (l.time[i] < from - 1e-12) continue;
        for (int k = 0; k < 2; k++) {
            char pa[512], pb[512];
            const char *file = k ? "boundary.vtu" : "fluid.vtu";
            snprintf(pa, sizeof pa, RUNS "/%s/%s/%s", a, l.name[i], file);
            snprintf(pb, sizeof pb, RUNS "/%s/%s/%s", b, l.name[i], file);
            if (!exists(pb)) fail_msg("%s has no %s/%s", b, l.name[i], file);
            if (!same_bytes(pa, pb)) fail_msg("%s differs between %s and %s", pb, a, b);
        }
        n++;
    }
    tdir_list_free(&l);
    return n;
}

/* The number after `key` in text (the first one); fails if absent. */
static double number_after(const char *text, const char *key)
{
    const char *at = strstr(text, key);
    if (!at) fail_msg("no '%s' in:\n%s", key, text);
    return strtod(at + strlen(key), NULL);
}

/* Item 6: a restart at an awkward time with an awkward write interval
 * continues bit-identically; item 7: the End summary after it counts this
 * session and the whole run apart. */
static void test_restart_awkward_time(void **state)
{
    (void)state;
    const char *adaptive = "printf 'mode adaptive;\\ndeltaT 0;\\n' > system/timeStepDict";
    run_copy("damBreakShort", "awkwardA", adaptive);
    control("awkwardA", "writeInterval", "0.0017");
    control("awkwardA", "endTime", "0.0306");
    run_copy("damBreakShort", "awkwardB", adaptive);
    control("awkwardB", "writeInterval", "0.0017");
    control("awkwardB", "endTime", "0.0187");
    char *a = solve("awkwardA", "", "run"), *b = solve("awkwardB", "", "run");
    control("awkwardB", "endTime", "0.0306");
    control("awkwardB", "startFrom", "latestTime");
    char *c = solve("awkwardB", "", "restart");
    assert_non_null(strstr(c, "Restarting from"));
    int n = compare_from("awkwardA", "awkwardB", 0.0187);
    print_message("restart from 0.0187 (writeInterval 0.0017): %d time directories equal\n", n);
    assert_true(n >= 7);
    /* the summaries: steps and mean iterations of each part */
    double all = number_after(a, "End: "), first = number_after(b, "End: ");
    double session = number_after(c, "End: this session: ");
    double whole = number_after(c, "  whole run: ");
    print_message("steps: uninterrupted %g, first part %g, restart session %g, whole run %g\n", all,
                  first, session, whole);
    assert_true(whole == all && session == all - first);
    const char *line = strstr(c, "End: this session: ");
    assert_close(number_after(line, "mean iterations "), 3.0, 0); /* adaptive: 3 per step */
    assert_close(number_after(strstr(c, "  whole run: "), "mean iterations "), 3.0, 0);
    free(a);
    free(b);
    free(c);
}

/* Item 6: restarted right before a shock, the run goes back past the
 * restart time as the uninterrupted one does: the restart file keeps the
 * state at the start of the step before (with the warm-started divergence
 * source, the pressures and densities it carries too: the rollback
 * restores them).  edit: the case's edit; the write intervals tried, n of
 * them; endTime end. */
static void restart_before_shock(const char *edit, const double *intervals, int n,
                                 const char *end_time)
{
    double w = -1, wi = 0;
    for (int i = 0; i < n && w < 0; i++) {
        char value[32];
        wi = intervals[i];
        snprintf(value, sizeof value, "%g", wi);
        run_copy("highDrop", "shockA", edit);
        control("shockA", "endTime", end_time);
        control("shockA", "writeInterval", value);
        free(solve("shockA", "", "run"));
        dat ts;
        dat_read(RUNS "/shockA/postProcessing/timeStep/0/timeStep.dat", &ts);
        for (int r = 2; r < ts.nrows && w < 0; r++) {
            if (ts.v[r][7] != 1) continue;
            double t = ts.v[r - 1][0], k = round(t / wi);
            if (k > 0 && fabs(t - wi * k) < 1e-9) w = wi * k;
        }
        dat_free(&ts);
    }
    if (w < 0) fail_msg("highDrop has no shock right after a write time: the test needs one");
    char end[32];
    snprintf(end, sizeof end, "%.10g", w);
    char value[32];
    snprintf(value, sizeof value, "%g", wi);
    run_copy("highDrop", "shockB", edit);
    control("shockB", "writeInterval", value);
    control("shockB", "endTime", end);
    free(solve("shockB", "", "run"));
    control("shockB", "endTime", end_time);
    control("shockB", "startFrom", "latestTime");
    char *c = solve("shockB", "", "restart");
    dat rb;
    char path[256];
    snprintf(path, sizeof path, RUNS "/shockB/postProcessing/timeStep/%s/timeStep.dat", end);
    dat_read(path, &rb);
    assert_true(rb.nrows > 2 && rb.v[0][7] == 1); /* the shock came, right away */
    dat_free(&rb);
    const int same = compare_from("shockA", "shockB", w);
    print_message("restart from %g, a shock in the next step: %d time directories equal\n", w,
                  same);
    assert_true(same >= 2);
    free(c);
}

static void test_restart_before_shock(void **state)
{
    (void)state;
    if (quick()) skip();
    /* a write time right before a shock step (the step after the write
     * shocks and goes back two steps, past the write): the case's own
     * schedule first, then writes every 0.005 s (every other step) */
    static const double intervals[] = {0.05, 0.005};
    restart_before_shock("true", intervals, 2, "0.85");
}

/* The same with pressureSource divergence (warm-started): its shock at 0.7
 * s comes right after a write every 0.0025 s. */
static void test_restart_before_shock_warm(void **state)
{
    (void)state;
    if (quick()) skip();
    static const double intervals[] = {0.0025};
    restart_before_shock("echo 'pressureSource divergence;' >> constant/fluidProperties", intervals,
                         1, "0.75");
}

/* Item 16b: with writeControl runTime the steps do not depend on the write
 * schedule: a run to 0.05 s writing every 0.01 s is the exact start of a
 * run to 0.1 s writing every 0.02 s (item 1: it still ends at endTime). */
static void test_run_time_prefix(void **state)
{
    (void)state;
    const char *adaptive = "printf 'mode adaptive;\\ndeltaT 0;\\n' > system/timeStepDict";
    run_copy("damBreakShort", "prefixA", adaptive);
    control("prefixA", "writeControl", "runTime");
    control("prefixA", "writeInterval", "0.01");
    control("prefixA", "endTime", "0.05");
    run_copy("damBreakShort", "prefixB", adaptive);
    control("prefixB", "writeControl", "runTime");
    control("prefixB", "writeInterval", "0.02");
    control("prefixB", "endTime", "0.1");
    free(solve("prefixA", "", "run"));
    free(solve("prefixB", "", "run"));
    assert_true(exists(RUNS "/prefixA/0.05/fluid.vtu")); /* endTime itself */
    /* A's writes at the first steps past 0.02 and 0.04 are B's */
    tdir_list l;
    sl_err err;
    assert_int_equal(tdir_list_read(RUNS "/prefixB", "fluid.vtu", &l, &err), 0);
    int n = 0;
    for (size_t i = 1; i < l.n && l.time[i] < 0.045; i++) {
        char pa[256], pb[256];
        snprintf(pa, sizeof pa, RUNS "/prefixA/%s/fluid.vtu", l.name[i]);
        snprintf(pb, sizeof pb, RUNS "/prefixB/%s/fluid.vtu", l.name[i]);
        if (!exists(pa)) fail_msg("prefixA has no %s (prefixB writes there)", l.name[i]);
        if (!same_bytes(pa, pb)) fail_msg("%s differs between the two runs", l.name[i]);
        assert_true(l.time[i] > 0.02 * (double)i - 1e-12); /* at or past the write time */
        n++;
    }
    tdir_list_free(&l);
    assert_int_equal(n, 2);
    /* the steps themselves: every row of A but the last two is B's */
    dat a, b;
    dat_read(RUNS "/prefixA/postProcessing/timeStep/0/timeStep.dat", &a);
    dat_read(RUNS "/prefixB/postProcessing/timeStep/0/timeStep.dat", &b);
    assert_true(a.nrows > 10 && b.nrows > a.nrows);
    for (int r = 0; r + 2 < a.nrows; r++)
        for (int k = 0; k < a.ncols; k++)
            if (k != dat_col(&a, "wallTime") && a.v[r][k] != b.v[r][k])
                fail_msg("row %d column %s: %.17g against %.17g", r, a.col[k], a.v[r][k],
                         b.v[r][k]);
    dat_free(&a);
    dat_free(&b);
}

/* Item 1: the state at endTime is written (with its restart file),
 * whatever writeInterval says, in both write controls. */
static void test_end_always_written(void **state)
{
    (void)state;
    static const char *cases[][4] = {{"adjustableRunTime", "5", "0.01", "0.01"},
                                     {"adjustableRunTime", "0.02", "0.03", "0.03"},
                                     {"runTime", "0.02", "0.03", "0.03"}};
    for (int k = 0; k < 3; k++) {
        run_copy("hydrostaticTank", "endTime", "true");
        control("endTime", "writeControl", cases[k][0]);
        control("endTime", "writeInterval", cases[k][1]);
        control("endTime", "endTime", cases[k][2]);
        free(solve("endTime", "", "run"));
        char path[256];
        snprintf(path, sizeof path, RUNS "/endTime/%s/uniform/restart", cases[k][3]);
        if (!exists(path))
            fail_msg("writeControl %s, writeInterval %s, endTime %s: no %s", cases[k][0],
                     cases[k][1], cases[k][2], path);
        char *series = slurp(RUNS "/endTime/fluid.vtu.series", NULL);
        snprintf(path, sizeof path, "\"%s/fluid.vtu\"", cases[k][3]);
        assert_non_null(strstr(series, path));
        free(series);
    }
}

/* Item 2: timePrecision 1 cannot name 0.012 and 0.016 apart from 0.01
 * and 0.02: the precision is raised with a warning, names are unique and
 * read back as their times, and a restart names the right time. */
static void test_time_names_unique_and_true(void **state)
{
    (void)state;
    run_copy("hydrostaticTank", "names", "true");
    control("names", "timePrecision", "1");
    control("names", "writeInterval", "0.002");
    control("names", "endTime", "0.016");
    char *log = solve("names", "", "run");
    assert_non_null(strstr(log, "Warning:"));
    assert_non_null(strstr(log, "timePrecision"));
    hostile_record("system/controlDict",
                   "timePrecision 1; writeInterval 0.002; (0.012 and 0.01 "
                   "would both be \"0.01\")",
                   log);
    tdir_list l;
    sl_err err;
    assert_int_equal(tdir_list_read(RUNS "/names", "fluid.vtu", &l, &err), 0);
    assert_int_equal(l.n, 9);
    for (size_t i = 0; i < l.n; i++) assert_close(l.time[i], 0.002 * (double)i, 1e-12);
    tdir_list_free(&l);
    char *series = slurp(RUNS "/names/fluid.vtu.series", NULL);
    const char *first = strstr(series, "\"0.01/fluid.vtu\"");
    assert_non_null(first);
    assert_null(strstr(first + 1, "\"0.01/fluid.vtu\"")); /* listed once */
    assert_non_null(strstr(series, "\"0.016/fluid.vtu\""));
    free(series);
    control("names", "endTime", "0.02");
    control("names", "startFrom", "latestTime");
    char *again = solve("names", "", "restart");
    assert_non_null(strstr(again, "names/0.016 (t = 0.016"));
    free(log);
    free(again);
}

/* Items 8 and 16a: the End summary's deltaT min/max are the steps taken
 * (a constant deltaT 1 cut to endTime 0.01 is a step of 0.01), and steps
 * the divergence guard stopped are not counted as stopped at
 * maxIterations. */
static void test_summary_steps_taken(void **state)
{
    (void)state;
    run_copy("hydrostaticTank", "cut",
             "printf 'mode constant;\\ndeltaT 1;\\n' > system/timeStepDict");
    control("cut", "endTime", "0.01");
    char *log = solve("cut", "", "run");
    assert_close(number_after(log, "deltaT min "), 0.01, 1e-12);
    assert_close(number_after(log, "s, max "), 0.01, 1e-12);
    free(log);
    if (quick()) return;
    /* constant 0.004 s on the dam break: some steps end above eta, stopped
     * by the guard well before maxIterations 50 */
    run_copy("damBreakShort", "guard",
             "printf 'mode constant;\\ndeltaT 0.004;\\n' > "
             "system/timeStepDict");
    log = solve("guard", "", "run");
    dat ts;
    dat_read(RUNS "/guard/postProcessing/timeStep/0/timeStep.dat", &ts);
    int at_max = 0, early = 0;
    double lo = INFINITY, hi = 0;
    for (int r = 0; r < ts.nrows; r++) {
        double it = ts.v[r][dat_col(&ts, "iterations")], e = ts.v[r][dat_col(&ts, "rhoErrMax")];
        lo = fmin(lo, ts.v[r][1]);
        hi = fmax(hi, ts.v[r][1]);
        if (e > 1.0 && it >= 50) at_max++;
        else if (e > 1.0) early++;
    }
    dat_free(&ts);
    print_message("constant 0.004 s: %d steps above eta before maxIterations, %d at it\n", early,
                  at_max);
    assert_true(early > 0);
    char want[128];
    snprintf(want, sizeof want, "  %d steps stopped at maxIterations", at_max);
    if (at_max) assert_non_null(strstr(log, want));
    else assert_null(strstr(log, "stopped at maxIterations"));
    snprintf(want, sizeof want, "  %d steps stopped by the divergence guard", early);
    if (!strstr(log, want)) fail_msg("no '%s' in:\n%s", want, log);
    assert_close(number_after(log, "deltaT min "), lo, 1e-5); /* printed with 6 digits */
    assert_close(number_after(log, "s, max "), hi, 1e-5);
    free(log);
}

/* A 0.5 s hydrostatic run: probe pressure and gauge height. */
static void test_run_hydrostatic(void **state)
{
    (void)state;
    if (quick()) skip();
    const double H = 0.4, z = 0.1;
    assert_int_equal(
        run_tank("endTime 0.5;\nwriteInterval 0.25;\nfunctions {\n"
                 "  p { type probes; fields (pressure); probeLocations ((0.15 0.15 0.1)); }\n"
                 "  g { type waterGauges; gaugeLocations ((0.15 0.15)); }\n}\n",
                 NULL),
        0);
    dat p, g;
    dat_read(TANK "/postProcessing/p/0/probes.dat", &p);
    dat_read(TANK "/postProcessing/g/0/waterGauges.dat", &g);
    double ps = 0, gs = 0;
    int n = 0;
    for (int r = 0; r < p.nrows; r++)
        if (p.v[r][0] >= 0.25) {
            ps += p.v[r][1];
            gs += g.v[r][1];
            n++;
        }
    assert_true(n > 50);
    ps /= n;
    gs /= n;
    print_message(
        "probe at depth %.2f m: %.1f Pa (rho0 g (H - z) = %.1f Pa); gauge %.4f m (H = %.2f m)\n",
        H - z, ps, RHO0 * G * (H - z), gs, H);
    assert_true(fabs(ps - RHO0 * G * (H - z)) < 0.1 * RHO0 * G * (H - z));
    assert_true(fabs(gs - H) < R0 / 2);
    dat_free(&p);
    dat_free(&g);
}

int main(void)
{
    sl_log_set_quiet(1);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vtkr_roundtrip),
        cmocka_unit_test(test_vtkr_missing),
        cmocka_unit_test(test_vtkr_truncated),
        cmocka_unit_test(test_vtkr_corrupted),
        cmocka_unit_test(test_fo_query_grid),
        cmocka_unit_test(test_fo_read),
        cmocka_unit_test(test_fo_rows),
        cmocka_unit_test(test_fo_errors),
        cmocka_unit_test(test_run_short),
        cmocka_unit_test(test_run_hydrostatic),
        cmocka_unit_test(test_restart_awkward_time),
        cmocka_unit_test(test_restart_before_shock),
        cmocka_unit_test(test_restart_before_shock_warm),
        cmocka_unit_test(test_run_time_prefix),
        cmocka_unit_test(test_end_always_written),
        cmocka_unit_test(test_time_names_unique_and_true),
        cmocka_unit_test(test_summary_steps_taken),
    };
    /* SLUICE_TEST_FILTER=test_restart* runs the matching tests only */
    if (getenv("SLUICE_TEST_FILTER")) cmocka_set_test_filter(getenv("SLUICE_TEST_FILTER"));
    return cmocka_run_group_tests_name("function objects", tests, NULL, NULL);
}
