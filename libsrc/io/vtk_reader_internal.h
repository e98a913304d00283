/*
 * vtk_reader_internal: what the parts of the VTK reader share (private to
 * libsrc/io): the reader's state, the declared arrays, the XML tags.
 *   vtk_reader_xml.c     the file and its XML: tags, attributes, structure
 *   vtk_reader_decode.c  the arrays' bytes: raw, zlib blocks, ASCII
 *   vtk_reader.c         checks across arrays and the public calls
 */
#ifndef SL_VTK_READER_INTERNAL_H
#define SL_VTK_READER_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "io/vtk_reader.h"

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
#define VTKR_HOST_ORDER "BigEndian"
#else
#define VTKR_HOST_ORDER "LittleEndian"
#endif

#define VTKR_MAX_ATTR 16 /* more attributes on one tag is an error */
#define VTKR_MAX_NAME 32 /* element and attribute names */
#define VTKR_MAX_COMP 64 /* components per tuple */
/* deflate cannot shrink data by more than about 1032:1; a header that
 * claims more is corrupt (and is not allowed to make us allocate). */
#define VTKR_MAX_RATIO 1040

/* ---- types ------------------------------------------------------------- */

typedef enum { T_F64, T_F32, T_I32, T_U32, T_I64, T_U8, T_NTYPES } vtkr_type;
extern const char *const vtkr_type_names[T_NTYPES];
extern const size_t vtkr_type_sizes[T_NTYPES];

typedef enum { SEC_FIELD, SEC_POINT, SEC_CELLDATA, SEC_POINTS, SEC_CELLS } vtkr_section;

/* One DataArray as declared, then decoded. */
typedef struct desc {
    vtkr_section sec;
    char *name;
    vtkr_type type;
    int ncomp;
    int known; /* ntuples given by the file structure */
    size_t ntuples;
    int ascii;
    size_t offset;     /* appended: from the start of the appended data */
    size_t tbeg, tend; /* ascii: the text between the tags */
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

/* "<path>: <message>" into r->err; returns 1. */
__attribute__((format(printf, 2, 3))) int vtkr_fail(rd *r, const char *fmt, ...);
/* XML whitespace; only whitespace in r->buf[from, to). */
int vtkr_is_ws(char c);
int vtkr_only_ws(const rd *r, size_t from, size_t to);
/* Read the whole file (NUL-terminated). */
int vtkr_slurp(rd *r);
/* Walk the XML and describe every DataArray. */
int vtkr_parse_document(rd *r);
/* Decode every described array. */
int vtkr_decode_all(rd *r);

#endif
