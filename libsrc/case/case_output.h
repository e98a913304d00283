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
#include "case/case_restart.h"
#include "core/sl_log.h"
#include "solver/pcisph.h"
#include "solver/pcs_snapshot.h"

typedef struct case_output {
    const sl_case *c;
    size_t n, cap;
    double *times;
    char **names;
    int precision;      /* digits of time names: timePrecision, raised when needed */
    char last_name[64]; /* name of the last time written */
} case_output;

/* Collect the time directories already present (for restarts) up to and
 * including `start_time`; later ones are left alone and not listed. */
void out_init(case_output *o, const sl_case *c, double start_time);
void out_free(case_output *o);
/* The name of time t, unique and true, in OpenFOAM's habit: with
 * timePrecision digits, or more when that name would read back more than
 * 1e-3 writeInterval away from t (0.016 as "0.02") or is the name of
 * another time already written (0.012 and 0.01 as "0.01").  A raised
 * precision is kept for the rest of the run, with a warning. */
void out_name(case_output *o, double t, char *name, size_t len);
/* Write time t, with the restart file of the nstates states (none: no
 * restart file; rst_state_of makes one of a snapshot), the boundary's
 * carried values bnd (NULL: none; rst_bstate_of) and the run's other
 * state ctrl (ctrl_size bytes); returns 0, or nonzero with err filled
 * (nothing half-written).  The name used is in o->last_name.  -parallel's
 * domain mode: on rank 0 between pcd_output_begin and pcd_output_end, the
 * files streamed from every rank's part (solver/pcs_domain.h). */
int out_write(case_output *o, pcs_solver *s, double t, const rst_state *states, int nstates,
              const rst_bstate *bnd, const void *ctrl, size_t ctrl_size, sl_err *err);
/* The run went back to time t (shock handling): time directories written
 * after t hold states it discarded; remove them and their entries. */
int out_discard_after(case_output *o, double t, sl_err *err);

#endif
