/*
 * sl_source: data handed to a writer piece by piece instead of as one
 * array in memory, so that the writer's caller need not hold it whole
 * (-parallel's domain mode streams rank 0's files from every rank's
 * part, solver/pcs_domain.h).  A writer asks for the bytes in order: the
 * first read starts at 0 and every read starts where the one before it
 * ended.  A source holds whatever the caller needs (a cursor, a window
 * of the data); the writer only calls read.
 */
#ifndef SL_SOURCE_H
#define SL_SOURCE_H

#include <stddef.h>

typedef struct sl_source {
    /* bytes [off, off + len) of the data into out */
    void (*read)(void *ctx, size_t off, size_t len, void *out);
    void *ctx;
    /* optional (NULL: the writer compresses what read gives): the same
     * bytes as zlib's compress2 at `level` makes of them, into out (cap
     * bytes, at least compressBound(len)); returns their count.  A writer
     * of independently compressed blocks (VTK's zlib appended data) asks
     * for each block this way, in order, instead of reading it, so that
     * the source can have the blocks compressed where the data is (the
     * domain mode: by each rank, at once).  Reads and compressed reads of
     * one source are not mixed. */
    size_t (*zread)(void *ctx, size_t off, size_t len, int level, void *out, size_t cap);
} sl_source;

#endif
