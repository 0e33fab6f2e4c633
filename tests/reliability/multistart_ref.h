/* The multi-start reference of the best-local-answer sweep (test_best_local.c): for a desired
 * pose, the closest reachable pose Ipopt finds from many seeded starts and the nominal pose,
 * the best reference answer a local method can be held to. Test side only, not product.
 *
 * The program is a cold plan's: the static limits and, for a rate-limited layout, the rate
 * windows around the nominal pressures. Started from another pose the planner would centre
 * its rate windows there, so the reference planner runs on a copy of the layout whose
 * pressure limits are cut to those windows ([P_nom − rate_max, P_nom + rate_max] within
 * [p_min, p_max]) and that has no rate limit: the same feasible set (both become the same
 * bounds on the radii through the same bladder law), any start.
 *
 * A start is a feasible pose of that program: the realtime planner's answer (REACHED or
 * CLOSEST) for a seeded pose, the desired pose scaled by a random factor in [0, 1.2] plus a
 * random offset of up to 10 mm and 10 deg per component; Ipopt (restarts 0, sw_planner: one
 * solve a start) starts from it with hp_planner_set_previous_result. Each start's answer counts only when Ipopt says REACHED
 * or CLOSEST (the planner has confirmed it by its forward model). */
#ifndef HP_TESTS_RELIABILITY_MULTISTART_REF_H
#define HP_TESTS_RELIABILITY_MULTISTART_REF_H

#include "sweep_draws.h"

#include <stdlib.h>
#include <string.h>

typedef struct ms_ref {
    hp_layout folded;    /* the layout with the rate windows as pressure limits */
    hp_planner *ipopt;   /* Ipopt (tolerance 1e-10), warm: starts from the previous answer */
    hp_planner *starter; /* realtime on the folded layout: the start poses */
} ms_ref;

/* A warm planner (starts from the previous answer: the start a caller sets). */
static inline hp_planner *ms_planner(const hp_layout *L, hp_backend b, hp_level level)
{
    return sw_planner(L, b, level, 1, NULL);
}

/* Folds L's rate windows around its nominal pressures into its pressure limits. */
static inline void ms_ref_create(ms_ref *r, const hp_layout *L, hp_level level)
{
    hp_planner *tmp = ms_planner(L, HP_BACKEND_REALTIME, level);
    double nom[HP_MAX_BLADDERS];
    assert_int_equal(hp_planner_nominal_pressures(tmp, nom), HP_OK);
    hp_planner_destroy(tmp);
    r->folded = *L;
    for (int k = 0; k < L->n; ++k) {
        hp_bladder *B = &r->folded.bladders[k];
        if (!isfinite(B->rate_max)) continue;
        B->p_min = fmax(B->p_min, nom[k] - B->rate_max);
        B->p_max = fmin(B->p_max, nom[k] + B->rate_max);
        B->rate_max = INFINITY;
    }
    assert_int_equal(hp_layout_prepare(&r->folded, NULL), HP_OK);
    r->ipopt = ms_planner(&r->folded, HP_BACKEND_IPOPT, level);
    r->starter = ms_planner(&r->folded, HP_BACKEND_REALTIME, level);
}

static inline void ms_ref_destroy(ms_ref *r)
{
    hp_planner_destroy(r->ipopt);
    hp_planner_destroy(r->starter);
}

static inline int ms_answer(const hp_result *a)
{
    return a->status == HP_STATUS_REACHED || a->status == HP_STATUS_CLOSEST ||
           a->status == HP_STATUS_UNCOMMANDED;
}

/* The best of Ipopt's answers for xi from the nominal pose and from `starts` seeded start
 * poses (seed: this call's own sequence), in *best (its status HP_STATUS_SOLVER_ERROR when
 * no start gave an answer). Returns the number of starts that gave an answer. */
static inline int ms_ref_best(ms_ref *r, const double xi[6], int starts, uint64_t seed,
                              hp_result *best)
{
    uint64_t s = seed;
    int got = 0;
    memset(best, 0, sizeof *best);
    best->status = HP_STATUS_SOLVER_ERROR;
    for (int j = 0; j <= starts; ++j) {
        hp_planner_reset(r->ipopt);
        if (j > 0) {
            double x0[6], f = test_rng_uniform(&s, 0.0, 1.2);
            for (int i = 0; i < 6; ++i)
                x0[i] = f * xi[i] + test_rng_uniform(&s, -1, 1) * (i < 3 ? 0.010 : 10 * PI / 180);
            hp_result a;
            hp_planner_reset(r->starter);
            assert_int_equal(hp_plan(r->starter, x0, &a), HP_OK);
            if (!ms_answer(&a) || hp_planner_set_previous_result(r->ipopt, &a) != HP_OK) continue;
        }
        hp_result b;
        assert_int_equal(hp_plan(r->ipopt, xi, &b), HP_OK);
        if (!ms_answer(&b)) continue;
        ++got;
        if (best->status == HP_STATUS_SOLVER_ERROR || sw_dist(&b) < sw_dist(best)) *best = b;
    }
    return got;
}

#endif
