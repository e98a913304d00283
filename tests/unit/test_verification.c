/* Verification against exact answers (doc/verification.md): the coarse
 * levels of cases/verification/ run by bin/pcisph and judged by
 * bin/verifyCase, with stated tolerances, and the observed order between
 * two levels where the method converges, so that a change that breaks
 * convergence fails here.  Then the inputs verifyCase must refuse.
 * Runs go to tests/output/verification/; about a minute on an idle core. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include "tool_run.h"
#include "kernel/kernel.h"
#include "parallel/par.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define OUT   "tests/output/verification"
#define CASES "cases/verification"

/* Copy <case>/<base> to OUT/<name>, set particleSpacing r0 and deltaT dt
 * and run the shell commands `edit` in it (may be ""), run the solver and
 * verifyCase; returns verifyCase's error (summary.dat's first column). */
static double level_of(const char *kase, const char *base, const char *name, double r0, double dt,
                       const char *edit)
{
    const char *b = bin_dir();
    assert_int_equal(run("rm -rf " OUT "/%s && mkdir -p " OUT " && %s/cloneCase " CASES
                         "/%s/%s " OUT "/%s",
                         name, b, kase, base, name),
                     0);
    assert_int_equal(run("cd " OUT "/%s && %s/editDictionary constant/fluidProperties -entry "
                         "particleSpacing -set %g && %s/editDictionary system/timeStepDict "
                         "-entry deltaT -set %g && %s",
                         name, b, r0, b, dt, edit[0] ? edit : "true"),
                     0);
    int rc = run("%s/pcisph -case " OUT "/%s > " OUT "/%s/log.pcisph 2>&1", b, name, name);
    if (rc) print_error("%s", output);
    assert_int_equal(rc, 0);
    rc = run("%s/verifyCase -case " OUT "/%s", b, name);
    assert_int_equal(rc, 0);
    char path[512];
    snprintf(path, sizeof path, OUT "/%s/postProcessing/verifyCase/summary.dat", name);
    char *s = slurp(path), *row = s;
    while (*row == '#') row = strchr(row, '\n') + 1;
    double e = strtod(row, NULL);
    free(s);
    print_message("%s r0 %g: error %.4g\n", name, r0, e);
    return e;
}

/* level_of() on <case>/base. */
static double level(const char *kase, const char *name, double r0, double dt, const char *edit)
{
    return level_of(kase, "base", name, r0, dt, edit);
}

/* Column `col` (0 = error) of the summary.dat row verifyCase wrote in
 * OUT/<name> (by level()). */
static double summary_column(const char *name, int col)
{
    char path[512];
    snprintf(path, sizeof path, OUT "/%s/postProcessing/verifyCase/summary.dat", name);
    char *s = slurp(path), *row = s;
    while (*row == '#') row = strchr(row, '\n') + 1;
    double v = strtod(row, &row);
    for (int k = 0; k < col; k++) v = strtod(row, &row);
    free(s);
    return v;
}

/* Column `col` (0 = error, 1 = pressureError) of the row of written time t
 * in the table verifyCase printed last (right after level()); NAN if none. */
static double time_column(double t, int col)
{
    for (const char *row = output; row && *row;
         row = strchr(row, '\n'), row = row ? row + 1 : NULL) {
        if (*row == '#') continue;
        char *end;
        const double rt = strtod(row, &end);
        if (end == row || fabs(rt - t) > 1e-9) continue;
        double v = NAN;
        for (int k = 0; k <= col; k++) v = strtod(end, &end);
        return v;
    }
    return NAN;
}

/* The sanitizer build (tests/run_tests --quick, SLUICE_QUICK=1) skips the
 * accuracy tests whose fine levels take minutes under ASan (r0 0.005 of
 * the standing wave: 1-2.5 min each there); their code paths run in its
 * other tests, and the release run asserts them.  Reported as skipped. */
#define SKIP_UNDER_SANITIZERS()                                                             \
    do {                                                                                    \
        const char *q_ = getenv("SLUICE_QUICK");                                            \
        if (q_ && !strcmp(q_, "1")) {                                                       \
            print_message("sanitizer build (SLUICE_QUICK=1): the fine levels take minutes " \
                          "here; the release run asserts this test: skipped\n");            \
            skip();                                                                         \
        }                                                                                   \
    } while (0)

/* Poiseuille flow with the laminar viscosity: the profile's error over
 * u_max falls at first order (measured 0.206 at r0 0.01 m, 0.104 at
 * 0.005 m: 1.98x).  Tolerances: 1.2x the measured, and >= 1.5x per halving. */
static void test_poiseuille_converges(void **state)
{
    (void)state;
    double e1 = level("poiseuille", "poiseuille_0.01", 0.01, 0.0005, "");
    double e2 = level("poiseuille", "poiseuille_0.005", 0.005, 0.00025, "");
    assert_true(e1 < 0.25);
    assert_true(e2 < 0.125);
    assert_true(e1 / e2 >= 1.5);
}

/* The artificial viscosity with the same nu (Becker-Teschner mapping
 * alpha h c = 10 nu, damping approaching pairs only) does not reach the
 * profile: its error at r0 0.005 m stays well above the laminar one. */
static void test_poiseuille_artificial_viscosity_misses(void **state)
{
    (void)state;
    double e = level("poiseuille", "poiseuille_artificial", 0.005, 0.00025,
                     "sed -i 's/^laminarViscosity.*/viscosity { nu 0.01; boundaryNu 0.01; }/' "
                     "constant/fluidProperties");
    assert_true(e > 0.3);
}

/* A tank translating at 0.2 m/s with its water: the spurious velocities'
 * rms over sqrt(g H) (measured 0.0034 at r0 0.01 m). */
static void test_translating_tank(void **state)
{
    (void)state;
    double e = level("translatingTank", "translatingTank_0.01", 0.01, 0.002, "");
    assert_true(e < 0.006);
}

/* The hydrostatic tank: the layer-averaged pressure against rho0 g (H - z),
 * rms over rho0 g H, mean over the written times.  With dt = r0 / 5 s/m it
 * does not fall with r0 (0.110 at r0 0.01 m from the cubic lattice, see
 * doc/verification.md); with dt = r0 / 20 from a relaxed packing it does:
 * at t = 0.25 s 0.02206 at r0 0.01 and 0.007425 at 0.005 (2.97x; 0.0033 at
 * 0.0025; over the whole second 0.0155, 0.00723, the cubic lattice's
 * 0.0496, 0.0193).  Tolerances 1.2x the measured, >= 1.5x per halving. */
#define RELAXED_TO_025                                                                    \
    "sed -i 's/^eta .*/&\\ninitialPacking relaxed;/' constant/fluidProperties && sed -i " \
    "'s/^endTime .*/endTime 0.25;/; s/^writeInterval .*/writeInterval 0.25;/' system/controlDict"
static void test_hydrostatic_tank(void **state)
{
    (void)state;
    double e0 = level("hydrostaticTank", "hydrostaticTank_0.01", 0.01, 0.002, "");
    assert_true(e0 < 0.135);
    double e1 = level("hydrostaticTank", "hydrostaticTank_0.01_relaxed_small", 0.01, 0.0005,
                      RELAXED_TO_025);
    double e2 = level("hydrostaticTank", "hydrostaticTank_0.005_relaxed_small", 0.005, 0.00025,
                      RELAXED_TO_025);
    assert_true(e1 < 0.027);
    assert_true(e2 < 0.009);
    assert_true(e1 / e2 >= 1.5);
}

/* pressureForce corrected (eq. 6 times the kernel gradient correction L_i
 * where the neighbourhood is isotropic): Wendland C2 at 2.2 r0 on the
 * hydrostatic tank (RELAXED_TO_025), whose symmetric pressure force is too
 * weak on the relaxed packing, so that the pressure's slope (verifyCase's
 * gradientError, summary column 18) is too steep.  Measured at r0 0.01:
 * slope +0.0474 symmetric, -0.0071 corrected, profile error 0.0346,
 * 0.0265; at r0 0.005: +0.0360, -0.0031, and 0.0213, 0.0051.  The
 * sanitizer build runs r0 0.01 (the correction's memory, the slope), the
 * release run also r0 0.005.  Tolerances about 1.5x the measured. */
#define WENDLAND_22 \
    " && sed -i 's/^eta .*/&\\nkernel wendlandC2;\\nkernelSupport 2.2;/' constant/fluidProperties"
#define CORRECTED " && sed -i 's/^eta .*/&\\npressureForce corrected;/' constant/fluidProperties"
#define CONSERVATIVE \
    " && sed -i 's/^eta .*/&\\npressureForce correctedConservative;/' constant/fluidProperties"
/* The symmetric and the corrected force at one level: gradientError (g)
 * and error (e) of each, [0] symmetric, [1] corrected. */
static void force_pair(double r0, double dt, const char *tag, double g[2], double e[2])
{
    for (int k = 0; k < 2; k++) {
        char name[128];
        snprintf(name, sizeof name, "hydrostatic_force_%s%s", k ? "corrected" : "symmetric", tag);
        level("hydrostaticTank", name, r0, dt,
              k ? RELAXED_TO_025 WENDLAND_22 CORRECTED : RELAXED_TO_025 WENDLAND_22);
        g[k] = summary_column(name, 18);
        e[k] = summary_column(name, 0);
    }
    print_message("r0 %g: gradient error %.4g symmetric, %.4g corrected\n", r0, g[0], g[1]);
}

static void test_pressure_force_corrected(void **state)
{
    (void)state;
    double g[2], e[2];
    force_pair(0.01, 0.0005, "", g, e);
    assert_true(g[0] > 0.03);
    assert_true(fabs(g[1]) < 0.3 * g[0]);
    assert_true(e[1] < e[0]);
    SKIP_UNDER_SANITIZERS();
    force_pair(0.005, 0.00025, "_0.005", g, e);
    assert_true(g[0] > 0.025);
    assert_true(fabs(g[1]) < 0.005);
    assert_true(e[1] < 0.0075);
    assert_true(e[1] < 0.5 * e[0]);
    /* correctedConservative (each pair's term times (L_i + L_j) / 2): the slope as right
     * (measured -0.0001), the error between the two (0.0120 at 0.25 s; 1 s of the sweep
     * conservativeForce/: 0.0076) */
    const char *name = "hydrostatic_force_conservative_0.005";
    level("hydrostaticTank", name, 0.005, 0.00025, RELAXED_TO_025 WENDLAND_22 CONSERVATIVE);
    const double gc = summary_column(name, 18), ec = summary_column(name, 0);
    print_message("r0 0.005: conservative gradient error %.4g, error %.4g\n", gc, ec);
    assert_true(fabs(gc) < 0.005);
    assert_true(ec < 0.018);
    assert_true(ec < 0.75 * e[0]);
}

/* initialPacking relaxed (the lattice jittered by 0.1 r0 and settled by
 * 300 FIRE-damped steps before t = 0): the hydrostatic error at r0 0.01 m,
 * dt 0.002 s falls from 0.110 (cubic) to 0.0338 (measured), and the
 * relaxation is the same on 1 and 2 threads (the files at 0.1 s are
 * identical). */
static void test_relaxed_packing(void **state)
{
    (void)state;
    const char *b = bin_dir();
    double e = level("hydrostaticTank", "hydrostaticTank_relaxed", 0.01, 0.002,
                     "sed -i 's/^eta .*/&\\ninitialPacking relaxed;/' constant/fluidProperties");
    assert_true(e < 0.045);
    assert_int_equal(run("grep -c 'Relaxed: ' " OUT "/hydrostaticTank_relaxed/log.pcisph"), 0);
    for (int n = 1; n <= 2; n++) {
        assert_int_equal(run("rm -rf " OUT "/relaxed_threads%d && %s/cloneCase " OUT
                             "/hydrostaticTank_relaxed " OUT "/relaxed_threads%d && cd " OUT
                             "/relaxed_threads%d && %s/editDictionary system/controlDict -entry "
                             "numberOfThreads -set %d && %s/editDictionary system/controlDict "
                             "-entry endTime -set 0.1 && %s/pcisph -case . > log.pcisph 2>&1",
                             n, b, n, n, b, n, b, b),
                         0);
    }
    assert_int_equal(
        run("cmp " OUT "/relaxed_threads1/0.1/fluid.vtu " OUT "/relaxed_threads2/0.1/fluid.vtu"),
        0);
}

/* initialPacking relaxed with a tolerance (the residual stop): the
 * translating tank at r0 0.01 m, dt = r0 / 20 s/m, measured at 0.25 s.
 * Relaxed until the largest displacement per step stays below 1e-4 r0 for
 * 100 steps (9493 steps), its spurious velocity rms is 0.00048 sqrt(g H)
 * against 0.0127 after the default 300 steps (measured): the stop is
 * reached (no warning), the error below 0.0007 and below a tenth of the
 * 300 steps' one; the stopping step and the files are the same on 1 and 2
 * threads; a cap reached first is a warning. */
#define TO_025                                                                         \
    "sed -i 's/^endTime .*/endTime 0.25;/; s/^writeInterval .*/writeInterval 0.25;/' " \
    "system/controlDict"
#define PACKING(p) \
    "sed -i 's/^eta .*/&\\ninitialPacking " p "/' constant/fluidProperties && " TO_025
static void test_relaxed_to_tolerance(void **state)
{
    (void)state;
    SKIP_UNDER_SANITIZERS(); /* 9493 relaxation steps: 1.5-3.5 min under ASan; the relaxation
                              * itself runs in test_relaxed_packing there */
    const char *b = bin_dir();
    double e = level("translatingTank", "translatingTank_tolerance", 0.01, 0.0005,
                     PACKING("{ type relaxed; steps 20000; tolerance 1e-4; }"));
    double e300 =
        level("translatingTank", "translatingTank_steps300", 0.01, 0.0005, PACKING("relaxed;"));
    assert_int_equal(
        run("grep -q '^Relaxed: [0-9]* steps' " OUT "/translatingTank_tolerance/log.pcisph"), 0);
    assert_int_not_equal(run("grep -q 'Warning' " OUT "/translatingTank_tolerance/log.pcisph"), 0);
    assert_true(e < 0.0007);
    assert_true(e < e300 / 10);
    assert_int_equal(run("rm -rf " OUT "/tolerance_threads2 && %s/cloneCase " OUT
                         "/translatingTank_tolerance " OUT "/tolerance_threads2 && cd " OUT
                         "/tolerance_threads2 && %s/editDictionary system/controlDict -entry "
                         "numberOfThreads -set 2 && %s/pcisph -case . > log.pcisph 2>&1",
                         b, b, b),
                     0);
    assert_int_equal(run("grep '^Relaxed: [0-9]* steps' " OUT
                         "/translatingTank_tolerance/log.pcisph | cut -d';' -f1 > " OUT
                         "/tolerance_threads2/steps1 && grep '^Relaxed: [0-9]* steps' " OUT
                         "/tolerance_threads2/log.pcisph | cut -d';' -f1 | cmp - " OUT
                         "/tolerance_threads2/steps1"),
                     0);
    assert_int_equal(run("cmp " OUT "/translatingTank_tolerance/0.25/fluid.vtu " OUT
                         "/tolerance_threads2/0.25/fluid.vtu"),
                     0);
    /* the cap reached first: a warning naming the file, line and keyword */
    assert_int_equal(run("rm -rf " OUT "/tolerance_cap && %s/cloneCase " OUT
                         "/translatingTank_tolerance " OUT "/tolerance_cap && cd " OUT
                         "/tolerance_cap && sed -i 's/steps 20000;/steps 150;/' "
                         "constant/fluidProperties && %s/editDictionary system/controlDict "
                         "-entry endTime -set 0.0005 && %s/pcisph -case . > log.pcisph 2>&1 && "
                         "grep -q 'fluidProperties:[0-9]*: initialPacking relaxed: the largest "
                         "displacement per step did not stay below tolerance' log.pcisph",
                         b, b, b),
                     0);
}

/* The standing wave's period from the zero crossings of the velocity's
 * projection on the linear mode (measured 0.0456 at r0 0.01 m, 0.0430 at
 * main c690de1; it levels off at 0.034 by r0 0.004 m, see
 * doc/verification.md), and the amplitude's decay rate with nu 1e-5
 * (measured 1.042 /s, 0.991 at c690de1: numerical damping, 2 nu k^2 is
 * 0.0049 /s). */
#define SW_DECAY_RATE  8 /* summary.dat's decayRate, decayError columns */
#define SW_DECAY_ERROR 10
static void test_standing_wave_period(void **state)
{
    (void)state;
    double e = level("standingWave", "standingWave_0.01", 0.01, 0.002, "");
    assert_true(e < 0.06);
    double g = summary_column("standingWave_0.01", SW_DECAY_RATE);
    print_message("standingWave_0.01: decay rate %.4g /s\n", g);
    assert_true(g > 0.8 && g < 1.3);
}

/* The standing wave at a constant step r0 / 5 s/m with nu 1e-3 m^2/s and
 * free-slip walls (boundaryNu 0: the linear mode satisfies them, so the
 * exact decay rate is 2 nu k^2 = 0.4935 /s; standingWave/viscous/).  The
 * excess is the numerical damping, which falls with r0: decayError
 * |rate - 2 nu k^2| / (2 nu k^2) measured 1.957 at r0 0.01 m, 0.8385 at
 * 0.005 (2.33x).  The period's error: measured 0.0542, 0.0407 (it levels
 * off, doc/verification.md).  Tolerances: 1.2x the measured, >= 1.5x per
 * halving.  Two threads (the same result as one). */
#define SW_VISCOUS                                                                           \
    "E=%s/editDictionary && $E constant/fluidProperties -entry laminarViscosity -set '{ nu " \
    "0.001; boundaryNu 0; }' && $E system/verifyDict -entry nu -set 0.001 && $E "            \
    "system/controlDict -entry numberOfThreads -set 2"

static void test_standing_wave_decay(void **state)
{
    (void)state;
    SKIP_UNDER_SANITIZERS();
    char edit[512];
    snprintf(edit, sizeof edit, SW_VISCOUS, bin_dir());
    double p1 = level("standingWave", "standingWave_viscous_0.01", 0.01, 0.002, edit);
    double p2 = level("standingWave", "standingWave_viscous_0.005", 0.005, 0.001, edit);
    double e1 = summary_column("standingWave_viscous_0.01", SW_DECAY_ERROR);
    double e2 = summary_column("standingWave_viscous_0.005", SW_DECAY_ERROR);
    print_message("decay error %.4g, %.4g (%.3gx); rates %.4g, %.4g /s\n", e1, e2, e1 / e2,
                  summary_column("standingWave_viscous_0.01", SW_DECAY_RATE),
                  summary_column("standingWave_viscous_0.005", SW_DECAY_RATE));
    assert_true(p1 < 0.065 && p2 < 0.049);
    assert_true(e1 < 2.35 && e2 < 1.0);
    assert_true(e1 / e2 >= 1.5);
}

/* The standing wave's period is 3.5-4 % short at h = 2 r0 whatever the
 * resolution; the kernel's support is the cause (doc/verification.md): at
 * r0 0.005 m, dt 0.001 s the period error from the zero crossings measured
 * 0.0320 at kernelSupport 2 and 0.0052 at 2.2.  Asserted: above 0.025 at 2,
 * below 0.012 at 2.2 (the zero crossings' round-off spread is about
 * +-0.005).  The least-squares fit of the whole record (summary.dat's
 * periodFit, periodFitSigma, fitError) measured 0.0323 and 0.0018 (the
 * same case with the amplitude changed in its 16th digit: 0.0348, 0.0368
 * and 0.0006, 0.0035, the runs' own spread): asserted above 0.025 at 2,
 * below 0.006 at 2.2, each within 0.01 of the zero crossings' error and
 * with a one-sigma uncertainty below 0.002 s (measured 0.00029, 0.00086 s).
 * Two threads (the same result as one). */
#define SW_PERIOD_FIT       11 /* summary.dat's periodFit, periodFitSigma, fitError */
#define SW_PERIOD_FIT_SIGMA 12
#define SW_FIT_ERROR        13
#define SW_DECAY_FIT        14
static void assert_period_fit(const char *name, double lo, double hi, double agree)
{
    const double t = summary_column(name, SW_PERIOD_FIT),
                 sd = summary_column(name, SW_PERIOD_FIT_SIGMA),
                 e = summary_column(name, SW_FIT_ERROR), ez = summary_column(name, 0);
    print_message("%s: period fit %.6g +- %.2g s, error %.4g (zero crossings %.4g)\n", name, t, sd,
                  e, ez);
    assert_true(isfinite(t) && sd > 0.0 && sd < 0.002);
    assert_true(e > lo && e < hi);
    assert_true(fabs(e - ez) < agree); /* the same oscillation as the zero crossings' */
}
static void test_standing_wave_period_kernel_support(void **state)
{
    (void)state;
    SKIP_UNDER_SANITIZERS();
    char edit[512], wide[768];
    snprintf(edit, sizeof edit,
             "%s/editDictionary system/controlDict -entry numberOfThreads -set 2", bin_dir());
    snprintf(wide, sizeof wide,
             "%s && %s/editDictionary constant/fluidProperties -entry kernelSupport -set 2.2", edit,
             bin_dir());
    double e20 = level("standingWave", "standingWave_h2.0_0.005", 0.005, 0.001, edit);
    double e22 = level("standingWave", "standingWave_h2.2_0.005", 0.005, 0.001, wide);
    print_message("period error %.4g at h = 2 r0, %.4g at 2.2 r0\n", e20, e22);
    assert_true(e20 > 0.025);
    assert_true(e22 < 0.012);
    assert_period_fit("standingWave_h2.0_0.005", 0.025, 1.0, 0.01);
    assert_period_fit("standingWave_h2.2_0.005", 0.0, 0.006, 0.01);
}

/* The Wendland C2 kernel (kernel wendlandC2) on the standing wave at r0
 * 0.01 m, dt 0.002 s, h = 2.2 r0: measured period error 0.0084 from the
 * zero crossings and 0.0009 from the fit of the whole record, where the
 * cubic spline at the same support measured 0.0110 and 0.0131
 * (doc/verification.md, "The kernel: Wendland C2").  Asserted: Wendland
 * below 0.015 and 0.005 (the runs' own spread is about +-0.005 and
 * +-0.002), the cubic spline's fit above 0.008 and within 0.02 of its zero
 * crossings (its record is the noisier: on a machine without AVX-512,
 * whose scalar sums round differently, it measured 0.0201 against 0.0098;
 * a fit locked on another oscillation is off by far more).  The sanitizer build runs
 * the Wendland level only (the solver's Wendland loops under ASan). */
static void test_standing_wave_period_wendland(void **state)
{
    (void)state;
    char edit[768], cubic[768];
    snprintf(edit, sizeof edit,
             "E=%s/editDictionary && $E system/controlDict -entry numberOfThreads -set 2 && $E "
             "constant/fluidProperties -entry kernelSupport -set 2.2",
             bin_dir());
    snprintf(cubic, sizeof cubic, "%s", edit);
    strncat(edit, " && $E constant/fluidProperties -entry kernel -set wendlandC2",
            sizeof edit - strlen(edit) - 1);
    double ew = level("standingWave", "standingWave_wendland_0.01", 0.01, 0.002, edit);
    print_message("period error %.4g with wendlandC2 at 2.2 r0 (r0 0.01)\n", ew);
    assert_true(ew < 0.015);
    assert_period_fit("standingWave_wendland_0.01", 0.0, 0.005, 0.01);
    SKIP_UNDER_SANITIZERS();
    double ec = level("standingWave", "standingWave_cubic22_0.01", 0.01, 0.002, cubic);
    print_message("period error %.4g with cubicSpline at 2.2 r0 (r0 0.01)\n", ec);
    assert_period_fit("standingWave_cubic22_0.01", 0.008, 1.0, 0.02);
}

/* pressureForce correctedConservative on the standing wave (Wendland C2 at
 * 2.2 r0, pressureSource mixed, r0 0.01 m, dt 0.002 s; doc/verification.md,
 * "The corrected force made conservative"): the corrected force, whose
 * pairs' forces do not cancel, makes the period long (fit measured +3.09 %),
 * the symmetric force's is +1.74 %, and the conservative form's -0.15 %
 * (-0.04 and +0.07 % with its sums in other orders).  Asserted: the
 * conservative fit within 0.6 %, less than half the symmetric force's, and
 * the corrected force's above 1.2 % (the lost momentum shows). */
static void test_standing_wave_conservative_force(void **state)
{
    (void)state;
    SKIP_UNDER_SANITIZERS();
    static const char *const force[3] = {"symmetric", "corrected", "correctedConservative"};
    double e[3];
    for (int k = 0; k < 3; k++) {
        char edit[1024], name[128];
        snprintf(edit, sizeof edit,
                 "E=%s/editDictionary && $E constant/fluidProperties -entry kernelSupport -set 2.2 "
                 "&& $E constant/fluidProperties -entry kernel -set wendlandC2 && $E "
                 "constant/fluidProperties -entry pressureSource -set mixed && $E "
                 "constant/fluidProperties -entry pressureForce -set %s",
                 bin_dir(), force[k]);
        snprintf(name, sizeof name, "standingWave_force_%s", force[k]);
        level("standingWave", name, 0.01, 0.002, edit);
        e[k] = summary_column(name, SW_FIT_ERROR);
        print_message("%s: period fit error %.4g\n", force[k], e[k]);
    }
    assert_true(e[2] < 0.006);
    assert_true(e[2] < 0.5 * e[0]);
    assert_true(e[1] > 0.012);
}

/* What sets the standing wave's period bias at 2.4 r0 (doc/verification.md,
 * "Which part sets the -0.7 %"), at r0 0.01, dt r0 / 5 unless said:
 * - not the side walls: without them (standingWave/basePeriodicX: a whole
 *   wavelength periodic along x, verifyDict's length 0.2 the half
 *   wavelength) the fit's period is -0.80 % short at a decay of 0.77 /s,
 *   with them +1.25 % long at 1.44 /s: their damping makes the coarse
 *   level long (measured; the runs of a level spread by +-0.3 %);
 * - the step: at dt = r0 / 10 the walled tank's period is -4.35 % (three
 *   runs -4.35, -3.70, -3.14 %), 5.6 points below r0 / 5's.
 * Asserts the periodic period short by 0.2-1.5 % and at least 1 % below
 * the walled one, the walled decay at least 1.4x the periodic one, the
 * half step's period at least 2 % below the full step's; and a length
 * that is not positive refused with the file, line and keyword. */
static void test_standing_wave_period_bias_parts(void **state)
{
    (void)state;
    char edit[512];
    snprintf(edit, sizeof edit,
             "%s/editDictionary constant/fluidProperties -entry kernelSupport -set 2.4", bin_dir());
    level_of("standingWave", "basePeriodicX", "standingWave_periodicX_0.01", 0.01, 0.002, edit);
    level("standingWave", "standingWave_walled24_0.01", 0.01, 0.002, edit);
    const double T = 0.528524, /* linear theory, k H = pi / 2 */
        ep = summary_column("standingWave_periodicX_0.01", SW_PERIOD_FIT) / T - 1.0,
                 ew = summary_column("standingWave_walled24_0.01", SW_PERIOD_FIT) / T - 1.0,
                 dp = summary_column("standingWave_periodicX_0.01", SW_DECAY_FIT),
                 dw = summary_column("standingWave_walled24_0.01", SW_DECAY_FIT);
    print_message("period fit %+.4f periodic, %+.4f walled; decay %.4g, %.4g /s\n", ep, ew, dp, dw);
    assert_true(ep < -0.002 && ep > -0.015);
    assert_true(ew > ep + 0.01);
    assert_true(dw > 1.4 * dp);
    level("standingWave", "standingWave_walled24_halfStep_0.01", 0.01, 0.001, edit);
    const double eh =
        summary_column("standingWave_walled24_halfStep_0.01", SW_PERIOD_FIT) / T - 1.0;
    print_message("period fit %+.4f at dt r0 / 10, %+.4f at r0 / 5\n", eh, ew);
    assert_true(eh < ew - 0.02);
    const char *c = OUT "/standingWave_periodicX_0.01";
    assert_int_equal(
        run("%s/editDictionary %s/system/verifyDict -entry length -set -1", bin_dir(), c), 0);
    assert_int_not_equal(run("%s/verifyCase -case %s", bin_dir(), c), 0);
    assert_non_null(strstr(output, "verifyDict:"));
    assert_non_null(strstr(output, "keyword 'length': must be a positive number"));
}

/* surfaceDensityCorrection (Bonet & Kulasegaram 2002) and a free surface at
 * rest: the corrected density of a surface particle is the harmonic mean of
 * its neighbours' (rho_i / S_i, S_i from the previous pass's densities), so
 * it takes the bulk's compression whatever the particle's own distance from
 * the fluid, and the pressure pushes the surface out.  hydrostaticTank at r0
 * 0.01 to 0.2 s: without the correction the surface stays within 0.4 mm and
 * the velocity rms below 0.009 m/s; with it the surface rises 1.2-2.2 cm
 * (0.112, 0.122, 0.119, 0.118 m at 0.05-0.2 s) at 0.07-0.15 m/s (measured).
 * Guards the plain tank's rest, and the truth of the warning the solver
 * prints with the correction (to be dropped with it when the correction is
 * made to keep a surface at rest). */
static void test_surface_density_free_surface_at_rest(void **state)
{
    (void)state;
    char plain[512], bk[768];
    snprintf(plain, sizeof plain,
             "E=%s/editDictionary && $E system/controlDict -entry endTime -set 0.2 && $E "
             "system/controlDict -entry writeInterval -set 0.05",
             bin_dir());
    snprintf(bk, sizeof bk,
             "%s && $E constant/fluidProperties -entry surfaceDensityCorrection -set on", plain);
    level("hydrostaticTank", "hydrostaticTank_rest_plain", 0.01, 0.002, plain);
    for (int k = 1; k <= 4; k++) {
        const double h = time_column(0.05 * k, 4), v = time_column(0.05 * k, 2);
        assert_true(fabs(h - 0.1) < 0.001 && v < 0.02);
    }
    level("hydrostaticTank", "hydrostaticTank_rest_bk", 0.01, 0.002, bk);
    assert_non_null(strstr(output, "keyword 'surfaceDensityCorrection': a free surface at rest"));
    double hmax = 0.0, vmax = 0.0;
    for (int k = 1; k <= 4; k++) {
        const double h = time_column(0.05 * k, 4), v = time_column(0.05 * k, 2);
        hmax = h > hmax ? h : hmax;
        vmax = v > vmax ? v : vmax;
    }
    print_message("with surfaceDensityCorrection: surface up to %.4f m, velocity rms up to %.3f\n",
                  hmax, vmax);
    assert_true(hmax > 0.105 && vmax > 0.05);
}

/* The Taylor-Green velocity field as set up (velocityField) and its first
 * 12.5 ms of viscous decay (measured 0.0073 of U at r0 0.01 m); later the
 * method fails, see doc/verification.md. */
static void test_taylor_green_start(void **state)
{
    (void)state;
    double e = level("taylorGreen", "taylorGreen_0.01", 0.01, 0.001,
                     "sed -i 's/^endTime .*/endTime 0.0125;/; s/^writeInterval .*/writeInterval "
                     "0.0125;/' system/controlDict");
    assert_true(e < 0.015);
}

/* ---- why Taylor-Green does not converge (doc/verification.md) ------------- */

/* The summation density of an infinite cubic lattice (spacing 1, support
 * radius `support`: 2 in the solver by default) under the volume-keeping
 * pure strain (x (1 + e), y / (1 + e), z), over the unstrained lattice's,
 * minus 1. */
static double strained_lattice_rise(double e, double support)
{
    krn_kernel k;
    krn_init(&k, support);
    double r[2] = {0, 0};
    for (int s = 0; s < 2; s++) {
        const double a = s ? 1.0 + e : 1.0;
        for (int i = -8; i <= 8; i++)
            for (int j = -8; j <= 8; j++)
                for (int l = -5; l <= 5; l++) {
                    const double x = a * i, y = j / a, z = l;
                    r[s] += krn_w(&k, sqrt(x * x + y * y + z * z));
                }
    }
    return r[1] / r[0] - 1.0;
}

/* A strained lattice keeps its volume per particle, yet its summation
 * density rises: +0.126 % at e = 0.1, +0.739 % at 0.2, +2.26 % at 0.3
 * (measured; the same in /usr/bin/python3 with numpy).  PCISPH reads that
 * rise as compression and pushes back.  The vortex strains the lattice at
 * its stagnation points at the rate U k (6.28 /s for U 0.1 m/s, L 0.1 m):
 * e = exp(U k t) - 1 reaches 0.2 at 0.029 s and 0.3 at 0.042 s, when the
 * runs' kinetic energy collapses (minimum at 0.05 s).  With the support at
 * 2.4 r0 (kernelSupport 2.4) the rise at e = 0.3 is +0.094 %, 24x less. */
static void test_taylor_green_lattice_strain(void **state)
{
    (void)state;
    const double r1 = strained_lattice_rise(0.1, 2.0), r2 = strained_lattice_rise(0.2, 2.0),
                 r3 = strained_lattice_rise(0.3, 2.0), w3 = strained_lattice_rise(0.3, 2.4);
    print_message("strained cubic lattice: summation density +%.3f %%, +%.3f %%, +%.3f %% at e = "
                  "0.1, 0.2, 0.3\n",
                  100 * r1, 100 * r2, 100 * r3);
    print_message("with h = 2.4 r0: +%.3f %% at e = 0.3\n", 100 * w3);
    assert_true(fabs(strained_lattice_rise(0.0, 2.0)) < 1e-14);
    assert_true(w3 > 0.0 && w3 < 0.0015);
    assert_true(r1 > 0.0011 && r1 < 0.0014);
    assert_true(r2 > 0.0070 && r2 < 0.0078);
    assert_true(r3 > 0.021 && r3 < 0.024);
}

/* The Taylor-Green run at U and U / 2 (r0 0.01 m, dt 0.001 s): the time of
 * the kinetic energy's minimum (the field reverses; the exact energy falls
 * monotonically).  A viscous or time-step effect would reverse at the same
 * time whatever U; a lattice locking at a strain e ~ U k t reverses at
 * twice the time for half the U.  Measured: 0.050 s at U 0.1 m/s, 0.080 s
 * at 0.05 (ratio 1.6; 0.030 s at 0.2, 0.13 s at 0.025: the reversal comes at
 * a strain U k t of 0.2-0.4, not at a time).  And eta does not change it:
 * at eta 1, 3, 10, 30 % the energies are the same to every printed digit
 * (the 3 minimum iterations always end below eta): the push-back is PCISPH's
 * pressure on any compression, not its tolerance. */
static double energy_minimum_time(const char *name, double U, double eta, double *ratio)
{
    const char *b = bin_dir();
    assert_int_equal(run("rm -rf " OUT "/%s && mkdir -p " OUT " && %s/cloneCase " CASES
                         "/taylorGreen/base " OUT "/%s && cd " OUT "/%s && sed -i 's/amplitude "
                         "*0.1;/amplitude %g;/' constant/fluidProperties system/verifyDict && sed "
                         "-i 's/^eta .*/eta %g;/' constant/fluidProperties && sed -i 's/^endTime "
                         ".*/endTime 0.12;/; s/^writeInterval .*/writeInterval 0.005;/' "
                         "system/controlDict",
                         name, b, name, name, U, eta),
                     0);
    int rc = run("%s/pcisph -case " OUT "/%s > " OUT "/%s/log.pcisph 2>&1", b, name, name);
    assert_int_equal(rc, 0);
    assert_int_equal(run("%s/verifyCase -case " OUT "/%s", b, name), 0);
    double tmin = NAN, emin = INFINITY, e0 = NAN;
    for (char *line = output; line && *line;
         line = strchr(line, '\n'), line = line ? line + 1 : NULL) {
        if (*line == '#') continue;
        double v[5];
        char *p = line, *end;
        int k = 0;
        for (; k < 5; k++, p = end) {
            v[k] = strtod(p, &end);
            if (end == p) break;
        }
        if (k < 5) continue;
        if (isnan(e0)) e0 = v[4];
        if (v[4] < emin) {
            emin = v[4];
            tmin = v[0];
        }
    }
    /* the exact energy decays as exp(-4 nu k^2 t), nu 0.001, k = 2 pi / 0.1 */
    const double kw = 2.0 * 3.14159265358979 / 0.1;
    *ratio = emin / (e0 * exp(-4.0 * 0.001 * kw * kw * (tmin - 0.005)));
    print_message("%s: U %g, eta %g %%: kinetic energy minimum at t = %.3f s, %.3g of the exact\n",
                  name, U, eta, tmin, *ratio);
    return tmin;
}

static void test_taylor_green_reverses_at_a_strain(void **state)
{
    (void)state;
    double q1, q2, q3;
    const double t1 = energy_minimum_time("taylorGreen_U0.1", 0.1, 1, &q1);
    const double t2 = energy_minimum_time("taylorGreen_U0.05", 0.05, 1, &q2);
    const double t3 = energy_minimum_time("taylorGreen_eta10", 0.1, 10, &q3);
    assert_true(t1 < 0.07 && q1 < 0.05); /* reversed: a few % of the exact energy */
    assert_true(t2 / t1 > 1.35 && t2 / t1 < 2.2);
    assert_true(fabs(t3 - t1) < 1e-9 && fabs(q3 - q1) < 1e-6 * q1);
}

/* The Taylor-Green error is a function of r0 / dt, PCISPH's pseudo sound
 * speed (its stiffness delta scales as r0^2 / dt^2), not of r0: 0.5119 at
 * r0 0.01 m, dt 0.004 s and 0.5124 at r0 0.005, dt 0.002 (both r0 / dt =
 * 2.5 m/s); at r0 0.01 it falls from 0.785 (dt 0.001) to 0.343 (dt 0.008)
 * as the pseudo sound speed falls.  So with dt proportional to r0 it
 * cannot converge (doc/verification.md). */
static void test_taylor_green_follows_r0_over_dt(void **state)
{
    (void)state;
    const double a = level("taylorGreen", "taylorGreen_0.01_dt0.004", 0.01, 0.004, "");
    const double b = level("taylorGreen", "taylorGreen_0.005_dt0.002", 0.005, 0.002, "");
    const double c = level("taylorGreen", "taylorGreen_0.01_dt0.001", 0.01, 0.001, "");
    const double d = level("taylorGreen", "taylorGreen_0.01_dt0.008", 0.01, 0.008, "");
    assert_true(fabs(a - b) < 0.05 * a);
    assert_true(c > 0.7 && d < 0.45 && d < 0.6 * c);
}

/* kernelSupport 2.4 (a strained lattice's summation density 24x less
 * sensitive, test_taylor_green_lattice_strain): the Taylor-Green error at
 * r0 0.01 m halves, 0.3904 against 0.7846 (and stays there: 0.4054 at
 * r0 0.005, 0.4017 at 0.0025). */
static void test_taylor_green_kernel_support(void **state)
{
    (void)state;
    const double e = level("taylorGreen", "taylorGreen_h2.4", 0.01, 0.001,
                           "sed -i 's/^eta .*/&\\nkernelSupport 2.4;/' constant/fluidProperties");
    assert_true(e > 0.3 && e < 0.47);
}

/* First time the height in column `column` of a waterGauges.dat exceeds
 * 0.02 m (compareExperiment's threshold), less t0. */
static double arrival_file(const char *path, int column, double t0)
{
    FILE *f = fopen(path, "r");
    if (!f) fail_msg("no gauge record %s", path);
    char line[1024];
    double t = NAN;
    while (fgets(line, sizeof line, f)) {
        if (line[0] == '#') continue;
        double v[6];
        char *p = line;
        int k = 0;
        for (; k < 6; k++) {
            char *e;
            v[k] = strtod(p, &e);
            if (e == p) break;
            p = e;
        }
        if (k > column && v[column] > 0.02) {
            t = v[0] - t0;
            break;
        }
    }
    fclose(f);
    return t;
}

/* The SPHERIC Test 2 front at H3 (issue 18): is the run's late arrival
 * (0.028-0.030 s at convergence) the gauges' colour threshold?  The same
 * run at r0 0.05 m read by three waterGauges at colour 0.5 (the case's),
 * 0.3 and 0.1: the arrival (height above 0.02 m) moves by at most 0.014 s
 * (measured 0.2707, 0.2663, 0.2573 s; at r0 0.025 to 0.4 s 0.2484, 0.2459,
 * 0.2434),
 * and a lower threshold only makes it earlier, so the threshold explains
 * at most half of the lateness at this level and a fifth at r0 0.025
 * (doc/accuracy-cost.md). */
static double arrival(const char *gauges, int column)
{
    char path[512];
    snprintf(path, sizeof path, OUT "/sphericFront/postProcessing/%s/0/waterGauges.dat", gauges);
    return arrival_file(path, column, 0.0);
}

static void test_spheric_front_threshold(void **state)
{
    (void)state;
    const char *b = bin_dir();
    const char *c = OUT "/sphericFront";
    assert_int_equal(run("rm -rf %s && %s/cloneCase cases/sphericTest2 %s && cd %s && "
                         "E=%s/editDictionary && $E system/controlDict -entry endTime -set 0.32 && "
                         "$E system/controlDict -entry writeInterval -set 0.32 && "
                         "$E system/controlDict -entry numberOfThreads -set 1 && "
                         "$E system/controlDict -entry functions/g3 -set '{ type waterGauges; "
                         "gaugeLocations ((1.488 0.5)); threshold 0.3; }' && "
                         "$E system/controlDict -entry functions/g1 -set '{ type waterGauges; "
                         "gaugeLocations ((1.488 0.5)); threshold 0.1; }'",
                         c, b, c, c, b),
                     0);
    assert_int_equal(run("%s/pcisph -case %s > %s/log.pcisph 2>&1", b, c, c), 0);
    const double t5 = arrival("gauges", 3), t3 = arrival("g3", 1), t1 = arrival("g1", 1);
    print_message("H3 arrival at colour 0.5, 0.3, 0.1: %.4f %.4f %.4f s (experiment 0.218 s)\n", t5,
                  t3, t1);
    assert_true(isfinite(t5) && isfinite(t3) && isfinite(t1));
    assert_true(t1 <= t3 + 1e-9 && t3 <= t5 + 1e-9);
    assert_true(t5 - t1 < 0.02);
    assert_true(t1 - 0.218 > 0.03); /* still late at r0 0.05 whatever the threshold */
}

/* The late SPHERIC front at H3 (issue 18), the candidate causes that live
 * in the run isolated at r0 0.05 m: a column released from rest on its
 * lattice with zero pressure (the case) against the same column settled
 * for 0.6 s behind a gate at x = 1.992 m (hydrostatic pressure, then the
 * gate removed), and that gate lifted at 1.5 m/s instead of removed.  The
 * settled start moves the arrival by less than 0.015 s (measured +0.003 s
 * here: 0.2707 and 0.2735 s; +0.010 s with Allrun-front's writes, -0.001 s
 * at r0 0.025), a lifted gate delays it (+0.029 s here, +0.020 s at
 * 0.025), and every run stays more than 0.03 s behind the
 * experiment's 0.218 s: neither the initial pressure nor a finite-speed
 * gate makes our front early enough (doc/accuracy-cost.md). */
static void test_spheric_front_start_and_gate(void **state)
{
    (void)state;
    const char *b = bin_dir();
    const char *lat = OUT "/sphericLattice", *set = OUT "/sphericSettled",
               *lift = OUT "/sphericLifted";
    /* the case as it is, to 0.32 s */
    assert_int_equal(run("rm -rf %s && %s/cloneCase cases/sphericTest2 %s && cd %s && "
                         "E=%s/editDictionary && $E system/controlDict -entry endTime -set 0.32 && "
                         "$E system/controlDict -entry writeInterval -set 0.32 && "
                         "$E system/controlDict -entry numberOfThreads -set 1",
                         lat, b, lat, lat, b),
                     0);
    assert_int_equal(run("%s/pcisph -case %s > %s/log.pcisph 2>&1", b, lat, lat), 0);
    /* settle behind a gate (damped by alpha 0.5), then copy */
    assert_int_equal(
        run("rm -rf %s %s && %s/cloneCase cases/sphericTest2 %s && cd %s && "
            "E=%s/editDictionary && $E system/controlDict -entry endTime -set 0.6 && "
            "$E system/controlDict -entry writeInterval -set 0.6 && "
            "$E system/controlDict -entry numberOfThreads -set 1 && "
            "$E constant/boundaryProperties -entry geometry/tank/max -set '(3.22 1 1.7)' && "
            "$E constant/boundaryProperties -entry geometry/gate -set "
            "'{ type box; min (1.79 0 0); max (1.992 1 0.6); }' && "
            "$E constant/fluidProperties -entry viscosity/alpha -set 0.5",
            set, lift, b, set, set, b),
        0);
    assert_int_equal(run("%s/pcisph -case %s > %s/log.pcisph 2>&1", b, set, set), 0);
    assert_int_equal(run("cp -r %s %s", set, lift), 0);
    /* released: gate removed, or lifted from 0.6 s at 1.5 m/s (a table) */
    assert_int_equal(run("cd %s && E=%s/editDictionary && "
                         "$E constant/fluidProperties -entry viscosity/alpha -set 0.05 && "
                         "$E constant/boundaryProperties -entry geometry/gate -remove && "
                         "$E system/controlDict -entry endTime -set 0.92 && "
                         "$E system/controlDict -entry writeInterval -set 0.32",
                         set, b),
                     0);
    assert_int_equal(
        run("cd %s && E=%s/editDictionary && "
            "awk 'BEGIN { for (t = 0; t <= 1.0; t += 0.001) { d = t > 0.6 ? 1.5 * (t - 0.6) : 0; "
            "if (d > 1.05) d = 1.05; printf \"%%.4f 0 0 %%.6f 0\\n\", t, d } }' > "
            "constant/gate.dat && "
            "$E constant/fluidProperties -entry viscosity/alpha -set 0.05 && "
            "$E constant/boundaryProperties -entry geometry/gate/motion -set '{ type table; "
            "file \"constant/gate.dat\"; axis (0 1 0); centre (0 0 0); }' && "
            "$E system/controlDict -entry endTime -set 0.92 && "
            "$E system/controlDict -entry writeInterval -set 0.32",
            lift, b),
        0);
    assert_int_equal(run("%s/pcisph -case %s -resume > %s/log.resume 2>&1", b, set, set), 0);
    assert_int_equal(run("%s/pcisph -case %s -resume > %s/log.resume 2>&1", b, lift, lift), 0);
    char path[512];
    snprintf(path, sizeof path, "%s/postProcessing/gauges/0/waterGauges.dat", lat);
    const double t_lat = arrival_file(path, 3, 0.0);
    snprintf(path, sizeof path, "%s/postProcessing/gauges/0.6/waterGauges.dat", set);
    const double t_set = arrival_file(path, 3, 0.6);
    snprintf(path, sizeof path, "%s/postProcessing/gauges/0.6/waterGauges.dat", lift);
    const double t_lift = arrival_file(path, 3, 0.6);
    print_message("H3 arrival after release (colour 0.5, h > 0.02 m): lattice start %.4f s, "
                  "settled start %.4f s, gate lifted at 1.5 m/s %.4f s (experiment 0.218 s)\n",
                  t_lat, t_set, t_lift);
    assert_true(isfinite(t_lat) && isfinite(t_set) && isfinite(t_lift));
    assert_true(fabs(t_set - t_lat) < 0.015);
    assert_true(t_lift - t_set > 0.015);
    assert_true(t_set - 0.218 > 0.03 && t_lat - 0.218 > 0.03);
}

/* ---- pressureSource: the divergence and mixed sources (doc/verification.md) ---- */

#define TG_DIVERGENCE(src, end)                                                             \
    "sed -i 's/^maxIterations .*/&\\npressureSource " src "/' constant/fluidProperties && " \
    "sed -i 's/^endTime .*/endTime " end ";/' system/controlDict"
#define TG_MIN6 " && sed -i 's/^minIterations .*/minIterations 6;/' constant/fluidProperties"

/* The Taylor-Green vortex with the gradient-corrected divergence source,
 * from zero each step, at least 6 iterations (taylorGreen/baseDivergence):
 * to 0.1 s, before the late collapse of the coarse level, measured 0.0876
 * at r0 0.01 m and 0.0084 at 0.005 m (10.4x; 0.0045 at 0.0025; the density
 * source: 0.785, 0.771).  Tolerances 1.25x the measured, >= 4x per halving.  The same source
 * warm-started (DFSPH's default) is the density source again: 0.779 at
 * r0 0.01 m to 0.25 s (> 0.6 here), since the SPH divergence is the time
 * derivative of the summation density. */
static void test_taylor_green_divergence_converges(void **state)
{
    (void)state;
    const char *src = "{ type divergence; warmStart off; gradientCorrection on; }";
    char edit[512];
    snprintf(edit, sizeof edit, TG_DIVERGENCE("%s", "0.1") TG_MIN6, src);
    double e1 = level("taylorGreen", "taylorGreen_div_0.01", 0.01, 0.001, edit);
    double e2 = level("taylorGreen", "taylorGreen_div_0.005", 0.005, 0.0005, edit);
    assert_true(e1 < 0.11);
    assert_true(e2 < 0.0105);
    assert_true(e1 / e2 >= 4.0);
    double w = level("taylorGreen", "taylorGreen_div_warm", 0.01, 0.001,
                     TG_DIVERGENCE("divergence;", "0.25"));
    assert_true(w > 0.6);
}

/* Particle shifting (particleShifting { coefficient 0.1; }, x -= 0.1 h^2
 * grad C each step, the velocity carried by its corrected gradient,
 * velocityCorrection on by default) on the gradient-corrected divergence
 * source (taylorGreen/baseShifting): the late collapse of the energy is
 * gone and the error over the whole 0.25 s converges, measured 0.0158 at
 * r0 0.01 m and 0.00712 at 0.005 m (2.22x; without the velocity
 * correction 0.0198, 0.0101: 1.96x; without shifting 0.138, 0.079).  The
 * amplitude's decay rate (verifyCase's decayRate, the projection on the
 * vortex's shape) is measured 6.4 % and 3.5 % below 2 nu k^2.  Tolerances
 * 1.25x the measured errors, >= 1.8x per halving, decay within 8 % and
 * 4.5 %; the uncorrected shift's r0 0.01 error above the corrected one's.
 * The shift is the same on 1 and 2 threads (r0 0.005, 4 blocks of the
 * shift's 1024: the files at 0.05 s are identical). */
/* The run `name` of level() again on 2 threads to 0.05 s (edit: the
 * edits it ran with, r0 0.005, dt 0.0005): its 0.05 s file must be the
 * 1-thread run's, bit for bit. */
static void assert_same_on_two_threads(const char *name, const char *edit)
{
    char edit2[1536], name2[256];
    snprintf(edit2, sizeof edit2,
             "%s && %s/editDictionary system/controlDict -entry numberOfThreads -set 2 && "
             "%s/editDictionary system/controlDict -entry endTime -set 0.05",
             edit, bin_dir(), bin_dir());
    snprintf(name2, sizeof name2, "%s_threads2", name);
    level("taylorGreen", name2, 0.005, 0.0005, edit2);
    assert_int_equal(run("cmp " OUT "/%s/0.05/fluid.vtu " OUT "/%s/0.05/fluid.vtu", name, name2),
                     0);
}

#define TG_SHIFT(opt)                                                                        \
    " && sed -i 's/^laminarViscosity .*/&\\nparticleShifting { coefficient 0.1;" opt " }/' " \
    "constant/fluidProperties"
static void test_taylor_green_shifting_converges(void **state)
{
    (void)state;
    const char *src = "{ type divergence; warmStart off; gradientCorrection on; }";
    char edit[768], edit2[1024];
    snprintf(edit, sizeof edit, TG_DIVERGENCE("%s", "0.25") TG_MIN6 TG_SHIFT(""), src);
    double e1 = level("taylorGreen", "taylorGreen_shift_0.01", 0.01, 0.001, edit);
    const double d1 = summary_column("taylorGreen_shift_0.01", 10);
    double e2 = level("taylorGreen", "taylorGreen_shift_0.005", 0.005, 0.0005, edit);
    const double d2 = summary_column("taylorGreen_shift_0.005", 10);
    print_message("shifted: error to 0.25 s %.4g, %.4g (%.3gx); decay %.3g, %.3g below 2 nu k^2\n",
                  e1, e2, e1 / e2, d1, d2);
    assert_true(e1 < 0.0198);
    assert_true(e2 < 0.0089);
    assert_true(e1 / e2 >= 1.8);
    assert_true(d1 < 0.08);
    assert_true(d2 < 0.045);
    snprintf(edit2, sizeof edit2,
             TG_DIVERGENCE("%s", "0.25") TG_MIN6 TG_SHIFT(" velocityCorrection off;"), src);
    double u1 = level("taylorGreen", "taylorGreen_shift_0.01_uncorrected", 0.01, 0.001, edit2);
    assert_true(u1 > e1 * 1.1);
    assert_same_on_two_threads("taylorGreen_shift_0.005", edit);
}

/* The same with the laminar viscosity normalized by the packing's second
 * moment (laminarViscosity { nu 0.001; normalized on; }): the Morris sum
 * misses nu Laplacian v by 3-4 % on the strained packing at r0 0.005 (a
 * resolution-independent deficit of the decay rate, which levels the
 * error off at r0 0.0025, doc/verification.md), and normalized it is
 * exact at long waves: measured 0.01162 at r0 0.01 and 0.002825 at 0.005
 * (4.11x), the decay 4.85 % and 0.78 % below 2 nu k^2.  Tolerances 1.25x
 * the measured errors, >= 3x per halving, decay within 1.5 % at r0 0.005. */
#define TG_NORMALIZED                                                                     \
    " && sed -i 's/^laminarViscosity .*/laminarViscosity { nu 0.001; normalized on; }/' " \
    "constant/fluidProperties"
static void test_taylor_green_normalized_viscosity(void **state)
{
    (void)state;
    SKIP_UNDER_SANITIZERS();
    const char *src = "{ type divergence; warmStart off; gradientCorrection on; }";
    char edit[1024];
    snprintf(edit, sizeof edit, TG_DIVERGENCE("%s", "0.25") TG_MIN6 TG_SHIFT("") TG_NORMALIZED,
             src);
    double e1 = level("taylorGreen", "taylorGreen_normalized_0.01", 0.01, 0.001, edit);
    double e2 = level("taylorGreen", "taylorGreen_normalized_0.005", 0.005, 0.0005, edit);
    const double d2 = summary_column("taylorGreen_normalized_0.005", 10);
    print_message("normalized: error to 0.25 s %.4g, %.4g (%.3gx); decay %.3g below 2 nu k^2\n", e1,
                  e2, e1 / e2, d2);
    assert_true(e1 < 0.0146);
    assert_true(e2 < 0.0036);
    assert_true(e1 / e2 >= 3.0);
    assert_true(d2 < 0.015);
}

/* meanPressure: in a periodic box the projection fixes the pressure only
 * up to a constant.  Clamped at zero (the default) the solve builds a
 * background level that grows with the iterations and damps the vortex
 * on the shifted packing; with the pressures free and their mean held at
 * 0 the answer no longer depends on the iteration count, and the error
 * falls with r0.  Normalized viscosity and the corrected shift as above;
 * measured: MP_E1 at r0 0.01 m, MP_E2 at 0.005 m (6 iterations), 0.003691
 * at 0.005 m with 24 iterations (0.003597 before the mean's sum took the
 * density error's association: round-off alone moves it 2.6 %); clamped at 0.005 m with 24 iterations
 * 0.001512 against 0.002825 with 6 (test_taylor_green_normalized_viscosity).
 * Tolerances: 1.2x the measured errors, >= 3x per halving, 24 iterations
 * within 5 % of 6, and the clamped solve's 24 iterations at most 0.7x its
 * 6 (the iteration effect the mean removes).  verifyCase's pressure error
 * (against rho0 U^2 F^2 (cos 2kx + cos 2ky) / 4 up to the mean, over
 * rho0 U^2) at 0.1 s at r0 0.005 m: measured MP_P2, tolerance 1.3x (the
 * exact field's amplitude there is 0.1 of rho0 U^2: a wrong sign or
 * scale is far above it).  Two threads give the files of one (r0 0.005,
 * 24 iterations, to 0.05 s: the mean is sl_sum's). */
#define MP_E1    0.01382
#define MP_E2    0.00359
#define MP_P2    0.00233
#define TG_MIN24 " && sed -i 's/^minIterations .*/minIterations 24;/' constant/fluidProperties"
static void test_taylor_green_mean_pressure(void **state)
{
    (void)state;
    SKIP_UNDER_SANITIZERS();
    const char *held = "{ type divergence; warmStart off; gradientCorrection on; meanPressure 0; }";
    const char *clamped = "{ type divergence; warmStart off; gradientCorrection on; }";
    char edit[1024];
    snprintf(edit, sizeof edit, TG_DIVERGENCE("%s", "0.25") TG_MIN6 TG_SHIFT("") TG_NORMALIZED,
             held);
    const double e1 = level("taylorGreen", "taylorGreen_mean_0.01", 0.01, 0.001, edit);
    const double e2 = level("taylorGreen", "taylorGreen_mean_0.005", 0.005, 0.0005, edit);
    const double p2 = time_column(0.1, 1); /* verifyCase's pressure error at 0.1 s */
    snprintf(edit, sizeof edit, TG_DIVERGENCE("%s", "0.25") TG_MIN24 TG_SHIFT("") TG_NORMALIZED,
             held);
    const double e24 = level("taylorGreen", "taylorGreen_mean_0.005_24", 0.005, 0.0005, edit);
    assert_same_on_two_threads("taylorGreen_mean_0.005_24", edit); /* the held mean's sum */
    snprintf(edit, sizeof edit, TG_DIVERGENCE("%s", "0.25") TG_MIN24 TG_SHIFT("") TG_NORMALIZED,
             clamped);
    const double c24 = level("taylorGreen", "taylorGreen_clamped_0.005_24", 0.005, 0.0005, edit);
    print_message("meanPressure 0: error to 0.25 s %.4g, %.4g (%.3gx); 24 iterations %.4g; "
                  "clamped with 24 iterations %.4g (6: 0.002825); pressure error at 0.1 s "
                  "%.4g\n",
                  e1, e2, e1 / e2, e24, c24, p2);
    assert_true(e1 < 1.2 * MP_E1);
    assert_true(e2 < 1.2 * MP_E2);
    assert_true(e1 / e2 >= 3.0);
    assert_true(fabs(e24 / e2 - 1.0) < 0.05);
    assert_true(c24 < 0.7 * 0.002825);
    assert_true(p2 < 1.3 * MP_P2);
}

/* laminarViscosity { normalized tensor; }: the shifted packing is strained
 * in the vortex's plane (second moment 0.96-0.97 in x and y, 0.987 along
 * z at r0 0.005), so the scalar normalization leaves the in-plane sum
 * short and the vortex decays too slowly (meanPressure above: 1.61 % at r0
 * 0.005); with each pair's weight corrected by the fourth moment the
 * deficit falls to 0.9 % there (0.03 % at r0 0.0025, not run here).  The
 * held mean as above; measured TN_E1 at r0 0.01 m and TN_E2 at 0.005 m.
 * Tolerances: 1.2x the measured, >= 4x per halving (measured 5.8x), the
 * r0 0.005 error at most 0.75x the scalar normalization's MP_E2 (measured
 * 0.61x) and its decay within 1.3 % of 2 nu k^2 (measured 0.90 %, the
 * scalar 1.61 %). */
#define TN_E1 0.01281
#define TN_E2 0.002196
#define TG_TENSOR                                                                             \
    " && sed -i 's/^laminarViscosity .*/laminarViscosity { nu 0.001; normalized tensor; }/' " \
    "constant/fluidProperties"
static void test_taylor_green_tensor_viscosity(void **state)
{
    (void)state;
    SKIP_UNDER_SANITIZERS();
    char edit[1024];
    snprintf(edit, sizeof edit, TG_DIVERGENCE("%s", "0.25") TG_MIN6 TG_SHIFT("") TG_TENSOR,
             "{ type divergence; warmStart off; gradientCorrection on; meanPressure 0; }");
    const double e1 = level("taylorGreen", "taylorGreen_tensor_0.01", 0.01, 0.001, edit);
    const double e2 = level("taylorGreen", "taylorGreen_tensor_0.005", 0.005, 0.0005, edit);
    const double d2 = summary_column("taylorGreen_tensor_0.005", 10);
    print_message("normalized tensor: error to 0.25 s %.4g, %.4g (%.3gx); decay %.3g below 2 nu "
                  "k^2\n",
                  e1, e2, e1 / e2, d2);
    assert_true(e1 < 1.2 * TN_E1);
    assert_true(e2 < 1.2 * TN_E2);
    assert_true(e1 / e2 >= 4.0);
    assert_true(e2 < 0.75 * MP_E2);
    assert_true(d2 < 0.013);
}

/* Without viscosity (laminarViscosity nu 0, verifyDict nu 0) the exact
 * vortex keeps its amplitude, so what it loses is the method's own
 * dissipation (the pressure solve and the shift on a packing that
 * rearranges): the held mean and the corrected shift as above; measured
 * the amplitude over the exact at 0.25 s 0.94428 at r0 0.01 m and 0.97552
 * at 0.005 m (losses 5.57 % and 2.45 %, 2.28x; 2.48 % in earlier builds; 1.30 % at r0 0.0025,
 * doc/verification.md, "What tensor corrects at the finest level").
 * Tolerances: the r0 0.005 loss below 1.2x the measured, at least 1.8x
 * per halving, and never a gain (the amplitude below the exact's at every
 * written time of both levels: the method must not feed the vortex). */
#define TG_INVISCID                                                    \
    " && sed -i 's/^laminarViscosity .*/laminarViscosity { nu 0; }/' " \
    "constant/fluidProperties && sed -i 's/^nu .*/nu 0;/' system/verifyDict"
static double largest_mode(void) /* the largest amplitude in verifyCase's last table */
{
    double m = 0.0;
    for (int k = 1; k <= 10; k++) m = fmax(m, time_column(0.025 * k, 5));
    return m;
}
/* The inviscid vortex at r0 0.01 and 0.005 m with the pressure force
 * `force` (NULL: the case's default, symmetric), runs OUT/<prefix>_<r0>:
 * the amplitude lost by 0.25 s (l) and the largest amplitude (m) of each. */
static void inviscid_levels(const char *force, const char *prefix, double l[2], double m[2])
{
    char edit[1024], name[128];
    snprintf(edit, sizeof edit,
             TG_DIVERGENCE("%s", "0.25") TG_MIN6 TG_SHIFT("") TG_INVISCID
             " && sed -i 's/^minIterations .*/&\\npressureForce %s;/' constant/fluidProperties",
             "{ type divergence; warmStart off; gradientCorrection on; meanPressure 0; }",
             force ? force : "symmetric");
    static const double r0[2] = {0.01, 0.005};
    for (int q = 0; q < 2; q++) {
        snprintf(name, sizeof name, "%s_%g", prefix, r0[q]);
        level("taylorGreen", name, r0[q], r0[q] / 10.0, edit);
        l[q] = 1.0 - time_column(0.25, 5) / 0.1;
        m[q] = largest_mode();
    }
}
static void test_taylor_green_inviscid_loss(void **state)
{
    (void)state;
    SKIP_UNDER_SANITIZERS();
    double l[2], m[2];
    inviscid_levels(NULL, "taylorGreen_inviscid", l, m);
    print_message("inviscid: amplitude lost by 0.25 s %.4g, %.4g (%.3gx); largest amplitude "
                  "%.6g, %.6g of 0.1\n",
                  l[0], l[1], l[0] / l[1], m[0], m[1]);
    assert_true(l[1] > 0.0 && l[1] < 1.2 * 0.0248);
    assert_true(l[0] / l[1] >= 1.8);
    assert_true(m[0] > 0.09 && m[0] < 0.1 && m[1] > 0.09 && m[1] < 0.1);
}

/* The same without viscosity with `pressureForce correctedConservative`:
 * the method's own dissipation is mostly the symmetric force's pressure
 * (its work over 0.25 s 6.5, 3.9, 2.4 % of the kinetic energy at r0 0.01,
 * 0.005, 0.0025 m), which the conservative correction cuts (2.1, 0.8,
 * 0.4 %; doc/verification.md, "Where the energy goes"): measured the
 * amplitude lost by 0.25 s 3.33 % at r0 0.01 and 0.88 % at 0.005 (the
 * symmetric force's 5.57 %, 2.48 %, above).  Tolerances: the r0 0.005 loss
 * below 1.2x the measured and below half the symmetric force's, at least
 * 3x per halving (measured 3.78x), never a gain. */
static void test_taylor_green_inviscid_loss_conservative(void **state)
{
    (void)state;
    SKIP_UNDER_SANITIZERS();
    double l[2], m[2];
    inviscid_levels("correctedConservative", "taylorGreen_inviscid_cons", l, m);
    print_message("inviscid, correctedConservative: amplitude lost by 0.25 s %.4g, %.4g (%.3gx); "
                  "largest amplitude %.6g, %.6g of 0.1\n",
                  l[0], l[1], l[0] / l[1], m[0], m[1]);
    assert_true(l[1] > 0.0 && l[1] < 1.2 * 0.0088);
    assert_true(l[1] < 0.5 * 0.0248);
    assert_true(l[0] / l[1] >= 3.0);
    assert_true(m[0] > 0.09 && m[0] < 0.1 && m[1] > 0.09 && m[1] < 0.1);
}

/* Where the vortex's energy goes (the `power` function object, every step):
 * W_p and W_o, the sums of dt times pressurePower and otherPower, and the
 * rest, the kinetic energy's change less them (Euler-Cromer's own loss and
 * the shift's velocity correction), each over the initial kinetic energy,
 * from OUT/<name>/postProcessing/power/0/power.dat. */
static void power_budget(const char *name, double *wp, double *wo, double *rest)
{
    char path[512];
    snprintf(path, sizeof path, OUT "/%s/postProcessing/power/0/power.dat", name);
    char *s = slurp(path), *row = s;
    double t0 = NAN, k0 = NAN, t = NAN, k = NAN;
    *wp = *wo = 0.0;
    int rows = 0;
    for (; row && *row; row = strchr(row, '\n'), row = row ? row + 1 : NULL) {
        if (*row == '#') continue;
        char *end;
        const double rt = strtod(row, &end), rk = strtod(end, &end);
        const double pp = strtod(end, &end), po = strtod(end, &end);
        if (rows++ == 0) { /* the initial state: no step, no power */
            assert_true(isnan(pp) && isnan(po));
            t0 = t = rt;
            k0 = k = rk;
            continue;
        }
        assert_false(isnan(pp) || isnan(po));
        *wp += (rt - t) * pp;
        *wo += (rt - t) * po;
        t = rt;
        k = rk;
    }
    free(s);
    assert_true(rows > 2 && t > t0);
    *rest = (k - k0 - *wp - *wo) / k0;
    *wp /= k0;
    *wo /= k0;
}

/* The corrected pressure forces and the vortex's decay: the held mean, the
 * shift and the scalar normalization as above at r0 0.01 m with the
 * `power` function object.  The symmetric force's pressure takes energy
 * out of the vortex (its work over 0.25 s -0.63 % of the initial kinetic
 * energy; the exact pressure of an incompressible flow does none), the
 * conservative correction's much less (-0.24 %): it removes a numerical
 * dissipation, which is why the vortex then decays more slowly
 * (doc/verification.md, "Where the energy goes").  The rest is negative
 * (-0.89 %: Euler-Cromer loses dt^2 m |a|^2 / 2 a step) and the viscous
 * work takes the bulk.  Tolerances: the symmetric work below -0.4 %, the
 * conservative one at most half of it in size, the rest in (-1.5 %, 0). */
static void test_taylor_green_pressure_work(void **state)
{
    (void)state;
    static const char *force[2] = {"symmetric", "correctedConservative"};
    double wp[2], wo[2], rest[2];
    for (int q = 0; q < 2; q++) {
        char edit[1536], name[128];
        snprintf(edit, sizeof edit,
                 TG_DIVERGENCE("%s", "0.25") TG_MIN6 TG_SHIFT("") TG_NORMALIZED
                 " && sed -i 's/^minIterations .*/&\\npressureForce %s;/' "
                 "constant/fluidProperties && %s/editDictionary system/controlDict -entry "
                 "functions -set '{ power { type power; } }'",
                 "{ type divergence; warmStart off; gradientCorrection on; meanPressure 0; }",
                 force[q], bin_dir());
        snprintf(name, sizeof name, "taylorGreen_power_%s", force[q]);
        level("taylorGreen", name, 0.01, 0.001, edit);
        power_budget(name, &wp[q], &wo[q], &rest[q]);
        print_message("%s: over the initial kinetic energy, pressure work %.5f, other %.5f, rest "
                      "%.5f\n",
                      force[q], wp[q], wo[q], rest[q]);
        assert_true(rest[q] < 0.0 && rest[q] > -0.015);
        assert_true(wo[q] < -0.9);
    }
    assert_true(wp[0] < -0.004);
    assert_true(fabs(wp[1]) < 0.5 * fabs(wp[0]));
}

/* particleShifting's refusals: not a dictionary, a coefficient out of
 * range, a velocityCorrection that is not a switch, and a case that is not
 * periodic along every axis (no free-surface treatment), each with the
 * file and line; a misspelt key is a warning naming the nearest. */
static void test_particle_shifting_refusals(void **state)
{
    (void)state;
    const char *b = bin_dir();
    const char *c = OUT "/badShifting";
    static const char *const bad[][2] = {
        {"taylorGreen", "particleShifting on;"},
        {"taylorGreen", "particleShifting { coefficient 0; }"},
        {"taylorGreen", "particleShifting { coefficent 0.1; }"},
        {"taylorGreen", "particleShifting { velocityCorrection maybe; }"},
        {"standingWave", "particleShifting { coefficient 0.1; }"}};
    static const char *const says[] = {
        "fluidProperties:[0-9]*: .*particleShifting.*must be a dictionary",
        "fluidProperties:[0-9]*: .*coefficient.*above 0 and at most 1",
        "fluidProperties:[0-9]*: .*coefficent.*coefficient",
        "fluidProperties:[0-9]*:[0-9]*: keyword .velocityCorrection.: expected on/off",
        "fluidProperties:[0-9]*: particleShifting: only in a box periodic along every axis"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        assert_int_equal(run("rm -rf %s && %s/cloneCase " CASES "/%s/base %s && sed -i "
                             "'s/^eta .*/&\\n%s/' %s/constant/fluidProperties",
                             c, b, bad[k][0], c, bad[k][1], c),
                         0);
        assert_int_equal(run("%s/editDictionary %s/system/controlDict -entry endTime -set 0.002 "
                             "&& %s/pcisph -case %s > %s/log 2>&1; grep -q '%s' %s/log",
                             b, c, b, c, c, says[k], c),
                         0);
    }
}

/* The mixed source (the divergence source warm-started plus 0.05 of the
 * density error) on the free-surface cases: the hydrostatic tank at r0
 * 0.01 m, dt 0.002 s, measured 0.0434 (density source 0.110), and the
 * standing wave's period error, measured 0.0322 at r0 0.01 m and 0.0080 at
 * 0.005 m (the density source levels off at 0.046, 0.035).  Tolerances
 * 1.25x the measured, >= 2x per halving. */
#define MIXED "sed -i 's/^eta .*/&\\npressureSource mixed;/' constant/fluidProperties"
static void test_mixed_source_free_surface(void **state)
{
    (void)state;
    SKIP_UNDER_SANITIZERS();
    double h = level("hydrostaticTank", "hydrostaticTank_mixed", 0.01, 0.002, MIXED);
    assert_true(h < 0.055);
    double e1 = level("standingWave", "standingWave_mixed_0.01", 0.01, 0.002, MIXED);
    double e2 = level("standingWave", "standingWave_mixed_0.005", 0.005, 0.001, MIXED);
    assert_true(e1 < 0.040);
    assert_true(e2 < 0.010);
    assert_true(e1 / e2 >= 2.0);
}

/* The mixed source's period does not move with the step (doc/verification.md,
 * "The mixed source: a period that does not move with the step"): with
 * Wendland C2 at 2.2 r0 (r0 0.01) +1.74 % at dt = r0 / 5 and +1.60 % at
 * r0 / 10 (measured; +0.40, +0.47 % at r0 0.005, +0.22, +0.12 % at
 * 0.00333, +0.30, +0.26 % at 0.0025), where the density source's moves
 * by 2.9 points with Wendland (+0.10, +2.99 %) and 5.6 with the cubic
 * spline at 2.4 r0 (test_standing_wave_period_bias_parts).  Asserted: both
 * 0.5-3 % long, within 1 point of each other (a coarse level's runs
 * spread by about +-0.4 %). */
static void test_mixed_source_step_independent(void **state)
{
    (void)state;
    SKIP_UNDER_SANITIZERS();
    char edit[512];
    snprintf(edit, sizeof edit,
             "E=%s/editDictionary && $E constant/fluidProperties -entry kernel -set wendlandC2 && "
             "$E constant/fluidProperties -entry kernelSupport -set 2.2 && $E "
             "constant/fluidProperties -entry pressureSource -set mixed",
             bin_dir());
    level("standingWave", "standingWave_wendlandMixed_0.01", 0.01, 0.002, edit);
    level("standingWave", "standingWave_wendlandMixed_halfStep_0.01", 0.01, 0.001, edit);
    const double T = 0.528524, /* linear theory, k H = pi / 2 */
        e5 = summary_column("standingWave_wendlandMixed_0.01", SW_PERIOD_FIT) / T - 1.0,
                 e10 =
                     summary_column("standingWave_wendlandMixed_halfStep_0.01", SW_PERIOD_FIT) / T -
        1.0;
    print_message("period fit %+.4f at dt r0 / 5, %+.4f at r0 / 10\n", e5, e10);
    assert_true(e5 > 0.005 && e5 < 0.03);
    assert_true(e10 > 0.005 && e10 < 0.03);
    assert_true(fabs(e10 - e5) < 0.01);
}

/* pressureSource's relaxation: the mixed source at 2.4 r0 (standingWave/
 * baseMixed, r0 0.00333, dt = r0 / 5) stops "not converging" at omega 1
 * within 0.02 s (measured 0.017 s: the warm start carries the modes that
 * one update grows, delta lambda > 2 on a packing 2 % closer:
 * test_kernel's test_delta_largest_mode), and runs at omega 0.5 (to 0.1
 * s here; the whole 1.1 s in cases/verification/standingWave/mixedRelaxed)
 * with the density source's velocities (the largest vmax of the steps
 * below 0.4 m/s; measured 0.277, the density source's 0.279, omega 0.7's
 * 0.275: a few particles at the surface's corners).  At omega 1 the solver
 * warns, naming the file, line, keyword and relaxation 0.5. */
static void test_mixed_source_relaxation(void **state)
{
    (void)state;
    SKIP_UNDER_SANITIZERS();
    const char *b = bin_dir();
    const char *c = OUT "/standingWave_mixedRelaxed";
    assert_int_equal(
        run("rm -rf %s " OUT "/standingWave_mixedUnrelaxed && %s/cloneCase " CASES
            "/standingWave/baseMixed %s && cd %s && "
            "%s/editDictionary constant/fluidProperties -entry particleSpacing -set "
            "0.0033333333333333335 && %s/editDictionary system/timeStepDict -entry deltaT -set "
            "0.0006666666666666666 && %s/editDictionary system/controlDict -entry endTime -set 0.1 "
            "&& cp -r . ../standingWave_mixedUnrelaxed && cd ../standingWave_mixedUnrelaxed && "
            "%s/editDictionary constant/fluidProperties -entry pressureSource/relaxation -set 1",
            c, b, c, c, b, b, b, b),
        0);
    assert_int_not_equal(run("%s/pcisph -case " OUT "/standingWave_mixedUnrelaxed", b), 0);
    assert_non_null(strstr(output, "not converging"));
    assert_non_null(strstr(output, "keyword 'pressureSource': warm-started at kernelSupport 2.4"));
    assert_non_null(strstr(output, "relaxation 0.5 keeps them damped"));
    const char *t = strstr(output, "Time = ");
    double last = 0.0;
    for (; t; t = strstr(t + 1, "Time = ")) last = strtod(t + 7, NULL);
    print_message("omega 1: stopped at %g s\n", last);
    assert_true(last < 0.05);
    assert_int_equal(run("%s/pcisph -case %s", b, c), 0);
    assert_null(strstr(output, "keeps them damped")); /* relaxed: no warning */
    double vmax = 0.0;
    for (t = strstr(output, "vmax "); t; t = strstr(t + 1, "vmax ")) {
        const double v = strtod(t + 5, NULL);
        vmax = v > vmax ? v : vmax;
    }
    print_message("omega 0.5: to 0.1 s, vmax %g m/s\n", vmax);
    assert_true(vmax > 0.05 && vmax < 0.4);
    assert_int_equal(run("test -e %s/0.1/fluid.vtu", c), 0);
}

/* Case c's pressureSource set to `value`: the solver refuses it, saying `why`. */
static void source_refused(const char *c, const char *value, const char *why)
{
    assert_int_equal(
        run("sed -i 's/^pressureSource .*/pressureSource %s/' %s/constant/fluidProperties", value,
            c),
        0);
    assert_int_not_equal(run("%s/pcisph -case %s", bin_dir(), c), 0);
    assert_non_null(strstr(output, why));
}

/* The sed edit `sed` of c's constant/fluidProperties stops the solver
 * with `why` in its message and nothing written. */
static void fluid_refused(const char *c, const char *sed, const char *why)
{
    assert_int_equal(run("sed -i '%s' %s/constant/fluidProperties", sed, c), 0);
    assert_int_not_equal(run("%s/pcisph -case %s", bin_dir(), c), 0);
    assert_non_null(strstr(output, why));
    assert_int_not_equal(run("test -e %s/0", c), 0);
}

/* pressureSource's and pressureForce's bad values stop the solver with file,
 * line and keyword. */
static void test_pressure_source_refusals(void **state)
{
    (void)state;
    const char *b = bin_dir();
    const char *c = OUT "/badSource";
    assert_int_equal(run("rm -rf %s && %s/cloneCase " CASES "/taylorGreen/base %s && sed -i "
                         "'s/^eta .*/&\\npressureSource divergense;/' %s/constant/fluidProperties",
                         c, b, c, c),
                     0);
    assert_int_not_equal(run("%s/pcisph -case %s", b, c), 0);
    assert_non_null(strstr(output, "fluidProperties:"));
    assert_non_null(strstr(output, "keyword 'pressureSource'"));
    assert_non_null(strstr(output, "'divergense' is not one of: density divergence mixed"));
    source_refused(c, "{ type divergence; densityWeight 0.1; }",
                   "keyword 'densityWeight': is the weight of type mixed only");
    source_refused(c, "{ type mixed; densityWeight 1.5; }", "keyword 'densityWeight': must be");
    source_refused(c, "{ type divergence; warmStart maybe; }", "warmStart");
    source_refused(c, "{ type mixed; relaxation 0; }", "keyword 'relaxation': must be omega");
    source_refused(c, "{ type density; relaxation 1.5; }", "keyword 'relaxation': must be omega");
    source_refused(c, "{ type density; relaxation 0.5; warmStart on; }",
                   "density takes no options but relaxation");
    assert_int_equal(run("sed -i 's/^pressureSource .*/pressureSource divergence;/' "
                         "%s/constant/fluidProperties && sed -i 's/^method .*/method "
                         "harada2007;/' %s/constant/boundaryProperties",
                         c, c),
                     0);
    assert_int_not_equal(run("%s/pcisph -case %s", b, c), 0);
    assert_non_null(strstr(output, "boundaryProperties:"));
    assert_non_null(strstr(output, "keyword 'method': harada2007"));
    assert_int_not_equal(run("test -e %s/0", c), 0); /* nothing written */
    /* pressureForce: symmetric, corrected or correctedConservative, nothing else; the
     * corrected forces with ihmsen2010 only (the case's method is still harada2007) */
    fluid_refused(c, "s/^pressureSource .*/pressureForce corected;/",
                  "keyword 'pressureForce': 'corected' is not one of: symmetric corrected "
                  "correctedConservative");
    fluid_refused(c, "s/^pressureForce .*/pressureForce corrected;/",
                  "keyword 'method': pressureForce corrected");
    fluid_refused(c, "s/^pressureForce .*/pressureForce correctedConservative;/",
                  "keyword 'method': pressureForce corrected");
}

/* ---- verifyCase refuses what it cannot judge ---------------------------------- */

static void test_verify_case_refusals(void **state)
{
    (void)state;
    const char *b = bin_dir();
    const char *c = OUT "/translatingTank_0.01";
    /* no verifyDict */
    assert_int_equal(run("rm -rf " OUT "/bad && %s/cloneCase %s " OUT "/bad && rm " OUT
                         "/bad/system/verifyDict",
                         b, c),
                     0);
    assert_int_not_equal(run("%s/verifyCase -case " OUT "/bad", b), 0);
    assert_non_null(strstr(output, "verifyDict"));
    /* no written time */
    assert_int_equal(run("cp %s/system/verifyDict " OUT "/bad/system/", c), 0);
    assert_int_not_equal(run("%s/verifyCase -case " OUT "/bad", b), 0);
    assert_non_null(strstr(output, "no written time"));
    /* a misspelt answer: file, line, keyword and the nearest name */
    assert_int_equal(
        run("%s/editDictionary %s/system/verifyDict -entry exact -set hydrostatc", b, c), 0);
    assert_int_not_equal(run("%s/verifyCase -case %s", b, c), 0);
    assert_non_null(strstr(output, "verifyDict:"));
    assert_non_null(strstr(output, "hydrostatic"));
    /* an answer that needs what the case does not have */
    assert_int_equal(
        run("%s/editDictionary %s/system/verifyDict -entry exact -set poiseuille", b, c), 0);
    assert_int_not_equal(run("%s/verifyCase -case %s", b, c), 0);
    assert_non_null(strstr(output, "nu"));
    /* the Poiseuille profile needs a viscosity (a Taylor-Green vortex may have none) */
    assert_int_equal(run("%s/editDictionary %s/system/verifyDict -entry nu -set 0", b, c), 0);
    assert_int_not_equal(run("%s/verifyCase -case %s", b, c), 0);
    assert_non_null(strstr(output, "'nu': must be a positive number"));
    assert_int_equal(run("%s/editDictionary %s/system/verifyDict -entry nu -remove", b, c), 0);
    /* above the tolerance: exit 1 and say so */
    assert_int_equal(run("%s/editDictionary %s/system/verifyDict -entry exact -set "
                         "translatingTank && %s/editDictionary %s/system/verifyDict -entry "
                         "tolerance -set 1e-6",
                         b, c, b, c),
                     0);
    assert_int_equal(run("%s/verifyCase -case %s", b, c), 1);
    assert_non_null(strstr(output, "above the tolerance"));
}

/* A fluid region's velocityField: a misspelt type and a bad length stop the
 * solver with the file, line and keyword before anything is written. */
static void test_velocity_field_refusals(void **state)
{
    (void)state;
    const char *b = bin_dir();
    const char *c = OUT "/badField";
    assert_int_equal(run("rm -rf %s && %s/cloneCase " CASES "/taylorGreen/base %s && sed -i "
                         "'s/type taylorGreen;/type taylorGren;/' %s/constant/fluidProperties",
                         c, b, c, c),
                     0);
    assert_int_not_equal(run("%s/pcisph -case %s", b, c), 0);
    assert_non_null(strstr(output, "fluidProperties:"));
    assert_non_null(strstr(output, "'taylorGren' is not one of: taylorGreen standingWave"));
    assert_int_equal(run("sed -i 's/type taylorGren; amplitude 0.1; length 0.1;/type "
                         "taylorGreen; amplitude 0.1; length -1;/' %s/constant/fluidProperties",
                         c),
                     0);
    assert_int_not_equal(run("%s/pcisph -case %s", b, c), 0);
    assert_non_null(strstr(output, "keyword 'length': must be a positive number"));
    assert_int_not_equal(run("test -e %s/0", c), 0); /* nothing written */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_poiseuille_converges),
        cmocka_unit_test(test_poiseuille_artificial_viscosity_misses),
        cmocka_unit_test(test_translating_tank),
        cmocka_unit_test(test_hydrostatic_tank),
        cmocka_unit_test(test_pressure_force_corrected),
        cmocka_unit_test(test_relaxed_packing),
        cmocka_unit_test(test_relaxed_to_tolerance),
        cmocka_unit_test(test_standing_wave_period),
        cmocka_unit_test(test_standing_wave_decay),
        cmocka_unit_test(test_standing_wave_period_kernel_support),
        cmocka_unit_test(test_standing_wave_period_wendland),
        cmocka_unit_test(test_standing_wave_conservative_force),
        cmocka_unit_test(test_standing_wave_period_bias_parts),
        cmocka_unit_test(test_surface_density_free_surface_at_rest),
        cmocka_unit_test(test_taylor_green_start),
        cmocka_unit_test(test_taylor_green_lattice_strain),
        cmocka_unit_test(test_taylor_green_reverses_at_a_strain),
        cmocka_unit_test(test_taylor_green_follows_r0_over_dt),
        cmocka_unit_test(test_taylor_green_kernel_support),
        cmocka_unit_test(test_taylor_green_divergence_converges),
        cmocka_unit_test(test_taylor_green_shifting_converges),
        cmocka_unit_test(test_taylor_green_normalized_viscosity),
        cmocka_unit_test(test_taylor_green_mean_pressure),
        cmocka_unit_test(test_taylor_green_inviscid_loss),
        cmocka_unit_test(test_taylor_green_inviscid_loss_conservative),
        cmocka_unit_test(test_taylor_green_pressure_work),
        cmocka_unit_test(test_taylor_green_tensor_viscosity),
        cmocka_unit_test(test_particle_shifting_refusals),
        cmocka_unit_test(test_mixed_source_free_surface),
        cmocka_unit_test(test_mixed_source_step_independent),
        cmocka_unit_test(test_mixed_source_relaxation),
        cmocka_unit_test(test_pressure_source_refusals),
        cmocka_unit_test(test_spheric_front_threshold),
        cmocka_unit_test(test_spheric_front_start_and_gate),
        cmocka_unit_test(test_verify_case_refusals),
        cmocka_unit_test(test_velocity_field_refusals),
    };
    /* SLUICE_TEST_FILTER=test_relaxed* runs the matching tests only */
    if (getenv("SLUICE_TEST_FILTER")) cmocka_set_test_filter(getenv("SLUICE_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
