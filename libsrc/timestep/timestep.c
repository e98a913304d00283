/*
 * timestep: adaptive time-stepping of Ihmsen et al. 2010, Sec. 3.3: the
 * initial step (eq. 14 with lambda 0.25), the 0.2 % increase when all of
 * (16)-(19) hold, the 0.2 % decrease when any of (20)-(23) holds, shock
 * detection (25)-(27) and the shock step (24).  See timestep.h.
 *
 * A zero Fmax or vmax sets no limit: sqrt(h / Fmax) and h / vmax are then
 * infinite, so (16), (19) hold and (20), (23), (27) do not.
 */
#include "timestep/timestep.h"

#include <math.h>
#include <stdarg.h>
#include <string.h>

static double force_scale(double h, double fmax) { return fmax > 0.0 ? sqrt(h / fmax) : HUGE_VAL; }

static double velocity_scale(double h, double vmax) { return vmax > 0.0 ? h / vmax : HUGE_VAL; }

void ts_init(ts_state *s, double dt0)
{
    memset(s, 0, sizeof *s);
    s->dt = dt0;
    s->count.dt_min = s->count.dt_max = dt0;
}

void ts_rollback(ts_state *s, const ts_state *snap)
{
    const double dt = s->dt;
    const ts_counts count = s->count;
    *s = *snap;
    s->dt = dt;
    s->count = count;
}

/* ---- initial step ---- */

static void append(char *buf, size_t len, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

static void append(char *buf, size_t len, const char *fmt, ...)
{
    size_t off = strlen(buf);
    va_list ap;
    if (off + 1 >= len) return;
    va_start(ap, fmt);
    vsnprintf(buf + off, len - off, fmt, ap);
    va_end(ap);
}

double ts_initial(const ts_params *p, double h, double v0max, double g_norm, double height,
                  char *rule, size_t len)
{
    const char *at_rest = v0max > 0.0 ? "" : ", fluid at rest";
    double dt = HUGE_VAL;
    if (len) rule[0] = '\0';
    if (p->mode == TS_CONSTANT || p->delta_t > 0.0) {
        snprintf(rule, len, "deltaT %g from timeStepDict (%s mode)", p->delta_t,
                 ts_mode_name(p->mode));
        return p->delta_t;
    }
    if (v0max > 0.0) {
        dt = p->initial_cfl * h / v0max; /* Sec. 3.3: 0.25 h / v0max, eq. (14) */
        snprintf(rule, len, "eq. (14): %g h / v0max, v0max = %g m/s", p->initial_cfl, v0max);
    }
    if (g_norm > 0.0) {
        double by_force = p->increase_force * sqrt(h / g_norm); /* eq. (16) with F = |g| */
        if (by_force < dt) {
            dt = by_force;
            snprintf(rule, len, "eq. (16) with F = |g|: %g sqrt(h / |g|), |g| = %g m/s^2%s",
                     p->increase_force, g_norm, at_rest);
        }
        if (height > 0.0) {
            double v_fall = sqrt(2.0 * g_norm * height);
            double by_fall = p->initial_cfl * h / v_fall; /* eq. (14) at the free-fall speed */
            if (by_fall < dt) {
                dt = by_fall;
                snprintf(rule, len,
                         "free fall: %g h / sqrt(2 |g| H), H = %g m, sqrt(2 |g| H) = %g m/s%s",
                         p->initial_cfl, height, v_fall, at_rest);
            }
        }
    }
    if (dt == HUGE_VAL) {
        if (p->delta_t_max > 0.0) {
            snprintf(rule, len, "deltaTMax %g (no velocity and no gravity)", p->delta_t_max);
            return p->delta_t_max;
        }
        snprintf(rule, len,
                 "no time scale (fluid at rest without gravity): "
                 "set deltaT or deltaTMax in system/timeStepDict");
        return 0.0;
    }
    if (p->delta_t_max > 0.0 && dt > p->delta_t_max) {
        append(rule, len, " = %g s, limited to deltaTMax", dt);
        dt = p->delta_t_max;
    }
    if (dt < p->delta_t_min) {
        append(rule, len, " = %g s, raised to deltaTMin", dt);
        dt = p->delta_t_min;
    }
    return dt;
}

double ts_initial_pressure(double eta_avg, int iterations, double delta_unit, double g_norm,
                           double height)
{
    if (!(eta_avg > 0.0 && iterations > 0 && delta_unit > 0.0 && g_norm > 0.0 && height > 0.0))
        return HUGE_VAL;
    /* bottom error rho0 g H / (k delta(dt)), delta(dt) = delta_unit / dt^2;
     * the average over the column is half of it: set it to eta_avg / 2 */
    return sqrt(eta_avg * iterations * delta_unit / (g_norm * height));
}

/* ---- one step ---- */

/* Flags of (16)-(23) (hold) and (25)-(27) (fired) for the step taken with s->dt. */
static unsigned evaluate(const ts_params *p, const ts_state *s, double eta_avg, double h,
                         const ts_obs *o)
{
    const double dt = s->dt, sf = force_scale(h, o->fmax), sv = velocity_scale(h, o->vmax);
    unsigned c = 0;
    if (p->increase_force * sf > dt) c |= TS_C16;                     /* eq. (16) */
    if (o->err_max < p->increase_max_density * eta_avg) c |= TS_C17;  /* eq. (17) */
    if (o->err_avg < p->increase_avg_density * eta_avg) c |= TS_C18;  /* eq. (18) */
    if (p->increase_velocity * sv > dt) c |= TS_C19;                  /* eq. (19) */
    if (p->decrease_force * sf < dt) c |= TS_C20;                     /* eq. (20) */
    if (o->err_max > p->decrease_max_density * eta_avg) c |= TS_C21;  /* eq. (21) */
    if (o->err_avg >= p->decrease_avg_density * eta_avg) c |= TS_C22; /* eq. (22) */
    if (p->decrease_velocity * sv <= dt) c |= TS_C23;                 /* eq. (23) */
    if (s->have_prev && o->err_max - s->prev_err_max > ts_delta_shock(p, eta_avg))
        c |= TS_C25;                                      /* eq. (25) */
    if (o->err_max > ts_eta_max(p, eta_avg)) c |= TS_C26; /* eq. (26) */
    if (p->shock_velocity_cfl * sv < dt) c |= TS_C27;     /* eq. (27) */
    return c;
}

/* dt_new of eq. (24), never above shockMaxRatio dt so that the repeated
 * steps differ from the ones that failed. */
double ts_shock_step(const ts_params *p, double dt, double h, const ts_obs *o, unsigned *c)
{
    double next = p->shock_max_ratio * dt;
    unsigned why = TS_LIMIT_RATIO;
    if (!(*c & TS_NONFINITE)) {
        double by_force = p->shock_force * force_scale(h, o->fmax);          /* eq. (24) */
        double by_velocity = p->shock_velocity * velocity_scale(h, o->vmax); /* eq. (24) */
        double dt24 = by_force <= by_velocity ? by_force : by_velocity;
        if (dt24 < next) {
            next = dt24;
            why = by_force <= by_velocity ? TS_C24_FORCE : TS_C24_VELOCITY;
        }
    }
    *c |= why;
    return next;
}

/* Adaptive mode: the next step from the flags; shock before decrease before increase. */
static ts_action decide(const ts_params *p, ts_state *s, double h, const ts_obs *o, unsigned *c)
{
    const double dt = s->dt;
    double next = dt;
    ts_action a = TS_KEEP;
    if (*c & TS_SHOCK_ANY) {
        next = ts_shock_step(p, dt, h, o, c);
        a = TS_SHOCK;
    } else if (*c & TS_DECREASE_ANY) {
        next = dt * p->decrease_factor;
        a = TS_DECREASE;
    } else if ((*c & TS_INCREASE_ALL) == TS_INCREASE_ALL) {
        next = dt * p->increase_factor;
        if (p->delta_t_max > 0.0 && next > p->delta_t_max) {
            next = dt > p->delta_t_max ? dt : p->delta_t_max;
            *c |= TS_LIMIT_MAX;
        }
        a = next > dt ? TS_INCREASE : TS_KEEP;
    }
    if (next < p->delta_t_min || !(next > 0.0)) a = TS_TOO_SMALL;
    s->dt = next;
    return a;
}

/* Whether the run can go on after action a. */
static ts_action verdict(const ts_params *p, const ts_state *s, double eta_avg, const ts_obs *o,
                         ts_action a, unsigned c, double dt_used)
{
    const double eta_max = ts_eta_max(p, eta_avg);
    if (a != TS_SHOCK && (c & TS_NONFINITE)) return TS_DIVERGED;
    /* constant mode: the step must let PCISPH reach eta; when iterating to
     * convergence cannot bring the error down (the average above eta, or
     * the maximum above eta_max), the step is too large for this case */
    if (p->mode == TS_CONSTANT &&
        (o->err_avg > eta_max ||
         (!o->converged && o->iterating && (o->err_max > eta_max || o->err_avg > eta_avg))))
        return TS_NOT_CONVERGING;
    if (a == TS_SHOCK && (!(s->dt > 1e-9 * dt_used) || !(s->dt > 1e-14))) return TS_SHOCK_STORM;
    return a;
}

ts_action ts_update(const ts_params *p, ts_state *s, double eta_avg, double h, const ts_obs *o,
                    unsigned *criteria)
{
    unsigned c;
    ts_action a = TS_KEEP;
    ts_counts *n = &s->count;
    n->steps++;
    if (s->dt < n->dt_min) n->dt_min = s->dt;
    if (s->dt > n->dt_max) n->dt_max = s->dt;
    if (isfinite(o->err_avg) && isfinite(o->err_max) && isfinite(o->vmax) && isfinite(o->fmax))
        c = evaluate(p, s, eta_avg, h, o);
    else c = TS_NONFINITE;
    s->prev_err_max = o->err_max; /* history of eq. (25) */
    s->have_prev = 1;
    const double dt_used = s->dt;
    if (ts_is_cost(p)) {
        a = ts_cost_decide(p, s, eta_avg, h, o, &c);
        if (s->dt < p->delta_t_min || !(s->dt > 0.0)) a = TS_TOO_SMALL;
    } else if (p->mode == TS_ADAPTIVE) {
        a = decide(p, s, h, o, &c);
    }
    switch (a) {
    case TS_KEEP:
        n->keep++;
        break;
    case TS_INCREASE:
        n->increase++;
        break;
    case TS_DECREASE:
        n->decrease++;
        break;
    case TS_SHOCK:
        n->shock++;
        break;
    default:
        break;
    }
    if (criteria) *criteria = c;
    return verdict(p, s, eta_avg, o, a, c, dt_used);
}

const char *ts_failure(ts_action a)
{
    switch (a) {
    case TS_TOO_SMALL:
        return "not stable: the time step fell below deltaTMin";
    case TS_DIVERGED:
        return "the solution diverged (non-finite velocity or density); reduce deltaT in "
               "system/timeStepDict or use mode adaptive";
    case TS_NOT_CONVERGING:
        return "not converging: PCISPH cannot bring the density error below eta at this "
               "deltaT; reduce deltaT in system/timeStepDict or use mode adaptive";
    case TS_SHOCK_STORM:
        return "not converging: shocks keep shrinking the time step";
    default:
        return NULL;
    }
}

/* ---- text for the log ---- */

const char *ts_action_name(ts_action a)
{
    switch (a) {
    case TS_KEEP:
        return "keep";
    case TS_INCREASE:
        return "increase";
    case TS_DECREASE:
        return "decrease";
    case TS_SHOCK:
        return "shock";
    case TS_TOO_SMALL:
        return "tooSmall";
    case TS_DIVERGED:
        return "diverged";
    case TS_NOT_CONVERGING:
        return "notConverging";
    case TS_SHOCK_STORM:
        return "shockStorm";
    }
    return "?";
}

/* Append "; " between items. */
static void item(char *buf, size_t len, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

static void item(char *buf, size_t len, const char *fmt, ...)
{
    size_t off = strlen(buf);
    va_list ap;
    if (off && off + 1 < len) {
        snprintf(buf + off, len - off, "; ");
        off = strlen(buf);
    }
    if (off + 1 >= len) return;
    va_start(ap, fmt);
    vsnprintf(buf + off, len - off, fmt, ap);
    va_end(ap);
}

static void increase_text(const ts_params *p, unsigned c, char *buf, size_t len)
{
    if ((c & TS_INCREASE_ALL) == TS_INCREASE_ALL) {
        item(buf, len, "(16)-(19) all hold");
        return;
    }
    if (!(c & TS_C16)) item(buf, len, "not (16) %g sqrt(h/Fmax) > dt", p->increase_force);
    if (!(c & TS_C17)) item(buf, len, "not (17) rho_err_max < %g eta_avg", p->increase_max_density);
    if (!(c & TS_C18)) item(buf, len, "not (18) rho_err_avg < %g eta_avg", p->increase_avg_density);
    if (!(c & TS_C19)) item(buf, len, "not (19) %g h/vmax > dt", p->increase_velocity);
}

void ts_criteria_text(const ts_params *p, unsigned c, char *buf, size_t len)
{
    if (!len) return;
    buf[0] = '\0';
    if (c & TS_NONFINITE) {
        item(buf, len, "non-finite density error, velocity or force");
    } else if (c & TS_SHOCK_ANY) {
        if (c & TS_C25) item(buf, len, "(25) rho_err_max rose > %g eta_avg", p->delta_shock_factor);
        if (c & TS_C26)
            item(buf, len, "(26) rho_err_max > eta_max = %g eta_avg", p->eta_max_factor);
        if (c & TS_C27) item(buf, len, "(27) %g h/vmax < dt", p->shock_velocity_cfl);
    } else if (ts_is_cost(p)) {
        /* the cost controller's reasons follow */
    } else if (c & TS_DECREASE_ANY) {
        if (c & TS_C20) item(buf, len, "(20) %g sqrt(h/Fmax) < dt", p->decrease_force);
        if (c & TS_C21) item(buf, len, "(21) rho_err_max > %g eta_avg", p->decrease_max_density);
        if (c & TS_C22) item(buf, len, "(22) rho_err_avg >= %g eta_avg", p->decrease_avg_density);
        if (c & TS_C23) item(buf, len, "(23) %g h/vmax <= dt", p->decrease_velocity);
    } else {
        increase_text(p, c, buf, len);
    }
    if (c & TS_C24_FORCE) item(buf, len, "dt_new = %g sqrt(h/Fmax) (24)", p->shock_force);
    if (c & TS_C24_VELOCITY) item(buf, len, "dt_new = %g h/vmax (24)", p->shock_velocity);
    if (c & TS_LIMIT_RATIO) item(buf, len, "dt_new = %g dt (shockMaxRatio)", p->shock_max_ratio);
    if (c & TS_LIMIT_MAX) item(buf, len, "limited by deltaTMax");
    if (c & TS_COST_ABOVE) item(buf, len, "cost: rho_err_avg above eta after the iterations");
    if (c & TS_COST_SHORT)
        item(buf, len, "cost: rho_err_max above %g eta_avg after the iterations",
             p->cost_max_density);
    if (c & TS_COST_FEWER)
        item(buf, len, "cost: fewer iterations than targetIterations %g", p->target_iterations);
    if (c & TS_COST_MORE)
        item(buf, len, "cost: more iterations than targetIterations %g", p->target_iterations);
    if (c & TS_COST_LIMIT) item(buf, len, "cost: limited by (16), (19) or deltaTMax");
}
