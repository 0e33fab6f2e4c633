/* Test fixture for the planner core: the default adult head and the paper's eight-bladder
 * layout, built here from the kinematics API (not from a scene file).
 *
 * Head: ellipsoid 77.5 (X) × 115 (Y) × 97.5 (Z) mm semi-axes at the origin, pivot at the
 * origin (or a sphere of radius 90 mm, for the translation-only case). Bladders: Ri 27 mm,
 * Ro 30 mm, C1 1.1e4 Pa, C2 2.2e4 Pa, pressure −5..+10 kPa, stretch 0.8..1.3, no rate limit,
 * placed by the surface point they touch (hp_head_center_from_touch, no preload):
 *   base, on the −Z back:  base_neck_left ( 25, −40, z)   base_neck_right (−25, −40, z)
 *                          base_skull_left( 25,  40, z)   base_skull_right(−25,  40, z)
 *   side, on ±X:           side_fore_left ( x,  50, −10)  side_fore_right (−x,  50, −10)
 *                          side_chin_left ( x, −50, −10)  side_chin_right (−x, −50, −10)
 * (mm; the missing coordinate on the surface; left = +X). For a sphere the same points are
 * scaled onto it. */
#ifndef HP_TEST_PLANNER_LAYOUT_FIXTURE_H
#define HP_TEST_PLANNER_LAYOUT_FIXTURE_H

#include "headplan/hp_contact.h"
#include "headplan/hp_planner.h"
#include "support/rng.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

static const char *const lf_names[8] = {"base_neck_left",   "base_neck_right", "base_skull_left",
                                        "base_skull_right", "side_fore_left",  "side_fore_right",
                                        "side_chin_left",   "side_chin_right"};

/* Builds (and prepares) the default layout on an ellipsoid (sphere = 0) or on a sphere of
 * radius 90 mm (sphere = 1). C2 is the second modulus [Pa]. Returns HP_OK or the error. */
static inline hp_error lf_layout_ex(hp_layout *L, int sphere, double C2)
{
    memset(L, 0, sizeof *L);
    const double def[3] = {HP_HEAD_DEFAULT_A, HP_HEAD_DEFAULT_B, HP_HEAD_DEFAULT_C};
    L->head.shape = sphere ? HP_HEAD_SPHERE : HP_HEAD_ELLIPSOID;
    for (int i = 0; i < 3; ++i) L->head.semi_axes[i] = sphere ? 0.090 : def[i];
    L->head.mass = HP_HEAD_DEFAULT_MASS;
    L->n = 8;
    static const double base[4][2] = {{25, -40}, {-25, -40}, {25, 40}, {-25, 40}};
    static const double side[4][3] = {{50, -10, 1}, {50, -10, -1}, {-50, -10, 1}, {-50, -10, -1}};
    for (int k = 0; k < 8; ++k) {
        double u[3]; /* point on the unit sphere of the head's own axes */
        if (k < 4) {
            u[0] = base[k][0] / (def[0] * 1e3);
            u[1] = base[k][1] / (def[1] * 1e3);
            u[2] = -sqrt(1.0 - u[0] * u[0] - u[1] * u[1]);
        } else {
            u[1] = side[k - 4][0] / (def[1] * 1e3);
            u[2] = side[k - 4][1] / (def[2] * 1e3);
            u[0] = side[k - 4][2] * sqrt(1.0 - u[1] * u[1] - u[2] * u[2]);
        }
        double p[3];
        for (int i = 0; i < 3; ++i) p[i] = u[i] * L->head.semi_axes[i];
        hp_bladder *B = &L->bladders[k];
        snprintf(B->name, sizeof B->name, "%s", lf_names[k]);
        B->iab.Ri = 0.027;
        B->iab.Ro = 0.030;
        B->iab.C1 = 1.1e4;
        B->iab.C2 = C2;
        B->p_min = -5e3;
        B->p_max = 10e3;
        B->stretch_min = 0.8;
        B->stretch_max = 1.3;
        B->rate_max = INFINITY;
        hp_error e = hp_head_center_from_touch(&L->head, p, B->iab.Ro, 0.0, B->center, NULL);
        if (e != HP_OK) return e;
    }
    return hp_layout_prepare(L, NULL);
}

static inline hp_error lf_layout(hp_layout *L) { return lf_layout_ex(L, 0, 2.2e4); }

/* A planner on the default layout with backend b and default settings at a level, every
 * bladder's rate_max set (INFINITY: none). Returns HP_OK or the error (*p NULL). */
/* A planner on the fixture layout with every bladder's rate_max and settings s. */
static inline hp_error lf_planner_settings(const hp_settings *s, double rate_max, hp_planner **p)
{
    hp_layout L;
    hp_error e = lf_layout(&L);
    *p = NULL;
    if (e != HP_OK) return e;
    for (int k = 0; k < L.n; ++k) L.bladders[k].rate_max = rate_max;
    return hp_planner_create(&L, s, p, NULL);
}

static inline hp_error lf_planner_backend(hp_backend b, hp_level level, double rate_max,
                                          hp_planner **p)
{
    hp_settings s;
    hp_settings_default(&s);
    s.max_time = 60.0; /* outcomes must not depend on the machine's speed */
    s.backend = b;
    s.level = level;
    return lf_planner_settings(&s, rate_max, p);
}

/* The same with the default backend. */
static inline hp_error lf_planner(hp_level level, double rate_max, hp_planner **p)
{
    hp_settings s;
    hp_settings_default(&s);
    return lf_planner_backend(s.backend, level, rate_max, p);
}

/* A planner on layout L with backend b at a level, default settings otherwise and a time
 * budget of 60 s, so that no outcome depends on the machine's speed. NULL (the message
 * printed) when create fails. */
static inline hp_planner *lf_planner_on(const hp_layout *L, hp_backend b, hp_level level)
{
    hp_settings s;
    hp_settings_default(&s);
    s.backend = b;
    s.level = level;
    s.max_time = 60.0;
    hp_planner *p = NULL;
    hp_diag d = {{0}};
    if (hp_planner_create(L, &s, &p, &d) != HP_OK) fprintf(stderr, "create: %s\n", d.text);
    return p;
}

/* The default layout in neo-Hookean rubber (C2 = 0, which has an inflation limit point) with
 * every stretch_max just below the limit point (closer than the planner's stable margin)
 * and p_max = p_max_factor × the peak pressure, so that the planner's stable-branch cap is
 * the binding upper limit. lp receives the limit point. */
static inline hp_error lf_soft_layout(hp_layout *L, double p_max_factor, hp_iab_limit *lp)
{
    hp_error e = lf_layout_ex(L, 0, 0.0);
    if (e == HP_OK) e = hp_iab_limit_point(&L->bladders[0].iab, lp);
    if (e != HP_OK) return e;
    if (!lp->exists) return HP_ERR_DOMAIN;
    for (int k = 0; k < L->n; ++k) {
        L->bladders[k].stretch_max = lp->lambda_i * (1.0 - 1e-6);
        L->bladders[k].p_max = p_max_factor * lp->pressure;
    }
    return hp_layout_prepare(L, NULL);
}

/* Uniform in [−1, 1). */
static inline double lf_uniform(uint64_t *s) { return test_rng_uniform(s, -1.0, 1.0); }

/* A correction in clinical units (mm, deg) -> SI. */
static inline void lf_pose(const double mm_deg[6], double xi[6])
{
    for (int i = 0; i < 3; ++i) {
        xi[i] = mm_deg[i] * 1e-3;
        xi[i + 3] = mm_deg[i + 3] * (3.14159265358979323846 / 180.0);
    }
}

/* The round trip a user would run: returned pressures -> hp_iab_fk radii -> hp_iab_ro ->
 * hp_contact_fk at level -> pose (SI). Returns HP_OK or the first error. */
static inline hp_error lf_round_trip(const hp_layout *L, hp_level level, const hp_result *r,
                                     double xi[6])
{
    double ro[HP_MAX_BLADDERS];
    for (int k = 0; k < L->n; ++k) {
        double ri;
        hp_error e = hp_iab_fk(&L->bladders[k].iab, r->bladders[k].pressure, &ri);
        if (e != HP_OK) return e;
        e = hp_iab_ro(&L->bladders[k].iab, ri, &ro[k]);
        if (e != HP_OK) return e;
    }
    /* From the nominal pose (xi0 NULL), as a user checks a plan: started at the answer
     * itself, the fit could not show a second pose with the same distances. */
    double resid;
    return hp_contact_fk(L, level, ro, NULL, xi, &resid, NULL);
}

#endif
