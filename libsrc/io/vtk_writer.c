/*
 * vtk_writer: VTK XML .vtu and .vtp writer (see vtk_writer.h).
 *
 * A binary file is the XML header, in which every DataArray tag has a blank
 * slot where ` offset="N"` is written once N is known, then
 * <AppendedData encoding="raw">_ and, per array, either
 *   [UInt64 nbytes][nbytes raw bytes]                              (plain), or
 *   [UInt64 nblocks, block, last, csize_1 .. csize_nblocks][zlib blocks],
 * with last = nbytes % block: 0 when nbytes is a multiple of the block size
 * (or 0), which is what vtkXMLWriter writes and vtkXMLDataParser expects.
 * Compressed sizes are known only after compressing, so that header is
 * first written as a placeholder and rewritten by seeking back, as are the
 * offsets; the data are thus streamed one block at a time.
 *
 * Header values and data are in host byte order, declared in byte_order.
 */
#include "io/vtk_writer.h"

#include "core/sl_mem.h"
#include "io/atomic_file.h"

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <zlib.h>

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
#define VTK_BYTE_ORDER "BigEndian"
#else
#define VTK_BYTE_ORDER "LittleEndian"
#endif

#define VTK_DEFAULT_BLOCK 32768
/* Room reserved in a DataArray tag for ` offset="<up to 20 digits>"`. */
#define VTK_OFFSET_SLOT 30
/* The largest tuple: 3 components of 8 bytes. */
#define VTK_MAX_TUPLE 24
/* Values per line in ascii arrays. */
#define VTK_ASCII_PER_LINE 6

typedef enum { VTK_SRC_SOA, VTK_SRC_IOTA, VTK_SRC_CONST, VTK_SRC_STREAM } vtk_src;

/* One DataArray as streamed: the caller's component arrays (SOA), or a
 * generated integer sequence start, start + step, ... (IOTA) or the
 * constant start (CONST), for the vertex cells and the triangles' offsets,
 * or the caller's source of the interleaved bytes (STREAM). */
typedef struct vtk_array {
    const char *name;
    vtk_type type;
    int ncomp;
    size_t ntuples;
    vtk_src src;
    const void *comp[3];
    const sl_source *stream;
    int64_t start, step;
    off_t slot;      /* file position of the blank offset slot */
    uint64_t offset; /* where the array starts in the appended data */
} vtk_array;

/* Everything one file holds: the arrays in file order (field data, point
 * data, then "Points", then the three cell arrays). */
typedef struct vtk_piece {
    vtk_array *arr;
    size_t narr, nfield_data, npoint_data;
    size_t npoints, ncells;
    int poly;    /* PolyData of triangles (two cell arrays), else UnstructuredGrid (three) */
    double time; /* the TimeValue array points here */
} vtk_piece;

/* The output stream.  After the first failure every write is a no-op and
 * err keeps that failure's errno, so callers check once at the end. */
typedef struct vtk_out {
    FILE *f;
    int err;
    int ascii, compress, level;
    size_t block;
    unsigned char *buf;  /* one uncompressed block */
    unsigned char *zbuf; /* one compressed block */
    size_t zcap;         /* compressBound(block) */
    uint64_t appended;   /* bytes of appended data written so far */
} vtk_out;

static size_t vtk_type_size(vtk_type t)
{
    switch (t) {
    case VTK_FLOAT64:
    case VTK_INT64:
        return 8;
    case VTK_FLOAT32:
    case VTK_INT32:
    case VTK_UINT32:
        return 4;
    case VTK_UINT8:
        return 1;
    }
    return 0;
}

/* VTK's name of the type; NULL for a value outside the enum. */
static const char *vtk_type_name(vtk_type t)
{
    switch (t) {
    case VTK_FLOAT64:
        return "Float64";
    case VTK_FLOAT32:
        return "Float32";
    case VTK_INT32:
        return "Int32";
    case VTK_UINT32:
        return "UInt32";
    case VTK_INT64:
        return "Int64";
    case VTK_UINT8:
        return "UInt8";
    }
    return NULL;
}

void vtk_options_default(vtk_options *o)
{
    memset(o, 0, sizeof *o);
    o->compress = 1;
    o->level = 1;
    o->block_size = VTK_DEFAULT_BLOCK;
    o->vertices = 1;
    o->time = NAN;
}

int vtk_format_double(double v, char *buf, size_t len)
{
    int r = 0;
    for (int prec = 15; prec <= 17; prec++) {
        r = snprintf(buf, len, "%.*g", prec, v);
        if (!isfinite(v) || strtod(buf, NULL) == v) break;
    }
    return r;
}

/* As vtk_format_double, for a float (6 to 9 significant digits). */
static int vtk_format_float(float v, char *buf, size_t len)
{
    int r = 0;
    for (int prec = 6; prec <= 9; prec++) {
        r = snprintf(buf, len, "%.*g", prec, (double)v);
        if (!isfinite(v) || strtof(buf, NULL) == v) break;
    }
    return r;
}

void vtk_xml_escape(FILE *f, const char *s)
{
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        switch (c) {
        case '&':
            fputs("&amp;", f);
            break;
        case '<':
            fputs("&lt;", f);
            break;
        case '>':
            fputs("&gt;", f);
            break;
        case '"':
            fputs("&quot;", f);
            break;
        case '\'':
            fputs("&apos;", f);
            break;
        case '\t':
        case '\n':
        case '\r':
            fprintf(f, "&#%u;", (unsigned)c);
            break;
        default:
            fputc(c < 0x20 ? '?' : c, f);
            break;
        }
    }
}

/* ---- output stream -------------------------------------------------- */

static void vtk_put(vtk_out *o, const void *p, size_t n)
{
    if (o->err || n == 0) return;
    errno = 0;
    if (fwrite(p, 1, n, o->f) != n) o->err = errno ? errno : EIO;
}

__attribute__((format(printf, 2, 3))) static void vtk_printf(vtk_out *o, const char *fmt, ...)
{
    va_list ap;
    if (o->err) return;
    errno = 0;
    va_start(ap, fmt);
    if (vfprintf(o->f, fmt, ap) < 0) o->err = errno ? errno : EIO;
    va_end(ap);
}

static void vtk_put_escaped(vtk_out *o, const char *s)
{
    if (o->err) return;
    errno = 0;
    vtk_xml_escape(o->f, s);
    if (ferror(o->f)) o->err = errno ? errno : EIO;
}

static void vtk_seek(vtk_out *o, off_t pos, int whence)
{
    if (!o->err && fseeko(o->f, pos, whence) != 0) o->err = errno;
}

static off_t vtk_tell(vtk_out *o)
{
    off_t p;
    if (o->err) return 0;
    p = ftello(o->f);
    if (p < 0) o->err = errno;
    return p;
}

static void vtk_out_init(vtk_out *o, FILE *f, const vtk_options *opt)
{
    memset(o, 0, sizeof *o);
    o->f = f;
    o->ascii = opt->ascii != 0;
    o->compress = !o->ascii && opt->compress;
    o->level = opt->level >= 1 && opt->level <= 9 ? opt->level : 1;
    o->block = opt->block_size ? opt->block_size : VTK_DEFAULT_BLOCK;
    if (o->ascii) return;
    o->buf = sl_malloc(o->block, "a VTK output block");
    if (o->compress) {
        o->zcap = compressBound(o->block);
        o->zbuf = sl_malloc(o->zcap, "a compressed VTK output block");
    }
}

/* ---- array data ----------------------------------------------------- */

static size_t vtk_array_nbytes(const vtk_array *a)
{
    return a->ntuples * (size_t)a->ncomp * vtk_type_size(a->type);
}

/* The bytes of tuple i of a, in VTK's interleaved layout. */
static void vtk_array_tuple(const vtk_array *a, size_t i, unsigned char *out)
{
    size_t es = vtk_type_size(a->type);
    int64_t v;
    if (a->src == VTK_SRC_STREAM) { /* read in order: tuples are asked for one after another */
        const size_t ts = es * (size_t)a->ncomp;
        a->stream->read(a->stream->ctx, i * ts, ts, out);
        return;
    }
    if (a->src == VTK_SRC_SOA) {
        for (int k = 0; k < a->ncomp; k++)
            memcpy(out + (size_t)k * es, (const unsigned char *)a->comp[k] + i * es, es);
        return;
    }
    v = a->src == VTK_SRC_IOTA ? a->start + a->step * (int64_t)i : a->start;
    if (a->type == VTK_UINT8) {
        uint8_t b = (uint8_t)v;
        memcpy(out, &b, 1);
    } else {
        memcpy(out, &v, sizeof v); /* generated arrays are UInt8 or Int64 */
    }
}

/* Bytes [off, off + len) of a's data into out.  Blocks need not start or end
 * on a tuple boundary, so partial tuples go through a small buffer. */
static void vtk_array_bytes(const vtk_array *a, size_t off, size_t len, unsigned char *out)
{
    size_t ts = vtk_type_size(a->type) * (size_t)a->ncomp;
    size_t i = off / ts, skip = off % ts;
    unsigned char tuple[VTK_MAX_TUPLE];
    if (len == 0) return;
    if (a->src == VTK_SRC_STREAM) {
        a->stream->read(a->stream->ctx, off, len, out);
        return;
    }
    if (a->src == VTK_SRC_SOA && a->ncomp == 1) {
        memcpy(out, (const unsigned char *)a->comp[0] + off, len);
        return;
    }
    while (len > 0) {
        size_t take = ts - skip < len ? ts - skip : len;
        if (take == ts) {
            vtk_array_tuple(a, i, out);
        } else {
            vtk_array_tuple(a, i, tuple);
            memcpy(out, tuple + skip, take);
        }
        out += take;
        len -= take;
        skip = 0;
        i++;
    }
}

static void vtk_append_raw(vtk_out *o, const vtk_array *a)
{
    uint64_t nbytes = vtk_array_nbytes(a);
    vtk_put(o, &nbytes, sizeof nbytes);
    for (size_t off = 0; off < nbytes && !o->err; off += o->block) {
        size_t len = nbytes - off < o->block ? nbytes - off : o->block;
        vtk_array_bytes(a, off, len, o->buf);
        vtk_put(o, o->buf, len);
    }
    o->appended += sizeof nbytes + nbytes;
}

static void vtk_append_zlib(vtk_out *o, const vtk_array *a)
{
    size_t nbytes = vtk_array_nbytes(a), bs = o->block;
    size_t nblocks = (nbytes + bs - 1) / bs;
    size_t hbytes = (nblocks + 3) * sizeof(uint64_t);
    uint64_t *hdr = sl_calloc(nblocks + 3, sizeof *hdr, "a VTK compression header");
    uint64_t total = hbytes;
    off_t at = vtk_tell(o);
    hdr[0] = nblocks;
    hdr[1] = bs;
    hdr[2] = nbytes % bs;
    vtk_put(o, hdr, hbytes); /* placeholder until the sizes are known */
    for (size_t b = 0; b < nblocks && !o->err; b++) {
        size_t len = nbytes - b * bs < bs ? nbytes - b * bs : bs;
        uLongf zlen = o->zcap;
        int rc;
        if (a->src == VTK_SRC_STREAM && a->stream->zread) { /* compressed by the source */
            zlen =
                (uLongf)a->stream->zread(a->stream->ctx, b * bs, len, o->level, o->zbuf, o->zcap);
        } else {
            vtk_array_bytes(a, b * bs, len, o->buf);
            rc = compress2(o->zbuf, &zlen, o->buf, len, o->level);
            if (rc != Z_OK) o->err = rc == Z_MEM_ERROR ? ENOMEM : EIO;
        }
        vtk_put(o, o->zbuf, zlen);
        hdr[3 + b] = zlen;
        total += zlen;
    }
    vtk_seek(o, at, SEEK_SET);
    vtk_put(o, hdr, hbytes);
    vtk_seek(o, 0, SEEK_END);
    o->appended += total;
    free(hdr);
}

/* Inline ascii values, VTK_ASCII_PER_LINE to a line, each the shortest text
 * that reads back exactly. */
static void vtk_write_ascii_value(vtk_out *o, vtk_type t, const unsigned char *p)
{
    char s[48] = "";
    double d;
    float f;
    int32_t i32;
    uint32_t u32;
    int64_t i64;
    switch (t) {
    case VTK_FLOAT64:
        memcpy(&d, p, 8);
        vtk_format_double(d, s, sizeof s);
        break;
    case VTK_FLOAT32:
        memcpy(&f, p, 4);
        vtk_format_float(f, s, sizeof s);
        break;
    case VTK_INT32:
        memcpy(&i32, p, 4);
        snprintf(s, sizeof s, "%" PRId32, i32);
        break;
    case VTK_UINT32:
        memcpy(&u32, p, 4);
        snprintf(s, sizeof s, "%" PRIu32, u32);
        break;
    case VTK_INT64:
        memcpy(&i64, p, 8);
        snprintf(s, sizeof s, "%" PRId64, i64);
        break;
    case VTK_UINT8:
        snprintf(s, sizeof s, "%u", (unsigned)*p);
        break;
    }
    vtk_printf(o, "%s", s);
}

static void vtk_write_ascii(vtk_out *o, const vtk_array *a, const char *indent)
{
    unsigned char tuple[VTK_MAX_TUPLE];
    size_t es = vtk_type_size(a->type), count = 0;
    for (size_t i = 0; i < a->ntuples && !o->err; i++) {
        vtk_array_tuple(a, i, tuple);
        for (int k = 0; k < a->ncomp; k++, count++) {
            if (count % VTK_ASCII_PER_LINE == 0) vtk_printf(o, "\n%s  ", indent);
            else vtk_printf(o, " ");
            vtk_write_ascii_value(o, a->type, tuple + (size_t)k * es);
        }
    }
    vtk_printf(o, "\n");
}

/* ---- document ------------------------------------------------------- */

/* field_data: FieldData arrays need NumberOfTuples. */
static void vtk_write_array_tag(vtk_out *o, vtk_array *a, const char *indent, int field_data)
{
    vtk_printf(o, "%s<DataArray type=\"%s\" Name=\"", indent, vtk_type_name(a->type));
    vtk_put_escaped(o, a->name);
    vtk_printf(o, "\"");
    if (a->ncomp > 1) vtk_printf(o, " NumberOfComponents=\"%d\"", a->ncomp);
    if (field_data) vtk_printf(o, " NumberOfTuples=\"%zu\"", a->ntuples);
    if (o->ascii) {
        vtk_printf(o, " format=\"ascii\">");
        vtk_write_ascii(o, a, indent);
        vtk_printf(o, "%s</DataArray>\n", indent);
    } else {
        vtk_printf(o, " format=\"appended\"");
        a->slot = vtk_tell(o);
        vtk_printf(o, "%*s/>\n", VTK_OFFSET_SLOT, "");
    }
}

static void vtk_write_section(vtk_out *o, const char *tag, vtk_array *a, size_t n, int field_data)
{
    const char *indent = field_data ? "      " : "        ";
    vtk_printf(o, "%s<%s>\n", field_data ? "    " : "      ", tag);
    for (size_t i = 0; i < n; i++) vtk_write_array_tag(o, &a[i], indent, field_data);
    vtk_printf(o, "%s</%s>\n", field_data ? "    " : "      ", tag);
}

static void vtk_write_xml(vtk_out *o, vtk_piece *p)
{
    vtk_array *pd = p->arr + p->nfield_data, *pts = pd + p->npoint_data;
    const char *type = p->poly ? "PolyData" : "UnstructuredGrid";
    vtk_printf(o,
               "<?xml version=\"1.0\"?>\n<VTKFile type=\"%s\" version=\"1.0\" "
               "byte_order=\"%s\" header_type=\"UInt64\"%s>\n",
               type, VTK_BYTE_ORDER, o->compress ? " compressor=\"vtkZLibDataCompressor\"" : "");
    vtk_printf(o, "  <%s>\n", type);
    if (p->nfield_data) vtk_write_section(o, "FieldData", p->arr, p->nfield_data, 1);
    if (p->poly)
        vtk_printf(o,
                   "    <Piece NumberOfPoints=\"%zu\" NumberOfVerts=\"0\" NumberOfLines=\"0\" "
                   "NumberOfStrips=\"0\" NumberOfPolys=\"%zu\">\n",
                   p->npoints, p->ncells);
    else
        vtk_printf(o, "    <Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n", p->npoints,
                   p->ncells);
    vtk_write_section(o, "PointData", pd, p->npoint_data, 0);
    vtk_write_section(o, "Points", pts, 1, 0);
    vtk_write_section(o, p->poly ? "Polys" : "Cells", pts + 1, p->poly ? 2 : 3, 0);
    vtk_printf(o, "    </Piece>\n  </%s>\n", type);
}

/* The appended data, then the offsets into the slots left in the header. */
static void vtk_write_appended(vtk_out *o, vtk_piece *p)
{
    vtk_printf(o, "  <AppendedData encoding=\"raw\">\n   _");
    for (size_t i = 0; i < p->narr && !o->err; i++) {
        p->arr[i].offset = o->appended;
        if (o->compress) vtk_append_zlib(o, &p->arr[i]);
        else vtk_append_raw(o, &p->arr[i]);
    }
    vtk_printf(o, "\n  </AppendedData>\n</VTKFile>\n");
    for (size_t i = 0; i < p->narr; i++) {
        vtk_seek(o, p->arr[i].slot, SEEK_SET);
        vtk_printf(o, " offset=\"%" PRIu64 "\"", p->arr[i].offset);
    }
}

/* ---- entry point ---------------------------------------------------- */

static int vtk_check_input(const char *path, size_t n, const double *x, const double *y,
                           const double *z, const vtk_field *fields, size_t nfields, sl_err *err)
{
    if (n > 0 && (!x || !y || !z)) {
        sl_err_set(err, "cannot write '%s': point positions missing", path);
        return 1;
    }
    if (nfields > 0 && !fields) {
        sl_err_set(err, "cannot write '%s': fields missing", path);
        return 1;
    }
    for (size_t i = 0; i < nfields; i++) {
        const vtk_field *f = &fields[i];
        const char *why = NULL;
        if (!f->name || !*f->name) why = "has no name";
        else if (!vtk_type_name(f->type)) why = "has an unknown type";
        else if (f->ncomp < 1 || f->ncomp > 3) why = "must have 1 to 3 components";
        for (int k = 0; !why && n > 0 && k < f->ncomp; k++)
            if (!f->comp[k]) why = "has a missing component array";
        if (why) {
            sl_err_set(err, "cannot write '%s': field %zu ('%s') %s", path, i,
                       f->name ? f->name : "", why);
            return 1;
        }
    }
    return 0;
}

static vtk_array *vtk_piece_add(vtk_piece *p, const char *name, vtk_type type, int ncomp,
                                size_t ntuples, vtk_src src)
{
    vtk_array *a = &p->arr[p->narr++];
    memset(a, 0, sizeof *a);
    a->name = name;
    a->type = type;
    a->ncomp = ncomp;
    a->ntuples = ntuples;
    a->src = src;
    a->step = 1;
    return a;
}

static void vtk_piece_init(vtk_piece *p, size_t n, const double *x, const double *y,
                           const double *z, const vtk_field *fields, size_t nfields,
                           const vtk_options *opt)
{
    vtk_array *a;
    memset(p, 0, sizeof *p);
    p->arr = sl_calloc(nfields + 5, sizeof *p->arr, "VTK arrays");
    p->npoints = n;
    p->ncells = opt->vertices ? n : 0;
    p->time = opt->time;
    if (!isnan(p->time)) {
        vtk_piece_add(p, "TimeValue", VTK_FLOAT64, 1, 1, VTK_SRC_SOA)->comp[0] = &p->time;
        p->nfield_data = 1;
    }
    for (size_t i = 0; i < nfields; i++) {
        a = vtk_piece_add(p, fields[i].name, fields[i].type, fields[i].ncomp, n, VTK_SRC_SOA);
        memcpy(a->comp, fields[i].comp, sizeof a->comp);
    }
    p->npoint_data = nfields;
    a = vtk_piece_add(p, "Points", VTK_FLOAT64, 3, n, VTK_SRC_SOA);
    a->comp[0] = x;
    a->comp[1] = y;
    a->comp[2] = z;
    /* Vertex i is point i: connectivity 0..n-1, end offsets 1..n. */
    vtk_piece_add(p, "connectivity", VTK_INT64, 1, p->ncells, VTK_SRC_IOTA)->start = 0;
    vtk_piece_add(p, "offsets", VTK_INT64, 1, p->ncells, VTK_SRC_IOTA)->start = 1;
    vtk_piece_add(p, "types", VTK_UINT8, 1, p->ncells, VTK_SRC_CONST)->start = 1; /* VTK_VERTEX */
}

/* Write p to path (atomically) and free its arrays. */
static int vtk_write_piece(const char *path, vtk_piece *pp, const vtk_options *opt, sl_err *err)
{
    vtk_piece p = *pp;
    vtk_out o;
    afile af;
    if (!afile_open(&af, path, err)) {
        free(p.arr);
        return 1;
    }
    vtk_out_init(&o, af.f, opt);
    vtk_write_xml(&o, &p);
    if (o.ascii) vtk_printf(&o, "</VTKFile>\n");
    else vtk_write_appended(&o, &p);
    free(p.arr);
    free(o.buf);
    free(o.zbuf);
    if (o.err) {
        afile_abort(&af);
        sl_err_set(err, "cannot write '%s': %s", path, strerror(o.err));
        return 1;
    }
    return afile_commit(&af, err);
}

int vtk_write_points(const char *path, size_t n, const double *x, const double *y, const double *z,
                     const vtk_field *fields, size_t nfields, const vtk_options *opt, sl_err *err)
{
    vtk_options def;
    vtk_piece p;
    if (!opt) {
        vtk_options_default(&def);
        opt = &def;
    }
    if (vtk_check_input(path, n, x, y, z, fields, nfields, err)) return 1;
    vtk_piece_init(&p, n, x, y, z, fields, nfields, opt);
    return vtk_write_piece(path, &p, opt, err);
}

int vtk_write_points_from(const char *path, size_t n, const sl_source *pos,
                          const vtk_stream_field *fields, size_t nfields, const vtk_options *opt,
                          sl_err *err)
{
    vtk_options def;
    vtk_piece p;
    static const double none = 0.0;
    if (!opt) {
        vtk_options_default(&def);
        opt = &def;
    }
    if (n > 0 && (!pos || !pos->read)) {
        sl_err_set(err, "cannot write '%s': point positions missing", path);
        return 1;
    }
    /* checked and laid out as array fields, then pointed at the sources */
    vtk_field *af = sl_calloc(nfields + 1, sizeof *af, "VTK fields");
    for (size_t i = 0; i < nfields; i++) {
        af[i] = (vtk_field){fields[i].name, fields[i].ncomp, fields[i].type, {&none, &none, &none}};
        if (n > 0 && (!fields[i].src || !fields[i].src->read)) af[i].comp[0] = NULL;
    }
    int rc = vtk_check_input(path, n, &none, &none, &none, af, nfields, err);
    if (!rc) vtk_piece_init(&p, n, &none, &none, &none, af, nfields, opt);
    free(af);
    if (rc) return 1;
    for (size_t i = 0; i <= nfields; i++) { /* the fields, then "Points" */
        vtk_array *a = p.arr + p.nfield_data + i;
        a->src = VTK_SRC_STREAM;
        a->stream = i < nfields ? fields[i].src : pos;
    }
    return vtk_write_piece(path, &p, opt, err);
}

int vtk_write_triangles(const char *path, size_t n, const double *x, const double *y,
                        const double *z, size_t ntri, const int64_t *tri, const vtk_field *fields,
                        size_t nfields, const vtk_options *opt, sl_err *err)
{
    vtk_options def;
    vtk_piece p;
    if (!opt) {
        vtk_options_default(&def);
        opt = &def;
    }
    if (vtk_check_input(path, n, x, y, z, fields, nfields, err)) return 1;
    if (ntri > 0 && !tri) {
        sl_err_set(err, "cannot write '%s': triangles missing", path);
        return 1;
    }
    for (size_t i = 0; i < 3 * ntri; i++)
        if (tri[i] < 0 || (uint64_t)tri[i] >= n) {
            sl_err_set(err, "cannot write '%s': triangle %zu refers to point %" PRId64 " of %zu",
                       path, i / 3, tri[i], n);
            return 1;
        }
    vtk_options o = *opt;
    o.vertices = 0;
    vtk_piece_init(&p, n, x, y, z, fields, nfields, &o);
    /* the vertex cells' three arrays become the triangles' two */
    p.narr -= 3;
    p.poly = 1;
    p.ncells = ntri;
    vtk_piece_add(&p, "connectivity", VTK_INT64, 1, 3 * ntri, VTK_SRC_SOA)->comp[0] = tri;
    vtk_array *off = vtk_piece_add(&p, "offsets", VTK_INT64, 1, ntri, VTK_SRC_IOTA);
    off->start = 3;
    off->step = 3;
    return vtk_write_piece(path, &p, &o, err);
}
