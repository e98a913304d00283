/*
 * verifyCase: the standing wave's period and decay from a least-squares
 * fit of the whole record (doc/verification.md, "The standing wave's
 * period from the whole record").
 *
 * The velocity's projection on the linear mode at every written time is
 * fitted to a damped cosine with an offset,
 *
 *   y(t) = exp(-d t) (a cos(w t) + b sin(w t)) + c
 *        = A exp(-d t) cos(w t + phi) + c,   A = hypot(a, b),
 *
 * by GSL's trust-region Levenberg-Marquardt (gsl_multifit_nlinear), seeded
 * from the zero crossings' period and the extremes' decay rate with a, b,
 * c from the linear least squares at that w and d.  The amplitude is
 * written as (a, b) rather than (A, phi) so that no phase wraps.  The
 * uncertainties are the fit's one-sigma ones: the covariance (J^T J)^-1
 * scaled by the residual variance chi^2 / (n - 5).  They assume
 * independent residuals, which a record of written times with higher
 * modes in it is not, so they are a lower bound on the measure's spread.
 */
#include "vc.h"

#include <math.h>

#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_multifit_nlinear.h>

enum { PA, PB, PW, PD, PC, NP };

typedef struct {
    const double *t, *y;
    size_t n;
} fit_data;

static int model_f(const gsl_vector *p, void *arg, gsl_vector *r)
{
    const fit_data *d = arg;
    const double a = gsl_vector_get(p, PA), b = gsl_vector_get(p, PB), w = gsl_vector_get(p, PW),
                 k = gsl_vector_get(p, PD), c = gsl_vector_get(p, PC);
    for (size_t i = 0; i < d->n; i++) {
        const double t = d->t[i], e = exp(-k * t);
        gsl_vector_set(r, i, e * (a * cos(w * t) + b * sin(w * t)) + c - d->y[i]);
    }
    return GSL_SUCCESS;
}

static int model_df(const gsl_vector *p, void *arg, gsl_matrix *J)
{
    const fit_data *d = arg;
    const double a = gsl_vector_get(p, PA), b = gsl_vector_get(p, PB), w = gsl_vector_get(p, PW),
                 k = gsl_vector_get(p, PD);
    for (size_t i = 0; i < d->n; i++) {
        const double t = d->t[i], e = exp(-k * t), cw = cos(w * t), sw = sin(w * t);
        gsl_matrix_set(J, i, PA, e * cw);
        gsl_matrix_set(J, i, PB, e * sw);
        gsl_matrix_set(J, i, PW, e * t * (b * cw - a * sw));
        gsl_matrix_set(J, i, PD, -t * e * (a * cw + b * sw));
        gsl_matrix_set(J, i, PC, 1.0);
    }
    return GSL_SUCCESS;
}

/* a, b, c of the linear least squares at fixed w and k (the seed). */
static int linear_seed(const fit_data *d, double w, double k, double abc[3])
{
    gsl_matrix *X = gsl_matrix_alloc(d->n, 3), *V = gsl_matrix_alloc(3, 3);
    gsl_vector *S = gsl_vector_alloc(3), *wk = gsl_vector_alloc(3), *x = gsl_vector_alloc(3);
    gsl_vector_const_view y = gsl_vector_const_view_array(d->y, d->n);
    for (size_t i = 0; i < d->n; i++) {
        const double t = d->t[i], e = exp(-k * t);
        gsl_matrix_set(X, i, 0, e * cos(w * t));
        gsl_matrix_set(X, i, 1, e * sin(w * t));
        gsl_matrix_set(X, i, 2, 1.0);
    }
    int st = gsl_linalg_SV_decomp(X, V, S, wk);
    if (!st) st = gsl_linalg_SV_solve(X, V, S, &y.vector, x);
    for (int j = 0; j < 3; j++) abc[j] = gsl_vector_get(x, (size_t)j);
    gsl_matrix_free(X);
    gsl_matrix_free(V);
    gsl_vector_free(S);
    gsl_vector_free(wk);
    gsl_vector_free(x);
    return st;
}

int vc_fit_wave(const double *t, const double *y, size_t n, double period0, double decay0,
                vc_wave_fit *out)
{
    const double pi = 3.14159265358979323846;
    fit_data d = {t, y, n};
    out->ok = 0;
    out->period = out->dperiod = out->decay = out->ddecay = NAN;
    out->amplitude = out->phase = out->offset = out->residual = NAN;
    out->iterations = 0;
    if (n < 2 * NP || !(period0 > 0.0)) return 1;
    const double w0 = 2.0 * pi / period0, k0 = isfinite(decay0) ? decay0 : 0.0;
    double abc[3];
    gsl_error_handler_t *old = gsl_set_error_handler_off();
    int st = linear_seed(&d, w0, k0, abc);
    gsl_multifit_nlinear_parameters prm = gsl_multifit_nlinear_default_parameters();
    gsl_multifit_nlinear_workspace *ws =
        gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &prm, n, NP);
    gsl_multifit_nlinear_fdf fdf = {
        .f = model_f, .df = model_df, .fvv = NULL, .n = n, .p = NP, .params = &d};
    double p0[NP] = {[PA] = abc[0], [PB] = abc[1], [PW] = w0, [PD] = k0, [PC] = abc[2]};
    gsl_vector_view x0 = gsl_vector_view_array(p0, NP);
    int info = 0;
    if (!st) st = gsl_multifit_nlinear_init(&x0.vector, &fdf, ws);
    if (!st) st = gsl_multifit_nlinear_driver(200, 1e-12, 1e-12, 1e-12, NULL, NULL, &info, ws);
    if (!st) {
        const gsl_vector *p = gsl_multifit_nlinear_position(ws);
        gsl_matrix *cov = gsl_matrix_alloc(NP, NP);
        double chi2;
        gsl_blas_ddot(gsl_multifit_nlinear_residual(ws), gsl_multifit_nlinear_residual(ws), &chi2);
        st = gsl_multifit_nlinear_covar(gsl_multifit_nlinear_jac(ws), 0.0, cov);
        const double s2 = chi2 / (double)(n - NP), a = gsl_vector_get(p, PA),
                     b = gsl_vector_get(p, PB), w = gsl_vector_get(p, PW);
        out->period = 2.0 * pi / w;
        out->dperiod = 2.0 * pi / (w * w) * sqrt(s2 * gsl_matrix_get(cov, PW, PW));
        out->decay = gsl_vector_get(p, PD);
        out->ddecay = sqrt(s2 * gsl_matrix_get(cov, PD, PD));
        out->amplitude = hypot(a, b);
        out->phase = atan2(-b, a);
        out->offset = gsl_vector_get(p, PC);
        out->residual =
            out->amplitude > 0.0 ? sqrt(chi2 / (double)n) / out->amplitude : (double)NAN;
        out->iterations = gsl_multifit_nlinear_niter(ws);
        out->ok = !st && w > 0.0 && isfinite(out->dperiod);
        gsl_matrix_free(cov);
    }
    gsl_multifit_nlinear_free(ws);
    gsl_set_error_handler(old);
    return !out->ok;
}
