/* The load level through hp_planner for the load tests: a planner at HP_LEVEL_LOAD carrying
 * spec, with settings s (NULL = defaults) whose level names the load level's contact
 * geometry (auto: surface), and tie-breaker tie; and a plan with the load level's details
 * (hp_planner_load_info) when info is not NULL. */
#ifndef TESTS_PLANNER_LOAD_FIXTURE_H
#define TESTS_PLANNER_LOAD_FIXTURE_H

#include "headplan/hp_planner.h"
#include "support/layout_fixture.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static inline hp_error load_create(const hp_layout *L, const hp_load_spec *spec,
                                   const hp_settings *s, hp_load_tiebreak tie, hp_planner **out,
                                   hp_diag *d)
{
    hp_settings set;
    if (s) set = *s;
    else {
        hp_settings_default(&set);
        set.max_time = 60.0; /* outcomes must not depend on the machine's speed */
    }
    set.load_geometry = set.level == HP_LEVEL_AUTO ? HP_LEVEL_SURFACE : set.level;
    set.level = HP_LEVEL_LOAD;
    set.load = *spec;
    set.load_tiebreak = tie;
    return hp_planner_create(L, &set, out, d);
}

static inline hp_error load_plan(hp_planner *p, const double desired[6], hp_result *r,
                                 hp_load_info *info)
{
    hp_error e = hp_plan(p, desired, r);
    if (e == HP_OK && info) e = hp_planner_load_info(p, info);
    return e;
}

/* The load the tests built on support/layout_fixture.h's default layout carry at the load
 * level: 20 % of the default head's weight along -Z (8.8 N; the neck rest carries the rest),
 * which that layout (stretch_max 1.3) holds; tests/reliability carries the same. */
#define LOAD_LF_FRACTION 0.2

/* A planner on layout_fixture.h's default layout (lf_layout)
 * with backend b at any level, every rate_max = rate [Pa]; at the load level carrying
 * LOAD_LF_FRACTION of the head's weight at the surface geometry. Returns NULL, the message
 * printed, when create fails, and NULL silently when b does not plan the load level and
 * create refuses it by name (*refused = 1 then; may be NULL). */
static inline hp_planner *load_lf_planner(hp_backend b, hp_level level, double rate, int *refused)
{
    if (refused) *refused = 0;
    hp_layout L;
    if (lf_layout(&L) != HP_OK) return NULL;
    for (int k = 0; k < L.n; ++k) L.bladders[k].rate_max = rate;
    hp_settings s;
    hp_settings_default(&s);
    s.max_time = 60.0; /* outcomes must not depend on the machine's speed */
    s.backend = b;
    s.level = level;
    hp_planner *p = NULL;
    hp_diag d = {{0}};
    hp_error e;
    if (level == HP_LEVEL_LOAD) {
        hp_load_spec spec;
        hp_load_spec_default(&L.head, &spec);
        spec.law = HP_LOAD_LAW_CAP; /* the default bladders carry the head under the cap law only */
        spec.mass *= LOAD_LF_FRACTION;
        s.level = HP_LEVEL_SURFACE;
        e = load_create(&L, &spec, &s, HP_TIE_LEAST_SQUEEZE, &p, &d);
        if (e == HP_ERR_INVALID && strstr(d.text, "not available at the load level")) {
            if (refused) *refused = 1;
            return NULL;
        }
    } else {
        e = hp_planner_create(&L, &s, &p, &d);
    }
    if (e != HP_OK)
        fprintf(stderr, "create %s/%s: %s\n", hp_backend_name(b), hp_level_name(level), d.text);
    return p;
}

/* The largest |Q_i| (N on the force rows, N·m on the moment rows) an answer held at its pose
 * may leave: the planner accepts 1e-9 N on the force rows (5.7e-11 N·m/rad on the moment
 * rows); 10x that, far below the ~1 N/mm x 1e-6 mm a visible pose change would take. */
#define LOAD_Q_TOL 1e-8

/* The forward model's verdict on a load-level answer r to `desired` of planner p, written
 * from hp_load_eval alone: an answer (REACHED, CLOSEST) holds the head at its achieved pose
 * (the generalized force of the returned pressures there within LOAD_Q_TOL), and a REACHED
 * one holds it at the desired pose itself (the achieved pose is the desired one, bit for
 * bit). Other statuses pass (the safe output is checked where it is the subject). Returns 1
 * when confirmed, else 0 with the reason in why. */
static inline int load_confirms(const hp_planner *p, const double desired[6], const hp_result *r,
                                char *why, size_t len)
{
    if (r->status != HP_STATUS_REACHED && r->status != HP_STATUS_CLOSEST) return 1;
    if (r->status == HP_STATUS_REACHED)
        for (int i = 0; i < 6; ++i)
            if (memcmp(&r->achieved[i], &desired[i], sizeof(double)) != 0) {
                snprintf(why, len, "reached, achieved[%d] %.17g is not desired %.17g", i,
                         r->achieved[i], desired[i]);
                return 0;
            }
    double P[HP_MAX_BLADDERS], Q[6];
    for (int k = 0; k < r->n; ++k) P[k] = r->bladders[k].pressure;
    if (hp_load_eval(hp_planner_load_model(p), r->achieved, P, Q, NULL, NULL, NULL, NULL) !=
        HP_OK) {
        snprintf(why, len, "%s, the load model cannot evaluate the answer",
                 hp_status_name(r->status));
        return 0;
    }
    for (int i = 0; i < 6; ++i)
        if (!(fabs(Q[i]) <= LOAD_Q_TOL)) {
            snprintf(why, len, "%s, not held at its pose: Q[%d] = %.3g", hp_status_name(r->status),
                     i, Q[i]);
            return 0;
        }
    return 1;
}

#endif
