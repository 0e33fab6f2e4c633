/* A plan's pressures against the finite-element reference (cli_fidelity.h). */
#include "cli/cli_fidelity.h"

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
    if (!hpi_fidelity_answered(r->status)) {
        snprintf(e->not_measured, sizeof e->not_measured, "plan %s", hp_status_name(r->status));
        return;
    }
    hpi_fidelity_ref ref;
    hp_error err = hpi_fidelity_open(&sc->layout, &spec, CLI_FIDELITY_LAW_BAND, &ref);
    if (err == HP_OK) {
        double P[HP_MAX_BLADDERS];
        for (int k = 0; k < r->n; ++k) P[k] = r->bladders[k].pressure;
        hpi_fidelity_measure(&ref, P, r->achieved, &e->m);
    } else {
        snprintf(e->not_measured, sizeof e->not_measured, "no load model: %s",
                 hp_error_message(err));
    }
    hpi_fidelity_close(&ref);
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
    const hpi_fidelity_result *m = &e->m;
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
