/* The seeded draws of the reliability sweeps (test_sweep.c, test_best_local.c): a random
 * layout of the kinds the control stack meets, a random correction inside the identifiable
 * range, and the distance both sweeps compare answers by. One home, so every sweep draws the same layouts from the same seed
 * (test_sweep.c's test_local_optima replays its draws by index). */
#ifndef HP_TESTS_RELIABILITY_SWEEP_DRAWS_H
#define HP_TESTS_RELIABILITY_SWEEP_DRAWS_H

#include "support/test_util.h"
#include "support/rng.h"
#include "support/ident_layouts.h"
#include "headplan/headplan.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const double PI = 3.14159265358979323846;

static inline void sw_unit3(uint64_t *s, double u[3])
{
    double n;
    do {
        for (int i = 0; i < 3; ++i) u[i] = test_rng_uniform(s, -1, 1);
        n = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    } while (n < 0.1 || n > 1.0);
    for (int i = 0; i < 3; ++i) u[i] /= n;
}

/* A random layout: head ellipsoid (or, one in four, a sphere) of adult size, centre up to
 * 10 mm off the origin, pivot up to 30 mm sideways and 0-120 mm below the centre, the eight
 * default rays tilted by up to ±0.15, bladders of random size; one in three soft
 * (neo-Hookean, stretch limit just below the limit point, p_max above its peak), one in
 * three with a rate limit of 0.5-3 kPa per plan. kind receives a short description. */
static inline hp_error sw_layout(uint64_t *s, hp_layout *L, char *kind, size_t kn)
{
    int sphere = test_rng_next(s) % 4 == 0;
    double ax[3] = {test_rng_uniform(s, 0.070, 0.090), test_rng_uniform(s, 0.100, 0.125),
                    test_rng_uniform(s, 0.085, 0.105)};
    if (sphere) ax[0] = test_rng_uniform(s, 0.080, 0.100);
    double c[3], pv[3], rays[8][3];
    for (int i = 0; i < 3; ++i) c[i] = test_rng_uniform(s, -0.010, 0.010);
    pv[0] = c[0] + test_rng_uniform(s, -0.030, 0.030);
    pv[1] = c[1] + test_rng_uniform(s, -0.030, 0.030);
    pv[2] = c[2] - test_rng_uniform(s, 0.0, 0.120);
    for (int k = 0; k < 8; ++k)
        for (int i = 0; i < 3; ++i)
            rays[k][i] = il_default_rays[k][i] + test_rng_uniform(s, -0.15, 0.15);
    hp_error e = il_layout(L, sphere ? HP_HEAD_SPHERE : HP_HEAD_ELLIPSOID, ax, c, pv, 8,
                           (const double(*)[3])rays, test_rng_uniform(s, 0.85, 1.15));
    if (e != HP_OK) return e;
    int mat = (int)(test_rng_next(s) % 3), rate = test_rng_next(s) % 3 == 0;
    double rmax = test_rng_uniform(s, 500.0, 3000.0);
    for (int k = 0; k < L->n; ++k) {
        hp_bladder *B = &L->bladders[k];
        if (mat == 1) {
            B->iab.C2 = 0.0;
            hp_iab_limit lp;
            e = hp_iab_limit_point(&B->iab, &lp);
            if (e != HP_OK || !lp.exists) return e != HP_OK ? e : HP_ERR_DOMAIN;
            B->stretch_max = lp.lambda_i * (1.0 - 1e-6);
            B->p_max = 2.0 * lp.pressure;
        }
        if (rate) B->rate_max = rmax;
    }
    snprintf(kind, kn, "%s%s%s", sphere ? "sphere" : "ellipsoid", mat == 1 ? " soft" : "",
             rate ? " rate" : "");
    return hp_layout_prepare(L, NULL);
}

/* One target (SI) from band b, inside the identifiable range: 0 the band where an early SQP
 * cycled (30-40 mm, 15-27 deg), 1 wide (0-100 mm, 0-89 deg), 2 small (0-10 mm, 0-10 deg).
 * A translation beyond 0.95 of the head's smallest semi-axis is shortened to it. */
static inline void sw_target(uint64_t *s, int band, const hp_identifiable *id, double xi[6])
{
    static const double tmax[3] = {40, 100, 10}, tmin[3] = {30, 0, 0};
    static const double amax[3] = {27, 89, 10}, amin[3] = {15, 0, 0};
    double u[3], v[3];
    sw_unit3(s, u);
    sw_unit3(s, v);
    double t = test_rng_uniform(s, tmin[band], tmax[band]) * 1e-3;
    double a = test_rng_uniform(s, amin[band], amax[band]) * PI / 180.0;
    if (t > 0.95 * id->trans_limit) t = 0.95 * id->trans_limit;
    for (int i = 0; i < 3; ++i) {
        xi[i] = t * u[i];
        xi[3 + i] = a * v[i]; /* pitch, roll, yaw of a rotation vector: an angle near a */
    }
    /* Keep the rotation angle about its own axis below 90 deg (identifiable). */
    while (!(hp_pose_rotation_angle(xi) < 0.97 * PI / 2))
        for (int i = 3; i < 6; ++i) xi[i] *= 0.9;
}

/* The weighted distance (mm, deg: the planner's default weight 1 mm per deg) from the
 * achieved pose to the desired one: the objective both backends minimise. */
static inline double sw_dist(const hp_result *r)
{
    double s = 0;
    for (int i = 0; i < 6; ++i) {
        double e = (r->achieved[i] - r->desired[i]) * (i < 3 ? 1e3 : 180 / PI);
        if (r->commanded[i]) s += e * e;
    }
    return sqrt(s);
}

/* Every layout scene of the catalogue (the paper_* scenes are single bladders). */
#define SW_CATALOGUE 11
static const char *const sw_catalogue[SW_CATALOGUE] = {
    "default.yaml",     "large_rotation.yaml", "load_heavy.yaml",      "load_prone.yaml",
    "load_supine.yaml", "load_tilted.yaml",    "near_degenerate.yaml", "nodding.yaml",
    "saturation.yaml",  "soft_material.yaml",  "sphere_head.yaml"};

/* The catalogue scene `name`, loaded (the caller frees it). */
static inline hp_scene *sw_scene(const char *name)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/scenarios/%s", HP_SOURCE_DIR, name);
    hp_scene *sc = calloc(1, sizeof *sc);
    assert_non_null(sc);
    hp_diag d = {{0}};
    if (hp_scene_load(path, sc, &d) != HP_OK) {
        print_error("%s\n", d.text);
        fail();
    }
    return sc;
}

/* A planner of backend b at the level, Ipopt at tolerance 1e-10 (the reference); warm = 1
 * starts each plan from the previous answer (the default), 0 cold; its nominal pressures in
 * prev unless NULL (a trace's first previous pressures). */
static inline hp_planner *sw_planner(const hp_layout *L, hp_backend b, hp_level level, int warm,
                                     double *prev)
{
    hp_settings st;
    hp_settings_default(&st);
    st.backend = b;
    st.level = level;
    st.warm_start = warm;
    st.max_time = 60.0; /* outcomes must not depend on the machine's speed */
    if (b == HP_BACKEND_IPOPT) st.tolerance = 1e-10;
    /* One start: the sweep compares the realtime answer with Ipopt's local optimum from the
     * same start (test_best_local.c holds it to the best of Ipopt with its restarts). */
    if (b == HP_BACKEND_IPOPT) st.restarts = 0;
    hp_planner *p = NULL;
    hp_diag d = {{0}};
    if (hp_planner_create(L, &st, &p, &d) != HP_OK) {
        print_error("create %s: %s\n", hp_backend_name(b), d.text);
        fail();
    }
    if (prev) assert_int_equal(hp_planner_nominal_pressures(p, prev), HP_OK);
    return p;
}

/* The seed of test_sweep.c's generated sweep. */
#define SW_SEED 0x16a2026u

/* Replays the generated sweep's draws (test_generated_layouts: layouts and, for every layout
 * the checks accept, its 30 targets of the full-size sweep) up to layout `layout`; returns
 * that layout in L and its target `target` in xi. */
#define SW_FULL_TARGETS 30
static inline void sw_replay(int layout, int target, hp_layout *L, char *kind, size_t kn,
                             double xi[6])
{
    uint64_t s = SW_SEED;
    for (int i = 0; i <= layout; ++i) {
        if (sw_layout(&s, L, kind, kn) != HP_OK) {
            assert_true(i != layout);
            continue;
        }
        hp_identifiable id;
        assert_int_equal(hp_layout_identify(L, &id), HP_OK);
        for (int j = 0; j < SW_FULL_TARGETS; ++j) {
            double t[6];
            sw_target(&s, j % 3, &id, t);
            if (i == layout && j == target) memcpy(xi, t, sizeof t);
        }
    }
}

#endif
