/*
 * timestep: the time-step controller of Ihmsen et al. 2010, Sec. 3.3
 * (eq. 14-27), read from system/timeStepDict.  Annotated defaults:
 * etc/caseDicts/timeStepDict (a unit test checks they equal ts_params_default).
 *
 *   initial step   dt = 0.25 h / v0max (Sec. 3.3, eq. 14), bounded for a
 *                  fluid at rest or slow by gravity (see ts_initial)
 *   increase       dt *= 1.002 when all of (16)-(19) hold
 *   decrease       dt *= 0.998 when any of (20)-(23) holds
 *   shock          when any of (25)-(27) holds: the caller goes two steps
 *                  back and resumes with dt_new of eq. (24)
 *
 * Mode `constant` keeps deltaT but evaluates the same criteria, so the
 * per-step record has the same columns in both modes.
 *
 * Units: h in m, velocities in m/s, forces per unit mass in m/s^2, density
 * errors and eta as fractions of rho0 (0.01 = 1 %).  The paper's eta_avg is
 * the fluid's `eta`; eta_max = etaMaxFactor eta_avg and delta_shock =
 * deltaShockFactor eta_avg, with eta_avg < delta_shock < eta_max (Sec. 3.3).
 *
 * Rollback: ts_state is plain data.  The solver copies it together with the
 * particle state at the start of each step (`snap = state`).  On TS_SHOCK it
 * restores the particles of two steps back and calls ts_rollback(&state,
 * &snap), which brings back the eq. (25) history of that time but keeps the
 * new step and the run's counters.  A plain `state = snap` restores the
 * controller exactly (used by tests; it would also forget the shock).
 */
#ifndef SL_TIMESTEP_H
#define SL_TIMESTEP_H

#include <stddef.h>
#include <stdio.h>

#include "core/sl_log.h"
#include "dictionary/dict.h"

typedef enum { TS_CONSTANT, TS_ADAPTIVE } ts_mode;

/* Adaptive mode's controller (`controller`):
 *   ihmsen2010  the paper's (Sec. 3.3): exactly `iterations` PCISPH
 *               iterations per step, dt by (16)-(23) in 0.2 % steps
 *   cost        not in the paper (ts_cost.c, doc/timestep-cost.md): every
 *               step iterates until the average compression is at most eta
 *               (and the largest at most costMaxDensity eta), between
 *               minIterations and maxIterations of constant/fluidProperties,
 *               and dt is steered to the step where a simulated second costs
 *               least: up by costIncreaseFactor while a step needs fewer than
 *               targetIterations iterations, down by costDecreaseFactor while
 *               it needs more; never above what (16) and (19) allow.  A step
 *               whose average compression stays above eta is a shock (back
 *               two steps, eq. 24), as are (25)-(27). */
typedef enum { TS_IHMSEN2010, TS_COST } ts_controller;

/* Every constant of eq. (16)-(27), by its timeStepDict key. */
typedef struct ts_params {
    ts_mode mode;                /* mode */
    ts_controller controller;    /* controller (adaptive mode) */
    double delta_t;              /* deltaT: the step (constant); adaptive: initial
                                  * step, 0 = estimate it (ts_initial) */
    double delta_t_min;          /* deltaTMin: below it the run is unstable; 0 = none */
    double delta_t_max;          /* deltaTMax: upper bound; 0 = none */
    int iterations;              /* iterations: PCISPH iterations per step, adaptive */
    double initial_cfl;          /* initialCFL: 0.25, initial step (Sec. 3.3) */
    double eta_max_factor;       /* etaMaxFactor: eta_max / eta_avg, 10 */
    double delta_shock_factor;   /* deltaShockFactor: delta_shock / eta_avg, 5.5 */
    double increase_factor;      /* increaseFactor: 1.002 */
    double decrease_factor;      /* decreaseFactor: 0.998 */
    double increase_force;       /* increaseForce: 0.19, eq. (16) */
    double increase_max_density; /* increaseMaxDensity: 4.5, eq. (17) */
    double increase_avg_density; /* increaseAvgDensity: 0.9, eq. (18) */
    double increase_velocity;    /* increaseVelocity: 0.39, eq. (19) */
    double decrease_force;       /* decreaseForce: 0.2, eq. (20) */
    double decrease_max_density; /* decreaseMaxDensity: 5.5, eq. (21) */
    double decrease_avg_density; /* decreaseAvgDensity: 1.0, eq. (22) */
    double decrease_velocity;    /* decreaseVelocity: 0.4, eq. (23) */
    double shock_force;          /* shockForce: 0.2, eq. (24) */
    double shock_velocity;       /* shockVelocity: 0.25, eq. (24) */
    double shock_velocity_cfl;   /* shockVelocityCFL: 0.45, eq. (27) */
    double shock_max_ratio;      /* shockMaxRatio: 0.5, dt_new <= ratio dt (not in
                                  * the paper: a shock must shrink the step) */
    /* controller cost (not in the paper) */
    double target_iterations;    /* targetIterations: iterations per step at the
                                  * cheapest step */
    double cost_increase_factor; /* costIncreaseFactor: 1.01 */
    double cost_decrease_factor; /* costDecreaseFactor: 0.98 */
    double cost_max_density;     /* costMaxDensity: the iterations go on while
                                  * rho_err_max > costMaxDensity eta_avg */
} ts_params;

/* The paper's values (and mode adaptive, deltaT 0 = estimated). */
void ts_params_default(ts_params *p);

/* Fill p from the defaults and the parsed system/timeStepDict d.  A bad value
 * stops the run: "<file>:<line>: keyword '<key>': <why>"; unknown keys are
 * warnings naming the nearest valid key.  deltaT is required in constant mode. */
void ts_read(const dict *d, ts_params *p);

/* 0 if p is usable with this eta_avg (> 0); else nonzero and err holds
 * "keyword '<key>': <why>".  ts_read applies the same checks. */
int ts_validate(const ts_params *p, double eta_avg, sl_err *err);

/* The keys of timeStepDict, NULL-terminated (for dict_warn_unknown). */
const char *const *ts_keys(void);
/* Value of a numeric key (everything but `mode`); 0 if known, else -1. */
int ts_param_value(const ts_params *p, const char *key, double *value);
const char *ts_mode_name(ts_mode m);
const char *ts_controller_name(ts_controller c);
/* Adaptive mode with controller cost. */
static inline int ts_is_cost(const ts_params *p)
{
    return p->mode == TS_ADAPTIVE && p->controller == TS_COST;
}
/* Write the parameters actually used, as timeStepDict entries. */
void ts_write(const ts_params *p, FILE *f);

static inline double ts_eta_max(const ts_params *p, double eta_avg)
{
    return p->eta_max_factor * eta_avg;
}
static inline double ts_delta_shock(const ts_params *p, double eta_avg)
{
    return p->delta_shock_factor * eta_avg;
}

/* Run statistics, kept across a rollback; they count discarded steps too. */
typedef struct ts_counts {
    long steps, keep, increase, decrease, shock;
    double dt_min, dt_max; /* smallest and largest step evaluated */
} ts_counts;

/* Plain data: copy it to take a snapshot. */
typedef struct ts_state {
    double dt;           /* step of the next (or current) step */
    double prev_err_max; /* rho_err_max of the previous step, eq. (25) */
    int have_prev;       /* prev_err_max is set */
    ts_counts count;
} ts_state;

/* Start with step dt0 (from ts_initial) and no history. */
void ts_init(ts_state *s, double dt0);

/* Initial step.  Constant mode, or adaptive with deltaT > 0: deltaT.
 * Otherwise the smallest of the rules that have a scale:
 *   eq. (14)  initialCFL h / v0max                    (v0max > 0; the paper's)
 *   eq. (16)  increaseForce sqrt(h / |g|)             (g_norm > 0: F = |g|)
 *   free fall initialCFL h / sqrt(2 |g| height)       (g_norm, height > 0)
 * so a fluid at rest starts at the speed it reaches falling over `height`
 * (pass the height of the fluid's top above the lowest wall) and never above
 * the force criterion for gravity.  Clamped to [deltaTMin, deltaTMax].
 * `rule` receives a one-line text naming the rule and its inputs.  Returns 0
 * when nothing gives a time scale (at rest, no gravity, no deltaTMax): the
 * caller must stop and ask for deltaT. */
double ts_initial(const ts_params *p, double h, double v0max, double g_norm, double height,
                  char *rule, size_t len);

/* Initial step of a fluid at rest under gravity, from the pressure it must
 * hold (not in the paper, which assumes a moving fluid).  PCISPH rebuilds
 * the pressure from zero in each step, so a column of height H settles at
 * the compression that gives rho0 g H in `iterations` corrections:
 * rho_err(bottom) = rho0 g H / (k delta(dt)), with delta(dt) = delta_unit /
 * dt^2 (eq. 4, 5; delta_unit is delta for dt = 1 s).  Returns the dt at
 * which the column's average compression is eta_avg / 2, half the (18)
 * threshold, so the controller starts below the step it will settle at
 * (the paper's advice: underestimate the initial step).  HUGE_VAL when an
 * input is missing. */
double ts_initial_pressure(double eta_avg, int iterations, double delta_unit, double g_norm,
                           double height);

/* What the solver measured in the step just taken (pcs_stats). */
typedef struct ts_obs {
    double err_avg, err_max; /* rho_err avg and max, fractions of rho0 */
    double vmax;             /* max |v(t + dt)|, m/s */
    double fmax;             /* max |F / m|, m/s^2 */
    int converged;           /* the iterations reached eta */
    int iterating;           /* iterating to convergence (maxIterations > minIterations) */
    int iterations;          /* PCISPH iterations of the step (controller cost) */
} ts_obs;

/* What to do after a step.  The first four go on (a shock: back two
 * steps, eq. 24-27); the others end the run with the last good state
 * (ts_failure says why). */
typedef enum {
    TS_KEEP,
    TS_INCREASE,
    TS_DECREASE,
    TS_SHOCK,
    TS_TOO_SMALL,      /* the step fell below deltaTMin */
    TS_DIVERGED,       /* a non-finite velocity or density, and no shock to go back from */
    TS_NOT_CONVERGING, /* constant mode: iterating cannot bring the error below eta */
    TS_SHOCK_STORM     /* shocks keep shrinking the step */
} ts_action;

/* Why the run cannot go on after action a (with what to do), or NULL. */
const char *ts_failure(ts_action a);

/* Criterion flags: (16)-(23) "holds", (25)-(27) "fired". */
#define TS_C16          (1u << 0)
#define TS_C17          (1u << 1)
#define TS_C18          (1u << 2)
#define TS_C19          (1u << 3)
#define TS_C20          (1u << 4)
#define TS_C21          (1u << 5)
#define TS_C22          (1u << 6)
#define TS_C23          (1u << 7)
#define TS_C25          (1u << 8)
#define TS_C26          (1u << 9)
#define TS_C27          (1u << 10)
#define TS_C24_FORCE    (1u << 11) /* dt_new from the force term of (24) */
#define TS_C24_VELOCITY (1u << 12) /* dt_new from the velocity term of (24) */
#define TS_LIMIT_RATIO  (1u << 13) /* dt_new limited to shockMaxRatio dt */
#define TS_LIMIT_MAX    (1u << 14) /* increase limited by deltaTMax */
#define TS_NONFINITE    (1u << 15) /* an observation is NaN or infinite */
#define TS_COST_FEWER   (1u << 16) /* cost: fewer iterations than targetIterations */
#define TS_COST_MORE    (1u << 17) /* cost: more iterations than targetIterations */
#define TS_COST_LIMIT   (1u << 18) /* cost: next step limited by (16), (19) or deltaTMax */
#define TS_COST_ABOVE   (1u << 19) /* cost: the average compression stayed above eta */
#define TS_COST_SHORT \
    (1u << 20) /* cost: the largest compression stayed above
                                    * costMaxDensity eta: dt *= costDecreaseFactor^5 */
#define TS_INCREASE_ALL (TS_C16 | TS_C17 | TS_C18 | TS_C19)
#define TS_DECREASE_ANY (TS_C20 | TS_C21 | TS_C22 | TS_C23)
#define TS_SHOCK_ANY    (TS_C25 | TS_C26 | TS_C27 | TS_NONFINITE)

/* Controller cost: the next step after a step taken with s->dt whose
 * criteria are *c (evaluate's flags, to which it adds TS_COST_*): see
 * ts_controller.  Returns TS_SHOCK (s->dt = dt_new), TS_INCREASE,
 * TS_DECREASE or TS_KEEP.  Called by ts_update. */
ts_action ts_cost_decide(const ts_params *p, ts_state *s, double eta_avg, double h, const ts_obs *o,
                         unsigned *c);
/* dt_new of eq. (24), at most shockMaxRatio dt (adds TS_C24_* or TS_LIMIT_RATIO to *c). */
double ts_shock_step(const ts_params *p, double dt, double h, const ts_obs *o, unsigned *c);

/* After a step taken with s->dt: evaluate (16)-(23) and (25)-(27), record
 * rho_err_max for (25) and set s->dt to the next step.  Precedence: shock,
 * then decrease, then increase.  Adaptive mode returns
 *   TS_SHOCK      s->dt = dt_new of (24) (<= shockMaxRatio dt); roll back
 *   TS_DECREASE   s->dt *= decreaseFactor
 *   TS_INCREASE   s->dt *= increaseFactor (at most deltaTMax)
 *   TS_KEEP       s->dt unchanged
 *   TS_TOO_SMALL  the new step is below deltaTMin (s->dt holds it): stop
 * Constant mode always returns TS_KEEP with s->dt unchanged.  A step the
 * solver shortened to land on a write time is still passed as s->dt, so the
 * controller's step is not shrunk by output.  *criteria (may be NULL)
 * receives the TS_C* flags. */
ts_action ts_update(const ts_params *p, ts_state *s, double eta_avg, double h, const ts_obs *o,
                    unsigned *criteria);

/* After TS_SHOCK: *s = *snap, but keep the new step and the statistics. */
void ts_rollback(ts_state *s, const ts_state *snap);

const char *ts_action_name(ts_action a);
/* Why the controller decided, e.g. "(21) rho_err_max > 5.5 eta_avg"; for
 * TS_KEEP the increase criteria that failed. */
void ts_criteria_text(const ts_params *p, unsigned criteria, char *buf, size_t len);

#endif
