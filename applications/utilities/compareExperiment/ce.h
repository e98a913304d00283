/*
 * ce: the parts of compareExperiment (one prefix, one header).
 *
 *   ce_table.c   tables: the experiment's CSV files (comma-separated, '#'
 *                lines, a header row) and the function-object files of a
 *                run (postProcessing/<name>/<startTime>/<type>.dat: '#'
 *                lines, the last naming the tab-separated columns)
 *   ce_run.c     the function-object files of a run, restarts merged
 *   ce_signal.c  time series: the low-pass filter, threshold crossings,
 *                time averages, peaks and errors on the experiment's times
 *   ce_setup.c   system/compareExperimentDict: which experimental column
 *                goes with which column of the run, thresholds and windows
 *   ce_report.c  the comparison of one series, table.md, table.csv
 *   ce_summary.c summary.dat: one row of scalar accuracy measures (for
 *                sweepCase's results)
 *   ce_plot.c    gnuplot overlays, one PNG per group
 *
 * A series is a time column and a value column with strictly increasing
 * times and no NaN (ce_series_clean); all times are in s, values in SI
 * units (m, Pa) once read.
 */
#ifndef CE_H
#define CE_H

#include <stddef.h>
#include <stdio.h>

/* ---- tables -------------------------------------------------------------- */

typedef struct ce_table {
    char *path;
    size_t ncol, nrow;
    char **name; /* ncol column names */
    double *v;   /* nrow x ncol, row-major; NaN where a field is missing or not a number */
} ce_table;

/* Header conventions: CE_CSV, the first line that is not a '#' comment
 * names the columns; CE_DAT, the last '#' line before the data does (its
 * '#' and a leading "Time" kept as the first name).  Fields are separated
 * by commas, tabs or spaces.  Exits naming the file if it cannot be read or
 * has no header or no data row. */
typedef enum { CE_CSV, CE_DAT } ce_format;
void ce_table_read(ce_table *t, const char *path, ce_format format);
void ce_table_free(ce_table *t);
/* Column index of name, or -1. */
int ce_table_column(const ce_table *t, const char *name);

/* ---- series -------------------------------------------------------------- */

typedef struct ce_series {
    size_t n;
    double *t, *v;
} ce_series;

/* Column `col` of t against column 0, values scaled by vscale and times by
 * tscale then shifted by tshift.  Rows whose time is not a number are
 * dropped; a value that is not a number becomes nan_as (the caller states
 * what a missing value means), or its row is dropped when nan_as is NaN.
 * *nan_count (may be NULL) gets the number of such values. */
void ce_series_from_table(ce_series *s, const ce_table *t, int col, double tscale, double tshift,
                          double vscale, double nan_as, size_t *nan_count);
/* Keeps strictly increasing times: a row whose time is not after the last
 * kept one replaces the kept rows from that time on (a restart that redid
 * part of a run), so the newest rows win. */
void ce_series_clean(ce_series *s);
void ce_series_copy(ce_series *dst, const ce_series *src);
void ce_series_free(ce_series *s);

/* ---- the run's function-object files (ce_run.c) ----------------------------- */

/* Every .dat file of postProcessing/<fo>/<startTime>/ of a case, the
 * start times in increasing order. */
typedef struct ce_run {
    char *dir; /* <case>/postProcessing/<fo> */
    size_t ntab;
    ce_table *tab;
    double *start; /* start time of each table's folder */
} ce_run;

/* Exits naming the folder when it is missing or holds no .dat file. */
void ce_run_read(ce_run *r, const char *case_dir, const char *fo);
/* The column over all start times: a run restarted at t0 replaces the rows
 * of earlier runs from t0 on.  Missing values (nan: a dry gauge, a probe
 * with no particle near) become 0, counted in *nan_count.  Exits naming the
 * folder and the columns it has when no file has the column. */
void ce_run_series(ce_series *s, const ce_run *r, const char *column, size_t *nan_count);
void ce_run_free(ce_run *r);

/* ---- signal processing (ce_signal.c) --------------------------------------- */

/* Centred moving average of width w (s) of the piecewise-linear signal:
 * out(t_i) = integral of s over [t_i - w/2, t_i + w/2] / w, the interval
 * cut to [t_0, t_n-1] at the ends.  w <= 0 copies.  out may be s. */
void ce_filter(ce_series *out, const ce_series *s, double w);
/* Linear interpolation at t (t inside [t_0, t_n-1]; clamped outside). */
double ce_value_at(const ce_series *s, double t);
/* The first time the signal exceeds thr, interpolated linearly between
 * the last sample at or below thr and the first above; t_0 if the first
 * sample is already above; NaN if never. */
double ce_crossing(const ce_series *s, double thr);
/* Time average of the piecewise-linear signal over [a, b] (inside its
 * range); NaN if b <= a. */
double ce_mean(const ce_series *s, double a, double b);
/* Largest sample in [a, b] and its time; NaN if none. */
double ce_peak(const ce_series *s, double a, double b, double *at);

/* The simulation against the experiment at the experiment's times in
 * [a, b] (the simulation interpolated linearly with GSL), e = sim - exp. */
typedef struct ce_error {
    size_t n;      /* experimental samples compared */
    double rms;    /* sqrt(mean e^2) */
    double max;    /* max |e| */
    double max_at; /* its time */
    double median; /* median |e|: robust to a few spikes */
    double bias;   /* mean e */
} ce_error;
void ce_compare(ce_error *e, const ce_series *sim, const ce_series *exp, double a, double b);
/* Fraction of the experiment's samples in [a, b] at which the simulation
 * lies within [lo, hi] (lo, hi on the same times as each other). */
double ce_inside_band(const ce_series *sim, const ce_series *lo, const ce_series *hi, double a,
                      double b);

/* ---- the setup (ce_setup.c) ------------------------------------------------- */

typedef enum { CE_HEIGHT, CE_PRESSURE } ce_kind;

typedef struct ce_entry {
    char *name;        /* the series' label (its key) */
    char *data;        /* experimental column (the central one for a band) */
    char *band[2];     /* experimental columns of the band (NULL: none) */
    char *column;      /* column of the function object's file */
    double threshold;  /* arrival (height, m) or rise (pressure, Pa) */
    double window[2];  /* s: errors and peaks */
    double plateau[2]; /* s: pressure plateau (NaN: none) */
} ce_entry;

typedef struct ce_group {
    char *name, *title;
    ce_kind kind;
    char *fo;    /* function object: postProcessing/<fo>/ */
    int summary; /* counted in summary.dat ('summary', default yes) */
    ce_entry *e;
    size_t n;
} ce_group;

typedef struct ce_setup {
    char *path;        /* the dictionary */
    int normalised;    /* experimental columns t*, p*, h* */
    double H, rho, g;  /* scales of the normalised columns */
    double time_shift; /* s added to the experimental times */
    double filter;     /* s: moving-average width for pressures */
    ce_group *grp;
    size_t ngrp;
} ce_setup;

/* Reads the dictionary; exits naming file, line and keyword on an error. */
void ce_setup_read(ce_setup *s, const char *path);
void ce_setup_free(ce_setup *s);
/* Factors from the experiment's columns to SI: time and value of kind. */
double ce_time_scale(const ce_setup *s);
double ce_value_scale(const ce_setup *s, ce_kind kind);

/* ---- comparing and reporting (ce_report.c) ------------------------------------ */

/* One compared series: the inputs (SI) and what came out. */
typedef struct ce_result {
    const ce_group *g;
    const ce_entry *e;
    const char *data_file; /* where the experimental column came from */
    ce_series sim, exp;    /* raw */
    ce_series simf, expf;  /* filtered (pressures; copies for heights) */
    ce_series lo, hi;      /* band, filtered like exp (n = 0: none) */
    ce_series lo_raw, hi_raw;
    size_t sim_nan;      /* NaN rows of the run taken as 0 */
    double window[2];    /* the window cut to both time ranges */
    double t_sim, t_exp; /* arrival (heights) / rise (pressures) */
    ce_error err;        /* heights raw, pressures filtered */
    double plateau_sim, plateau_exp;
    double peak_sim, peak_sim_at, peak_exp, peak_exp_at;     /* filtered */
    double rpeak_sim, rpeak_sim_at, rpeak_exp, rpeak_exp_at; /* raw */
    double band_peak[3], band_rpeak[3]; /* max of lo, data, hi (filtered; raw) */
    double inside;                      /* fraction of time inside the band */
} ce_result;

void ce_result_compute(ce_result *r, double filter);
void ce_result_free(ce_result *r);
/* table.md and table.csv in dir. */
void ce_report_write(const char *dir, const char *case_dir, const ce_setup *s,
                     const char *const *data_files, size_t ndata, const ce_result *r, size_t n);

/* ---- the one-row summary (ce_summary.c) ---------------------------------------------- */

/* Means over the series of the groups with 'summary yes', from the same
 * numbers as table.csv; NaN where no series enters a mean. */
typedef struct ce_summary {
    double height_rms;  /* mean RMS error of the heights, m */
    double height_max;  /* largest max |e| of the heights, m */
    double arrival;     /* mean |arrival sim - exp|, s (both arrive, neither wet at t_0) */
    double arrival_max; /* largest of those, s */
    double plateau;     /* mean |plateau sim - exp| / |plateau exp| */
    double peak;        /* mean |filtered peak sim - exp| / filtered peak exp */
    size_t nheight;     /* series in height_rms and height_max */
    size_t npressure;   /* series in peak */
} ce_summary;

void ce_summary_compute(ce_summary *m, const ce_result *r, size_t n);
/* The tab-separated header line ("# heightRms ...") and the data row. */
void ce_summary_print(FILE *f, const ce_summary *m);
/* <dir>/summary.dat (atomically): comment lines defining the columns and
 * naming the series, then ce_summary_print. */
void ce_summary_write(const char *dir, const char *case_dir, const ce_setup *s,
                      const char *const *data_files, size_t ndata, const ce_result *r, size_t n,
                      const ce_summary *m);

/* ---- plots (ce_plot.c) ---------------------------------------------------------- */

/* <dir>/<group>/ data files and <group>.gp, and <dir>/<group>.png through
 * gnuplot when plot is set.  Returns the number of plots made. */
int ce_plot_group(const char *dir, const ce_group *g, const ce_result *r, size_t n, double filter,
                  int plot);

/* "a/b", allocated. */
char *ce_join(const char *a, const char *b);

#endif
