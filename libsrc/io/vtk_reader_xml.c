/* vtk_reader_xml: the file and its XML part (see vtk_reader.c). */
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

/* ---- file ---------------------------------------------------------------- */

int vtkr_slurp(rd *r)
{
    FILE *f = fopen(r->path, "rb");
    struct stat st;
    if (!f) return vtkr_fail(r, "cannot open: %s", strerror(errno));
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        fclose(f);
        return vtkr_fail(r, "not a regular file");
    }
    r->len = (size_t)st.st_size;
    r->buf = malloc(r->len + 1);
    if (!r->buf) {
        fclose(f);
        return vtkr_fail(r, "out of memory for %zu bytes", r->len);
    }
    size_t got = fread(r->buf, 1, r->len, f);
    int bad = ferror(f);
    fclose(f);
    if (bad || got != r->len) return vtkr_fail(r, "read error");
    r->buf[r->len] = '\0';
    return 0;
}

/* ---- XML scanning -------------------------------------------------------- */

int vtkr_is_ws(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

static int is_name_char(char c)
{
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
        c == ':' || c == '-' || c == '.';
}

static void skip_ws(rd *r)
{
    while (r->pos < r->len && vtkr_is_ws(r->buf[r->pos])) r->pos++;
}

static int skip_past(rd *r, const char *end, const char *what)
{
    const char *p = strstr(r->buf + r->pos, end);
    if (!p) return vtkr_fail(r, "unterminated %s at byte %zu (truncated?)", what, r->pos);
    r->pos = (size_t)(p - r->buf) + strlen(end);
    return 0;
}

static int read_name(rd *r, char *out)
{
    size_t n = 0;
    while (r->pos < r->len && is_name_char(r->buf[r->pos])) {
        if (n + 1 >= VTKR_MAX_NAME) return vtkr_fail(r, "name too long at byte %zu", r->pos);
        out[n++] = r->buf[r->pos++];
    }
    out[n] = '\0';
    if (n == 0) return vtkr_fail(r, "expected a name at byte %zu", r->pos);
    return 0;
}

static int read_attrs(rd *r, tag *t)
{
    for (;;) {
        skip_ws(r);
        if (r->pos >= r->len)
            return vtkr_fail(r, "unexpected end of file in <%s> (truncated?)", t->name);
        char c = r->buf[r->pos];
        if (c == '>') {
            r->pos++;
            return 0;
        }
        if (c == '/') {
            if (r->pos + 1 >= r->len || r->buf[r->pos + 1] != '>')
                return vtkr_fail(r, "expected '/>' at byte %zu", r->pos);
            r->pos += 2;
            t->empty = 1;
            return 0;
        }
        if (t->nattr == VTKR_MAX_ATTR)
            return vtkr_fail(r, "more than %d attributes on <%s>", VTKR_MAX_ATTR, t->name);
        attr *a = &t->a[t->nattr++];
        if (read_name(r, a->key)) return 1;
        skip_ws(r);
        if (r->pos >= r->len || r->buf[r->pos] != '=')
            return vtkr_fail(r, "expected '=' after attribute '%s' at byte %zu", a->key, r->pos);
        r->pos++;
        skip_ws(r);
        char q = r->pos < r->len ? r->buf[r->pos] : '\0';
        if (q != '"' && q != '\'')
            return vtkr_fail(r, "expected a quoted value for attribute '%s' at byte %zu", a->key,
                             r->pos);
        size_t b = ++r->pos;
        while (r->pos < r->len && r->buf[r->pos] != q && r->buf[r->pos] != '<') r->pos++;
        if (r->pos >= r->len || r->buf[r->pos] != q)
            return vtkr_fail(r, "unterminated value of attribute '%s' at byte %zu", a->key, b);
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
        if (r->pos >= r->len) return vtkr_fail(r, "unexpected end of file (truncated?)");
        if (r->buf[r->pos] != '<') return vtkr_fail(r, "unexpected text at byte %zu", r->pos);
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
            return vtkr_fail(r, "expected '>' after </%s at byte %zu", t->name, r->pos);
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

static int is_open(const tag *t, const char *name) { return !t->closing && !strcmp(t->name, name); }

static int is_close(const tag *t, const char *name) { return t->closing && !strcmp(t->name, name); }

static int unexpected(rd *r, const tag *t, const char *where)
{
    return vtkr_fail(r, "unexpected <%s%s> in %s at byte %zu", t->closing ? "/" : "", t->name,
                     where, t->at);
}

/* A decimal size attribute: digits only, no overflow. */
static int attr_size(rd *r, const tag *t, const char *key, int required, size_t def, size_t *out)
{
    const attr *a = find_attr(t, key);
    if (!a) {
        if (required) return vtkr_fail(r, "<%s> at byte %zu has no %s", t->name, t->at, key);
        *out = def;
        return 0;
    }
    size_t v = 0;
    if (a->vlen == 0) return vtkr_fail(r, "<%s> at byte %zu: %s is empty", t->name, t->at, key);
    for (size_t i = 0; i < a->vlen; i++) {
        unsigned c = (unsigned char)a->val[i];
        if (c < '0' || c > '9' || v > (SIZE_MAX - (c - '0')) / 10)
            return vtkr_fail(r, "<%s> at byte %zu: %s=\"%.*s\" is not a valid count", t->name,
                             t->at, key, (int)(a->vlen < 40 ? a->vlen : 40), a->val);
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
        vtkr_fail(r, "out of memory");
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
                int dig = p[j] >= '0' && p[j] <= '9'    ? p[j] - '0'
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
            vtkr_fail(r, "unsupported character reference in attribute '%s'", a->key);
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
            vtkr_fail(r, "out of memory");
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
    if (!nm) return vtkr_fail(r, "<DataArray> at byte %zu has no Name", t->at);
    if (!(d->name = decode_text(r, nm))) return 1;
    if (!ty) return vtkr_fail(r, "array '%s' has no type", d->name);
    d->type = T_NTYPES;
    for (int k = 0; k < T_NTYPES; k++)
        if (attr_is(ty, vtkr_type_names[k])) d->type = (vtkr_type)k;
    if (d->type == T_NTYPES)
        return vtkr_fail(r, "array '%s': unsupported type \"%.*s\"", d->name,
                         (int)(ty->vlen < 40 ? ty->vlen : 40), ty->val);
    if (attr_size(r, t, "NumberOfComponents", 0, 1, &nc)) return 1;
    if (nc < 1 || nc > VTKR_MAX_COMP)
        return vtkr_fail(r, "array '%s': NumberOfComponents %zu out of range", d->name, nc);
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
                return vtkr_fail(r, "array '%s': NumberOfTuples %zu, expected %zu", d->name, nt,
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
        if (!lt) return vtkr_fail(r, "array '%s': no </DataArray> (truncated?)", d->name);
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
        return vtkr_fail(r, "array '%s': inline (base64) binary arrays are not supported", d->name);
    return vtkr_fail(r, "array '%s': missing or unknown format", d->name);
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
    if (t->empty) return vtkr_fail(r, "<Piece> holds no Points");
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
            if (r->have_points) return vtkr_fail(r, "more than one <Points>");
            if (parse_section(r, &s, SEC_POINTS, r->npoints, 1)) return 1;
            if (r->nd - first != 1 || r->d[first].ncomp != 3)
                return vtkr_fail(r, "<Points> must hold one array of 3 components");
            r->have_points = 1;
        } else if (!strcmp(s.name, "Cells")) {
            if (r->have_cells) return vtkr_fail(r, "more than one <Cells>");
            if (parse_section(r, &s, SEC_CELLS, r->ncells, 1)) return 1;
            for (size_t i = first; i < r->nd; i++)
                if (!strcmp(r->d[i].name, "connectivity")) r->d[i].known = 0;
            r->have_cells = 1;
        } else {
            return unexpected(r, &s, "Piece");
        }
    }
    if (!r->have_points) return vtkr_fail(r, "<Piece> holds no Points");
    if (!r->have_cells && r->ncells > 0)
        return vtkr_fail(r, "<Piece> declares cells but has no <Cells>");
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

int vtkr_only_ws(const rd *r, size_t from, size_t to)
{
    for (size_t i = from; i < to; i++)
        if (!vtkr_is_ws(r->buf[i])) return 0;
    return 1;
}

/* <AppendedData encoding="raw">, then locate [dbeg, dend). */
static int parse_appended(rd *r, const tag *t)
{
    if (!attr_is(find_attr(t, "encoding"), "raw"))
        return vtkr_fail(r, "<AppendedData> must have encoding=\"raw\" (base64 is not supported)");
    if (t->empty) return vtkr_fail(r, "empty <AppendedData/>");
    skip_ws(r);
    if (r->pos >= r->len || r->buf[r->pos] != '_')
        return vtkr_fail(r, "expected '_' at the start of the appended data (byte %zu)", r->pos);
    r->dbeg = r->pos + 1;
    size_t end = rfind(r->buf, r->dbeg, r->len, "</AppendedData>");
    if (end == SIZE_MAX)
        return vtkr_fail(r, "no </AppendedData> at the end of the file (truncated?)");
    r->dend = end;
    r->pos = end;
    tag c;
    if (next_tag(r, &c) || !is_close(&c, "AppendedData")) return 1;
    if (next_tag(r, &c)) return 1;
    if (!is_close(&c, "VTKFile")) return unexpected(r, &c, "the end of the file");
    if (!vtkr_only_ws(r, r->pos, r->len)) return vtkr_fail(r, "unexpected data after </VTKFile>");
    return 0;
}

int vtkr_parse_document(rd *r)
{
    tag t;
    if (next_tag(r, &t)) return 1;
    if (!is_open(&t, "VTKFile") || t.empty)
        return vtkr_fail(r, "not a VTK XML file (no <VTKFile>)");
    if (!attr_is(find_attr(&t, "type"), "UnstructuredGrid"))
        return vtkr_fail(r, "not an UnstructuredGrid file");
    if (!attr_is(find_attr(&t, "byte_order"), VTKR_HOST_ORDER))
        return vtkr_fail(r, "byte_order must be %s (the host's)", VTKR_HOST_ORDER);
    if (!attr_is(find_attr(&t, "header_type"), "UInt64"))
        return vtkr_fail(r, "header_type must be UInt64");
    const attr *cmp = find_attr(&t, "compressor");
    if (cmp && !attr_is(cmp, "vtkZLibDataCompressor"))
        return vtkr_fail(r, "unsupported compressor \"%.*s\"",
                         (int)(cmp->vlen < 40 ? cmp->vlen : 40), cmp->val);
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
            if (pieces++) return vtkr_fail(r, "more than one <Piece> (not supported)");
            if (parse_piece(r, &t)) return 1;
        } else {
            return unexpected(r, &t, "UnstructuredGrid");
        }
    }
    if (!pieces) return vtkr_fail(r, "no <Piece>");
    if (next_tag(r, &t)) return 1;
    if (is_open(&t, "AppendedData")) return parse_appended(r, &t);
    if (!is_close(&t, "VTKFile")) return unexpected(r, &t, "VTKFile");
    if (!vtkr_only_ws(r, r->pos, r->len)) return vtkr_fail(r, "unexpected data after </VTKFile>");
    if (r->have_appended) return vtkr_fail(r, "appended arrays but no <AppendedData>");
    return 0;
}
