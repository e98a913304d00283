/*
 * fo_type: the contract every function-object type fulfils, and helpers
 * shared by the types (reading keys with errors that name file, line and
 * key; writing values).  Private to libsrc/functionObjects.
 *
 * Life of an object: read() once from its dictionary (exits on bad input);
 * on the first execution the list opens <type>.dat and calls header() and
 * columns(); then execute() writes the values of one row (the list writes
 * the time before and the newline after); at_write(), if any, runs at every
 * write time whether or not a row is due (per-time files).  execute() and
 * at_write() must not allocate after their first call.
 */
#ifndef SL_FO_TYPE_H
#define SL_FO_TYPE_H

#include <stdio.h>

#include "dictionary/dict.h"
#include "functionObjects/fo.h"
#include "functionObjects/fo_query.h"
#include "solver/pcisph.h"

typedef struct fo_call {
    const pcs_view *s;
    const fo_index *ix; /* point queries (checked when an object needing them is due) */
    double time;
    const char *time_name; /* time-folder name of `time` */
    int write_time;
    FILE *dat;       /* <type>.dat, positioned for this row's values; NULL: write nothing */
    const char *dir; /* postProcessing/<name>/<startTime> */
} fo_call;

typedef struct fo_type {
    const char *name;
    const char *const *keys; /* its own keys (NULL-terminated); the common ones are added */
    unsigned needs;          /* FO_NEED_* */
    void *(*read)(const dict *d);
    /* '#' lines describing the quantities (not the column line) */
    void (*header)(const void *st, const pcs_view *s, FILE *f);
    /* "\t<name>" for every value column */
    void (*columns)(const void *st, FILE *f);
    void (*execute)(void *st, const fo_call *call);
    void (*at_write)(void *st, const fo_call *call); /* optional */
    void (*free)(void *st);
    /* Optional: the object reads only point queries (fo_query) at points
     * inside these boxes (6 doubles each: lo x y z, hi x y z; infinite
     * bounds allowed), at most max of them written; returns how many it
     * needs.  Without it the object reads the whole state. */
    size_t (*region)(const void *st, double *box, size_t max);
    /* Set: the object reads every fluid particle through the view's sums
     * only (solver/pcs_sums.h), so in -parallel's domain mode execute()
     * and at_write() run on every rank (fo_serve), making the same
     * collective calls, and write only where call->dat is set (rank 0, and
     * only while its file is good); nothing is gathered for it. */
    int collective;
} fo_type;

extern const fo_type fo_type_density_error;
extern const fo_type fo_type_probes;
extern const fo_type fo_type_water_gauges;
extern const fo_type fo_type_energy;
extern const fo_type fo_type_power;

/* ---- reading (all exit with "<file>:<line>: keyword '<key>': <why>") ---- */

__attribute__((noreturn)) void fo_bad_key(const dict *d, const char *key, const char *why);
/* Stop on a getter's error. */
void fo_need(int status, const sl_err *err);
/* `key ((x y z) ...)` with `dim` (2 or 3) numbers per point; *out malloc'd. */
void fo_get_points(const dict *d, const char *key, int dim, double **out, size_t *n);

/* ---- writing ---- */

/* "\t%.10g", or "\tnan" for any NaN; nothing when f is NULL. */
void fo_put(FILE *f, double v);

#endif
