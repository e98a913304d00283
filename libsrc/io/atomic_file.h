/*
 * atomic_file: write a file so that it appears complete or not at all.
 *
 * afile_open creates "<path>.tmp.<pid>"; afile_commit flushes, fsyncs,
 * closes and renames it over <path> (then fsyncs the folder so the rename
 * survives a crash); afile_abort, or any failure, removes the temp file.
 * One process must not write the same path from two threads at once.
 */
#ifndef ATOMIC_FILE_H
#define ATOMIC_FILE_H

#include <stdio.h>

#include "core/sl_log.h"

typedef struct afile {
    FILE *f;    /* the temp file; NULL once committed or aborted */
    char *path; /* final path */
    char *tmp;  /* "<path>.tmp.<pid>" */
} afile;

/* Returns the stream to write, or NULL with err filled
 * ("cannot write '<path>': <strerror>"). */
FILE *afile_open(afile *a, const char *path, sl_err *err);

/* Returns 0, or nonzero with err filled and the temp file removed. */
int afile_commit(afile *a, sl_err *err);

/* Discard the temp file (safe after a failed open or a commit). */
void afile_abort(afile *a);

#endif
