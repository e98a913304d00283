/*
 * case_step: the first time step of a case, from its physics: the
 * controller's estimate (timestep/: CFL on the initial speeds and
 * emitters, free fall over the fluid's height), and, in adaptive mode
 * without a given deltaT, the step that holds the hydrostatic pressure of
 * the fluid column with the controller's iterations at eta / 2 when that
 * is smaller.  Stops with a message naming timeStepDict when no step can
 * be estimated (fluid at rest, no gravity).
 */
#ifndef SL_CASE_STEP_H
#define SL_CASE_STEP_H

#include <stddef.h>

#include "case/case.h"

/* The first step; `rule` says which estimate gave it. */
double case_initial_step(const sl_case *c, char *rule, size_t len);

#endif
