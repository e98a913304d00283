/*
 * ce_plot: one gnuplot overlay per group, a panel per series, simulation
 * over experiment.  The data go to <dir>/<group>/<series>_{sim,exp}.dat
 * and the script to <dir>/<group>.gp, so a user can restyle and rerun it
 * (`gnuplot <group>.gp` in <dir>); the PNG is <dir>/<group>.png.
 *
 * Pressure panels show the raw signals faintly and the filtered ones
 * strongly, with the experimental band (filtered) shaded when there is
 * one; the y range follows the filtered curves, so raw SPH spikes may be
 * cut off at the top.
 */
#include "ce.h"

#include "caseFolder/caseFolder.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Rows of the raw and filtered series (and band) inside [x0, x1]. */
static void write_dat(const char *path, const ce_series *raw, const ce_series *filt,
                      const ce_series *lo, const ce_series *hi, double x0, double x1)
{
    FILE *f = fopen(path, "w");
    if (!f) sl_fatal("cannot write '%s': %s", path, strerror(errno));
    fprintf(f, "# t (s)\traw\tfiltered%s\n", lo && lo->n ? "\tband low\tband high" : "");
    for (size_t k = 0; k < raw->n; k++) {
        if (raw->t[k] < x0 || raw->t[k] > x1) continue;
        fprintf(f, "%.8g\t%.8g\t%.8g", raw->t[k], raw->v[k], filt->v[k]);
        if (lo && lo->n == raw->n && hi->n == raw->n)
            fprintf(f, "\t%.8g\t%.8g", lo->v[k], hi->v[k]);
        fputc('\n', f);
    }
    if (fclose(f) != 0) sl_fatal("cannot write '%s': %s", path, strerror(errno));
}

/* The largest filtered value inside [x0, x1] of any curve of the panel. */
static double panel_top(const ce_result *r, double x0, double x1)
{
    double at, top = 0.0;
    const ce_series *s[] = {&r->simf, &r->expf, &r->hi};
    for (size_t i = 0; i < 3; i++) {
        double m = s[i]->n ? ce_peak(s[i], x0, x1, &at) : (double)NAN;
        if (isfinite(m) && m > top) top = m;
    }
    return top;
}

static void write_script(FILE *f, const char *dir_name, const ce_group *g, const ce_result *r,
                         size_t n, double filter, double x0, double x1)
{
    const int p = g->kind == CE_PRESSURE;
    fprintf(f,
            "# %s: simulation against experiment, written by compareExperiment (Sluice).\n"
            "# Run again with: gnuplot %s.gp   (in this folder)\n"
            "if (strstrt(GPVAL_TERMINALS, \"pngcairo\") > 0) {\n"
            "    set terminal pngcairo size 900,%zu noenhanced font \",9\"\n"
            "} else {\n"
            "    set terminal png size 900,%zu noenhanced\n"
            "}\n"
            "set output \"%s.png\"\n"
            "set multiplot layout %zu,1 title \"%s\"\n"
            "set grid\n"
            "set format x \"%%g\"\n"
            "set key top right font \",8\" opaque box\n"
            "set xrange [%g:%g]\n"
            "set ylabel \"%s\"\n"
            "set lmargin 10\n",
            g->name, g->name, 60 + 210 * n, 60 + 210 * n, g->name, n, g->title, x0, x1,
            p ? "pressure (Pa)" : "height (m)");
    for (size_t i = 0; i < n; i++) {
        const ce_result *x = &r[i];
        const char *s = x->e->name;
        fprintf(f, "set title \"%s: %s (exp) / %s (sim)\"\n", s, x->e->data, x->e->column);
        fputs(i + 1 == n ? "set xlabel \"t (s)\"\n" : "unset xlabel\n", f);
        if (!p) {
            fprintf(f,
                    "set yrange [*:*]\n"
                    "plot \"%s/%s_exp.dat\" using 1:2 with lines lw 1.5 lc rgb \"black\" "
                    "title \"experiment\", \\\n"
                    "     \"%s/%s_sim.dat\" using 1:2 with lines lw 1.5 lc rgb \"#d62728\" "
                    "title \"Sluice\"\n",
                    dir_name, s, dir_name, s);
            continue;
        }
        double top = panel_top(x, x0, x1);
        fprintf(f, "set yrange [%g:%g]\nplot ", -0.1 * top, 1.25 * top + 1.0);
        if (x->lo_raw.n)
            fprintf(f,
                    "\"%s/%s_exp.dat\" using 1:4:5 with filledcurves fc rgb \"#c6dbef\" "
                    "fs solid 1.0 noborder title \"experimental band (%s-%s)\", \\\n     ",
                    dir_name, s, x->e->band[0], x->e->band[1]);
        fprintf(f,
                "\"%s/%s_exp.dat\" using 1:2 with lines lc rgb \"#b0b0b0\" title "
                "\"experiment\", \\\n"
                "     \"%s/%s_sim.dat\" using 1:2 with lines lc rgb \"#f4b6b6\" title "
                "\"Sluice\", \\\n"
                "     \"%s/%s_exp.dat\" using 1:3 with lines lw 2 lc rgb \"black\" title "
                "\"experiment, filtered %g s\", \\\n"
                "     \"%s/%s_sim.dat\" using 1:3 with lines lw 2 lc rgb \"#d62728\" title "
                "\"Sluice, filtered %g s\"\n",
                dir_name, s, dir_name, s, dir_name, s, filter, dir_name, s, filter);
    }
    fputs("unset multiplot\n", f);
}

/* gnuplot <name>.gp in dir; 0 when the PNG was made.  Problems are warnings. */
static int run_gnuplot(const char *dir, const char *name)
{
    char script[512];
    sl_err err;
    snprintf(script, sizeof script, "%s.gp", name);
    if (!cf_plot_script(dir, script, NULL, &err)) return 0;
    sl_warning("%s: no plot; run 'gnuplot %s' in %s later", err.msg, script, dir);
    return 1;
}

int ce_plot_group(const char *dir, const ce_group *g, const ce_result *r, size_t n, double filter,
                  int plot)
{
    if (n == 0) return 0;
    /* x range: from the earliest window start (at least 0) to the end of the
     * run, where the comparison stops. */
    double x0 = INFINITY, x1 = -INFINITY;
    for (size_t i = 0; i < n; i++) {
        x0 = fmin(x0, fmax(r[i].window[0], fmin(r[i].sim.t[0], r[i].exp.t[0])));
        x1 = fmax(x1, r[i].sim.t[r[i].sim.n - 1]);
    }
    x0 = fmin(fmax(x0, 0.0), x1);
    if (!(x1 > x0)) x1 = x0 + 1.0;
    char *sub = ce_join(dir, g->name);
    if (mkdir(sub, 0777) != 0 && errno != EEXIST)
        sl_fatal("cannot create '%s': %s", sub, strerror(errno));
    for (size_t i = 0; i < n; i++) {
        const ce_result *x = &r[i];
        char name[512];
        snprintf(name, sizeof name, "%s/%s_sim.dat", sub, x->e->name);
        write_dat(name, &x->sim, &x->simf, NULL, NULL, x0, x1);
        snprintf(name, sizeof name, "%s/%s_exp.dat", sub, x->e->name);
        write_dat(name, &x->exp, &x->expf, &x->lo, &x->hi, x0, x1);
    }
    free(sub);
    char gp[512];
    snprintf(gp, sizeof gp, "%s/%s.gp", dir, g->name);
    FILE *f = fopen(gp, "w");
    if (!f) sl_fatal("cannot write '%s': %s", gp, strerror(errno));
    write_script(f, g->name, g, r, n, filter, x0, x1);
    if (fclose(f) != 0) sl_fatal("cannot write '%s': %s", gp, strerror(errno));
    if (!plot || run_gnuplot(dir, g->name)) return 0;
    sl_info("Plot: %s/%s.png", dir, g->name);
    return 1;
}
