/*
 * motion: prescribed rigid motion of boundary bodies (the movingBoundary
 * effect; the paper's wave generator, Sec. 4.3).
 *
 * A body with a `motion { }` sub-dictionary moves rigidly: at time t its
 * particles are at R(t) (x0 - c) + c + d(t), with normals R(t) n0, where
 * x0 is the position sampled at rest, c the centre of rotation, d(t) the
 * displacement and R(t) a rotation by angle(t) about a fixed axis.  Types:
 *
 *   cosine       wave generator: velocity v(t) = peakVelocity cos(2 pi t/period),
 *                so d(t) = peakVelocity period / (2 pi) sin(2 pi t / period)
 *   oscillating  rotation angle(t) = amplitude sin(2 pi t / period) (degrees)
 *                about `axis` through `centre` (a rocking tank or flap)
 *   table        "file": columns t dx dy dz angle (degrees, about axis
 *                through centre), interpolated with GSL cubic splines (akima
 *                when there are at least 5 rows); outside the table the first
 *                or last row holds
 *
 * Wall velocities are the time derivatives of the same formulas (the
 * splines' derivatives for tables); they enter the collision response
 * (relative velocity) and the viscosity.
 */
#ifndef SL_MOTION_H
#define SL_MOTION_H

#include <gsl/gsl_spline.h>

#include "core/sl_log.h"
#include "dictionary/dict.h"
#include "particles/particles.h"

typedef enum { MOT_NONE, MOT_COSINE, MOT_OSCILLATING, MOT_TABLE } mot_type;

typedef struct mot_motion {
    mot_type type;
    double peak_velocity[3], period, amplitude; /* cosine, oscillating */
    double axis[3], centre[3];                  /* rotations (unit axis) */
    /* table */
    size_t nrows;
    double *t, *col[4]; /* dx dy dz angle */
    gsl_spline *spline[4];
    gsl_interp_accel *acc[4];
} mot_motion;

/* Read a body's motion { } dictionary (file names are relative to the case
 * folder); exits with "<file>:<line>: keyword ...: why" on bad input. */
void mot_read(mot_motion *m, const dict *d, const char *case_dir);
void mot_free(mot_motion *m);

/* Whether the motion is a translation that keeps the coordinates along
 * `axes` (bit d: axis d) fixed: no rotation, no displacement along them
 * (the periodic images of such a body stay its exact images, within a
 * rounding: -parallel's domain mode, solver/pcs_domain.h). */
int mot_translates_across(const mot_motion *m, unsigned axes);

/* Displacement d(t), rotation angle (radians) and their rates. */
void mot_eval(const mot_motion *m, double t, double d[3], double *angle, double v[3],
              double *omega);

/* Move the particles of body `body` to time t and set their velocities. */
void mot_apply(const mot_motion *m, uint32_t body, double t, sl_boundary *b);

#endif
