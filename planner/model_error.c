/* A plan's pressures against the finite-element reference (model_error.h). */
#include "planner/model_error.h"
#include "common/units.h"
#include "kinematics/load_law_pick.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

hp_error hpi_fidelity_open(const hp_layout *L, const hp_load_spec *spec, double band,
                           hpi_fidelity_ref *r)
{
    const double scale[3] = {1.0, 1.0 + band, 1.0 - band};
    memset(r, 0, sizeof *r);
    if (!(band >= 0.0 && band < 0.5)) return HP_ERR_INVALID;
    r->n = band > 0.0 ? 3 : 1;
    for (int i = 0; i < r->n; ++i) {
        hp_load_spec s = *spec;
        s.mass /= scale[i];
        hp_error e = hp_load_model_create(L, &s, HP_LEVEL_SURFACE, &r->M[i], NULL);
        if (!e) e = hpi_load_model_set_law(r->M[i], HP_CLAW_LAW_FEM);
        if (e) return e;
    }
    return HP_OK;
}

void hpi_fidelity_close(hpi_fidelity_ref *r)
{
    for (int i = 0; i < 3; ++i) hp_load_model_destroy(r->M[i]);
    memset(r, 0, sizeof *r);
}

/* The angle [deg] of the rotation between two poses' orientations: 2·asin(|Ra − Rb|_F /
 * (2·sqrt 2)), well conditioned at small angles where acos of the trace is not. */
static double rotation_between_deg(const double a[6], const double b[6])
{
    double Ra[9], Rb[9], s = 0.0;
    hp_rotation(a[3], a[4], a[5], Ra);
    hp_rotation(b[3], b[4], b[5], Rb);
    for (int i = 0; i < 9; ++i) s += (Ra[i] - Rb[i]) * (Ra[i] - Rb[i]);
    return 2.0 * asin(fmin(1.0, sqrt(s) / (2.0 * sqrt(2.0)))) * 180.0 / HP_PI;
}

double hpi_pose_translation_mm(const double a[6], const double b[6])
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2])) *
           1e3;
}

/* The share of the weight the bladders' forces bear along gravity at pose xi: Q's
 * translation rows are sum f + m·g (hp_load.h), so sum f = Q − m·g. NaN when M cannot
 * evaluate there. */
static double carried_fraction(const hp_load_model *M, const double *P, const double xi[6])
{
    double Q[6];
    if (hp_load_eval(M, xi, P, Q, NULL, NULL, NULL, NULL) != HP_OK) return NAN;
    const hp_load_spec *s = hp_load_model_spec(M);
    double g2 = 0.0, fg = 0.0;
    for (int i = 0; i < 3; ++i) {
        g2 += s->gravity[i] * s->gravity[i];
        fg += (Q[i] - s->mass * s->gravity[i]) * s->gravity[i];
    }
    return -fg / (s->mass * g2);
}

void hpi_fidelity_measure(const hpi_fidelity_ref *r, const double *P, const double xi[6],
                          hpi_fidelity_result *c)
{
    double rest[6];
    hp_load_rest_info info;
    c->pose_mm = c->pose_deg = c->band_mm = c->band_deg = INFINITY;
    c->indent_max = NAN;
    c->carried = carried_fraction(r->M[0], P, xi);
    snprintf(c->domain, sizeof c->domain, "no rest");
    if (hp_load_rest(r->M[0], P, xi, rest, &info) != HP_OK) return;
    c->pose_mm = c->band_mm = hpi_pose_translation_mm(rest, xi);
    c->pose_deg = c->band_deg = rotation_between_deg(rest, xi);
    c->indent_max = info.indent_max;
    int k;
    hp_claw_domain g;
    if (hpi_load_fem_domain_at(r->M[0], rest, P, &k, &g) != HP_OK)
        snprintf(c->domain, sizeof c->domain, "unknown");
    else if (k < 0) snprintf(c->domain, sizeof c->domain, "in");
    else
        snprintf(c->domain, sizeof c->domain, "%s:%s",
                 hp_load_model_layout(r->M[0])->bladders[k].name, hpi_claw_domain_name(g));
    for (int i = 1; i < r->n; ++i) {
        double r2[6];
        if (hp_load_rest(r->M[i], P, xi, r2, NULL) != HP_OK) {
            c->band_mm = c->band_deg = INFINITY;
            return;
        }
        c->band_mm = fmax(c->band_mm, hpi_pose_translation_mm(r2, xi));
        c->band_deg = fmax(c->band_deg, rotation_between_deg(r2, xi));
    }
}

int hpi_fidelity_answered(hp_status status)
{
    return status == HP_STATUS_REACHED || status == HP_STATUS_CLOSEST ||
           status == HP_STATUS_UNCOMMANDED;
}
