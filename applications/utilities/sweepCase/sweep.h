/*
 * sweep: the parts of sweepCase -- the sweep dictionary and its points
 * (sweep_dict.c), preparing and running one case per point (sweep_run.c)
 * and the table of results (sweep_table.c).
 *
 * A sweep dictionary (OpenFOAM syntax; paths relative to its folder):
 *
 *   baseCase    ../../tutorials/damBreak;   // required: the case to clone
 *   combine     product;                    // product (default) or zip
 *   parameters                              // required, at least one
 *   {
 *       // "<file of the case>/<entry path in it>"   (<value> <value> ...);
 *       "constant/fluidProperties/eta"       (0.5 1 2);
 *       "system/timeStepDict/mode"           (adaptive constant);
 *       "constant/fluidProperties/gravity"   ((0 0 -9.81) (0 0 -1.62));
 *   }
 *   results     ("postProcessing/densityError/0/densityError.dat:rhoErrAvg");
 *                                           // optional: <file>:<column>, last row
 *
 * The key of a parameter is a path into the base case: its leading part
 * names a file of the case, the rest the entry in that file (sub-
 * dictionaries separated by '/': "constant/fluidProperties/viscosity/alpha").
 * Its values are a list; each element (a word, number, "string" or a
 * bracketed vector) is one value, written into the case as it is.
 * `product` runs every combination (the first parameter varies slowest),
 * `zip` the i-th values of all parameters together (equal list lengths).
 */
#ifndef SWEEP_H
#define SWEEP_H

#include <stddef.h>

typedef struct sweep_param {
    char *key;   /* as written, for messages */
    char *file;  /* "constant/fluidProperties" */
    char *entry; /* "viscosity/alpha" */
    char *label; /* short unique name: "alpha" (table column, case names) */
    char **value;
    size_t nvalue;
    int line;
} sweep_param;

typedef struct sweep_result {
    char *file;   /* relative to the case */
    char *column; /* name or 1-based number */
    char *label;  /* table column */
} sweep_result;

typedef struct sweep {
    char *path, *dir; /* the sweep dictionary and its folder */
    char *base;       /* the base case */
    char *cases;      /* <dir>/cases */
    char *application;
    int zip;
    sweep_param *param;
    size_t nparam;
    sweep_result *result;
    size_t nresult;
    size_t npoint;
    size_t *choice; /* npoint x nparam: index of the value of each parameter */
    char **name;    /* npoint case names */
} sweep;

/* Reads and checks the sweep dictionary; exits with an error naming the
 * file, line and key on any problem. */
void sweep_read(sweep *s, const char *path);
void sweep_free(sweep *s);
const char *sweep_value(const sweep *s, size_t point, size_t param);
/* "<cases>/<name>", allocated. */
char *sweep_case_dir(const sweep *s, size_t point);

/* ---- running -------------------------------------------------------------- */

/* SWEEP_STOPPED: stopped by a signal (INT, TERM), its state written: the
 * next run of the sweep resumes it (-resume) instead of starting again. */
typedef enum { SWEEP_NOT_RUN, SWEEP_FAILED, SWEEP_FINISHED, SWEEP_STOPPED } sweep_status;

/* From the log: stopped if it has the solver's "Stopped by a signal" or
 * "Stopped by the file stopNow" line, else finished if it has its "End:"
 * line. */
sweep_status sweep_case_status(const sweep *s, size_t point);
/* Clone the base case into the point's folder (replacing it; a failed
 * run's folder is kept as <case>.failed.<n>) and set the point's values;
 * exits on error. */
void sweep_prepare(const sweep *s, size_t point);
/* The solver (bin/<application> beside this program), allocated. */
char *sweep_solver(const sweep *s);
/* Print one shell command per unfinished point (preparing its case; a
 * stopped point's command resumes it). */
void sweep_print_jobs(const sweep *s, int threads, int force);
/* Prepare and run the unfinished points, `jobs` at a time with `threads`
 * OpenMP threads each (0: leave OMP_NUM_THREADS alone); a stopped point is
 * resumed where it stopped (its log kept as log.<application>.<n>), not
 * cloned again (with force every point is).  Returns the number of points
 * that failed. */
int sweep_run(const sweep *s, int jobs, int threads, int force);

/* ---- results --------------------------------------------------------------- */

/* Collect the results of every point and write <dir>/results.csv and
 * <dir>/results.md; prints the Markdown table to stdout. */
void sweep_collect(const sweep *s);

#endif
