/*
 * case_record: the per-step record postProcessing/timeStep/<startTime>/
 * timeStep.dat, in OpenFOAM's function-object format ('#' header lines, the
 * last naming the columns, tab-separated values), so that gnuplot and
 * OpenFOAM users' scripts read it as it is.
 */
#ifndef SL_CASE_RECORD_H
#define SL_CASE_RECORD_H

#include <stdio.h>

#include "case/case.h"
#include "solver/pcisph.h"

typedef struct case_record {
    FILE *f;
    char *path;
    double flushed; /* wall clock (s) of the last flush */
} case_record;

/* Rows reach the file at least once per second of wall time (so that
 * monitorCase sees a large case's first steps, and kill -9 loses at most
 * a second), and at every rec_flush (the solver calls it on every write
 * and on signals). */
#define REC_FLUSH_SECONDS 1.0

/* Open (creating folders) the record postProcessing/timeStep/<start_name>/
 * of a run starting from the time directory named start_name. */
void rec_open(case_record *r, const sl_case *c, const char *start_name);
void rec_flush(case_record *r);
/* One row: time after the step, the deltaT it used, the step's
 * statistics, a shock flag, the step's wall-clock seconds and the
 * controller's deltaT for the next step (the step used may differ from it
 * by the spreading that lands on write times). */
void rec_step(case_record *r, double t, double dt, const pcs_stats *st, int shock, double wall,
              double dt_next);
void rec_close(case_record *r);

#endif
