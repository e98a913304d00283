/* sl_progress: progress and time left (see sl_progress.h). */
#include "core/sl_progress.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define SL_PROGRESS_TAU    10.0 /* s: time constant of the rate's smoothing */
#define SL_PROGRESS_SAMPLE 0.5  /* s: shortest interval a rate is measured over */
#define SL_PROGRESS_REDRAW 0.25 /* s: shortest interval between terminal redraws */

static double wall_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static sl_progress_mode choose_mode(FILE *out)
{
    const char *m = getenv("SLUICE_PROGRESS");
    if (m && !strcmp(m, "off")) return SL_PROGRESS_OFF;
    if (m && !strcmp(m, "plain")) return SL_PROGRESS_PLAIN;
    if (m && !strcmp(m, "line")) return SL_PROGRESS_LINE;
    return out && isatty(fileno(out)) ? SL_PROGRESS_LINE : SL_PROGRESS_PLAIN;
}

void sl_progress_start(sl_progress *p, FILE *out, double done0, double total, double period)
{
    const char *e = getenv("SLUICE_PROGRESS_PERIOD");
    memset(p, 0, sizeof *p);
    p->out = out;
    p->mode = choose_mode(out);
    p->period = e && atof(e) > 0 ? atof(e) : period;
    p->done0 = p->sample_done = done0;
    p->total = total;
    p->wall0 = p->last_print = p->sample_wall = wall_now();
}

double sl_progress_elapsed(const sl_progress *p) { return wall_now() - p->wall0; }

/* Exponential smoothing over wall time, so a burst of slow steps (a
 * shock) moves the estimate within ~10 s but a single one does not. */
static void sample(sl_progress *p, double done, double now)
{
    const double dt = now - p->sample_wall;
    if (dt < SL_PROGRESS_SAMPLE || done < p->sample_done) {
        if (done < p->sample_done) p->sample_done = done; /* went back (rollback) */
        return;
    }
    const double inst = (done - p->sample_done) / dt;
    if (p->rate <= 0.0) p->rate = inst;
    else p->rate += (1.0 - exp(-dt / SL_PROGRESS_TAU)) * (inst - p->rate);
    p->sample_wall = now;
    p->sample_done = done;
}

double sl_progress_eta(const sl_progress *p, double done)
{
    if (!(p->rate > 0.0)) return -1.0;
    double left = p->total - done;
    return left > 0.0 ? left / p->rate : 0.0;
}

void sl_progress_duration(double s, char *buf, size_t len)
{
    if (!(s >= 0.0) || s > 1e8) {
        snprintf(buf, len, "?");
        return;
    }
    long n = lround(s);
    if (n < 60) snprintf(buf, len, "%ld s", n);
    else if (n < 3600) snprintf(buf, len, "%ld min %02ld s", n / 60, n % 60);
    else snprintf(buf, len, "%ld h %02ld min", n / 3600, (n % 3600) / 60);
}

void sl_progress_text(const sl_progress *p, double done, const char *what, char *buf, size_t len)
{
    char eta[32], el[32];
    double frac = p->total > p->done0 ? (done - p->done0) / (p->total - p->done0) : 1.0;
    double left = sl_progress_eta(p, done);
    if (frac < 0) frac = 0;
    if (frac > 1) frac = 1;
    sl_progress_duration(sl_progress_elapsed(p), el, sizeof el);
    if (left < 0) snprintf(eta, sizeof eta, "estimating");
    else sl_progress_duration(left, eta, sizeof eta);
    snprintf(buf, len, "%s%s%5.1f %%  wall %s  ETA %s", what ? what : "", what ? "  " : "",
             100.0 * frac, el, eta);
}

void sl_progress_update(sl_progress *p, double done, const char *what)
{
    if (p->mode == SL_PROGRESS_OFF) return;
    const double now = wall_now();
    sample(p, done, now);
    const double due = p->mode == SL_PROGRESS_LINE ? SL_PROGRESS_REDRAW : p->period;
    if (now - p->last_print < due) return;
    p->last_print = now;
    char text[512];
    sl_progress_text(p, done, what, text, sizeof text);
    if (p->mode == SL_PROGRESS_LINE) {
        size_t n = strlen(text);
        fprintf(p->out, "\r%s%*s", text, p->shown > n ? (int)(p->shown - n) : 0, "");
        p->shown = n;
    } else {
        fprintf(p->out, "Progress: %s\n", text);
    }
    fflush(p->out);
}

void sl_progress_end(sl_progress *p)
{
    if (p->mode == SL_PROGRESS_LINE && p->shown) {
        fputc('\n', p->out);
        fflush(p->out);
        p->shown = 0;
    }
}
