/* mesh_io: OBJ and STL readers, OBJ writer and vertex welding (see mesh.h).
 *
 * Hostile input is an error, never a crash: counts are checked against the
 * file size before anything is allocated, numbers must be finite, indices
 * in range, and binary bytes in a text file are reported with their line. */
#include "geometry/mesh.h"

#include "core/sl_mem.h"
#include "geometry/mesh_grid.h"
#include "geometry/mesh_progress.h"
#include "io/atomic_file.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

static int open_error(const char *path, sl_err *err)
{
    sl_err_set(err, "cannot open file '%s': %s", path, strerror(errno));
    return 1;
}

/* Bytes that do not occur in text: the sign of a binary or corrupt file. */
static int is_binary_byte(unsigned char c)
{
    return c == 0x7f || (c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\v' && c != '\f');
}

/* A token for a message: at most 40 bytes, non-printables as '?'. */
static void quote_token(const char *s, size_t len, char out[48])
{
    size_t n = len < 40 ? len : 40, i;
    for (i = 0; i < n; i++) out[i] = (s[i] > 0x20 && s[i] < 0x7f) ? s[i] : '?';
    if (len > 40) {
        out[i++] = '.';
        out[i++] = '.';
        out[i++] = '.';
    }
    out[i] = '\0';
}

/* ---- welding ----------------------------------------------------------- */

size_t mesh_weld(mesh *m, double tol)
{
    mgrid g;
    uint32_t *map;
    size_t nv = m->nv;
    if (nv == 0 || !(tol > 0.0) || !isfinite(tol)) return 0;
    map = sl_malloc(nv * sizeof *map, "a vertex map");
    mgrid_init(&g, tol, nv);
    mesh_progress mp;
    mesh_progress_start(&mp, nv, "welding %zu vertices", nv);
    for (size_t i = 0; i < nv; i++) {
        mesh_progress_at(&mp, i);
        double p[3] = {m->v[3 * i], m->v[3 * i + 1], m->v[3 * i + 2]};
        size_t q = mgrid_nearest_within(&g, p, tol, MGRID_NONE, NULL);
        if (q == MGRID_NONE) {
            q = mgrid_insert(&g, p);
            memcpy(m->v + 3 * q, p, sizeof p); /* q <= i: compacts in place */
        }
        map[i] = (uint32_t)q;
    }
    mesh_progress_end(&mp);
    for (size_t i = 0; i < 3 * m->nt; i++) m->t[i] = map[m->t[i]];
    m->nv = g.n;
    mgrid_free(&g);
    free(map);
    mesh_touch(m);
    return nv - m->nv;
}

/* Weld with 1e-6 of the bounding-box diagonal. */
static void weld_default(mesh *m)
{
    double lo[3], hi[3], diag = 0.0;
    mesh_bounds(m, lo, hi);
    for (int d = 0; d < 3; d++) diag += (hi[d] - lo[d]) * (hi[d] - lo[d]);
    diag = sqrt(diag);
    mesh_weld(m, diag > 0.0 ? 1e-6 * diag : 1.0);
}

/* ---- OBJ ------------------------------------------------------------------ */

typedef struct obj_reader {
    const char *path;
    long line;
    mesh *m;
    uint32_t *poly; /* vertex indices of the current face */
    size_t npoly, cap;
    long unknown_line; /* first unrecognised statement (0: none) */
    char unknown[48];
    size_t nunknown;
    sl_err *err;
} obj_reader;

static int obj_error(obj_reader *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static int obj_error(obj_reader *r, const char *fmt, ...)
{
    char msg[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    sl_err_set(r->err, "%s:%ld: %s", r->path, r->line, msg);
    return 1;
}

static const char *skip_space(const char *s)
{
    while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\v' || *s == '\f' || *s == '\n') s++;
    return s;
}

static size_t token_len(const char *s)
{
    size_t n = 0;
    while (s[n] && s[n] != ' ' && s[n] != '\t' && s[n] != '\r' && s[n] != '\v' && s[n] != '\f' &&
           s[n] != '\n')
        n++;
    return n;
}

static int obj_vertex(obj_reader *r, const char *s)
{
    double x[3];
    for (int d = 0; d < 3; d++) {
        char *end, tok[48];
        size_t n;
        s = skip_space(s);
        n = token_len(s);
        quote_token(s, n, tok);
        if (n == 0) return obj_error(r, "vertex has %d coordinates, expected 3", d);
        x[d] = strtod(s, &end);
        if (end != s + n) return obj_error(r, "expected a number, found '%s'", tok);
        if (!isfinite(x[d]))
            return obj_error(r, "vertex coordinate '%s' is not a finite number", tok);
        s += n;
    }
    if (r->m->nv >= MESH_MAX_VERTICES)
        return obj_error(r, "more than %zu vertices", MESH_MAX_VERTICES);
    mesh_add_vertex(r->m, x[0], x[1], x[2]);
    return 0;
}

/* One `i`, `i/t`, `i//n` or `i/t/n` item of a face. */
static int obj_index(obj_reader *r, const char *s, size_t n, uint32_t *out)
{
    char *end, tok[48];
    long nv = (long)r->m->nv, i;
    quote_token(s, n, tok);
    errno = 0;
    i = strtol(s, &end, 10);
    if (end == s || (end != s + n && *end != '/'))
        return obj_error(r, "expected a vertex index, found '%s'", tok);
    if (i == 0) return obj_error(r, "vertex index 0 in '%s' (OBJ indices start at 1)", tok);
    if (errno == ERANGE || (i > 0 && i > nv) || (i < 0 && i < -nv)) {
        if (nv == 0) return obj_error(r, "vertex index '%s' used before any vertex", tok);
        return obj_error(r, "vertex index '%s' out of range (1..%ld or -1..-%ld defined so far)",
                         tok, nv, nv);
    }
    *out = (uint32_t)(i > 0 ? i - 1 : nv + i);
    return 0;
}

static int obj_face(obj_reader *r, const char *s)
{
    r->npoly = 0;
    for (;;) {
        size_t n;
        s = skip_space(s);
        n = token_len(s);
        if (n == 0) break;
        if (r->npoly == r->cap) {
            r->cap = r->cap ? 2 * r->cap : 16;
            r->poly = sl_realloc(r->poly, r->cap * sizeof *r->poly, "an OBJ face");
        }
        if (obj_index(r, s, n, &r->poly[r->npoly])) return 1;
        r->npoly++;
        s += n;
    }
    if (r->npoly < 3) return obj_error(r, "face has %zu vertices, expected at least 3", r->npoly);
    for (size_t k = 1; k + 1 < r->npoly; k++) /* fan */
        mesh_add_triangle(r->m, r->poly[0], r->poly[k], r->poly[k + 1]);
    return 0;
}

/* Statements of the OBJ format that carry nothing for a triangle mesh. */
static int obj_ignored(const char *kw, size_t n)
{
    static const char *const known[] = {
        "vt",        "vn",    "vp",       "g",        "o",    "s",      "mg",     "usemtl",
        "mtllib",    "l",     "p",        "cstype",   "deg",  "bmat",   "step",   "curv",
        "curv2",     "surf",  "parm",     "trim",     "hole", "scrv",   "sp",     "end",
        "con",       "bevel", "c_interp", "d_interp", "lod",  "maplib", "usemap", "shadow_obj",
        "trace_obj", "ctech", "stech",    "call",     "csh"};
    for (size_t i = 0; i < sizeof known / sizeof known[0]; i++)
        if (strlen(known[i]) == n && strncmp(kw, known[i], n) == 0) return 1;
    return 0;
}

static int obj_line(obj_reader *r, const char *line, size_t len)
{
    const char *s;
    size_t n;
    for (size_t i = 0; i < len; i++)
        if (is_binary_byte((unsigned char)line[i]))
            return obj_error(r, "invalid byte 0x%02x (binary or corrupt file?)",
                             (unsigned)(unsigned char)line[i]);
    s = skip_space(line);
    n = token_len(s);
    if (n == 0 || *s == '#') return 0;
    if (n == 1 && *s == 'v') return obj_vertex(r, s + 1);
    if (n == 1 && *s == 'f') return obj_face(r, s + 1);
    if (obj_ignored(s, n)) return 0;
    if (r->nunknown++ == 0) {
        r->unknown_line = r->line;
        quote_token(s, n, r->unknown);
    }
    return 0;
}

int mesh_read_obj(const char *path, mesh *m, sl_err *err)
{
    obj_reader r = {.path = path, .m = m, .err = err};
    FILE *f = fopen(path, "rb");
    char *line = NULL;
    size_t cap = 0;
    ssize_t len;
    int status = 0;
    mesh_init(m);
    if (!f) return open_error(path, err);
    struct stat st;
    size_t size = fstat(fileno(f), &st) == 0 && st.st_size > 0 ? (size_t)st.st_size : 0, got = 0;
    mesh_progress mp;
    mesh_progress_start(&mp, size, "reading %s (%zu bytes)", path, size);
    while (!status && (len = getline(&line, &cap, f)) != -1) {
        r.line++;
        got += (size_t)len;
        mesh_progress_at(&mp, got);
        status = obj_line(&r, line, (size_t)len);
    }
    mesh_progress_end(&mp);
    if (!status && ferror(f)) {
        sl_err_set(err, "cannot read file '%s': %s", path, strerror(errno));
        status = 1;
    }
    fclose(f);
    free(line);
    free(r.poly);
    if (!status && m->nt == 0) {
        if (r.nunknown)
            sl_err_set(err,
                       "%s: no faces found; not an OBJ file? (line %ld: unknown statement '%s')",
                       path, r.unknown_line, r.unknown);
        else sl_err_set(err, "%s: no faces found", path);
        status = 1;
    }
    if (status) {
        mesh_free(m);
        return 1;
    }
    if (r.nunknown)
        sl_warning("%s:%ld: ignored %zu unknown OBJ statements (the first is '%s')", path,
                   r.unknown_line, r.nunknown, r.unknown);
    return 0;
}

/* ---- STL ------------------------------------------------------------------- */

static uint32_t le32(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static double le_float(const unsigned char *b)
{
    uint32_t u = le32(b);
    float f;
    memcpy(&f, &u, sizeof f);
    return (double)f;
}

static int stl_binary(FILE *f, const char *path, uint32_t n, mesh *m, sl_err *err)
{
    enum { CHUNK = 4096 };
    unsigned char *buf = sl_malloc(50 * CHUNK, "an STL buffer");
    uint32_t done = 0;
    mesh_progress mp;
    if ((uint64_t)n * 3 > MESH_MAX_VERTICES) {
        sl_err_set(err, "%s: byte 80: %lu triangles are more than this reader handles", path,
                   (unsigned long)n);
        free(buf);
        return 1;
    }
    mesh_progress_start(&mp, n, "reading %s (%lu triangles)", path, (unsigned long)n);
    while (done < n) {
        uint32_t chunk = n - done < CHUNK ? n - done : CHUNK;
        mesh_progress_at(&mp, done);
        if (fread(buf, 50, chunk, f) != chunk) {
            sl_err_set(err, "%s: byte %llu: unexpected end of file (%s)", path,
                       84ull + 50ull * done, ferror(f) ? strerror(errno) : "file shrank?");
            mesh_progress_end(&mp);
            free(buf);
            return 1;
        }
        for (uint32_t i = 0; i < chunk; i++) {
            const unsigned char *t = buf + 50 * (size_t)i;
            uint32_t a = (uint32_t)m->nv;
            double x[9];
            for (int k = 0; k < 9; k++) {
                x[k] = le_float(t + 12 + 4 * k);
                if (!isfinite(x[k])) {
                    unsigned long long off = 84ull + 50ull * (done + i) + 12u + 4u * (unsigned)k;
                    sl_err_set(err, "%s: byte %llu: triangle %lu has a non-finite coordinate", path,
                               off, (unsigned long)(done + i) + 1);
                    mesh_progress_end(&mp);
                    free(buf);
                    return 1;
                }
            }
            for (int k = 0; k < 3; k++) mesh_add_vertex(m, x[3 * k], x[3 * k + 1], x[3 * k + 2]);
            mesh_add_triangle(m, a, a + 1, a + 2);
        }
        done += chunk;
    }
    mesh_progress_end(&mp);
    free(buf);
    return 0;
}

typedef struct stl_text {
    const char *path;
    const char *s; /* NUL-terminated text */
    const char *p; /* cursor */
    long line;
    sl_err *err;
} stl_text;

/* Next whitespace-separated token: *tok and its length (0 at the end). */
static size_t stl_next(stl_text *x, const char **tok)
{
    size_t n;
    while (*x->p == ' ' || *x->p == '\t' || *x->p == '\r' || *x->p == '\n' || *x->p == '\v' ||
           *x->p == '\f')
        x->line += *x->p++ == '\n';
    *tok = x->p;
    n = token_len(x->p);
    x->p += n;
    return n;
}

static int stl_error(stl_text *x, const char *what, const char *tok, size_t n)
{
    char q[48];
    quote_token(tok, n, q);
    if (n) sl_err_set(x->err, "%s:%ld: expected %s, found '%s'", x->path, x->line, what, q);
    else
        sl_err_set(x->err, "%s:%ld: expected %s, found the end of the file", x->path, x->line,
                   what);
    return 1;
}

static int stl_expect(stl_text *x, const char *word)
{
    const char *tok;
    size_t n = stl_next(x, &tok);
    char what[32];
    if (n == strlen(word) && strncasecmp(tok, word, n) == 0) return 0;
    snprintf(what, sizeof what, "'%s'", word);
    return stl_error(x, what, tok, n);
}

static int stl_number(stl_text *x, double *out, int finite)
{
    const char *tok;
    char *end;
    size_t n = stl_next(x, &tok);
    if (n == 0) return stl_error(x, "a number", tok, n);
    *out = strtod(tok, &end);
    if (end != tok + n) return stl_error(x, "a number", tok, n);
    if (finite && !isfinite(*out)) return stl_error(x, "a finite number", tok, n);
    return 0;
}

static void stl_skip_line(stl_text *x)
{
    while (*x->p && *x->p != '\n') x->p++;
}

static int stl_facet(stl_text *x, mesh *m)
{
    double v[9], nrm;
    uint32_t a = (uint32_t)m->nv;
    if (stl_expect(x, "normal")) return 1;
    for (int k = 0; k < 3; k++)
        if (stl_number(x, &nrm, 0)) return 1; /* ignored; some writers put nan */
    if (stl_expect(x, "outer") || stl_expect(x, "loop")) return 1;
    for (int k = 0; k < 3; k++) {
        if (stl_expect(x, "vertex")) return 1;
        for (int d = 0; d < 3; d++)
            if (stl_number(x, &v[3 * k + d], 1)) return 1;
    }
    if (stl_expect(x, "endloop") || stl_expect(x, "endfacet")) return 1;
    if (m->nv + 3 > MESH_MAX_VERTICES) {
        sl_err_set(x->err, "%s:%ld: too many triangles", x->path, x->line);
        return 1;
    }
    for (int k = 0; k < 3; k++) mesh_add_vertex(m, v[3 * k], v[3 * k + 1], v[3 * k + 2]);
    mesh_add_triangle(m, a, a + 1, a + 2);
    return 0;
}

/* One "solid ... endsolid" of an ascii STL, from its first token. */
static int stl_solid(stl_text *x, mesh *m, const char *tok, size_t n, mesh_progress *mp)
{
    if (n != 5 || strncasecmp(tok, "solid", 5) != 0) return stl_error(x, "'solid'", tok, n);
    stl_skip_line(x); /* the name */
    for (;;) {
        mesh_progress_at(mp, (size_t)(x->p - x->s));
        n = stl_next(x, &tok);
        if (n == 8 && strncasecmp(tok, "endsolid", 8) == 0) break;
        if (n != 5 || strncasecmp(tok, "facet", 5) != 0)
            return stl_error(x, "'facet' or 'endsolid'", tok, n);
        if (stl_facet(x, m)) return 1;
    }
    stl_skip_line(x);
    return 0;
}

static int stl_ascii(stl_text *x, mesh *m)
{
    const char *tok;
    size_t n, size = 0;
    mesh_progress mp;
    int rc = 0;
    for (const char *c = x->s; *c; c++, size++) {
        if (*c == '\n') x->line++;
        if (is_binary_byte((unsigned char)*c)) {
            sl_err_set(x->err, "%s:%ld: invalid byte 0x%02x in an ascii STL (binary or corrupt?)",
                       x->path, x->line, (unsigned)(unsigned char)*c);
            return 1;
        }
    }
    x->line = 1;
    /* bytes, not facets: an ascii STL does not say how many it holds */
    mesh_progress_start(&mp, size, "reading %s (%zu bytes)", x->path, size);
    while (!rc && (n = stl_next(x, &tok)) != 0) rc = stl_solid(x, m, tok, n, &mp);
    mesh_progress_end(&mp);
    return rc;
}

/* Is the whole file text?  (A binary STL may start with "solid" too.) */
static int has_binary_bytes(const char *s, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (is_binary_byte((unsigned char)s[i])) return 1;
    return 0;
}

static int read_all(FILE *f, const char *path, size_t size, char **out, sl_err *err)
{
    char *s = sl_malloc(size + 1, "an STL file");
    if (fread(s, 1, size, f) != size) {
        sl_err_set(err, "cannot read file '%s': %s", path,
                   ferror(f) ? strerror(errno) : "it shrank while being read");
        free(s);
        return 1;
    }
    s[size] = '\0';
    *out = s;
    return 0;
}

static int stl_dispatch(FILE *f, const char *path, unsigned long long size, mesh *m, sl_err *err)
{
    unsigned char head[84];
    uint32_t n = 0;
    unsigned long long want = 0;
    char *text;
    int status;
    if (size >= 84) {
        if (fread(head, 1, 84, f) != 84) {
            sl_err_set(err, "cannot read file '%s': %s", path, strerror(errno));
            return 1;
        }
        n = le32(head + 80);
        want = 84ull + 50ull * n;
        if (want == size) return stl_binary(f, path, n, m, err);
        rewind(f);
    }
    if (size > (unsigned long long)SIZE_MAX / 2) {
        sl_err_set(err, "%s: file too large", path);
        return 1;
    }
    if (read_all(f, path, (size_t)size, &text, err)) return 1;
    {
        const char *p = text;
        while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n') p++;
        if (strncasecmp(p, "solid", 5) != 0 || has_binary_bytes(text, (size_t)size)) {
            if (size >= 84)
                sl_err_set(err,
                           "%s: byte 80: not an STL file, or a truncated one: as binary STL it "
                           "declares %lu triangles (%llu bytes) but has %llu bytes, and it is "
                           "not an ascii STL (%s)",
                           path, (unsigned long)n, want, size,
                           has_binary_bytes(text, (size_t)size) ? "binary bytes"
                                                                : "no 'solid' at the start");
            else
                sl_err_set(err,
                           "%s: byte 0: not an STL file: %llu bytes are too few for a binary "
                           "STL and it does not start with 'solid'",
                           path, size);
            free(text);
            return 1;
        }
    }
    stl_text x = {.path = path, .s = text, .p = text, .line = 1, .err = err};
    status = stl_ascii(&x, m);
    free(text);
    return status;
}

int mesh_read_stl(const char *path, mesh *m, sl_err *err)
{
    FILE *f = fopen(path, "rb");
    struct stat st;
    int status;
    mesh_init(m);
    if (!f) return open_error(path, err);
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        sl_err_set(err, "cannot open file '%s': not a regular file", path);
        fclose(f);
        return 1;
    }
    status = stl_dispatch(f, path, (unsigned long long)st.st_size, m, err);
    fclose(f);
    if (!status && m->nt == 0) {
        sl_err_set(err, "%s: STL file has no triangles", path);
        status = 1;
    }
    if (status) {
        mesh_free(m);
        return 1;
    }
    weld_default(m);
    return 0;
}

int mesh_read(const char *path, mesh *m, sl_err *err)
{
    const char *dot = strrchr(path, '.'), *slash = strrchr(path, '/');
    mesh_init(m);
    if (dot && (!slash || dot > slash)) {
        if (strcasecmp(dot, ".obj") == 0) return mesh_read_obj(path, m, err);
        if (strcasecmp(dot, ".stl") == 0) return mesh_read_stl(path, m, err);
    }
    sl_err_set(err, "%s: unknown mesh format '%s' (expected .obj or .stl)", path,
               dot && (!slash || dot > slash) ? dot : "");
    return 1;
}

/* ---- OBJ writer ------------------------------------------------------------ */

int mesh_write_obj(const mesh *m, const char *path, const char *comment, sl_err *err)
{
    afile a;
    FILE *f = afile_open(&a, path, err);
    if (!f) return 1;
    if (comment) {
        fputs("# ", f);
        for (const char *c = comment; *c; c++) {
            fputc(*c, f);
            if (*c == '\n') fputs("# ", f);
        }
        fputc('\n', f);
    }
    fprintf(f, "# %zu vertices, %zu triangles\n", m->nv, m->nt);
    for (size_t i = 0; i < m->nv; i++)
        fprintf(f, "v %.17g %.17g %.17g\n", m->v[3 * i], m->v[3 * i + 1], m->v[3 * i + 2]);
    for (size_t j = 0; j < m->nt; j++)
        fprintf(f, "f %lu %lu %lu\n", (unsigned long)m->t[3 * j] + 1,
                (unsigned long)m->t[3 * j + 1] + 1, (unsigned long)m->t[3 * j + 2] + 1);
    return afile_commit(&a, err);
}
