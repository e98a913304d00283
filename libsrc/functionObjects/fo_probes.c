/*
 * fo_probes: pressure, density and velocity at fixed points, interpolated
 * from fluid and active boundary particles with Shepard normalisation
 * (fo_query.h), so that a point on a wall reads the wall pressure.  A point
 * with no particle within h reads nan.
 *
 *   type probes; fields (pressure density velocity);
 *   probeLocations ((0.5 0.3 0.1) (1.6 0.3 0.05));
 *
 * Columns, field by field as OpenFOAM's probes: pressure_0 pressure_1 ...
 * density_0 ... velocity_0_x velocity_0_y velocity_0_z ...
 */
#include "functionObjects/fo_type.h"

#include "core/sl_log.h"
#include "core/sl_mem.h"

#include <stdlib.h>
#include <string.h>

static const char *const pr_keys[] = {"fields", "probeLocations", NULL};

typedef enum { PR_PRESSURE, PR_DENSITY, PR_VELOCITY, PR_NFIELDS } pr_field;
static const char *const pr_field_names[PR_NFIELDS + 1] = {"pressure", "density", "velocity", NULL};

typedef struct pr_state {
    int field[PR_NFIELDS];
    int nfields;
    double *pts; /* 3 per probe */
    size_t n;
    fo_sample *val; /* one per probe */
} pr_state;

static void *pr_read(const dict *d)
{
    pr_state *st = sl_calloc(1, sizeof *st, "probes");
    sl_err err;
    if (dict_has(d, "fields")) {
        char **w;
        size_t n;
        int seen[PR_NFIELDS] = {0};
        fo_need(dict_get_word_list(d, "fields", &w, &n, &err), &err);
        for (size_t i = 0; i < n; i++) {
            int k = 0;
            while (k < PR_NFIELDS && strcmp(w[i], pr_field_names[k])) k++;
            if (k == PR_NFIELDS) {
                char why[256];
                snprintf(why, sizeof why,
                         "unknown field '%s'; valid fields: pressure density velocity", w[i]);
                dict_free_word_list(w, n);
                fo_bad_key(d, "fields", why);
            }
            if (!seen[k]) st->field[st->nfields++] = k;
            seen[k] = 1;
        }
        dict_free_word_list(w, n);
        if (st->nfields == 0) fo_bad_key(d, "fields", "names no field");
    } else {
        for (int k = 0; k < PR_NFIELDS; k++) st->field[st->nfields++] = k;
    }
    fo_get_points(d, "probeLocations", 3, &st->pts, &st->n);
    st->val = sl_calloc(st->n, sizeof *st->val, "probe values");
    return st;
}

static void pr_header(const void *vs, const pcs_view *s, FILE *f)
{
    const pr_state *st = vs;
    (void)s;
    fprintf(f,
            "# Shepard-normalised SPH interpolation sum_j V_j A_j W / sum_j V_j W, V_j = m_j / "
            "rho_j, over fluid and active boundary particles within h;\n"
            "# nan: no particle within h.  pressure in Pa, density in kg/m^3, velocity in "
            "m/s\n");
    for (size_t i = 0; i < st->n; i++)
        fprintf(f, "# Probe %zu (%.10g %.10g %.10g)\n", i, st->pts[3 * i], st->pts[3 * i + 1],
                st->pts[3 * i + 2]);
}

static void pr_columns(const void *vs, FILE *f)
{
    const pr_state *st = vs;
    for (int k = 0; k < st->nfields; k++)
        for (size_t i = 0; i < st->n; i++) {
            if (st->field[k] == PR_VELOCITY)
                fprintf(f, "\tvelocity_%zu_x\tvelocity_%zu_y\tvelocity_%zu_z", i, i, i);
            else fprintf(f, "\t%s_%zu", pr_field_names[st->field[k]], i);
        }
}

static void pr_execute(void *vs, const fo_call *call)
{
    pr_state *st = vs;
    for (size_t i = 0; i < st->n; i++) {
        const double *x = st->pts + 3 * i;
        fo_query_sample(call->ix, x[0], x[1], x[2], &st->val[i]);
    }
    for (int k = 0; k < st->nfields; k++)
        for (size_t i = 0; i < st->n; i++) {
            const fo_sample *v = &st->val[i];
            switch ((pr_field)st->field[k]) {
            case PR_PRESSURE:
                fo_put(call->dat, v->pressure);
                break;
            case PR_DENSITY:
                fo_put(call->dat, v->density);
                break;
            case PR_VELOCITY:
            case PR_NFIELDS:
                for (int c = 0; c < 3; c++) fo_put(call->dat, v->velocity[c]);
                break;
            }
        }
}

static void pr_free(void *vs)
{
    pr_state *st = vs;
    if (!st) return;
    free(st->pts);
    free(st->val);
    free(st);
}

/* Point queries at the probes only: a box of each point. */
static size_t pr_region(const void *vs, double *box, size_t max)
{
    const pr_state *st = vs;
    for (size_t i = 0; i < st->n && i < max; i++)
        for (int k = 0; k < 6; k++) box[6 * i + k] = st->pts[3 * i + k % 3];
    return st->n;
}

const fo_type fo_type_probes = {
    .name = "probes",
    .keys = pr_keys,
    .needs = FO_NEED_BOUNDARY | FO_NEED_GRID,
    .read = pr_read,
    .header = pr_header,
    .columns = pr_columns,
    .execute = pr_execute,
    .at_write = NULL,
    .free = pr_free,
    .region = pr_region,
};
