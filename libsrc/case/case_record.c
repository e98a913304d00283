/* case_record: the per-step record timeStep.dat (see case_record.h). */
#include "case/case_record.h"
#include "core/sl_log.h"
#include "core/sl_mem.h"
#include "io/time_dir.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double rec_wall(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

void rec_flush(case_record *r)
{
    if (r->f && fflush(r->f) != 0) sl_warning("could not write '%s': %s", r->path, strerror(errno));
    r->flushed = rec_wall();
}

void rec_open(case_record *r, const sl_case *c, const char *tname)
{
    sl_err err;
    size_t n = strlen(c->dir) + strlen(tname) + 64;
    char *dir = sl_malloc(n, "path");
    snprintf(dir, n, "%s/postProcessing/timeStep/%s", c->dir, tname);
    if (tdir_mkdirs(dir, &err)) sl_fatal("%s", err.msg);
    r->path = sl_malloc(n + 16, "path");
    snprintf(r->path, n + 16, "%s/timeStep.dat", dir);
    free(dir);
    r->f = fopen(r->path, "w");
    if (!r->f) sl_fatal("cannot write '%s': %s", r->path, strerror(errno));
    fprintf(r->f,
            "# Time step record (Sluice pcisph)\n"
            "# rhoErr: compression max(rho - rho0, 0) / rho0 in percent, after the last "
            "PCISPH iteration\n"
            "# Fmax: largest force per unit mass (m/s^2)\n"
            "# shock 1: the step was discarded, the run went back two steps\n"
            "# controllerDeltaT: the controller's step after this one\n"
            "# volErr: the same compression with the wall's density from the boundary "
            "particles of eq. (13), whatever the boundary method (= rhoErr for "
            "ihmsen2010)\n"
            "# Time\tdeltaT\titerations\trhoErrAvg\trhoErrMax\tvMax\tFMax\tshock\twallTime"
            "\tcontrollerDeltaT\tvolErrAvg\tvolErrMax\n");
    rec_flush(r);
}

void rec_step(case_record *r, double t, double dt, const pcs_stats *st, int shock, double wall,
              double dt_next)
{
    fprintf(r->f, "%.10g\t%.17g\t%d\t%.6g\t%.6g\t%.6g\t%.6g\t%d\t%.6g\t%.17g\t%.6g\t%.6g\n", t, dt,
            st->iterations, 100 * st->err_avg, 100 * st->err_max, st->vmax, st->fmax, shock, wall,
            dt_next, 100 * st->vol_avg, 100 * st->vol_max);
    if (rec_wall() - r->flushed >= REC_FLUSH_SECONDS) rec_flush(r);
}

void rec_close(case_record *r)
{
    if (r->f && fclose(r->f) != 0)
        sl_warning("could not finish '%s': %s", r->path, strerror(errno));
    free(r->path);
    r->f = NULL;
    r->path = NULL;
}
