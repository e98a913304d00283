/*
 * vtk_writer: VTK XML UnstructuredGrid (.vtu) files of particles, and
 * PolyData (.vtp) files of triangles (the reconstructed surface).
 *
 * Binary files are "appended raw" (no base64) with UInt64 headers, by default
 * zlib-compressed in blocks exactly as vtkZLibDataCompressor expects; ascii
 * is there for debugging.  Point fields are given as structure of arrays and
 * interleaved into VTK's tuple layout block by block while writing, so the
 * writer never holds more than one block of a field in memory.
 *
 * A file appears complete or not at all: it is written to
 * "<path>.tmp.<pid>", fsync'd, then renamed over <path>.
 */
#ifndef VTK_WRITER_H
#define VTK_WRITER_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "core/sl_log.h"
#include "core/sl_source.h"

typedef enum { VTK_FLOAT64, VTK_FLOAT32, VTK_INT32, VTK_UINT32, VTK_INT64, VTK_UINT8 } vtk_type;

/* One point-data field.  comp[k] are the component arrays of n elements
 * each, of the C type matching `type` (double, float, int32_t, uint32_t,
 * int64_t, uint8_t); only comp[0] is used when ncomp == 1.  ncomp is 1..3. */
typedef struct vtk_field {
    const char *name;
    int ncomp;
    vtk_type type;
    const void *comp[3];
} vtk_field;

/* A point-data field streamed: its bytes in VTK's layout (n tuples of ncomp
 * interleaved values) from src, read once, in order, one block (ascii: one
 * tuple) at a time; the file is the same bytes as from arrays holding
 * those values. */
typedef struct vtk_stream_field {
    const char *name;
    int ncomp;
    vtk_type type;
    const sl_source *src;
} vtk_stream_field;

typedef struct vtk_options {
    int ascii;         /* 0: appended raw binary (no base64); 1: ascii */
    int compress;      /* zlib (vtkZLibDataCompressor) for binary; ignored for ascii */
    int level;         /* zlib level 1 (fast) .. 9 (small); 0 or out of range means 1 */
    size_t block_size; /* uncompressed bytes per zlib block; 0 means 32768 (VTK's default) */
    int vertices;      /* one VTK_VERTEX cell per point, so ParaView's default
                          "Surface" representation shows the points */
    double time;       /* written as FieldData "TimeValue" unless NaN (= no time) */
} vtk_options;

/* Defaults: binary, zlib level 1, 32768-byte blocks, vertices on, no time.
 * Start from these rather than from a zeroed struct (time 0 is a time). */
void vtk_options_default(vtk_options *o);

/* Write an UnstructuredGrid of n points (positions as x, y, z arrays, written
 * as Float64 "Points") with point-data fields; opt NULL means the defaults.
 * Returns 0, or nonzero with err filled ("cannot write '<path>': <reason>")
 * and no file left behind (an existing <path> is left untouched). */
int vtk_write_points(const char *path, size_t n, const double *x, const double *y, const double *z,
                     const vtk_field *fields, size_t nfields, const vtk_options *opt, sl_err *err);

/* The same with every array streamed: pos gives the n (x, y, z) Float64
 * tuples in VTK's layout (see vtk_stream_field). */
int vtk_write_points_from(const char *path, size_t n, const sl_source *pos,
                          const vtk_stream_field *fields, size_t nfields, const vtk_options *opt,
                          sl_err *err);

/* Write a PolyData of n points and ntri triangles (tri[3 t + k]: 0-based
 * point indices, written as Int64 "connectivity" with "offsets" 3, 6, ...)
 * with point-data fields, in the same encoding as vtk_write_points
 * (opt->vertices is ignored).  An index outside [0, n) is an error. */
int vtk_write_triangles(const char *path, size_t n, const double *x, const double *y,
                        const double *z, size_t ntri, const int64_t *tri, const vtk_field *fields,
                        size_t nfields, const vtk_options *opt, sl_err *err);

/* The shortest decimal text ("%.15g" to "%.17g") that reads back as exactly
 * v, e.g. 0.1 -> "0.1", 1e-05 -> "1e-05".  Returns snprintf's result. */
int vtk_format_double(double v, char *buf, size_t len);

/* Write s to f as XML attribute text (& < > " ' escaped; control characters
 * other than tab, newline and return, which XML 1.0 cannot hold, become '?').
 * Errors are left in ferror(f). */
void vtk_xml_escape(FILE *f, const char *s);

#endif
