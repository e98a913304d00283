/*
 * caseFolder: the files of a case folder as the case tools (cloneCase,
 * cleanCase, listTimes, sweepCase, monitorCase) see them -- which root
 * entries are input and which are results, copying and removing trees,
 * rewriting the ParaView collections from the time directories left,
 * reading OpenFOAM function-object tables such as timeStep.dat, and plotting
 * them with gnuplot.
 *
 * A case root holds input (system/, constant/, Allrun, Allclean, other
 * files) and results: time directories ("0", "0.02", ...; "0" counts as
 * input when it holds files other than the solver's output fluid.vtu,
 * boundary.vtu and uniform/), "*.tmp.*" folders of interrupted writes, collections
 * ("*.pvd", "*.vtu.series"), logs ("log.*") and postProcessing/.
 * Functions returning int give 0 on success, nonzero with err filled.
 */
#ifndef CASEFILES_H
#define CASEFILES_H

#include <stddef.h>
#include <stdio.h>

#include "core/sl_log.h"

/* "a/b", allocated (free() it). */
char *cf_join(const char *a, const char *b);
int cf_is_dir(const char *path);  /* follows symlinks */
int cf_is_file(const char *path); /* a regular file, following symlinks */
int cf_exists(const char *path);  /* anything, even a dangling symlink */
/* A case folder: one with system/controlDict. */
int cf_is_case(const char *dir);

/* ---- trees ------------------------------------------------------------------ */

/* Copy a file (keeping its permission bits) or a symlink (as a symlink). */
int cf_copy_file(const char *src, const char *dst, sl_err *err);
/* Copy a folder recursively into dst (created); symlinks stay symlinks. */
int cf_copy_tree(const char *src, const char *dst, sl_err *err);
/* rm -rf: symlinks are removed, never followed.  A missing path is fine. */
int cf_remove_tree(const char *path, sl_err *err);
/* Copy the input of case src into dst (created; existing files are
 * overwritten): root entries of kind CF_INPUT and the input files of a time
 * directory 0.  *copied (may be NULL) gets the number of root entries. */
int cf_clone_case(const char *src, const char *dst, int *copied, sl_err *err);

/* ---- what a root entry is ------------------------------------------------------ */

typedef enum cf_kind {
    CF_INPUT,          /* system/, constant/, scripts, other files */
    CF_TIME,           /* a time directory (see cf_time_is_input for "0") */
    CF_TMP,            /* "*.tmp.*": an interrupted write */
    CF_COLLECTION,     /* "*.pvd", "*.vtu.series" */
    CF_LOG,            /* "log.*" */
    CF_POSTPROCESSING, /* postProcessing/ */
    CF_HIDDEN          /* ".*": left alone */
} cf_kind;

cf_kind cf_root_kind(const char *case_dir, const char *name);
/* 1 if name is a time ("0", "0.05", "1e-05") and then *t is its value. */
int cf_time_name(const char *name, double *t);
/* The solver's output in a time directory: fluid.vtu, boundary.vtu and
 * uniform/ (the restart file). */
int cf_is_output_file(const char *name);
/* 1 if the time directory holds anything but the solver's output files
 * (initial conditions, like OpenFOAM's 0/). */
int cf_time_has_input(const char *time_dir);

/* Rewrite each collection of the case ("<set>.pvd" and "<set>.vtu.series"
 * at its root) to list exactly the time directories holding "<set>.vtu";
 * a collection left with no time is removed.  *sets (may be NULL) gets the
 * number of collections rewritten. */
int cf_rewrite_collections(const char *case_dir, int *sets, sl_err *err);

/* The per-step record postProcessing/timeStep/<startTime>/timeStep.dat of
 * the run starting at the controlDict's startTime, else the newest record
 * found; NULL (err filled) if there is none.  Allocated. */
char *cf_record_path(const char *case_dir, sl_err *err);

/* Folder of the running program (from /proc/self/exe), allocated. */
char *cf_self_dir(sl_err *err);

/* ---- function-object tables --------------------------------------------------- */

/* An OpenFOAM function-object file: '#' lines, the last of which names the
 * columns, then rows of numbers separated by tabs or spaces. */
typedef struct cf_table {
    size_t ncol, nrow;
    char **name; /* ncol column names ("col1", ... when there is no header) */
    double *v;   /* nrow x ncol, row-major; NaN where a row is short or not a number */
} cf_table;

int cf_table_read(const char *path, cf_table *t, sl_err *err);
/* The same for either format: CF_TABLE_DAT as above, CF_TABLE_CSV with
 * '#' lines, then a header row, then rows, fields separated by commas (or
 * tabs, spaces), quotes stripped.  strict: a row before the header (DAT) or
 * with another number of fields than the header names is an error naming
 * the file and line. */
typedef enum cf_table_format { CF_TABLE_DAT, CF_TABLE_CSV } cf_table_format;
int cf_table_read_as(const char *path, cf_table_format fmt, int strict, cf_table *t, sl_err *err);
void cf_table_free(cf_table *t);
/* Index of the column called name, or of the 1-based number name; -1. */
int cf_table_column(const cf_table *t, const char *name);
/* "a, b, c": the column names, for messages.  Allocated. */
char *cf_table_names(const cf_table *t);

/* The whole per-step record of a case: every start-time folder of
 * postProcessing/timeStep/ in time order (one per run and restart), rows
 * of a folder kept up to the start of the next one (a restart from an
 * earlier time replaces the rows after it), as one table with the first
 * folder's columns.  *folders (may be NULL) gets "postProcessing/timeStep/
 * {0,0.5}/timeStep.dat" for titles and *newest (may be NULL) the path of
 * the newest file (to watch); both allocated.  Nonzero with err filled if
 * there is no record. */
int cf_record_read(const char *case_dir, cf_table *t, char **folders, char **newest, sl_err *err);

/* ---- plotting with gnuplot ------------------------------------------------- */

/* "pngcairo" if gnuplot has it, else "png". */
const char *cf_plot_png_terminal(void);
/* A pipe to a new gnuplot (at most 4 at once); NULL with err filled if
 * gnuplot is missing. */
FILE *cf_plot_open(sl_err *err);
/* Closes the pipe; nonzero (err filled) if gnuplot reported an error. */
int cf_plot_close(FILE *p, sl_err *err);
/* Runs `gnuplot <script>` in dir (NULL: here; stdin /dev/null), or with
 * args (NULL-terminated) `gnuplot -c <script> <args...>` (ARG1, ...);
 * nonzero with err filled if gnuplot is not installed or fails. */
int cf_plot_script(const char *dir, const char *script, const char *const *args, sl_err *err);
/* Writes s as a gnuplot '...' string. */
void cf_plot_string(FILE *p, const char *s);

#endif
