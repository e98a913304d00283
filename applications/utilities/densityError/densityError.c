/*
 * densityError: the density error of a finished (or running) case over
 * time, from its written time directories, with a plot.
 *
 *   densityError [-case <dir>] [-time <times> | -latestTime] [-noPlot]
 *
 * Runs the densityError function object (the entry called densityError in
 * system/controlDict's functions if there is one, else the defaults) on
 * every selected time's fluid.vtu, writing
 *   postProcessing/densityError/<firstTime>/densityError.dat
 * with the same columns as during a run, then densityError.gp next to it
 * and, through gnuplot, densityError.png: average and maximum compression
 * over time.  A missing gnuplot is a warning (the .gp file stays, to run
 * later with `gnuplot densityError.gp` in that folder).
 */
#include "app/app.h"
#include "case/case.h"
#include "caseFolder/caseFolder.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "functionObjects/fo.h"
#include "functionObjects/fo_post.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const app_option options[] = {
    APP_CASE,
    APP_TIMES,
    {.name = "noPlot", .help = "write the data (and densityError.gp), do not run gnuplot"},
    APP_END};

static const app_info info = {
    .name = "densityError",
    .what = "Density error (percent of rho0) of the written times of a case, into\n"
            "postProcessing/densityError/<firstTime>/densityError.dat and a gnuplot\n"
            "plot densityError.png next to it.",
    .options = options};

/* The gnuplot script, run in the folder of the data. */
static const char plot_script[] =
    "# Density error over time, written by Sluice's densityError utility.\n"
    "# Run again with: gnuplot densityError.gp   (in this folder)\n"
    "if (strstrt(GPVAL_TERMINALS, \"pngcairo\") > 0) {\n"
    "    set terminal pngcairo size 1000,600 noenhanced\n"
    "} else {\n"
    "    set terminal png size 1000,600 noenhanced\n"
    "}\n"
    "set output \"densityError.png\"\n"
    "set title \"Density error: compression max(rho - rho0, 0) / rho0\"\n"
    "set xlabel \"time (s)\"\n"
    "set ylabel \"density error (% of rho0)\"\n"
    "set grid\n"
    "set key below\n"
    "plot \"densityError.dat\" using 1:2 with linespoints pt 7 ps 0.5 title \"average\", \\\n"
    "     \"densityError.dat\" using 1:3 with linespoints pt 5 ps 0.5 title \"maximum\"\n";

/* Write <dir>/densityError.gp; returns 0 on success. */
static int write_script(const char *dir)
{
    size_t n = strlen(dir) + 32;
    char *path = sl_malloc(n, "path");
    snprintf(path, n, "%s/densityError.gp", dir);
    FILE *f = fopen(path, "w");
    int bad = !f || fputs(plot_script, f) < 0;
    if (f && fclose(f) != 0) bad = 1;
    if (bad) sl_warning("cannot write '%s': %s", path, strerror(errno));
    free(path);
    return bad;
}

/* Run gnuplot on the script in dir; problems are warnings. */
static void run_gnuplot(const char *dir)
{
    sl_err err;
    if (cf_plot_script(dir, "densityError.gp", NULL, &err))
        sl_warning("%s: no plot; run 'gnuplot densityError.gp' in %s later", err.msg, dir);
    else sl_info("Plot: %s/densityError.png", dir);
}

int main(int argc, char **argv)
{
    app a;
    app_parse(&a, &info, argc, argv);
    const char *dir = app_case(&a), *spec = app_string(&a, "time", NULL);
    int latest = app_found(&a, "latestTime"), plot = !app_found(&a, "noPlot");
    sl_case c;
    tdir_list times;
    sl_err err;
    const char *name = "densityError";
    case_read(&c, dir);
    fo_list *l = fo_select(&c, &name, 1);
    if (strcmp(fo_type_name(l, 0), "densityError"))
        sl_fatal("%s/system/controlDict: function object 'densityError' has type '%s'; the "
                 "densityError utility needs type densityError",
                 c.dir, fo_type_name(l, 0));
    if (fo_post_times(c.dir, spec, latest, &times, &err)) sl_fatal("%s", err.msg);
    for (size_t i = 0; i < times.n; i++) {
        fo_snapshot sn;
        if (fo_snapshot_load(&sn, &c, times.name[i], fo_needs(l), &err)) sl_fatal("%s", err.msg);
        fo_execute(l, &sn.v, times.time[i], (long)i, 1);
        fo_snapshot_free(&sn);
    }
    char *dat = sl_strdup(fo_dat_path(l, 0));
    fo_free(l);
    sl_info("densityError: %zu time%s -> %s", times.n, times.n == 1 ? "" : "s", dat);
    char *slash = strrchr(dat, '/');
    if (slash) *slash = '\0';
    if (!write_script(dat) && plot) run_gnuplot(dat);
    free(dat);
    tdir_list_free(&times);
    case_free(&c);
    app_free(&a);
    return 0;
}
