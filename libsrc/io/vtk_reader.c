/*
 * vtk_reader: strict reader of Sluice's .vtu files (see vtk_reader.h).
 *
 * The whole file is read into memory (NUL-terminated, so that number
 * parsing can never run off the end).  A small tag scanner walks the XML
 * part, which has a fixed shape:
 *
 *   VTKFile > UnstructuredGrid > [FieldData] Piece > {PointData, CellData,
 *   Points, Cells} > DataArray, then AppendedData (raw) or </VTKFile>.
 *
 * Every DataArray is first described (type, components, expected tuples,
 * where its data are), then decoded.  Appended data start after the '_'
 * that follows <AppendedData encoding="raw"> and end at the last
 * "</AppendedData>" of the file, which must be followed only by
 * </VTKFile>; every array must lie inside, and only whitespace may follow
 * the last one.  A zlib array is [nblocks, block, last, csize...] (UInt64)
 * then the blocks; every block must inflate to exactly its size and use up
 * exactly its compressed bytes.
 */
#include "io/vtk_reader.h"

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

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
#define VTKR_HOST_ORDER "BigEndian"
#else
#define VTKR_HOST_ORDER "LittleEndian"
#endif

#define VTKR_MAX_ATTR 16   /* more attributes on one tag is an error */
#define VTKR_MAX_NAME 32   /* element and attribute names */
#define VTKR_MAX_COMP 64   /* components per tuple */
/* deflate cannot shrink data by more than about 1032:1; a header that
 * claims more is corrupt (and is not allowed to make us allocate). */
#define VTKR_MAX_RATIO 1040

/* ---- types ------------------------------------------------------------- */

typedef enum { T_F64, T_F32, T_I32, T_U32, T_I64, T_U8, T_NTYPES } vtkr_type;
static const char *const type_names[T_NTYPES] = {"Float64", "Float32", "Int32",
                                                 "UInt32",  "Int64",   "UInt8"};
static const size_t type_sizes[T_NTYPES] = {8, 4, 4, 4, 8, 1};

typedef enum { SEC_FIELD, SEC_POINT, SEC_CELLDATA, SEC_POINTS, SEC_CELLS } vtkr_section;

/* One DataArray as declared, then decoded. */
typedef struct desc {
    vtkr_section sec;
    char *name;
    vtkr_type type;
    int ncomp;
    int known;            /* ntuples given by the file structure */
    size_t ntuples;
    int ascii;
    size_t offset;        /* appended: from the start of the appended data */
    size_t tbeg, tend;    /* ascii: the text between the tags */
    double *data;
    size_t nvalues;
} desc;

typedef struct attr {
    char key[VTKR_MAX_NAME];
    const char *val;
    size_t vlen;
} attr;

typedef struct tag {
    char name[VTKR_MAX_NAME];
    int closing, empty;
    int nattr;
    attr a[VTKR_MAX_ATTR];
    size_t at; /* byte offset of '<' */
} tag;

typedef struct rd {
    const char *path;
    char *buf; /* file contents + NUL */
    size_t len, pos;
    sl_err *err;
    int compress;
    desc *d;
    size_t nd, dcap;
    size_t npoints, ncells;
    int have_points, have_cells, have_appended;
    size_t dbeg, dend; /* appended data [dbeg, dend) */
} rd;

__attribute__((format(printf, 2, 3))) static int fail(rd *r, const char *fmt, ...)
{
    char msg[SL_ERR_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    sl_err_set(r->err, "%s: %s", r->path, msg);
    return 1;
}

/* ---- file ---------------------------------------------------------------- */

static int slurp(rd *r)
{
    FILE *f = fopen(r->path, "rb");
    struct stat st;
    if (!f) return fail(r, "cannot open: %s", strerror(errno));
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        fclose(f);
        return fail(r, "not a regular file");
    }
    r->len = (size_t)st.st_size;
    r->buf = malloc(r->len + 1);
    if (!r->buf) {
        fclose(f);
        return fail(r, "out of memory for %zu bytes", r->len);
    }
    size_t got = fread(r->buf, 1, r->len, f);
    int bad = ferror(f);
    fclose(f);
    if (bad || got != r->len) return fail(r, "read error");
    r->buf[r->len] = '\0';
    return 0;
}

/* ---- XML scanning -------------------------------------------------------- */

static int is_ws(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

static int is_name_char(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
           c == '_' || c == ':' || c == '-' || c == '.';
}

static void skip_ws(rd *r)
{
    while (r->pos < r->len && is_ws(r->buf[r->pos])) r->pos++;
}

static int skip_past(rd *r, const char *end, const char *what)
{
    const char *p = strstr(r->buf + r->pos, end);
    if (!p) return fail(r, "unterminated %s at byte %zu (truncated?)", what, r->pos);
    r->pos = (size_t)(p - r->buf) + strlen(end);
    return 0;
}

static int read_name(rd *r, char *out)
{
    size_t n = 0;
    while (r->pos < r->len && is_name_char(r->buf[r->pos])) {
        if (n + 1 >= VTKR_MAX_NAME) return fail(r, "name too long at byte %zu", r->pos);
        out[n++] = r->buf[r->pos++];
    }
    out[n] = '\0';
    if (n == 0) return fail(r, "expected a name at byte %zu", r->pos);
    return 0;
}

static int read_attrs(rd *r, tag *t)
{
    for (;;) {
        skip_ws(r);
        if (r->pos >= r->len)
            return fail(r, "unexpected end of file in <%s> (truncated?)", t->name);
        char c = r->buf[r->pos];
        if (c == '>') { r->pos++; return 0; }
        if (c == '/') {
            if (r->pos + 1 >= r->len || r->buf[r->pos + 1] != '>')
                return fail(r, "expected '/>' at byte %zu", r->pos);
            r->pos += 2;
            t->empty = 1;
            return 0;
        }
        if (t->nattr == VTKR_MAX_ATTR)
            return fail(r, "more than %d attributes on <%s>", VTKR_MAX_ATTR, t->name);
        attr *a = &t->a[t->nattr++];
        if (read_name(r, a->key)) return 1;
        skip_ws(r);
        if (r->pos >= r->len || r->buf[r->pos] != '=')
            return fail(r, "expected '=' after attribute '%s' at byte %zu", a->key, r->pos);
        r->pos++;
        skip_ws(r);
        char q = r->pos < r->len ? r->buf[r->pos] : '\0';
        if (q != '"' && q != '\'')
            return fail(r, "expected a quoted value for attribute '%s' at byte %zu", a->key,
                        r->pos);
        size_t b = ++r->pos;
        while (r->pos < r->len && r->buf[r->pos] != q && r->buf[r->pos] != '<') r->pos++;
        if (r->pos >= r->len || r->buf[r->pos] != q)
            return fail(r, "unterminated value of attribute '%s' at byte %zu", a->key, b);
        a->val = r->buf + b;
        a->vlen = r->pos - b;
        r->pos++;
    }
}

/* The next tag, skipping the XML declaration, comments and whitespace.
 * Text other than whitespace between tags is an error. */
static int next_tag(rd *r, tag *t)
{
    memset(t, 0, sizeof *t);
    for (;;) {
        skip_ws(r);
        if (r->pos >= r->len) return fail(r, "unexpected end of file (truncated?)");
        if (r->buf[r->pos] != '<') return fail(r, "unexpected text at byte %zu", r->pos);
        t->at = r->pos;
        if (!strncmp(r->buf + r->pos, "<?", 2)) {
            if (skip_past(r, "?>", "XML declaration")) return 1;
            continue;
        }
        if (!strncmp(r->buf + r->pos, "<!--", 4)) {
            if (skip_past(r, "-->", "comment")) return 1;
            continue;
        }
        break;
    }
    r->pos++;
    if (r->pos < r->len && r->buf[r->pos] == '/') {
        t->closing = 1;
        r->pos++;
        if (read_name(r, t->name)) return 1;
        skip_ws(r);
        if (r->pos >= r->len || r->buf[r->pos] != '>')
            return fail(r, "expected '>' after </%s at byte %zu", t->name, r->pos);
        r->pos++;
        return 0;
    }
    if (read_name(r, t->name)) return 1;
    return read_attrs(r, t);
}

static const attr *find_attr(const tag *t, const char *key)
{
    for (int i = 0; i < t->nattr; i++)
        if (!strcmp(t->a[i].key, key)) return &t->a[i];
    return NULL;
}

static int attr_is(const attr *a, const char *s)
{
    return a && a->vlen == strlen(s) && !memcmp(a->val, s, a->vlen);
}

static int is_open(const tag *t, const char *name)
{
    return !t->closing && !strcmp(t->name, name);
}

static int is_close(const tag *t, const char *name)
{
    return t->closing && !strcmp(t->name, name);
}

static int unexpected(rd *r, const tag *t, const char *where)
{
    return fail(r, "unexpected <%s%s> in %s at byte %zu", t->closing ? "/" : "", t->name, where,
                t->at);
}

/* A decimal size attribute: digits only, no overflow. */
static int attr_size(rd *r, const tag *t, const char *key, int required, size_t def,
                     size_t *out)
{
    const attr *a = find_attr(t, key);
    if (!a) {
        if (required) return fail(r, "<%s> at byte %zu has no %s", t->name, t->at, key);
        *out = def;
        return 0;
    }
    size_t v = 0;
    if (a->vlen == 0) return fail(r, "<%s> at byte %zu: %s is empty", t->name, t->at, key);
    for (size_t i = 0; i < a->vlen; i++) {
        unsigned c = (unsigned char)a->val[i];
        if (c < '0' || c > '9' || v > (SIZE_MAX - (c - '0')) / 10)
            return fail(r, "<%s> at byte %zu: %s=\"%.*s\" is not a valid count", t->name, t->at,
                        key, (int)(a->vlen < 40 ? a->vlen : 40), a->val);
        v = 10 * v + (c - '0');
    }
    *out = v;
    return 0;
}

/* Decode the XML attribute text (entities) into a new string. */
static char *decode_text(rd *r, const attr *a)
{
    char *s = malloc(a->vlen + 1);
    size_t n = 0;
    if (!s) {
        fail(r, "out of memory");
        return NULL;
    }
    for (size_t i = 0; i < a->vlen; i++) {
        if (a->val[i] != '&') {
            s[n++] = a->val[i];
            continue;
        }
        static const char *const ent[] = {"amp;", "lt;", "gt;", "quot;", "apos;"};
        static const char rep[] = {'&', '<', '>', '"', '\''};
        const char *p = a->val + i + 1;
        size_t left = a->vlen - i - 1;
        int done = 0;
        for (int k = 0; k < 5 && !done; k++) {
            size_t el = strlen(ent[k]);
            if (left >= el && !memcmp(p, ent[k], el)) {
                s[n++] = rep[k];
                i += el;
                done = 1;
            }
        }
        if (!done && left >= 3 && p[0] == '#') {
            size_t j = 1;
            unsigned long v = 0;
            int hex = p[1] == 'x', base = hex ? 16 : 10;
            for (j = hex ? 2 : 1; j < left && j < 10 && p[j] != ';'; j++) {
                int dig = p[j] >= '0' && p[j] <= '9'   ? p[j] - '0'
                          : hex && p[j] >= 'a' && p[j] <= 'f' ? p[j] - 'a' + 10
                          : hex && p[j] >= 'A' && p[j] <= 'F' ? p[j] - 'A' + 10
                                                               : -1;
                if (dig < 0) break;
                v = v * (unsigned long)base + (unsigned long)dig;
            }
            if (j < left && p[j] == ';' && v >= 1 && v < 128) {
                s[n++] = (char)v;
                i += j + 1;
                done = 1;
            }
        }
        if (!done) {
            free(s);
            fail(r, "unsupported character reference in attribute '%s'", a->key);
            return NULL;
        }
    }
    s[n] = '\0';
    return s;
}

/* ---- structure ------------------------------------------------------------- */

static desc *push_desc(rd *r)
{
    if (r->nd == r->dcap) {
        size_t cap = r->dcap ? 2 * r->dcap : 16;
        desc *d = realloc(r->d, cap * sizeof *d);
        if (!d) {
            fail(r, "out of memory");
            return NULL;
        }
        r->d = d;
        r->dcap = cap;
    }
    desc *d = &r->d[r->nd++];
    memset(d, 0, sizeof *d);
    return d;
}

/* <DataArray ...> (t) of section sec: describe it and move past it. */
static int parse_data_array(rd *r, const tag *t, vtkr_section sec, size_t ntuples, int known)
{
    const attr *ty = find_attr(t, "type"), *nm = find_attr(t, "Name"), *fm = find_attr(t, "format");
    desc *d = push_desc(r);
    size_t nc;
    if (!d) return 1;
    if (!nm) return fail(r, "<DataArray> at byte %zu has no Name", t->at);
    if (!(d->name = decode_text(r, nm))) return 1;
    if (!ty) return fail(r, "array '%s' has no type", d->name);
    d->type = T_NTYPES;
    for (int k = 0; k < T_NTYPES; k++)
        if (attr_is(ty, type_names[k])) d->type = (vtkr_type)k;
    if (d->type == T_NTYPES)
        return fail(r, "array '%s': unsupported type \"%.*s\"", d->name,
                    (int)(ty->vlen < 40 ? ty->vlen : 40), ty->val);
    if (attr_size(r, t, "NumberOfComponents", 0, 1, &nc)) return 1;
    if (nc < 1 || nc > VTKR_MAX_COMP)
        return fail(r, "array '%s': NumberOfComponents %zu out of range", d->name, nc);
    d->ncomp = (int)nc;
    d->sec = sec;
    if (sec == SEC_FIELD) {
        if (attr_size(r, t, "NumberOfTuples", 1, 0, &d->ntuples)) return 1;
        d->known = 1;
    } else {
        size_t nt;
        d->ntuples = ntuples;
        d->known = known;
        if (find_attr(t, "NumberOfTuples")) {
            if (attr_size(r, t, "NumberOfTuples", 1, 0, &nt)) return 1;
            if (known && nt != ntuples)
                return fail(r, "array '%s': NumberOfTuples %zu, expected %zu", d->name, nt,
                            ntuples);
        }
    }
    if (attr_is(fm, "ascii")) {
        tag c;
        d->ascii = 1;
        if (t->empty) {
            d->tbeg = d->tend = r->pos;
            return 0;
        }
        d->tbeg = r->pos;
        const char *lt = memchr(r->buf + r->pos, '<', r->len - r->pos);
        if (!lt) return fail(r, "array '%s': no </DataArray> (truncated?)", d->name);
        d->tend = (size_t)(lt - r->buf);
        r->pos = d->tend;
        if (next_tag(r, &c)) return 1;
        if (!is_close(&c, "DataArray")) return unexpected(r, &c, "an ascii DataArray");
        return 0;
    }
    if (attr_is(fm, "appended")) {
        r->have_appended = 1;
        if (attr_size(r, t, "offset", 1, 0, &d->offset)) return 1;
        if (!t->empty) {
            tag c;
            if (next_tag(r, &c)) return 1;
            if (!is_close(&c, "DataArray")) return unexpected(r, &c, "an appended DataArray");
        }
        return 0;
    }
    if (attr_is(fm, "binary"))
        return fail(r, "array '%s': inline (base64) binary arrays are not supported", d->name);
    return fail(r, "array '%s': missing or unknown format", d->name);
}

/* DataArrays up to </name>; t is the section's opening tag. */
static int parse_section(rd *r, const tag *t, vtkr_section sec, size_t ntuples, int known)
{
    tag a;
    if (t->empty) return 0;
    for (;;) {
        if (next_tag(r, &a)) return 1;
        if (is_close(&a, t->name)) return 0;
        if (!is_open(&a, "DataArray")) return unexpected(r, &a, t->name);
        if (parse_data_array(r, &a, sec, ntuples, known)) return 1;
    }
}

static int parse_piece(rd *r, const tag *t)
{
    tag s;
    if (attr_size(r, t, "NumberOfPoints", 1, 0, &r->npoints)) return 1;
    if (attr_size(r, t, "NumberOfCells", 0, 0, &r->ncells)) return 1;
    if (t->empty) return fail(r, "<Piece> holds no Points");
    for (;;) {
        if (next_tag(r, &s)) return 1;
        if (is_close(&s, "Piece")) break;
        if (s.closing) return unexpected(r, &s, "Piece");
        size_t first = r->nd;
        if (!strcmp(s.name, "PointData")) {
            if (parse_section(r, &s, SEC_POINT, r->npoints, 1)) return 1;
        } else if (!strcmp(s.name, "CellData")) {
            if (parse_section(r, &s, SEC_CELLDATA, r->ncells, 1)) return 1;
        } else if (!strcmp(s.name, "Points")) {
            if (r->have_points) return fail(r, "more than one <Points>");
            if (parse_section(r, &s, SEC_POINTS, r->npoints, 1)) return 1;
            if (r->nd - first != 1 || r->d[first].ncomp != 3)
                return fail(r, "<Points> must hold one array of 3 components");
            r->have_points = 1;
        } else if (!strcmp(s.name, "Cells")) {
            if (r->have_cells) return fail(r, "more than one <Cells>");
            if (parse_section(r, &s, SEC_CELLS, r->ncells, 1)) return 1;
            for (size_t i = first; i < r->nd; i++)
                if (!strcmp(r->d[i].name, "connectivity")) r->d[i].known = 0;
            r->have_cells = 1;
        } else {
            return unexpected(r, &s, "Piece");
        }
    }
    if (!r->have_points) return fail(r, "<Piece> holds no Points");
    if (!r->have_cells && r->ncells > 0)
        return fail(r, "<Piece> declares cells but has no <Cells>");
    return 0;
}

/* The last occurrence of s in buf[from, to), or SIZE_MAX. */
static size_t rfind(const char *buf, size_t from, size_t to, const char *s)
{
    size_t n = strlen(s);
    if (to < from + n) return SIZE_MAX;
    for (size_t i = to - n + 1; i-- > from;)
        if (!memcmp(buf + i, s, n)) return i;
    return SIZE_MAX;
}

static int only_ws(const rd *r, size_t from, size_t to)
{
    for (size_t i = from; i < to; i++)
        if (!is_ws(r->buf[i])) return 0;
    return 1;
}

/* <AppendedData encoding="raw">, then locate [dbeg, dend). */
static int parse_appended(rd *r, const tag *t)
{
    if (!attr_is(find_attr(t, "encoding"), "raw"))
        return fail(r, "<AppendedData> must have encoding=\"raw\" (base64 is not supported)");
    if (t->empty) return fail(r, "empty <AppendedData/>");
    skip_ws(r);
    if (r->pos >= r->len || r->buf[r->pos] != '_')
        return fail(r, "expected '_' at the start of the appended data (byte %zu)", r->pos);
    r->dbeg = r->pos + 1;
    size_t end = rfind(r->buf, r->dbeg, r->len, "</AppendedData>");
    if (end == SIZE_MAX) return fail(r, "no </AppendedData> at the end of the file (truncated?)");
    r->dend = end;
    r->pos = end;
    tag c;
    if (next_tag(r, &c) || !is_close(&c, "AppendedData")) return 1;
    if (next_tag(r, &c)) return 1;
    if (!is_close(&c, "VTKFile")) return unexpected(r, &c, "the end of the file");
    if (!only_ws(r, r->pos, r->len)) return fail(r, "unexpected data after </VTKFile>");
    return 0;
}

static int parse_document(rd *r)
{
    tag t;
    if (next_tag(r, &t)) return 1;
    if (!is_open(&t, "VTKFile") || t.empty) return fail(r, "not a VTK XML file (no <VTKFile>)");
    if (!attr_is(find_attr(&t, "type"), "UnstructuredGrid"))
        return fail(r, "not an UnstructuredGrid file");
    if (!attr_is(find_attr(&t, "byte_order"), VTKR_HOST_ORDER))
        return fail(r, "byte_order must be %s (the host's)", VTKR_HOST_ORDER);
    if (!attr_is(find_attr(&t, "header_type"), "UInt64"))
        return fail(r, "header_type must be UInt64");
    const attr *cmp = find_attr(&t, "compressor");
    if (cmp && !attr_is(cmp, "vtkZLibDataCompressor"))
        return fail(r, "unsupported compressor \"%.*s\"", (int)(cmp->vlen < 40 ? cmp->vlen : 40),
                    cmp->val);
    r->compress = cmp != NULL;
    if (next_tag(r, &t)) return 1;
    if (!is_open(&t, "UnstructuredGrid") || t.empty) return unexpected(r, &t, "VTKFile");
    int pieces = 0;
    for (;;) {
        if (next_tag(r, &t)) return 1;
        if (is_close(&t, "UnstructuredGrid")) break;
        if (is_open(&t, "FieldData")) {
            if (parse_section(r, &t, SEC_FIELD, 0, 1)) return 1;
        } else if (is_open(&t, "Piece")) {
            if (pieces++) return fail(r, "more than one <Piece> (not supported)");
            if (parse_piece(r, &t)) return 1;
        } else {
            return unexpected(r, &t, "UnstructuredGrid");
        }
    }
    if (!pieces) return fail(r, "no <Piece>");
    if (next_tag(r, &t)) return 1;
    if (is_open(&t, "AppendedData")) return parse_appended(r, &t);
    if (!is_close(&t, "VTKFile")) return unexpected(r, &t, "VTKFile");
    if (!only_ws(r, r->pos, r->len)) return fail(r, "unexpected data after </VTKFile>");
    if (r->have_appended) return fail(r, "appended arrays but no <AppendedData>");
    return 0;
}

/* ---- decoding ---------------------------------------------------------- */

static double value_at(vtkr_type t, const unsigned char *p)
{
    double d;
    float f;
    int32_t i32;
    uint32_t u32;
    int64_t i64;
    switch (t) {
    case T_F64: memcpy(&d, p, 8); return d;
    case T_F32: memcpy(&f, p, 4); return (double)f;
    case T_I32: memcpy(&i32, p, 4); return (double)i32;
    case T_U32: memcpy(&u32, p, 4); return (double)u32;
    case T_I64: memcpy(&i64, p, 8); return (double)i64;
    case T_U8:
    case T_NTYPES: break;
    }
    return (double)*p;
}

/* Expected byte count of d, or check a count read from the file. */
static int check_nbytes(rd *r, desc *d, uint64_t nbytes)
{
    size_t es = type_sizes[d->type], ts = es * (size_t)d->ncomp, want;
    if (!d->known) {
        if (nbytes % ts) return fail(r, "array '%s': %llu bytes is not a whole number of values",
                                     d->name, (unsigned long long)nbytes);
        d->ntuples = (size_t)(nbytes / ts);
        return 0;
    }
    if (__builtin_mul_overflow(d->ntuples, ts, &want) || nbytes != want)
        return fail(r, "array '%s': holds %llu bytes, expected %zu tuples of %zu bytes", d->name,
                    (unsigned long long)nbytes, d->ntuples, ts);
    return 0;
}

static int alloc_values(rd *r, desc *d)
{
    d->nvalues = d->ntuples * (size_t)d->ncomp;
    d->data = malloc((d->nvalues ? d->nvalues : 1) * sizeof *d->data);
    if (!d->data) return fail(r, "array '%s': out of memory", d->name);
    return 0;
}

static void convert(desc *d, const unsigned char *bytes)
{
    size_t es = type_sizes[d->type];
    for (size_t i = 0; i < d->nvalues; i++) d->data[i] = value_at(d->type, bytes + i * es);
}

static int read_u64(rd *r, const desc *d, size_t at, uint64_t *v)
{
    if (at > r->dend || r->dend - at < 8)
        return fail(r, "array '%s': header runs past the end of the appended data (truncated?)",
                    d->name);
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
        return fail(r, "array '%s': data run past the end of the appended data (truncated?)",
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
    if (nb > avail / 8) return fail(r, "array '%s': block count %llu runs past the end of the data",
                                    d->name, (unsigned long long)nb);
    const size_t hdr = at + 24, data = hdr + 8 * (size_t)nb;
    if (nb > 0) {
        if (bs == 0 || last >= bs)
            return fail(r, "array '%s': bad compression header (block %llu, last %llu)", d->name,
                        (unsigned long long)bs, (unsigned long long)last);
        if (__builtin_mul_overflow(nb - 1, bs, &total) ||
            __builtin_add_overflow(total, last ? last : bs, &total))
            return fail(r, "array '%s': bad compression header", d->name);
    }
    for (uint64_t b = 0; b < nb; b++) {
        uint64_t c;
        memcpy(&c, r->buf + hdr + 8 * b, 8);
        if (c > avail || __builtin_add_overflow(csum, c, &csum) || csum > r->dend - data)
            return fail(r, "array '%s': compressed blocks run past the end of the appended data "
                        "(truncated?)", d->name);
    }
    if (check_nbytes(r, d, total)) return 1;
    if (total / VTKR_MAX_RATIO > csum + 64 * nb)
        return fail(r, "array '%s': %llu compressed bytes cannot hold %llu bytes", d->name,
                    (unsigned long long)csum, (unsigned long long)total);
    unsigned char *raw = malloc(total ? (size_t)total : 1);
    if (!raw) return fail(r, "array '%s': out of memory", d->name);
    size_t src = data;
    for (uint64_t b = 0; b < nb; b++) {
        uint64_t c;
        memcpy(&c, r->buf + hdr + 8 * b, 8);
        uLongf want = (uLongf)(b + 1 < nb || !last ? bs : last), got = want;
        uLong used = (uLong)c;
        int rc = uncompress2(raw + b * bs, &got, (const Bytef *)r->buf + src, &used);
        if (rc != Z_OK || got != want || used != c) {
            free(raw);
            return fail(r, "array '%s': block %llu of %llu does not inflate to its %lu bytes "
                        "(corrupt data)", d->name, (unsigned long long)b + 1,
                        (unsigned long long)nb, (unsigned long)want);
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
            return fail(r, "array '%s': too few values for %zu tuples", d->name, d->ntuples);
    } else {
        cap = (d->tend - d->tbeg + 1) / 2 + 1;
    }
    d->data = malloc((cap ? cap : 1) * sizeof *d->data);
    if (!d->data) return fail(r, "array '%s': out of memory", d->name);
    for (;;) {
        while (pos < d->tend && is_ws(r->buf[pos])) pos++;
        if (pos >= d->tend) break;
        if (n == cap) return fail(r, "array '%s': more values than expected", d->name);
        char *next;
        if (parse_ascii_value(d->type, r->buf + pos, &next, &d->data[n]) ||
            (size_t)(next - r->buf) > d->tend ||
            ((size_t)(next - r->buf) < d->tend && !is_ws(*next)))
            return fail(r, "array '%s': value %zu is not a valid %s", d->name, n + 1,
                        type_names[d->type]);
        pos = (size_t)(next - r->buf);
        n++;
    }
    if (!d->known) {
        if (n % (size_t)d->ncomp)
            return fail(r, "array '%s': %zu values is not a whole number of tuples", d->name, n);
        d->ntuples = n / (size_t)d->ncomp;
    } else if (n != cap) {
        return fail(r, "array '%s': %zu values, expected %zu", d->name, n, cap);
    }
    d->nvalues = n;
    return 0;
}

static int decode_all(rd *r)
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
            return fail(r, "array '%s': offset %zu is past the end of the appended data "
                        "(truncated?)", d->name, d->offset);
        if ((r->compress ? decode_zlib : decode_raw)(r, d, r->dbeg + d->offset, &end)) return 1;
        if (end > last_end) last_end = end;
    }
    if (r->have_appended && !only_ws(r, last_end, r->dend))
        return fail(r, "unexpected bytes after the last array of the appended data");
    return 0;
}

static const desc *find_desc(const rd *r, vtkr_section sec, const char *name)
{
    for (size_t i = 0; i < r->nd; i++)
        if (r->d[i].sec == sec && !strcmp(r->d[i].name, name)) return &r->d[i];
    return NULL;
}

/* Cells must be consistent: offsets non-decreasing and ending at the
 * connectivity length, connectivity indices naming existing points. */
static int check_cells(rd *r)
{
    if (!r->have_cells) return 0;
    const desc *c = find_desc(r, SEC_CELLS, "connectivity");
    const desc *o = find_desc(r, SEC_CELLS, "offsets");
    if (!c || !o || !find_desc(r, SEC_CELLS, "types"))
        return fail(r, "<Cells> needs connectivity, offsets and types");
    if (o->ncomp != 1 || c->ncomp != 1) return fail(r, "cell arrays must have one component");
    double prev = 0;
    for (size_t i = 0; i < o->nvalues; i++) {
        if (!(o->data[i] >= prev)) return fail(r, "cell offsets decrease at cell %zu", i);
        prev = o->data[i];
    }
    if (prev != (double)c->nvalues)
        return fail(r, "cell offsets end at %.17g, connectivity holds %zu", prev, c->nvalues);
    for (size_t i = 0; i < c->nvalues; i++)
        if (!(c->data[i] >= 0 && c->data[i] < (double)r->npoints))
            return fail(r, "connectivity entry %zu (%.17g) is not a point index", i, c->data[i]);
    return 0;
}

/* Hand the decoded arrays to out (ownership moves). */
static int collect(rd *r, vtkr_file *out)
{
    size_t np = 0;
    for (size_t i = 0; i < r->nd; i++) {
        const desc *d = &r->d[i];
        if (d->sec == SEC_POINT) np++;
        if (d->sec == SEC_FIELD && !strcmp(d->name, "TimeValue") && d->nvalues >= 1)
            out->time = d->data[0];
    }
    for (size_t i = 0; i < r->nd; i++)
        for (size_t j = 0; j < i; j++)
            if (r->d[i].sec == SEC_POINT && r->d[j].sec == SEC_POINT &&
                !strcmp(r->d[i].name, r->d[j].name))
                return fail(r, "two point-data arrays named '%s'", r->d[i].name);
    out->arrays = calloc(np ? np : 1, sizeof *out->arrays);
    if (!out->arrays) return fail(r, "out of memory");
    for (size_t i = 0; i < r->nd; i++) {
        desc *d = &r->d[i];
        if (d->sec == SEC_POINTS) {
            out->points = d->data;
            d->data = NULL;
        } else if (d->sec == SEC_POINT) {
            vtkr_array *a = &out->arrays[out->narrays++];
            a->name = d->name;
            a->ncomp = d->ncomp;
            a->data = d->data;
            d->name = NULL;
            d->data = NULL;
        }
    }
    out->npoints = r->npoints;
    return 0;
}

int vtkr_read(const char *path, vtkr_file *out, sl_err *err)
{
    rd r;
    memset(&r, 0, sizeof r);
    memset(out, 0, sizeof *out);
    out->time = NAN;
    r.path = path;
    r.err = err;
    int rc = slurp(&r) || parse_document(&r) || decode_all(&r) || check_cells(&r) ||
             collect(&r, out);
    for (size_t i = 0; i < r.nd; i++) {
        free(r.d[i].name);
        free(r.d[i].data);
    }
    free(r.d);
    free(r.buf);
    if (rc) {
        vtkr_free(out);
        out->time = NAN;
    }
    return rc;
}

const vtkr_array *vtkr_find(const vtkr_file *f, const char *name)
{
    for (size_t i = 0; i < f->narrays; i++)
        if (!strcmp(f->arrays[i].name, name)) return &f->arrays[i];
    return NULL;
}

void vtkr_free(vtkr_file *f)
{
    for (size_t i = 0; i < f->narrays; i++) {
        free(f->arrays[i].name);
        free(f->arrays[i].data);
    }
    free(f->arrays);
    free(f->points);
    memset(f, 0, sizeof *f);
    f->time = NAN;
}
