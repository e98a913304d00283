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
} sl_source;

#endif
