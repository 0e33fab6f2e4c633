/* A plan's pressures against the finite-element reference (cli_fidelity.h). */
#include "cli/cli_fidelity.h"
#include "common/units.h"
#include "kinematics/load_law_pick.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

int cli_fidelity_spec(const hp_scene *sc, hp_load_spec *spec)
{
    if (sc->has_load) {
        *spec = sc->load;
        return 1;
    }
    hp_head h = sc->layout.head; /* a head that states no mass weighs the default's */
    if (!(h.mass > 0)) h.mass = HP_HEAD_DEFAULT_MASS;
    hp_load_spec_default(&h, spec);
    return 0;
}

hp_error cli_fidelity_open(const hp_layout *L, const hp_load_spec *spec, double band,
                           cli_fidelity_ref *r)
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

void cli_fidelity_close(cli_fidelity_ref *r)
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

double cli_fidelity_translation_mm(const double a[6], const double b[6])
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

void cli_fidelity_measure(const cli_fidelity_ref *r, const double *P, const double xi[6],
                          cli_fidelity_result *c)
{
    double rest[6];
    hp_load_rest_info info;
    c->pose_mm = c->pose_deg = c->band_mm = c->band_deg = INFINITY;
    c->indent_max = NAN;
    c->carried = carried_fraction(r->M[0], P, xi);
    snprintf(c->domain, sizeof c->domain, "no rest");
    if (hp_load_rest(r->M[0], P, xi, rest, &info) != HP_OK) return;
    c->pose_mm = c->band_mm = cli_fidelity_translation_mm(rest, xi);
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
        c->band_mm = fmax(c->band_mm, cli_fidelity_translation_mm(r2, xi));
        c->band_deg = fmax(c->band_deg, rotation_between_deg(r2, xi));
    }
}

int cli_fidelity_answered(hp_status status)
{
    return status == HP_STATUS_REACHED || status == HP_STATUS_CLOSEST ||
           status == HP_STATUS_UNCOMMANDED;
}

void cli_fidelity_settings(const hp_scene *sc, const hp_settings *base, hp_level level,
                           const hp_load_spec *spec, hp_settings *s)
{
    *s = *base;
    s->level = level;
    s->use_rate_limits = 0;
    s->warm_start = 0;
    if (level == HP_LEVEL_LOAD) {
        s->load = *spec;
        if (!sc->has_load) s->load_geometry = HP_LEVEL_SURFACE;
    } else {
        memset(&s->load, 0, sizeof s->load); /* the kinematic levels leave the weight out */
    }
}

void cli_model_error_of(const hp_scene *sc, const hp_result *r, hp_level level, double tol,
                        cli_model_error *e)
{
    hp_load_spec spec;
    memset(e, 0, sizeof *e);
    e->level = level;
    e->tolerance = tol;
    e->own_mass = cli_fidelity_spec(sc, &spec);
    e->mass = spec.mass;
    e->m.pose_mm = e->m.pose_deg = e->m.band_mm = e->m.band_deg = NAN;
    e->m.indent_max = e->m.carried = NAN;
    snprintf(e->m.domain, sizeof e->m.domain, "-");
    if (!cli_fidelity_answered(r->status)) {
        snprintf(e->not_measured, sizeof e->not_measured, "plan %s", hp_status_name(r->status));
        return;
    }
    cli_fidelity_ref ref;
    hp_error err = cli_fidelity_open(&sc->layout, &spec, CLI_FIDELITY_LAW_BAND, &ref);
    if (err == HP_OK) {
        double P[HP_MAX_BLADDERS];
        for (int k = 0; k < r->n; ++k) P[k] = r->bladders[k].pressure;
        cli_fidelity_measure(&ref, P, r->achieved, &e->m);
    } else {
        snprintf(e->not_measured, sizeof e->not_measured, "no load model: %s",
                 hp_error_message(err));
    }
    cli_fidelity_close(&ref);
}

void cli_model_error_text(const cli_model_error *e, char *buf, size_t len)
{
    const char *lv = hp_level_name(e->level);
    if (*e->not_measured) {
        snprintf(buf, len, "level %s: not measured: %s", lv, e->not_measured);
        return;
    }
    char head[96] = "", band[128];
    if (!e->own_mass)
        snprintf(head, sizeof head, " (default head: %.3g kg at its centre, supine)", e->mass);
    const cli_fidelity_result *m = &e->m;
    if (isfinite(m->band_mm))
        snprintf(band, sizeof band, "up to %.4g mm, %.4g deg", m->band_mm, m->band_deg);
    else snprintf(band, sizeof band, "unbounded");
    const int in = strcmp(m->domain, "in") == 0;
    if (isfinite(m->pose_mm))
        snprintf(buf, len,
                 "level %s: %.4g mm, %.4g deg against the fitted law, %s with its ±%.3g %% band "
                 "(rest %s%s)%s; solver tolerance %g mm and deg",
                 lv, m->pose_mm, m->pose_deg, band, 100.0 * CLI_FIDELITY_LAW_BAND,
                 in ? "in its domain" : "outside its domain: ", in ? "" : m->domain, head,
                 e->tolerance);
    else
        snprintf(buf, len,
                 "level %s: unbounded (no rest under the fitted law; the pressures bear %.0f %% "
                 "of the weight at the planned pose)%s; solver tolerance %g mm and deg",
                 lv, 100.0 * m->carried + 0.0, head, e->tolerance);
}

void cli_fidelity_text(const hp_scene *sc, hp_level level, char *buf, size_t len)
{
    hp_settings base, s;
    hp_load_spec spec;
    hp_diag d = {{0}};
    cli_fidelity_spec(sc, &spec);
    if (hp_scene_settings(sc, &base, &d) != HP_OK) {
        snprintf(buf, len, "level %s: not measured (settings: %s)", hp_level_name(level), d.text);
        return;
    }
    cli_fidelity_settings(sc, &base, level, &spec, &s);
    const double zero[6] = {0};
    const double *want = sc->has_correction ? sc->correction : zero;
    hp_planner *p = NULL;
    hp_result r;
    hp_error e = hp_planner_create(&sc->layout, &s, &p, &d);
    if (e) {
        snprintf(buf, len, "level %s: not planned (%s)", hp_level_name(level), d.text);
        return;
    }
    e = hp_plan(p, want, &r);
    hp_planner_destroy(p);
    if (e) {
        snprintf(buf, len, "level %s: not planned (%s)", hp_level_name(level), hp_error_message(e));
        return;
    }
    cli_model_error me;
    cli_model_error_of(sc, &r, level, s.tolerance, &me);
    cli_model_error_text(&me, buf, len);
}
