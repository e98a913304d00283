/*
 * vtk_reader: reads back the .vtu files that vtk_writer writes (Sluice's own
 * particle files), for the post-processing tools.
 *
 * Accepted: a VTKFile of type UnstructuredGrid with one Piece, arrays
 * "appended" raw (encoding="raw", header_type UInt64, optionally
 * compressor vtkZLibDataCompressor) or inline ascii, in the host byte order;
 * types Float64, Float32, Int32, UInt32, Int64, UInt8.  FieldData may hold a
 * TimeValue; PointData any number of named arrays; Points three components;
 * Cells connectivity, offsets and types (checked, not returned).
 *
 * The reader is strict: anything else (base64, UInt32 headers, a byte count
 * or compressed size that does not add up, an array running past the data,
 * a zlib stream that does not inflate to exactly its block, an ascii array
 * with too few or too many values or a stray character, a missing closing
 * tag, a truncated file, ...) is an error "<path>: <what is wrong>", never a
 * crash and never a silent partial result.  Declared sizes are checked
 * against the file size before anything is allocated.
 *
 * All values are returned as double (exact for every type except Int64
 * beyond 2^53), in VTK's interleaved tuple layout.
 */
#ifndef VTK_READER_H
#define VTK_READER_H

#include <stddef.h>

#include "core/sl_log.h"

/* One point-data array: ntuples (= npoints) tuples of ncomp values. */
typedef struct vtkr_array {
    char *name;
    int ncomp;
    double *data; /* data[i * ncomp + k] */
} vtkr_array;

typedef struct vtkr_file {
    size_t npoints;
    double *points; /* points[3 i + k], k = x, y, z */
    double time;    /* FieldData TimeValue, NAN if absent */
    size_t narrays;
    vtkr_array *arrays; /* point data in file order */
} vtkr_file;

/* Returns 0, or nonzero with err filled ("<path>: <reason>") and *out
 * empty (safe to vtkr_free). */
int vtkr_read(const char *path, vtkr_file *out, sl_err *err);
/* The point-data array called name, NULL if there is none. */
const vtkr_array *vtkr_find(const vtkr_file *f, const char *name);
void vtkr_free(vtkr_file *f);

#endif
