/* Tests of compareExperiment, run as a program (from $SLUICE_BIN, default
 * bin/) on a synthetic case written under tests/output/validation/: fake
 * function-object files and a fake experimental CSV whose arrival times,
 * errors, plateaus and peaks are known in closed form, and the means of
 * them in summary.dat.  Then the inputs that must stop it with a message
 * naming what is wrong. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "tool_run.h"

#include "caseFolder/caseFolder.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

#define OUT     "tests/output/validation"
#define CASE    OUT "/case"
#define CSV     OUT "/exp.csv"
#define TABLE   CASE "/postProcessing/compareExperiment/table.csv"
#define SUMMARY CASE "/postProcessing/compareExperiment/summary.dat"

/* compareExperiment with arguments. */
#define compare(...) run("%s/compareExperiment " __VA_ARGS__)

/* ---- the synthetic case ---------------------------------------------------------
 *
 * Run (function-object files), times in s:
 *   height_0  max(0, t - 0.5), nan (dry) before 0.5   -> arrival 0.6 at 0.1 m
 *   height_1  0.2                                      -> wet from the start
 *   pressure_0  0 before 0.9, ramp to 1000 at 1.0, then 1000
 *   pressure_1  1000 + 300 (-1)^k, k the row (noise a filter must remove)
 * sampled every 0.01 s up to 1 and every 0.005 s from 1 to 2, so that the
 * results must not depend on the sampling.  The gauges were restarted at
 * t = 1: postProcessing/gauges/0 holds wrong heights (5 m) from t = 1 on,
 * which postProcessing/gauges/1 replaces.
 *
 * Experiment (CSV, 1 kHz, 0..3 s):
 *   H1_m   max(0, t - 0.4)                  -> arrival 0.5
 *   H2_m   0.2 + 0.05 (-1)^k                -> RMS error 0.05
 *   P1_Pa  0 before 0.8, ramp to 2000 at 0.9, then 2000
 *   P2_Pa  1000;  P2_lo 800;  P2_hi 1200 (a band around it)
 */

static double run_time(int k) { return k <= 100 ? 0.01 * k : 1.0 + 0.005 * (k - 100); }
#define RUN_ROWS 301 /* up to t = 2 */

static double ramp(double t, double t0, double t1, double top)
{
    return t <= t0 ? 0.0 : t >= t1 ? top : top * (t - t0) / (t1 - t0);
}

static void write_run(void)
{
    assert_int_equal(run("mkdir -p %s/postProcessing/gauges/0 %s/postProcessing/gauges/1 "
                         "%s/postProcessing/probes/0 %s/system",
                         CASE, CASE, CASE, CASE),
                     0);
    FILE *g0 = fopen(CASE "/postProcessing/gauges/0/waterGauges.dat", "w");
    FILE *g1 = fopen(CASE "/postProcessing/gauges/1/waterGauges.dat", "w");
    FILE *p = fopen(CASE "/postProcessing/probes/0/probes.dat", "w");
    assert_non_null(g0);
    assert_non_null(g1);
    assert_non_null(p);
    const char *gh = "# waterGauges: function object 'gauges' (Sluice)\n"
                     "# Gauge 0 (0.5 0.5)\n# Gauge 1 (1 0.5)\n# Time\theight_0\theight_1\n";
    fputs(gh, g0);
    fputs(gh, g1);
    fputs("# probes: function object 'probes' (Sluice)\n# Probe 0 (1 1 1)\n"
          "# Time\tpressure_0\tpressure_1\n",
          p);
    for (int k = 0; k < RUN_ROWS; k++) {
        double t = run_time(k);
        FILE *g = t < 1.0 ? g0 : g1;
        if (t < 0.5) fprintf(g, "%.10g\tnan\t0.2\n", t);
        else fprintf(g, "%.10g\t%.10g\t0.2\n", t, t - 0.5);
        if (t >= 1.0) fprintf(g0, "%.10g\t5\t5\n", t); /* replaced by the restart */
        fprintf(p, "%.10g\t%.10g\t%.10g\n", t, ramp(t, 0.9, 1.0, 1000.0),
                1000.0 + (k % 2 ? -300.0 : 300.0));
    }
    fclose(g0);
    fclose(g1);
    fclose(p);
}

static void write_csv(void)
{
    FILE *f = fopen(CSV, "w");
    assert_non_null(f);
    fputs("# source: synthetic, written by tests/unit/test_validation.c\n"
          "# columns: t_s = time; heights in m, pressures in Pa\n"
          "t_s,H1_m,H2_m,P1_Pa,P2_Pa,P2_lo,P2_hi\n",
          f);
    for (int k = 0; k <= 3000; k++) {
        double t = 0.001 * k;
        fprintf(f, "%.10g,%.10g,%.10g,%.10g,1000,800,1200\n", t, fmax(0.0, t - 0.4),
                0.2 + (k % 2 ? -0.05 : 0.05), ramp(t, 0.8, 0.9, 2000.0));
    }
    fclose(f);
}

static const char *dict_text =
    "FoamFile { version 2.0; format ascii; class dictionary; object compareExperimentDict; }\n"
    "experiment { normalised off; }\n"
    "filter 0.2;\n"
    "groups\n"
    "{\n"
    "    heights\n"
    "    {\n"
    "        quantity height; functionObject gauges; threshold 0.1; window (0 2);\n"
    "        H1 { data H1_m; column height_0; }\n"
    "        H2 { data H2_m; column height_1; }\n"
    "    }\n"
    "    loads\n"
    "    {\n"
    "        quantity pressure; functionObject probes; threshold 500; window (0 2);\n"
    "        plateau (1.2 1.8);\n"
    "        P1 { data P1_Pa; column pressure_0; }\n"
    "        P2 { data P2_Pa; column pressure_1; band (P2_lo P2_hi); }\n"
    "    }\n"
    "}\n";

static void fresh_case(void)
{
    assert_int_equal(run("rm -rf %s && mkdir -p %s", OUT, OUT), 0);
    write_run();
    write_csv();
    spit(CASE "/system/compareExperimentDict", dict_text);
}

#define metric table_metric

static char *run_default(void)
{
    fresh_case();
    int rc = compare("-case %s -data %s -noPlot", bin_dir(), CASE, CSV);
    if (rc) fail_msg("compareExperiment failed: %s", output);
    return slurp(TABLE);
}

/* ---- results --------------------------------------------------------------------- */

static void test_arrival_times(void **state)
{
    (void)state;
    char *t = run_default();
    assert_float_equal(metric(t, "heights,H1,arrival_sim"), 0.6, 1e-9);
    assert_float_equal(metric(t, "heights,H1,arrival_exp"), 0.5, 1e-9);
    assert_float_equal(metric(t, "heights,H1,arrival_diff"), 0.1, 1e-9);
    /* wet from the first sample: arrival at the first time */
    assert_float_equal(metric(t, "heights,H2,arrival_sim"), 0.0, 1e-12);
    assert_float_equal(metric(t, "heights,H2,arrival_exp"), 0.0, 1e-12);
    /* the 50 dry rows before t = 0.5 were nan, counted and taken as 0 */
    assert_float_equal(metric(t, "heights,H1,nan_rows_sim"), 50, 0);
    free(t);
}

static void test_height_errors(void **state)
{
    (void)state;
    char *t = run_default();
    /* window 0..2 cut to the run's end: experimental samples 0, 0.001 .. 2 */
    assert_float_equal(metric(t, "heights,H2,samples"), 2001, 0);
    assert_float_equal(metric(t, "heights,H2,window_end"), 2.0, 0);
    /* H2: the experiment is 0.2 -+ 0.05, the run 0.2 (and 5 m before the
     * restart replaced it): |e| = 0.05 everywhere, 1001 times -0.05 */
    assert_float_equal(metric(t, "heights,H2,rms_error"), 0.05, 1e-9);
    assert_float_equal(metric(t, "heights,H2,max_error"), 0.05, 1e-9);
    assert_float_equal(metric(t, "heights,H2,median_abs_error"), 0.05, 1e-9);
    assert_float_equal(metric(t, "heights,H2,bias"), -0.05 / 2001, 1e-9);
    /* H1: e = max(0, t - 0.5) - max(0, t - 0.4), summed here independently */
    double s2 = 0, s = 0;
    for (int k = 0; k <= 2000; k++) {
        double x = 0.001 * k, e = fmax(0.0, x - 0.5) - fmax(0.0, x - 0.4);
        s2 += e * e;
        s += e;
    }
    assert_float_equal(metric(t, "heights,H1,rms_error"), sqrt(s2 / 2001), 1e-9);
    assert_float_equal(metric(t, "heights,H1,bias"), s / 2001, 1e-9);
    assert_float_equal(metric(t, "heights,H1,max_error"), 0.1, 1e-9);
    /* |e| is 0 on 0..0.4 (401 samples), t - 0.4 on 0.4..0.5, 0.1 after
     * (1500 samples): the median of 2001 is 0.1 */
    assert_float_equal(metric(t, "heights,H1,median_abs_error"), 0.1, 1e-9);
    free(t);
}

static void test_pressure_rise_plateau_peak(void **state)
{
    (void)state;
    char *t = run_default();
    /* a ramp of height A over 0.1 s under a 0.2 s moving average is linear
     * while the window holds it, and crosses A/2 at the ramp's middle:
     * threshold 500 is A/2 for the run (0.95), A/4 for the experiment,
     * whose filtered ramp 2000 (t - 0.75) / 0.2 reaches 500 at 0.8 */
    assert_float_equal(metric(t, "loads,P1,rise_sim"), 0.95, 1e-9);
    assert_float_equal(metric(t, "loads,P1,rise_exp"), 0.80, 1e-9);
    assert_float_equal(metric(t, "loads,P1,plateau_sim"), 1000, 1e-6);
    assert_float_equal(metric(t, "loads,P1,plateau_exp"), 2000, 1e-6);
    assert_float_equal(metric(t, "loads,P1,peak_filtered_sim"), 1000, 1e-6);
    assert_float_equal(metric(t, "loads,P1,peak_filtered_exp"), 2000, 1e-6);
    assert_float_equal(metric(t, "loads,P1,peak_raw_sim"), 1000, 1e-9);
    /* P2: +-300 Pa of noise on every row; raw peak 1300, filtered ~1000 */
    assert_float_equal(metric(t, "loads,P2,peak_raw_sim"), 1300, 1e-9);
    assert_float_equal(metric(t, "loads,P2,peak_filtered_sim"), 1000, 20);
    assert_float_equal(metric(t, "loads,P2,plateau_sim"), 1000, 5);
    assert_true(metric(t, "loads,P2,rms_error") < 20);
    /* the band 800..1200 holds the filtered run everywhere */
    assert_float_equal(metric(t, "loads,P2,band_peak_filtered_low"), 800, 1e-9);
    assert_float_equal(metric(t, "loads,P2,band_peak_filtered_high"), 1200, 1e-9);
    assert_float_equal(metric(t, "loads,P2,inside_band_fraction"), 1.0, 0);
    free(t);
    char *md = slurp(CASE "/postProcessing/compareExperiment/table.md");
    assert_non_null(strstr(md, "| P2 | P2_lo / P2_Pa / P2_hi |"));
    assert_non_null(strstr(md, "| inside |"));
    assert_non_null(strstr(md, "moving average of width 0.2 s"));
    free(md);
}

static void test_window_and_filter_options(void **state)
{
    (void)state;
    fresh_case();
    assert_int_equal(
        compare("-case %s -data %s -noPlot -window 0.45:0.55 -filter 0", bin_dir(), CASE, CSV), 0);
    char *t = slurp(TABLE);
    /* in 0.45..0.55 the H1 error is -(t - 0.4) up to 0.5, then -0.1 */
    assert_float_equal(metric(t, "heights,H1,window_start"), 0.45, 1e-12);
    assert_float_equal(metric(t, "heights,H1,samples"), 101, 0);
    assert_float_equal(metric(t, "heights,H1,max_error"), 0.1, 1e-9);
    /* unfiltered, P2's raw and filtered peaks are the same 1300 */
    assert_float_equal(metric(t, "loads,P2,peak_filtered_sim"), 1300, 1e-9);
    free(t);
}

static void test_normalised_columns(void **state)
{
    (void)state;
    fresh_case();
    /* t* = t sqrt(g/H) = 2 t, h* = h/H = h, p* = p/(rho g H) = p/4000 */
    FILE *f = fopen(OUT "/star.csv", "w");
    assert_non_null(f);
    fputs("# normalised\nt_star,h_star,p_star\n", f);
    for (int k = 0; k <= 4000; k++) {
        double ts = 0.001 * k;
        fprintf(f, "%.10g,%.10g,0.25\n", ts, fmax(0.0, ts - 1.0));
    }
    fclose(f);
    spit(OUT "/star.dict",
         "experiment { normalised on; length 1; density 1000; gravity 4; }\n"
         "groups {\n"
         "  h { quantity height; functionObject gauges; threshold 0.1; H { data h_star; column "
         "height_0; } }\n"
         "  p { quantity pressure; functionObject probes; threshold 500; plateau (1.2 1.8);\n"
         "      P { data p_star; column pressure_0; } }\n"
         "}\n");
    assert_int_equal(compare("-case %s -data %s -dict %s -noPlot", bin_dir(), CASE, OUT "/star.csv",
                             OUT "/star.dict"),
                     0);
    char *t = slurp(TABLE);
    /* h = max(0, 2t - 1) reaches 0.1 at t = 0.55 */
    assert_float_equal(metric(t, "h,H,arrival_exp"), 0.55, 1e-9);
    assert_float_equal(metric(t, "p,P,plateau_exp"), 1000, 1e-9);
    /* the experiment ends at t* = 4, t = 2 */
    assert_float_equal(metric(t, "h,H,window_end"), 2.0, 1e-12);
    free(t);
}

static void test_plots(void **state)
{
    (void)state;
    fresh_case();
    assert_int_equal(compare("-case %s -data %s", bin_dir(), CASE, CSV), 0);
    const char *dir = CASE "/postProcessing/compareExperiment";
    char path[256];
    snprintf(path, sizeof path, "%s/heights.gp", dir);
    assert_true(exists(path));
    snprintf(path, sizeof path, "%s/loads/P2_exp.dat", dir);
    assert_true(exists(path));
    if (run("command -v gnuplot") == 0) {
        snprintf(path, sizeof path, "%s/heights.png", dir);
        assert_true(exists(path));
        snprintf(path, sizeof path, "%s/loads.png", dir);
        assert_true(exists(path));
    }
}

/* ---- summary.dat ------------------------------------------------------------------ */

/* |a - b| <= tol in double precision (cmocka's assert_float_equal compares
 * floats); NaN fails. */
#define assert_near(a, b, tol)                                                       \
    do {                                                                             \
        double a_ = (a), b_ = (b);                                                   \
        if (!(fabs(a_ - b_) <= (tol)))                                               \
            fail_msg("%s = %.12g, expected %.12g +- %g", #a, a_, b_, (double)(tol)); \
    } while (0)

enum { S_RMS, S_MAX, S_ARRIVAL, S_ARRIVAL_MAX, S_PLATEAU, S_PEAK, S_NH, S_NP, S_N };
static const char *const summary_column[S_N] = {"heightRms",       "heightMaxAbs", "arrivalError",
                                                "arrivalErrorMax", "plateauError", "peakError",
                                                "nHeights",        "nPressures"};

/* summary.dat read as sweepCase reads a result (cf_table_read: the last
 * '#' line names the columns): exactly these columns, one row. */
static void read_summary(double v[S_N])
{
    cf_table t;
    sl_err err;
    if (cf_table_read(SUMMARY, &t, &err)) fail_msg("%s", err.msg);
    assert_int_equal(t.ncol, S_N);
    assert_int_equal(t.nrow, 1);
    for (int c = 0; c < S_N; c++) {
        assert_string_equal(t.name[c], summary_column[c]);
        v[c] = t.v[c];
    }
    cf_table_free(&t);
}

/* H1's RMS error over 0..2, summed as in test_height_errors. */
static double h1_rms(void)
{
    double s2 = 0;
    for (int k = 0; k <= 2000; k++) {
        double x = 0.001 * k, e = fmax(0.0, x - 0.5) - fmax(0.0, x - 0.4);
        s2 += e * e;
    }
    return sqrt(s2 / 2001);
}

static void test_summary(void **state)
{
    (void)state;
    char *t = run_default();
    double v[S_N];
    read_summary(v);
    /* heights: RMS H1 and 0.05 (H2); max |e| 0.1 (H1) and 0.05 */
    assert_near(v[S_RMS], 0.5 * (h1_rms() + 0.05), 1e-9);
    assert_near(v[S_MAX], 0.1, 1e-9);
    /* arrivals: H1 0.6 - 0.5; H2 is wet from the start and left out (with it,
     * the mean would be 0.05) */
    assert_near(v[S_ARRIVAL], 0.1, 1e-9);
    assert_near(v[S_ARRIVAL_MAX], 0.1, 1e-9);
    /* plateaus: P1 |1000 - 2000| / 2000, P2 1000 against 1000 (the noise
     * averages out over whole segments) */
    assert_near(v[S_PLATEAU], 0.5 * (0.5 + 0.0), 1e-6);
    /* filtered peaks: P1 1000 against 2000; P2's 0.2 s average is 1000 over
     * whole segments of the +-300 noise, and the windows around t = 1.015,
     * 1.035, ... end half-way into a 0.01 s segment rising 1000 -> 1300:
     * + 150 Pa * 0.005 s / 0.2 s = 3.75 Pa over the experiment's 1000 */
    assert_near(v[S_PEAK], 0.5 * (0.5 + 0.00375), 1e-6);
    /* ... which is what table.csv holds */
    double p2 = metric(t, "loads,P2,peak_filtered_sim");
    assert_near(v[S_PEAK], 0.5 * (0.5 + fabs(p2 - 1000) / 1000), 1e-9);
    assert_near(v[S_NH], 2, 0);
    assert_near(v[S_NP], 2, 0);
    free(t);
    /* printed after the table, too */
    assert_non_null(strstr(output,
                           "# heightRms\theightMaxAbs\tarrivalError\tarrivalErrorMax\t"
                           "plateauError\tpeakError\tnHeights\tnPressures\n"));
    assert_non_null(strstr(output, "\t2\t2\n"));
    /* the comment lines say what went in */
    char *s = slurp(SUMMARY);
    assert_non_null(strstr(s, "# height series: heights/H1, heights/H2 (window 0-2 s)\n"));
    assert_non_null(strstr(s, "# arrivals of: heights/H1\n"));
    assert_non_null(strstr(s, "moving average of 0.2 s"));
    assert_non_null(strstr(s, "# plateaus of: loads/P1, loads/P2 (plateau 1.2-1.8 s)\n"));
    free(s);
    /* written through a temporary file, none left behind */
    assert_int_not_equal(run("ls %s/postProcessing/compareExperiment | grep tmp", CASE), 0);
}

static void test_summary_unfiltered(void **state)
{
    (void)state;
    fresh_case();
    assert_int_equal(compare("-case %s -data %s -noPlot -filter 0", bin_dir(), CASE, CSV), 0);
    double v[S_N];
    read_summary(v);
    /* raw peaks: P1 1000 against 2000, P2 1300 against 1000 */
    assert_near(v[S_PEAK], 0.5 * (0.5 + 0.3), 1e-9);
    /* plateaus are time averages of the unfiltered pressures anyway */
    assert_near(v[S_PLATEAU], 0.25, 1e-6);
}

static void test_summary_groups(void **state)
{
    (void)state;
    fresh_case();
    /* 'summary no' leaves out H1 and P2: were they counted, the means would
     * be those of test_summary */
    spit(CASE "/system/compareExperimentDict",
         "filter 0.2;\n"
         "groups {\n"
         "  wet { quantity height; functionObject gauges; threshold 0.1; window (0 2);\n"
         "        H2 { data H2_m; column height_1; } }\n"
         "  front { quantity height; functionObject gauges; threshold 0.1; window (0 2);\n"
         "          summary no; H1 { data H1_m; column height_0; } }\n"
         "  wall { quantity pressure; functionObject probes; threshold 500; window (0 2);\n"
         "         plateau (1.2 1.8); summary no; P2 { data P2_Pa; column pressure_1; } }\n"
         "  fluid { quantity pressure; functionObject probes; threshold 500; window (0 2);\n"
         "          plateau (1.2 1.8); summary yes; P1 { data P1_Pa; column pressure_0; } }\n"
         "}\n");
    assert_int_equal(compare("-case %s -data %s -noPlot", bin_dir(), CASE, CSV), 0);
    double v[S_N];
    read_summary(v);
    assert_near(v[S_RMS], 0.05, 1e-9);
    assert_near(v[S_MAX], 0.05, 1e-9);
    /* the one gauge left is wet from the start: no arrival, nan */
    assert_true(isnan(v[S_ARRIVAL]));
    assert_true(isnan(v[S_ARRIVAL_MAX]));
    assert_near(v[S_PLATEAU], 0.5, 1e-6);
    assert_near(v[S_PEAK], 0.5, 1e-6);
    assert_near(v[S_NH], 1, 0);
    assert_near(v[S_NP], 1, 0);
    /* the table still has them */
    char *t = slurp(TABLE);
    assert_near(metric(t, "front,H1,arrival_sim"), 0.6, 1e-9);
    assert_near(metric(t, "wall,P2,peak_raw_sim"), 1300, 1e-9);
    free(t);
    char *s = slurp(SUMMARY);
    assert_non_null(strstr(s, "# groups not counted (summary no): front, wall\n"));
    free(s);

    /* no height series counted, no pressure with a plateau: nan, and 0 */
    spit(CASE "/system/compareExperimentDict",
         "filter 0.2;\n"
         "groups {\n"
         "  heights { quantity height; functionObject gauges; threshold 0.1; window (0 2);\n"
         "            summary off; H1 { data H1_m; column height_0; } }\n"
         "  loads { quantity pressure; functionObject probes; threshold 500; window (0 2);\n"
         "          P2 { data P2_Pa; column pressure_1; } }\n"
         "}\n");
    assert_int_equal(compare("-case %s -data %s -noPlot", bin_dir(), CASE, CSV), 0);
    read_summary(v);
    for (int c = S_RMS; c <= S_PLATEAU; c++)
        if (!isnan(v[c])) fail_msg("%s is %g, not nan", summary_column[c], v[c]);
    assert_near(v[S_PEAK], 0.00375, 1e-6);
    assert_near(v[S_NH], 0, 0);
    assert_near(v[S_NP], 1, 0);
    assert_non_null(strstr(output, "nan\tnan\tnan\tnan\tnan\t"));
}

static void test_summary_bad_keyword(void **state)
{
    (void)state;
    fresh_case();
    spit(CASE "/system/compareExperimentDict",
         "groups\n{\n  h\n  {\n    quantity height; functionObject gauges; threshold 0.1;\n"
         "    summary maybe;\n    H1 { data H1_m; column height_0; }\n  }\n}\n");
    assert_int_not_equal(compare("-case %s -data %s -noPlot", bin_dir(), CASE, CSV), 0);
    assert_non_null(strstr(output, "compareExperimentDict:6"));
    assert_non_null(strstr(output, "'summary'"));
    assert_non_null(strstr(output, "maybe"));
    assert_false(exists(SUMMARY));
}

/* ---- bad inputs ------------------------------------------------------------------- */

static void test_missing_files(void **state)
{
    (void)state;
    fresh_case();
    assert_int_not_equal(compare("-case %s/nothing -data %s", bin_dir(), OUT, CSV), 0);
    assert_non_null(strstr(output, "nothing"));
    assert_int_not_equal(compare("-case %s -data %s/none.csv", bin_dir(), CASE, OUT), 0);
    assert_non_null(strstr(output, "none.csv"));
    assert_int_not_equal(compare("-case %s -data %s -dict %s/no.dict", bin_dir(), CASE, CSV, OUT),
                         0);
    assert_non_null(strstr(output, "no.dict"));
    assert_int_equal(run("rm -rf %s/postProcessing/probes", CASE), 0);
    assert_int_not_equal(compare("-case %s -data %s", bin_dir(), CASE, CSV), 0);
    assert_non_null(strstr(output, "postProcessing/probes"));
    assert_int_not_equal(compare("-case %s", bin_dir(), CASE), 0); /* no -data */
    assert_non_null(strstr(output, "-data"));
    assert_false(exists(TABLE));
}

static void test_bad_columns_and_dictionary(void **state)
{
    (void)state;
    fresh_case();
    /* a column the run does not have */
    char *d = strdup(dict_text);
    char *at = strstr(d, "column pressure_1");
    memcpy(at, "column pressure_9", 17);
    spit(CASE "/system/compareExperimentDict", d);
    free(d);
    assert_int_not_equal(compare("-case %s -data %s", bin_dir(), CASE, CSV), 0);
    assert_non_null(strstr(output, "pressure_9"));
    /* a data file with none of the columns */
    spit(CASE "/system/compareExperimentDict", dict_text);
    spit(OUT "/other.csv", "t,x\n0,1\n1,2\n");
    assert_int_not_equal(compare("-case %s -data %s/other.csv", bin_dir(), CASE, OUT), 0);
    assert_non_null(strstr(output, "other.csv"));
    /* a window the wrong way round: file, line and keyword */
    spit(CASE "/system/compareExperimentDict",
         "groups\n{\n  h\n  {\n    quantity height; functionObject gauges; threshold 0.1;\n"
         "    window (2 1);\n    H1 { data H1_m; column height_0; }\n  }\n}\n");
    assert_int_not_equal(compare("-case %s -data %s", bin_dir(), CASE, CSV), 0);
    assert_non_null(strstr(output, "compareExperimentDict:6"));
    assert_non_null(strstr(output, "'window'"));
    /* no threshold anywhere */
    spit(CASE "/system/compareExperimentDict",
         "groups { h { quantity height; functionObject gauges; H1 { data H1_m; column "
         "height_0; } } }\n");
    assert_int_not_equal(compare("-case %s -data %s", bin_dir(), CASE, CSV), 0);
    assert_non_null(strstr(output, "threshold"));
    /* an experimental row with a field missing */
    spit(CASE "/system/compareExperimentDict", dict_text);
    spit(OUT "/short.csv", "t_s,H1_m\n0,1\n1\n");
    assert_int_not_equal(compare("-case %s -data %s/short.csv", bin_dir(), CASE, OUT), 0);
    assert_non_null(strstr(output, "short.csv:3"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_arrival_times),
        cmocka_unit_test(test_height_errors),
        cmocka_unit_test(test_pressure_rise_plateau_peak),
        cmocka_unit_test(test_window_and_filter_options),
        cmocka_unit_test(test_normalised_columns),
        cmocka_unit_test(test_plots),
        cmocka_unit_test(test_summary),
        cmocka_unit_test(test_summary_unfiltered),
        cmocka_unit_test(test_summary_groups),
        cmocka_unit_test(test_summary_bad_keyword),
        cmocka_unit_test(test_missing_files),
        cmocka_unit_test(test_bad_columns_and_dictionary),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
