/*
 * verifyCase: the error of a case against an exact (or accepted analytic)
 * answer, from its written times (doc/verification.md).
 *
 * The answer is named by system/verifyDict:
 *
 *   exact      poiseuille;   // hydrostatic translatingTank poiseuille taylorGreen standingWave
 *   nu         0.01;         // m^2/s: poiseuille, taylorGreen, standingWave (decay)
 *   amplitude  0.05;         // m/s (taylorGreen U) or m (standingWave A)
 *   length     0.2;          // m: taylorGreen period L; standingWave half
 *                            // wavelength L (default the tank's length; a
 *                            // tank periodic along x holds whole wavelengths)
 *   from       0;            // only written times at or after it enter the norm
 *   tolerance  0.05;         // optional: exit 1 when the error is above it
 *
 * Everything else comes from the case: rho0, r0, gravity, the container
 * (the tank's area and the channel's gap), the container's motion (the
 * translating tank's velocity) and the written fluid.vtu files.
 */
#ifndef VC_H
#define VC_H

#include <stddef.h>

#include "case/case.h"
#include "dictionary/dict.h"
#include "functionObjects/fo_post.h"

typedef enum {
    VC_HYDROSTATIC,
    VC_TRANSLATING,
    VC_POISEUILLE,
    VC_TAYLOR_GREEN,
    VC_WAVE,
    VC_KINDS
} vc_kind;

typedef struct vc_setup {
    vc_kind kind;
    double nu, amplitude, length, from, tolerance; /* tolerance < 0: none */
    double rho0, r0, g[3], gmag;
    double support;           /* the kernel's support radius h (m) */
    double lo[3], hi[3];      /* the container's inner walls */
    const mot_motion *motion; /* the container's, or NULL */
    size_t nfluid;
    double depth; /* fluid volume / container area */
} vc_setup;

/* One written time's measures (what the kind defines; unused ones NAN). */
typedef struct vc_sample {
    double t;
    double err;    /* the norm this kind is judged by, at this time */
    double perr;   /* hydrostatic pressure error / (rho0 g H); taylorGreen: the rms of p
                         against rho0 U^2 F^2 (cos 2kx + cos 2ky) / 4, each up to its
                         mean (the periodic box fixes no level), over rho0 U^2 */
    double vrms;   /* rms speed against the exact velocity (m/s) */
    double ke;     /* kinetic energy per unit mass (m^2/s^2) */
    double height; /* the highest particle + r0/2 (m) */
    double grad;   /* hydrostatic: the least-squares slope of p(z) over the particles more
                         than h above the floor and below the highest one, over rho0 g,
                         less 1 (the pressure gradient's error, free of the level) */
    double mode;   /* standingWave: the velocity's projection on the linear mode
                         (m/s; A w cos(w t) for the exact answer); taylorGreen: on
                         the vortex's shape (m/s; U exp(-2 nu k^2 t) exactly) */
} vc_sample;

extern const char *const vc_kind_names[];

/* Read system/verifyDict of case c into s (stops with file, line, key). */
void vc_read(vc_setup *s, const sl_case *c);
/* The measures of one snapshot at time t. */
void vc_measure(const vc_setup *s, const sl_fluid *f, double t, vc_sample *out);
/* The exact Poiseuille velocity (series solution from rest) at height z
 * above the lower plate of a gap d, time t. */
double vc_poiseuille(double g, double nu, double d, double z, double t);
/* The standing wave's linear period 2 pi / sqrt(g k tanh(k H)), k = pi / L. */
double vc_wave_period(double g, double L, double H);
/* The standing wave's half wavelength: verifyDict's length, else the tank's. */
double vc_wave_length(const vc_setup *s);

/* The standing wave's record fitted to A exp(-d t) cos(w t + phi) + c
 * (vc_fit.c): period 2 pi / w and decay d with their one-sigma fit
 * uncertainties, residual rms over A. */
typedef struct vc_wave_fit {
    int ok;
    double period, dperiod; /* s */
    double decay, ddecay;   /* 1/s */
    double amplitude, phase, offset, residual;
    size_t iterations;
} vc_wave_fit;

/* Fit the n samples y(t), seeded with the period period0 (> 0) and the
 * decay rate decay0 (NAN: 0).  Returns 0 when the fit converged, else 1
 * with out->ok 0 and NAN figures. */
int vc_fit_wave(const double *t, const double *y, size_t n, double period0, double decay0,
                vc_wave_fit *out);

#endif
