/*
 * ts_cost: the time-step controller `controller cost;` (not in the paper;
 * see timestep.h and doc/timestep-cost.md).
 *
 * The paper keeps 3 PCISPH iterations per step and lets the density error
 * set the step.  At a small eta that forces a tiny step: the error of a
 * step with k iterations grows with dt faster than k pays for.  A step
 * costs about c0 + c1 k (neighbour search, forces and integration, plus k
 * predictions and pressure forces), so a simulated second costs
 * (c0 + c1 k(dt)) / dt, with k(dt) the iterations that dt needs to bring the
 * average compression down to eta.  This controller lets every step iterate
 * to eta (the solver stops when rho_err_avg <= eta and rho_err_max <=
 * costMaxDensity eta) and steers dt by the iterations it measured: up by
 * costIncreaseFactor while they are below targetIterations, down by
 * costDecreaseFactor while they are above, so dt settles where the steps
 * take targetIterations iterations on average.  The default target is the
 * measured minimum of the wall time per simulated second
 * (doc/timestep-cost.md: a sweep of targetIterations on the benchmark
 * scenes); the controller itself measures no time, so the same case takes
 * the same steps for any thread count and after a restart.
 *
 * Limits: the next step never exceeds increaseVelocity h / vmax (19),
 * increaseForce sqrt(h / Fmax) (16) nor deltaTMax.  Shocks: (25)-(27) as in
 * the paper, and a step whose average compression stayed above eta after
 * maxIterations (or when the divergence guard stopped the iterations): back
 * two steps with dt_new of eq. (24), at most shockMaxRatio dt.  A step
 * whose largest compression stayed above costMaxDensity eta while the
 * average reached eta is kept, and the next is costDecreaseFactor^5 smaller.
 *
 * State: only ts_state (dt and the eq. 25 history), which the restart
 * files and the rollback copies hold.
 */
#include "timestep/timestep.h"

#include <math.h>

static double cap_of(const ts_params *p, double h, const ts_obs *o)
{
    double cap = HUGE_VAL;
    if (o->vmax > 0.0) cap = fmin(cap, p->increase_velocity * h / o->vmax);    /* (19) */
    if (o->fmax > 0.0) cap = fmin(cap, p->increase_force * sqrt(h / o->fmax)); /* (16) */
    if (p->delta_t_max > 0.0) cap = fmin(cap, p->delta_t_max);
    return cap;
}

ts_action ts_cost_decide(const ts_params *p, ts_state *s, double eta_avg, double h, const ts_obs *o,
                         unsigned *c)
{
    const double dt = s->dt;
    if (!(*c & TS_NONFINITE) && o->err_avg > eta_avg) *c |= TS_COST_ABOVE;
    if (*c & (TS_SHOCK_ANY | TS_COST_ABOVE)) {
        s->dt = ts_shock_step(p, dt, h, o, c);
        return TS_SHOCK;
    }
    double next = dt;
    ts_action a = TS_KEEP;
    if (o->err_max > p->cost_max_density * eta_avg) {
        *c |= TS_COST_SHORT;
        next = dt * pow(p->cost_decrease_factor, 5);
        a = TS_DECREASE;
    } else if ((double)o->iterations > p->target_iterations) {
        *c |= TS_COST_MORE;
        next = dt * p->cost_decrease_factor;
        a = TS_DECREASE;
    } else if ((double)o->iterations < p->target_iterations) {
        *c |= TS_COST_FEWER;
        next = dt * p->cost_increase_factor;
        a = TS_INCREASE;
    }
    const double cap = cap_of(p, h, o);
    if (next > cap) {
        *c |= TS_COST_LIMIT;
        next = cap;
        a = next > dt ? TS_INCREASE : next < dt ? TS_DECREASE : TS_KEEP;
    }
    s->dt = next;
    return a;
}
