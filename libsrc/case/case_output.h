/*
 * case_output: OpenFOAM-style time directories of VTK files.
 *
 * Each write fills "<case>/<time>.tmp.<pid>/" (fluid.vtu, boundary.vtu) and
 * renames it to "<case>/<time>/" only when every file is complete, so a
 * crash never leaves a half-written time directory.  The collections
 * "<case>/fluid.pvd" and "<case>/boundary.pvd" (and their .vtu.series twins,
 * which ParaView also reads) are rewritten atomically after each write and
 * list every complete time directory.
 */
#ifndef SL_CASE_OUTPUT_H
#define SL_CASE_OUTPUT_H

#include "case/case.h"
#include "core/sl_log.h"
#include "solver/pcisph.h"
#include "solver/pcs_snapshot.h"

typedef struct case_output {
    const sl_case *c;
    size_t n, cap;
    double *times;
    char **names;
} case_output;

/* Collect the time directories already present (for restarts) up to and
 * including `start_time`; later ones are left alone and not listed. */
void out_init(case_output *o, const sl_case *c, double start_time);
void out_free(case_output *o);
/* Write time t, with the restart file of snapshot `snap` and the
 * controller state ctrl (ctrl_size bytes) when snap != NULL; returns 0, or
 * nonzero with err filled (nothing half-written). */
int out_write(case_output *o, const pcs_solver *s, double t, const pcs_snapshot *snap,
              const void *ctrl, size_t ctrl_size, sl_err *err);

#endif
