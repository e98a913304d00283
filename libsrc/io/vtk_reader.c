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
 *
 * The parts: vtk_reader_xml.c (the file and its XML), vtk_reader_decode.c
 * (the arrays' bytes), this file (checks across arrays, the public calls).
 */
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

const char *const vtkr_type_names[T_NTYPES] = {"Float64", "Float32", "Int32",
                                               "UInt32",  "Int64",   "UInt8"};
const size_t vtkr_type_sizes[T_NTYPES] = {8, 4, 4, 4, 8, 1};

int vtkr_fail(rd *r, const char *fmt, ...)
{
    char msg[SL_ERR_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    sl_err_set(r->err, "%s: %s", r->path, msg);
    return 1;
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
        return vtkr_fail(r, "<Cells> needs connectivity, offsets and types");
    if (o->ncomp != 1 || c->ncomp != 1) return vtkr_fail(r, "cell arrays must have one component");
    double prev = 0;
    for (size_t i = 0; i < o->nvalues; i++) {
        if (!(o->data[i] >= prev)) return vtkr_fail(r, "cell offsets decrease at cell %zu", i);
        prev = o->data[i];
    }
    if (prev != (double)c->nvalues)
        return vtkr_fail(r, "cell offsets end at %.17g, connectivity holds %zu", prev, c->nvalues);
    for (size_t i = 0; i < c->nvalues; i++)
        if (!(c->data[i] >= 0 && c->data[i] < (double)r->npoints))
            return vtkr_fail(r, "connectivity entry %zu (%.17g) is not a point index", i,
                             c->data[i]);
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
                return vtkr_fail(r, "two point-data arrays named '%s'", r->d[i].name);
    out->arrays = calloc(np ? np : 1, sizeof *out->arrays);
    if (!out->arrays) return vtkr_fail(r, "out of memory");
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
    int rc = vtkr_slurp(&r) || vtkr_parse_document(&r) || vtkr_decode_all(&r) || check_cells(&r) ||
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
